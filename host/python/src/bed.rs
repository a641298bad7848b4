//! `dashpot.bed`: the vibrated bed of McNamara & Falcon, run by the host's `dashpot bed` code
//! with `--json`, its document returned.

use super::*;
use crate::interrupt::watched;

/// The arguments of `dashpot bed`, parsed by the CLI's own parser.
#[derive(clap::Parser)]
#[command(name = "dashpot.bed", no_binary_name = true, disable_help_flag = true)]
struct BedCommand {
    #[command(flatten)]
    bed: dashpot::cli::bed::BedArgs,
}

/// Runs `dashpot bed ARGS --json` (the arguments as the CLI takes them, e.g. `["--restitution",
/// "mcnamara-falcon", "--layers", "1", "--freq", "20"]`) and returns the JSON it prints, as
/// text. The GIL is released while it runs; Ctrl-C stops it (`KeyboardInterrupt`).
#[pyfunction]
pub(crate) fn bed(py: Python<'_>, args: Vec<String>) -> PyResult<String> {
    let mut argv = args;
    argv.push("--json".into());
    let cmd = <BedCommand as clap::Parser>::try_parse_from(&argv)
        .map_err(|e| PyValueError::new_err(e.to_string().trim().to_string()))?;
    let reg = registry(py)?;
    let reg: &Registry = &reg;
    let out = watched(py, |stop| {
        dashpot::cli::bed::run_bed(reg, &cmd.bed, &|_| stop.check())
    })?
    .map_err(run_err)?;
    let v = out.ok_or_else(|| PyRuntimeError::new_err("dashpot bed --json printed no document"))?;
    Ok(v.to_string())
}
