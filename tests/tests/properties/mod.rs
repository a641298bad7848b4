//! What the property tests share: the registry of every shipped law, the proptest runner from
//! a fixed seed, and the random cases' building blocks. Each test crate that includes it uses
//! part of it.
#![allow(dead_code)]

use dashpot::{Registry, SearchPath};
use dashpot_sdk::testkit::Rng;
use dashpot_sdk::{LawInfo, LawKind, Particle};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// Every plugin library of the build but the test fixtures and LAMMPS's sub-models (the
/// `dashpot_granular` library, whose `gran-*` laws mirror LAMMPS on purpose and are held to
/// LAMMPS's numbers by their own tests; along these random paths their energy books do not
/// close yet), in one registry.
pub fn shipped() -> Registry {
    let deps = dashpot_tests::deps_dir();
    let mut files: Vec<_> = std::fs::read_dir(&deps)
        .expect("the build's deps directory")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
            name.starts_with("libdashpot_")
                && name.ends_with(dashpot::registry::DYLIB_EXT)
                && !name.contains("fixture")
                && !name.contains("capi")
                && !name.contains("granular")
        })
        .collect();
    files.sort();
    let reg = Registry::discover(&SearchPath {
        dirs: vec![],
        files,
        use_env: false,
        use_default: false,
    })
    .expect("the shipped plugins load");
    assert!(reg.laws.len() >= 15, "the shipped laws: {}", reg.laws.len());
    reg
}

/// Whether a law mirrors LAMMPS's bookkeeping on purpose (`gran-*`).
pub fn lammps_mirror(name: &str) -> bool {
    name.starts_with("gran-")
}

/// A law created or bound from random parameters: a combination its law refuses (say
/// Walton–Braun's k2 < k1) is no case, rejected; any other error fails the case.
pub fn made<T>(r: Result<T, dashpot_sdk::LawError>) -> Result<T, TestCaseError> {
    r.map_err(|e| match e.kind {
        dashpot_sdk::ErrorKind::InvalidParameter => TestCaseError::reject(e.to_string()),
        _ => TestCaseError::fail(e.to_string()),
    })
}

/// The runner: `cases` cases (or `PROPTEST_CASES`) from a fixed seed, no failure files.
pub fn runner(cases: u32) -> TestRunner {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|c| c.parse().ok())
        .unwrap_or(cases);
    let config = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    TestRunner::new_with_rng(config, TestRng::deterministic_rng(RngAlgorithm::ChaCha))
}

/// Runs `case` on `cases` seeds for each law of `laws`, and panics with every law's failure.
pub fn for_each_law(laws: &[LawInfo], cases: u32, case: impl Fn(&LawInfo, u64) -> Result<(), TestCaseError>) {
    let failed: Vec<String> = laws
        .iter()
        .filter_map(|info| {
            runner(cases)
                .run(&any::<u64>(), |seed| case(info, seed))
                .err()
                .map(|e| format!("{}: {e}", info.name))
        })
        .collect();
    assert!(
        failed.is_empty(),
        "{} law(s) failed:\n{}",
        failed.len(),
        failed.join("\n\n")
    );
}

/// A random particle of a case: 0.2 mm to 4 cm, 1000–8000 kg/m³, E from 1 MPa to 200 GPa.
pub fn particle(rng: &mut Rng) -> Particle {
    Particle {
        diameter: rng.log_between(2e-4, 4e-2),
        density: rng.between(1000.0, 8000.0),
        young: rng.log_between(1e6, 2e11),
        poisson: rng.between(0.0, 0.45),
    }
}

/// The laws of `kind` among the registry's.
pub fn of_kind(reg: &Registry, kind: LawKind) -> Vec<LawInfo> {
    reg.laws
        .iter()
        .map(|l| l.info.clone())
        .filter(|i| i.kind == kind)
        .collect()
}

/// One of `laws` at random.
pub fn pick<'a>(rng: &mut Rng, laws: &'a [LawInfo]) -> &'a LawInfo {
    &laws[((rng.uniform() * laws.len() as f64) as usize).min(laws.len() - 1)]
}
