//! Helpers shared by the integration tests: where the real plugin libraries are, and how to
//! build the out-of-workspace plugins (a deliberately incompatible one, the third-party example).

pub mod lammps;

use dashpot::{Registry, SearchPath};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Mutex, OnceLock};

/// A batch of contacts without history (no slots) whose forces go to `force`.
pub fn memoryless_batch<'a>(
    delta: &'a [f64],
    rate: &'a [f64],
    mass: &'a [f64],
    radius: &'a [f64],
    force: &'a mut [f64],
) -> dashpot_sdk::NormalBatch<'a> {
    dashpot_sdk::NormalBatch {
        delta,
        rate,
        mass,
        radius,
        slots: 0,
        history: &mut [],
        force,
    }
}

/// A restitution table's r(v) is within 1e-6 of the restitution the collision driver realizes
/// for contact law `law` (effective mass `mass`, kg; contact ending when the force returns to 0)
/// at every speed of `speeds` (m/s).
pub fn within_1e6_of_the_driver(
    table: &impl dashpot_sdk::BoundRestitution,
    law: &impl dashpot::collide::ContactForce,
    mass: f64,
    speeds: &[f64],
    opt: &dashpot::collide::Options,
) {
    for &v in speeds {
        let exact = dashpot::collide::collide(law, mass, v, dashpot_sdk::EndCriterion::Force, opt)
            .unwrap()
            .restitution;
        let r = table.restitution(v);
        assert!((r - exact).abs() <= 1e-6, "v {v}: {r} vs {exact}");
    }
}

/// `got` is within the relative tolerance `tol` of `want` (|got/want − 1| < tol); `what` names
/// the quantity in the failure message.
pub fn assert_rel(got: f64, want: f64, tol: f64, what: &str) {
    assert!((got / want - 1.0).abs() < tol, "{what} = {got} vs {want}");
}

/// `a` and `b` hold the same values to the bit (what is promised across sdk series, thread
/// counts and call paths); `what(i)` names value `i` in the failure message.
pub fn assert_same_bits(a: &[f64], b: &[f64], what: impl Fn(usize) -> String) {
    assert_eq!(a.len(), b.len(), "{}: lengths differ", what(0));
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert_eq!(x.to_bits(), y.to_bits(), "{}: {x:e} vs {y:e}", what(i));
    }
}

/// Uniform numbers in [0, 1) from a 64-bit linear congruential generator (Knuth's MMIX
/// constants) seeded with `seed`: reproducible initial states without a dependency (the DEM
/// tests' and the piles' of the benchmarks, the same sequence since their first figures).
pub fn lcg_uniform(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The directory named by the environment variable `var`, else `default()`, if it holds the file
/// `probe`; else why not: "no `missing` DIR (`hint`)", e.g. for a peer code a benchmark compares
/// against and skips without.
pub fn dir_holding(
    var: &str,
    default: impl FnOnce() -> Result<PathBuf, String>,
    probe: &str,
    missing: &str,
    hint: &str,
) -> Result<PathBuf, String> {
    let dir = match std::env::var_os(var) {
        Some(d) => PathBuf::from(d),
        None => default()?,
    };
    if dir.join(probe).is_file() {
        Ok(dir)
    } else {
        Err(format!("no {missing} {} ({hint})", dir.display()))
    }
}

/// The workspace root.
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ has a parent")
        .to_path_buf()
}

/// The directory holding the test executable: `target/<profile>/deps`, where cargo leaves the
/// plugin `.so` files it built as dev-dependencies of this crate.
pub fn deps_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("current_exe");
    exe.parent().expect("exe dir").to_path_buf()
}

/// The file of library `lib_name` in `dir` (`dashpot_hsd` → `DIR/libdashpot_hsd.so`).
pub fn lib_in(dir: &Path, lib_name: &str) -> PathBuf {
    dir.join(format!(
        "{}{lib_name}{}",
        std::env::consts::DLL_PREFIX,
        std::env::consts::DLL_SUFFIX
    ))
}

/// The path of a plugin library by crate name (`dashpot_hsd` → `deps/libdashpot_hsd.so`).
pub fn plugin_file(lib_name: &str) -> PathBuf {
    lib_in(&deps_dir(), lib_name)
}

/// The five seed plugins, by library name.
pub const SEED_PLUGINS: [&str; 5] = [
    "dashpot_lsd",
    "dashpot_hsd",
    "dashpot_kuwabara_kono",
    "dashpot_mcnamara_falcon",
    "dashpot_constant",
];

