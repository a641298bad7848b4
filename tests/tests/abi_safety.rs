//! What the host does with plugins that are incompatible or misbehave.

use dashpot::collide::ContactForce as _;
use dashpot::{Registry, SearchPath};
use dashpot_sdk::abi::LoadedPlugin;
use dashpot_sdk::{ErrorKind, Pair, ParamValue, Particle};
use dashpot_tests::BindPair as _;
use dashpot_tests::{plugin_file, seed_registry, wrong_abi_plugin};

fn pair() -> Pair {
    Pair::spheres(&Particle::MCC, &Particle::MCC).unwrap()
}

fn faulty() -> LoadedPlugin {
    LoadedPlugin::load(&plugin_file("dashpot_fixture_faulty")).expect("fixture loads")
}

#[test]
fn a_plugin_built_against_another_sdk_version_is_refused_naming_both() {
    let path = wrong_abi_plugin();
    let err = LoadedPlugin::load(&path).unwrap_err();
    assert_eq!(err.kind, ErrorKind::Load);
    assert!(err.message.contains("1.0.0"), "{}", err.message);
    assert!(
        err.message.contains(dashpot_sdk::abi::ABI_VERSION),
        "{}",
        err.message
    );
    assert!(err.message.contains("Rebuild the plugin"), "{}", err.message);
    // Through the registry as an explicit file: the same refusal, no crash.
    let sp = SearchPath {
        files: vec![path],
        ..Default::default()
    };
    assert!(Registry::discover(&sp).unwrap_err().message.contains("1.0.0"));
}

#[test]
fn a_plugin_whose_types_have_another_layout_is_refused() {
    let err = LoadedPlugin::load(&dashpot_tests::wrong_layout_plugin()).unwrap_err();
    assert_eq!(err.kind, ErrorKind::Load);
    assert!(
        err.message.contains("do not have the layout this host expects"),
        "{}",
        err.message
    );
    assert!(
        err.message.contains("Pair"),
        "the message names the type: {}",
        err.message
    );
    assert!(
        err.message.lines().count() < 40,
        "a summary, not pages of dumps:\n{}",
        err.message
    );
}

#[test]
fn a_library_that_is_not_a_plugin_is_refused() {
    // libc is a shared library with no dashpot root module.
    let err = LoadedPlugin::load(std::path::Path::new("libc.so.6")).unwrap_err();
    assert_eq!(err.kind, ErrorKind::Load);
    assert!(err.message.contains("not a dashpot plugin"), "{}", err.message);
    let err = LoadedPlugin::load(std::path::Path::new("/nonexistent/libnothing.so")).unwrap_err();
    assert!(err.message.contains("cannot be opened"), "{}", err.message);
}

#[test]
fn a_panicking_law_is_an_error_and_the_host_goes_on() {
    let p = faulty();
    let law = p.new_contact("panicky", &[ParamValue::new("at", 1e-6)]).unwrap();
    let b = law.bind_pair(&pair()).unwrap();
    assert_eq!(b.force(1e-7, 1.0).unwrap(), 1e-7);
    let e = b.force(1e-5, 1.0).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Panic);
    assert!(
        e.message.contains("deliberate panic at delta = 0.00001"),
        "{}",
        e.message
    );
    // the same object keeps working after the panic
    assert_eq!(b.force(5e-7, 1.0).unwrap(), 5e-7);
    // in a batch
    let d = vec![0.0, 1e-7, 1e-3];
    let mut out = vec![0.0; 3];
    let e = b.force_batch(&d, &[0.0; 3], &mut out).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Panic);
    // in bind
    let law = p
        .new_contact("panicky", &[ParamValue::new("bind_panics", 1.0)])
        .unwrap();
    let e = law.bind_pair(&pair()).err().expect("bind panics");
    assert_eq!(e.kind, ErrorKind::Panic);
    assert!(e.message.contains("deliberate panic in bind"), "{}", e.message);
    // and other laws still work in this process
    let reg = seed_registry();
    let f = reg
        .contact("hsd", &[])
        .unwrap()
        .bind_pair(&pair())
        .unwrap()
        .force(1e-5, 0.0)
        .unwrap();
    assert!(f > 0.0);
}

