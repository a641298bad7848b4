//! The Python package's pytest suite (`host/python/tests`), run against this build's plugins
//! and CLI and a third-party plugin built as an outside author builds it, when a venv with the
//! package is given by `DASHPOT_PY_VENV` (`.ci/run` makes one: `pip install ./host/python`
//! and pytest); otherwise it says why it skips.

mod common;

#[allow(dead_code)]
#[path = "../../tests/lib.rs"]
mod ext;

use std::path::PathBuf;
use std::process::Command;

#[test]
fn the_python_package_passes_its_pytest_suite() {
    let Some(venv) = std::env::var_os("DASHPOT_PY_VENV").map(PathBuf::from) else {
        let msg = "set DASHPOT_PY_VENV to a venv with `pip install ./host/python pytest` (.ci/run makes one)";
        // Under CI the suite must run, as the LAMMPS and old-sdk tests must.
        assert!(
            std::env::var_os("CI").is_none(),
            "the Python suite did not run: {msg}"
        );
        eprintln!("skipped: {msg}");
        return;
    };
    let python = venv.join("bin").join("python");
    let bin = PathBuf::from(env!("CARGO_BIN_EXE_dashpot"));
    let plugins = common::all_plugins_dir();
    let third_party = ext::build_external(
        &ext::workspace_root().join("tests/fixtures/third-party/Cargo.toml"),
        "dashpot-fixture-limited",
        "dashpot_fixture_limited",
        &[],
    );
    let tests = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("python")
        .join("tests");
    let out = Command::new(&python)
        .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
        .arg(&tests)
        .env("DASHPOT_PLUGIN_PATH", &plugins)
        .env("DASHPOT_BIN", &bin)
        .env("DASHPOT_THIRD_PARTY_PLUGIN", &third_party)
        .env("PYTHONDONTWRITEBYTECODE", "1")
        .output()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", python.display()));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "pytest failed:\n{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    eprintln!("{}", text.lines().last().unwrap_or(""));
}