/// The laws added with sdk 0.2 (tangential and plastic), by library name.
pub const SDK02_PLUGINS: [&str; 4] = [
    "dashpot_mindlin",
    "dashpot_linear_history",
    "dashpot_thornton",
    "dashpot_walton_braun",
];

/// The laws added with sdk 0.3 (adhesive normal, rolling, twisting), by library name.
pub const SDK03_PLUGINS: [&str; 6] = [
    "dashpot_jkr",
    "dashpot_dmt",
    "dashpot_rolling_sds",
    "dashpot_rolling_epsd",
    "dashpot_twisting_sds",
    "dashpot_twisting_marshall",
];

/// The heat laws of sdk 0.4, by library name.
pub const HEAT_PLUGINS: [&str; 3] = [
    "dashpot_heat_radius",
    "dashpot_heat_area",
    "dashpot_heat_radius_corrected",
];

/// A registry of exactly the plugin libraries `files`, nothing else.
pub fn registry_of(files: Vec<PathBuf>) -> Registry {
    let sp = SearchPath {
        dirs: vec![],
        files,
        use_env: false,
        use_default: false,
    };
    Registry::discover(&sp).expect("the plugins load")
}

/// A registry of the plugins of these groups of library names, from the test build.
fn registry_of_groups(groups: &[&[&str]]) -> Registry {
    registry_of(
        groups
            .iter()
            .flat_map(|g| g.iter())
            .map(|n| plugin_file(n))
            .collect(),
    )
}

/// A registry of every plugin of the workspace, those of sdk 0.3 included.
pub fn registry_03() -> Registry {
    registry_of_groups(&[&SEED_PLUGINS, &SDK02_PLUGINS, &SDK03_PLUGINS])
}

/// A registry of every plugin of the workspace and the context fixture (sdk 0.4's
/// `context-probe` normal law and the laws that echo the context they receive).
pub fn registry_with_context_fixture() -> Registry {
    registry_of_groups(&[
        &SEED_PLUGINS,
        &SDK02_PLUGINS,
        &SDK03_PLUGINS,
        &["dashpot_fixture_context"],
    ])
}

/// A registry of every plugin of the workspace, the heat laws of sdk 0.4 included.
pub fn registry_04() -> Registry {
    registry_of_groups(&[&SEED_PLUGINS, &SDK02_PLUGINS, &SDK03_PLUGINS, &HEAT_PLUGINS])
}

/// A registry of the seed laws and those of sdk 0.2.
pub fn full_registry() -> Registry {
    registry_of_groups(&[&SEED_PLUGINS, &SDK02_PLUGINS])
}

/// A registry of exactly the five seed plugins, loaded from their `.so` files.
pub fn seed_registry() -> Registry {
    registry_of_groups(&[&SEED_PLUGINS])
}

fn target_root() -> PathBuf {
    // deps_dir() = <target>/<profile>/deps
    deps_dir()
        .parent()
        .and_then(Path::parent)
        .expect("target dir")
        .to_path_buf()
}

/// Builds a crate outside the main build (its own target directory, so that a nested cargo
/// never waits on the lock of the build running these tests) and returns its library file.
/// `env` is set for the build only.
pub fn build_external(manifest: &Path, package: &str, lib_name: &str, env: &[(&str, &str)]) -> PathBuf {
    build_external_with(manifest, package, lib_name, env, &[], None)
}

/// [`build_external`] with extra cargo arguments (e.g. `--features`); with `copy_as`, the
/// library is copied to that file name beside it before the build lock is released (builds of
/// the same crate with other settings overwrite the original).
pub fn build_external_with(
    manifest: &Path,
    package: &str,
    lib_name: &str,
    env: &[(&str, &str)],
    extra: &[&str],
    copy_as: Option<&str>,
) -> PathBuf {
    static LOCK: OnceLock<Mutex<()>> = OnceLock::new();
    let _g = LOCK
        .get_or_init(|| Mutex::new(()))
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    let target = target_root().join("external");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let mut cmd = Command::new(cargo);
    cmd.arg("build")
        .arg("--quiet")
        .arg("--manifest-path")
        .arg(manifest)
        .arg("-p")
        .arg(package)
        .arg("--target-dir")
        .arg(&target)
        .args(extra)
        .env_remove("DASHPOT_SDK_FAKE_ABI_VERSION");
    for (k, v) in env {
        cmd.env(k, v);
    }
    let status = cmd.status().expect("run cargo");
    assert!(status.success(), "building {package} failed");
    let built = lib_in(&target.join("debug"), lib_name);
    match copy_as {
        Some(name) => {
            let dst = built.with_file_name(format!("lib{name}{}", std::env::consts::DLL_SUFFIX));
            std::fs::copy(&built, &dst).expect("copy the built plugin");
            dst
        }
        None => built,
    }
}