#[test]
fn a_law_returning_nan_is_reported_with_its_inputs() {
    let p = faulty();
    let b = p
        .new_contact("nan-force", &[ParamValue::new("at", 1e-6)])
        .unwrap()
        .bind_pair(&pair())
        .unwrap();
    let e = b.force(2e-6, 0.25).unwrap_err();
    assert_eq!(e.kind, ErrorKind::NonFinite);
    assert!(
        e.message.contains("nan-force") && e.message.contains("2e-6") && e.message.contains("2.5e-1"),
        "{}",
        e.message
    );
    // batch: the first bad element is named
    let d: Vec<f64> = (0..5000).map(|i| if i == 4321 { 1e-3 } else { 1e-7 }).collect();
    let mut out = vec![0.0; d.len()];
    let e = b.force_batch(&d, &vec![0.5; d.len()], &mut out).unwrap_err();
    assert_eq!(e.kind, ErrorKind::NonFinite);
    assert!(e.message.contains("1e-3"), "{}", e.message);

    let r = p
        .new_restitution("nan-restitution", &[])
        .unwrap()
        .bind(&pair())
        .unwrap();
    assert_eq!(r.restitution(0.5).unwrap(), 0.5);
    let e = r.restitution(2.0).unwrap_err();
    assert_eq!(e.kind, ErrorKind::NonFinite);
    assert!(e.message.contains("2e0"), "{}", e.message);
}

#[test]
fn bad_requests_are_errors_not_crashes() {
    let reg = seed_registry();
    let e = reg.contact("nope", &[]).err().unwrap();
    assert_eq!(e.kind, ErrorKind::UnknownLaw);
    for n in ["lsd", "hsd", "kuwabara-kono", "mcnamara-falcon", "constant"] {
        assert!(e.message.contains(n), "{}", e.message);
    }
    let e = reg.contact("constant", &[]).err().unwrap();
    assert!(e.message.contains("restitution law"), "{}", e.message);
    let e = reg.restitution("hsd", &[]).err().unwrap();
    assert!(e.message.contains("contact law"), "{}", e.message);
    let e = reg.contact("hsd", &[ParamValue::new("eps", 0.0)]).err().unwrap();
    assert_eq!(e.kind, ErrorKind::InvalidParameter);
    assert!(e.message.contains("(0, 1]"), "{}", e.message);
    let e = reg.contact("hsd", &[ParamValue::new("k", 1.0)]).err().unwrap();
    assert_eq!(e.kind, ErrorKind::UnknownParameter);
    // a pair built by hand with a bad field is refused before the plugin sees it
    let bad = Pair {
        mass: -1.0,
        radius: 1.0,
        young: 1.0,
    };
    let e = reg.contact("hsd", &[]).unwrap().bind_pair(&bad).err().unwrap();
    assert_eq!(e.kind, ErrorKind::InvalidPair);
    // slices of different lengths
    let b = reg.contact("hsd", &[]).unwrap().bind_pair(&pair()).unwrap();
    let mut out = vec![0.0; 2];
    assert!(b.force_batch(&[0.0; 3], &[0.0; 3], &mut out).is_err());
}

#[test]
fn a_directory_scan_skips_libraries_that_are_not_plugins() {
    // deps/ holds proc-macro libraries and the plugins; only the plugins are registered.
    let sp = SearchPath {
        dirs: vec![dashpot_tests::deps_dir()],
        ..Default::default()
    };
    let reg = Registry::discover(&sp).unwrap();
    for n in [
        "lsd",
        "hsd",
        "kuwabara-kono",
        "mcnamara-falcon",
        "constant",
        "panicky",
    ] {
        assert!(reg.find(n).is_ok(), "{n} missing");
    }
}

#[test]
fn a_refused_plugin_in_a_directory_does_not_stop_the_others() {
    let dir =
        std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("mixed-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(wrong_abi_plugin(), dir.join("libdashpot_constant.so")).unwrap();
    std::fs::copy(plugin_file("dashpot_hsd"), dir.join("libdashpot_hsd.so")).unwrap();
    let reg = Registry::discover(&SearchPath {
        dirs: vec![dir.clone()],
        ..Default::default()
    })
    .unwrap();
    assert!(reg.find("hsd").is_ok());
    assert_eq!(reg.refused.len(), 1);
    let e = reg.find("constant").unwrap_err();
    assert!(
        e.message.contains("unknown law 'constant'") && e.message.contains("1.0.0"),
        "{}",
        e.message
    );
    std::fs::remove_dir_all(&dir).ok();
}
