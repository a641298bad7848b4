//! `--check`'s estimates against real runs of minutes and gigabytes: 3D piles of 10³, 10⁵ and
//! 10⁶ spheres, the event-driven and the DEM vibrated bed, each a row of estimated and measured
//! peak memory and wall time (the table of docs/dem.md, "Before a run"). `cargo test` checks the
//! smaller runs (`tests/budget_validation.rs`); this measures them all:
//!
//! ```text
//! cargo bench -p dashpot --bench budget          # DASHPOT_VALIDATE_SIZES=1000,100000 picks the piles
//! ```

#[cfg(target_os = "linux")]
#[path = "../tests/budget/mod.rs"]
mod budget;
#[cfg(target_os = "linux")]
#[path = "../tests/common/mod.rs"]
mod common;

#[cfg(target_os = "linux")]
use budget::*;

#[cfg(not(target_os = "linux"))]
fn main() {
    eprintln!("the budget measurement reads wait4's peak resident memory: Linux only");
}

#[cfg(target_os = "linux")]
fn main() {
    let dir = scratch();
    let sizes: Vec<usize> = std::env::var("DASHPOT_VALIDATE_SIZES")
        .ok()
        .map(|s| s.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_else(|| vec![1000, 100_000, 1_000_000]);
    for n in sizes {
        // 10³ spheres settle fully (0.1 s), the larger piles run a few hundred steps
        let steps = match n {
            0..=10_000 => None,
            10_001..=200_000 => Some(2000.0),
            _ => Some(300.0),
        };
        pile_pair(&dir, n, steps);
    }
    cli_pair(
        "bed event n = 5, f = 20 Hz",
        "bed --restitution mcnamara-falcon --layers 5 --freq 20",
    );
    cli_pair(
        "bed dem n = 2, f = 20 Hz",
        "bed --engine dem --law hsd --young 1e7 --layers 2 --freq 20 --cycles 40 --transient 10",
    );
    let _ = std::fs::remove_dir_all(&dir);
}