/// The `constant` plugin rebuilt with the environment `env` and the cargo arguments `extra`,
/// copied to `lib<copy_as>.so` (building the real plugin again would overwrite it); built once
/// per test process.
fn rebuilt_constant(copy_as: &str, env: &[(&str, &str)], extra: &[&str]) -> PathBuf {
    static BUILT: Mutex<Vec<(String, PathBuf)>> = Mutex::new(Vec::new());
    let mut built = BUILT.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, p)) = built.iter().find(|(n, _)| n == copy_as) {
        return p.clone();
    }
    let root = workspace_root().join("Cargo.toml");
    let p = build_external_with(
        &root,
        "dashpot-constant",
        "dashpot_constant",
        env,
        extra,
        Some(copy_as),
    );
    built.push((copy_as.to_string(), p.clone()));
    p
}

/// The `constant` plugin rebuilt against a dashpot-sdk that claims ABI version 1.0.0 (a future
/// major).
pub fn wrong_abi_plugin() -> PathBuf {
    rebuilt_constant(
        "wrong_abi_constant",
        &[("DASHPOT_SDK_FAKE_ABI_VERSION", "1.0.0")],
        &[],
    )
}

/// The `constant` plugin rebuilt against a dashpot-sdk that claims the next series, 0.5.0 (a
/// series this host does not speak).
pub fn next_series_plugin() -> PathBuf {
    rebuilt_constant(
        "next_series_constant",
        &[("DASHPOT_SDK_FAKE_ABI_VERSION", "0.5.0")],
        &[],
    )
}

/// The `constant` plugin rebuilt against a dashpot-sdk of the same version whose `Pair` has an
/// extra field: a stale or mismatched build that only the layout check can catch.
pub fn wrong_layout_plugin() -> PathBuf {
    rebuilt_constant(
        "wrong_layout_constant",
        &[],
        &["--features", "dashpot-sdk/__layout_skew_for_tests"],
    )
}

/// The third-party example plugin, built from its own workspace as an outside author would.
pub fn third_party_plugin() -> PathBuf {
    static P: OnceLock<PathBuf> = OnceLock::new();
    P.get_or_init(|| {
        build_external(
            &workspace_root().join("examples/third-party-law/Cargo.toml"),
            "dashpot-example-law",
            "dashpot_example_law",
            &[],
        )
    })
    .clone()
}

/// A plugin contact law bound to one pair, as the two-body tests use it: `force(δ, δ̇)`,
/// `force_batch`, `coefficients()` ([`dashpot::collide::ContactForce`] must be in scope).
pub type PluginPair = dashpot::collide::PairLaw<dashpot_sdk::abi::ContactModelHandle>;

/// Binds a plugin contact law to a [`dashpot_sdk::Pair`] (both bodies of Poisson's ratio 0.3,
/// which only the shear modulus depends on).
pub trait BindPair {
    /// The law bound to `pair`.
    fn bind_pair(&self, pair: &dashpot_sdk::Pair) -> Result<PluginPair, dashpot_sdk::LawError>;
}

impl BindPair for dashpot_sdk::abi::ContactLawHandle {
    fn bind_pair(&self, pair: &dashpot_sdk::Pair) -> Result<PluginPair, dashpot_sdk::LawError> {
        dashpot::collide::PairLaw::bind(self, pair, 0.3)
    }
}

/// Contact law `name` of `reg` with `params`, bound to `pair` (Poisson's ratio 0.3).
pub fn pair_law(
    reg: &Registry,
    name: &str,
    params: &[dashpot_sdk::ParamValue],
    pair: &dashpot_sdk::Pair,
) -> PluginPair {
    reg.contact(name, params).unwrap().bind_pair(pair).unwrap()
}

/// A release of dashpot-sdk as this repository's history holds it: the commit whose tree is
/// the last of its series, and the seed plugins a user of it has on disk.
#[derive(Debug, Clone, Copy)]
pub struct OldSdk {
    /// The series, e.g. `"0.1"`.
    pub series: &'static str,
    /// The commit of its last tree.
    pub commit: &'static str,
    /// The plugin packages built from it.
    pub packages: &'static [&'static str],
    /// Their library names.
    pub libs: &'static [&'static str],
}

/// dashpot-sdk 0.1.0: the last release before sdk 0.2 (the five seed plugins).
pub const SDK_0_1: OldSdk = OldSdk {
    series: "0.1",
    commit: "32de0ccd4878fc8a8166c3337f6dc30793566041",
    packages: &[
        "dashpot-lsd",
        "dashpot-hsd",
        "dashpot-kuwabara-kono",
        "dashpot-mcnamara-falcon",
        "dashpot-constant",
    ],
    libs: &SEED_PLUGINS,
};

/// dashpot-sdk 0.2.0: the last commit before sdk 0.3 (HSD, and the history laws Mindlin and
/// Thornton).
pub const SDK_0_2: OldSdk = OldSdk {
    series: "0.2",
    commit: "ffb1e69f6adcad922353a3f797794e36c0815fcc",
    packages: &["dashpot-hsd", "dashpot-mindlin", "dashpot-thornton"],
    libs: &["dashpot_hsd", "dashpot_mindlin", "dashpot_thornton"],
};

/// dashpot-sdk 0.3.0: the last commit before sdk 0.4 (normal laws with and without history, an
/// adhesive one with its reach, a tangential, a rolling and a twisting law).
pub const SDK_0_3: OldSdk = OldSdk {
    series: "0.3",
    commit: "ba5111dae4f99edd44647b5a23b264716ae5b0b4",
    packages: &[
        "dashpot-hsd",
        "dashpot-thornton",
        "dashpot-jkr",
        "dashpot-mindlin",
        "dashpot-rolling-sds",
        "dashpot-twisting-sds",
    ],
    libs: &[
        "dashpot_hsd",
        "dashpot_thornton",
        "dashpot_jkr",
        "dashpot_mindlin",
        "dashpot_rolling_sds",
        "dashpot_twisting_sds",
    ],
};

/// The commit of this repository whose tree is dashpot-sdk 0.1.0.
pub const SDK_0_1_COMMIT: &str = SDK_0_1.commit;

/// The plugins of `sdk` built from the sources of its commit (extracted with `git archive`,
/// built in a target directory of their own, `target/sdk-<series>/`, in `profile` "debug" or
/// "release"): the directory holding their libraries. `None`, with the reason printed, when
/// this is not a git checkout holding that commit (a fatal error under `CI=true`).
pub fn old_sdk_plugins(sdk: &OldSdk, profile: &str) -> Option<PathBuf> {
    static LOCK: OnceLock<Mutex<()>> = OnceLock::new();
    let _g = LOCK
        .get_or_init(|| Mutex::new(()))
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    let root = workspace_root();
    let base = target_root().join(format!("sdk-{}", sdk.series));
    let src = base.join("src");
    let stamp = src.join(".dashpot-commit");
    let commit = sdk.commit;
    let have = std::fs::read_to_string(&stamp).is_ok_and(|s| s.trim() == commit);
    if !have {
        let ok = Command::new("git")
            .arg("-C")
            .arg(&root)
            .args(["cat-file", "-e", &format!("{commit}^{{commit}}")])
            .status()
            .is_ok_and(|s| s.success());
        if !ok {
            let msg = format!(
                "the sdk {} sources (commit {commit}) are not in this checkout's git history",
                sdk.series
            );
            assert!(std::env::var_os("CI").is_none(), "{msg}");
            eprintln!("skipped: {msg}");
            return None;
        }
        let _ = std::fs::remove_dir_all(&src);
        std::fs::create_dir_all(&src).expect("create the old sdk's source dir");
        let archive = Command::new("git")
            .arg("-C")
            .arg(&root)
            .args(["archive", "--format=tar", commit])
            .output()
            .expect("run git archive");
        assert!(archive.status.success(), "git archive {commit} failed");
        let mut tar = Command::new("tar")
            .arg("-x")
            .arg("-C")
            .arg(&src)
            .stdin(std::process::Stdio::piped())
            .spawn()
            .expect("run tar");
        {
            use std::io::Write;
            tar.stdin
                .take()
                .expect("tar stdin")
                .write_all(&archive.stdout)
                .expect("feed tar");
        }
        assert!(tar.wait().expect("tar").success(), "tar failed");
        std::fs::write(&stamp, commit).expect("stamp");
    }
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let mut cmd = Command::new(cargo);
    cmd.arg("build")
        .arg("--quiet")
        .arg("--locked")
        .arg("--manifest-path")
        .arg(src.join("Cargo.toml"));
    for p in sdk.packages {
        cmd.args(["-p", p]);
    }
    cmd.arg("--target-dir")
        .arg(base.join("target"))
        .env_remove("DASHPOT_SDK_FAKE_ABI_VERSION")
        .env_remove("RUSTFLAGS");
    if profile == "release" {
        cmd.arg("--release");
    }
    let status = cmd.status().expect("run cargo");
    assert!(status.success(), "building the sdk {} plugins failed", sdk.series);
    Some(base.join("target").join(profile))
}

/// The seed plugins built from the sdk 0.1 sources (see [`old_sdk_plugins`]).
pub fn sdk01_plugins(profile: &str) -> Option<PathBuf> {
    old_sdk_plugins(&SDK_0_1, profile)
}

/// A registry holding only the plugins of `sdk`, as built from its sources.
pub fn old_sdk_registry(sdk: &OldSdk, profile: &str) -> Option<Registry> {
    let dir = old_sdk_plugins(sdk, profile)?;
    let sp = SearchPath {
        dirs: vec![],
        files: sdk.libs.iter().map(|n| lib_in(&dir, n)).collect(),
        use_env: false,
        use_default: false,
    };
    let reg = Registry::discover(&sp)
        .unwrap_or_else(|e| panic!("the sdk {} plugins load in this host: {}", sdk.series, e.message));
    // every plugin was built against that sdk and is spoken to as one of its series
    let series = match sdk.series {
        "0.1" => dashpot::laws::SdkSeries::V0_1,
        "0.2" => dashpot::laws::SdkSeries::V0_2,
        _ => dashpot::laws::SdkSeries::V0_3,
    };
    for p in &reg.plugins {
        let version = format!("{}.", sdk.series);
        assert!(
            p.sdk_version.starts_with(&version),
            "{}: {}",
            p.name,
            p.sdk_version
        );
        assert_eq!(p.series, series, "{}", p.name);
    }
    Some(reg)
}

/// A registry holding only the five seed plugins as built from the sdk 0.1 sources.
pub fn sdk01_registry(profile: &str) -> Option<Registry> {
    old_sdk_registry(&SDK_0_1, profile)
}

/// A registry holding HSD, Mindlin and Thornton as built from the sdk 0.2 sources.
pub fn sdk02_registry(profile: &str) -> Option<Registry> {
    old_sdk_registry(&SDK_0_2, profile)
}

/// A registry holding the laws of [`SDK_0_3`] as built from the sdk 0.3 sources.
pub fn sdk03_registry(profile: &str) -> Option<Registry> {
    old_sdk_registry(&SDK_0_3, profile)
}

/// Masses (kg), radii (m), and per step the overlaps (m) and overlap rates (m/s) of a
/// load–unload–reload cycle ([`load_cycle`]).
pub type Cycle = (Vec<f64>, Vec<f64>, Vec<Vec<f64>>, Vec<Vec<f64>>);

/// `n` contacts of assorted geometry over `steps` steps of one and a half sine periods of
/// overlap (contact i of amplitude 2 (1 + i) µm, shifted by `offset(i)` m, so some go into
/// tension): loading, unloading, reloading, with the matching rates.
pub fn load_cycle(n: usize, steps: usize, offset: impl Fn(usize) -> f64) -> Cycle {
    let mass: Vec<f64> = (0..n).map(|i| 1e-4 * (1.0 + 0.37 * i as f64)).collect();
    let radius: Vec<f64> = (0..n).map(|i| 1e-3 * (1.0 + 0.11 * i as f64)).collect();
    let (mut delta, mut rate) = (Vec::new(), Vec::new());
    for s in 0..steps {
        let ph = 3.0 * std::f64::consts::PI * s as f64 / steps as f64;
        delta.push(
            (0..n)
                .map(|i| 2e-6 * (1.0 + i as f64) * ph.sin() + offset(i))
                .collect(),
        );
        rate.push((0..n).map(|i| 0.3 * (1.0 + i as f64) * ph.cos()).collect());
    }
    (mass, radius, delta, rate)
}
