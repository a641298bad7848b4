//! LAMMPS's own granular decks through `pair_style dashpot` by one word: the switch itself
//! (`examples/lammps/switch.sh`, no LAMMPS needed), and the setups of LAMMPS's example decks
//! (`in.restitution`, `in.pour.flatwall`, `in.pour.drum`, `in.pour.chute`, `in.pour.2d`) run
//! short with `pair_style granular` and with `pair_style dashpot`, on 1 and 2 ranks.

use super::lammps::{lmp_command, succeeded};
use super::{deps_dir, lammps_dir, lib_dir, num, plugin, run_deck, venv};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The switch of a deck that uses every granular style: each style line changes by its one word
/// (plus the plugin's load before the first), every other line stays as it was.
#[test]
fn switch_sh_changes_one_word_per_style_and_nothing_else() {
    let deck = "\
units           lj
atom_style      sphere
region          box block 0 10 0 10 0 10
create_box      2 box
pair_style      granular
pair_coeff      1 * hertz/material 1e5 0.2 0.3 tangential mindlin NULL 1.0 0.5 damping tsuji
pair_coeff      2 2 jkr 1e5 0.1 0.3 50 tangential mindlin NULL 1.0 0.5 rolling sds 1e3 1e3 0.1 twisting marshall
fix             3 all wall/gran granular hertz/material 1e5 1e3 0.3 tangential mindlin NULL 1.0 0.5 zplane 0 NULL
fix             4 all wall/gran/region granular hertz/material 1e5 0.1 0.3 tangential mindlin NULL 1.0 0.5 region drum
fix             zlower all wall/gran hooke/history 2000.0 NULL 50.0 NULL 0.5 0 zplane 0.0 2000.0
fix             5 all wall/gran/region hertz/history 4000.0 NULL 100.0 NULL 0 1 region drum
pair_style      gran/hooke/history 2000.0 NULL 50.0 NULL 0.5 0
pair_style      hybrid granular lj/cut 2.5
pair_coeff      1 1 granular hooke 1 1 tangential linear_nohistory 0 0
run             100
";
    let (text, path) = switch_sh(deck, "lammps-switch");
    let lines: Vec<&str> = text.lines().collect();
    let expect = [
        "units           lj",
        "atom_style      sphere",
        "region          box block 0 10 0 10 0 10",
        "create_box      2 box",
        "plugin load     /p/dashpotplugin.so",
        "pair_style      dashpot plugin_dir=/laws",
        "pair_coeff      1 * hertz/material 1e5 0.2 0.3 tangential mindlin NULL 1.0 0.5 damping tsuji",
        "pair_coeff      2 2 jkr 1e5 0.1 0.3 50 tangential mindlin NULL 1.0 0.5 rolling sds 1e3 1e3 0.1 twisting marshall",
        "fix             3 all wall/dashpot hertz/material 1e5 1e3 0.3 tangential mindlin NULL 1.0 0.5 zplane 0 NULL plugin_dir=/laws",
        "fix             4 all wall/dashpot/region hertz/material 1e5 0.1 0.3 tangential mindlin NULL 1.0 0.5 region drum plugin_dir=/laws",
        "fix             zlower all wall/dashpot hooke/history 2000.0 NULL 50.0 NULL 0.5 0 zplane 0.0 2000.0 plugin_dir=/laws",
        "fix             5 all wall/dashpot/region hertz/history 4000.0 NULL 100.0 NULL 0 1 region drum plugin_dir=/laws",
        "pair_style      dashpot gran/hooke/history 2000.0 NULL 50.0 NULL 0.5 0 plugin_dir=/laws",
        "pair_style      hybrid dashpot plugin_dir=/laws lj/cut 2.5",
        "pair_coeff      1 1 dashpot hooke 1 1 tangential linear_nohistory 0 0",
        "run             100",
    ];
    assert_eq!(lines, expect, "switched deck:\n{text}");
    // a deck that loads the plugin itself gets no second load; a bad option is refused
    std::fs::write(&path, "plugin load x.so\npair_style granular\n").expect("write deck");
    let out = Command::new("bash")
        .arg(lammps_dir().join("switch.sh"))
        .arg(&path)
        .output()
        .expect("switch.sh");
    assert_eq!(
        String::from_utf8_lossy(&out.stdout),
        "plugin load x.so\npair_style dashpot\n"
    );
    let out = Command::new("bash")
        .arg(lammps_dir().join("switch.sh"))
        .args(["--plugins", "x"])
        .arg(&path)
        .output()
        .expect("switch.sh");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("unknown option '--plugins'"),
        "{err}"
    );
}

/// `switch.sh --plugin /p/dashpotplugin.so --plugin-dir /laws` on `deck`, written to
/// `in.granular` in directory `dir` of the test build: the switched deck, and the file.
pub(super) fn switch_sh(deck: &str, dir: &str) -> (String, PathBuf) {
    let dir = lib_dir().join(dir);
    std::fs::create_dir_all(&dir).expect("switch dir");
    let path = dir.join("in.granular");
    std::fs::write(&path, deck).expect("write deck");
    let out = Command::new("bash")
        .arg(lammps_dir().join("switch.sh"))
        .args(["--plugin", "/p/dashpotplugin.so", "--plugin-dir", "/laws"])
        .arg(&path)
        .output()
        .expect("run switch.sh");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    (String::from_utf8_lossy(&out.stdout).into_owned(), path)
}

/// A deck of LAMMPS's, shortened: its file, its variables, and the RESULT keys compared, each
/// with its tolerance: a fraction of granular's value (0.02: the 2 %), or with a
/// negative number -L, the length L (the turned drum's centre of mass, which moves by several
/// percent of its diameter from one pour to the next, granular's own included).
pub(super) struct Deck {
    pub(super) file: &'static str,
    pub(super) vars: &'static [(&'static str, &'static str)],
    pub(super) com: &'static [(&'static str, f64)],
    /// fix pour's seeds to average over (none: the deck's own)
    pub(super) seeds: &'static [&'static str],
}

/// Each deck through `granular` and through `dashpot` (both on 1 and 2 ranks, for each seed):
/// the same atom counts, and the mean of each compared value over the dashpot runs within the
/// spread of granular's own runs or the deck's tolerance, whichever is larger, of granular's
/// mean. The laws are LAMMPS's to
/// rounding (the step-by-step tests): the runs part only as a many-body trajectory amplifies
/// rounding, so agreement is statistical.
pub(super) fn deck_agrees(v: &Path, deck: &Deck) {
    let run = |style: &str, ranks: u32, seed: &str| -> HashMap<String, String> {
        let mut vars: Vec<(&str, String)> = vec![("style", style.to_string())];
        vars.extend(deck.vars.iter().map(|&(k, x)| (k, x.to_string())));
        if !seed.is_empty() {
            vars.push(("seed", seed.to_string()));
        }
        run_deck(v, deck.file, ranks, &vars)
    };
    let seeds: &[&str] = if deck.seeds.is_empty() { &[""] } else { deck.seeds };
    let (mut g, mut d) = (Vec::new(), Vec::new());
    for seed in seeds {
        for ranks in [1, 2] {
            g.push(run("granular", ranks, seed));
            d.push(run("dashpot", ranks, seed));
        }
    }
    eprintln!("{}: granular {g:?}\n  dashpot {d:?}", deck.file);
    for (s, seed) in seeds.iter().enumerate() {
        let atoms = num(&g[2 * s], "atoms");
        assert!(atoms > 0.0, "{}: no atoms", deck.file);
        for r in g[2 * s..2 * s + 2].iter().chain(&d[2 * s..2 * s + 2]) {
            assert_eq!(num(r, "atoms"), atoms, "{} (seed {seed}): atoms {r:?}", deck.file);
        }
    }
    let mean = |runs: &[HashMap<String, String>], k: &str| {
        runs.iter().map(|r| num(r, k)).sum::<f64>() / runs.len() as f64
    };
    for &(k, scale) in deck.com {
        let values: Vec<f64> = g.iter().map(|r| num(r, k)).collect();
        let spread =
            values.iter().cloned().fold(f64::MIN, f64::max) - values.iter().cloned().fold(f64::MAX, f64::min);
        let (gm, dm) = (mean(&g, k), mean(&d, k));
        let bound = if scale < 0.0 { -scale } else { scale * gm.abs() };
        let tol = spread.max(bound);
        eprintln!(
            "{}: {k}: dashpot {dm}, granular {gm} (spread {spread}), tolerance {tol}",
            deck.file
        );
        assert!(
            (dm - gm).abs() <= tol,
            "{}: {k}: dashpot's mean {dm} against granular's {gm} (runs {values:?}): beyond {tol}",
            deck.file
        );
    }
}

/// LAMMPS's in.restitution (hertz/material, damping coeff_restitution e = 0.8, Mindlin) at a
/// 1e-8 s step: the same realized restitution as granular's to the last digit printed, e to
/// 1e-6, on 1 and 2 ranks (the two spheres on either side of the ranks' split).
#[test]
fn in_restitution_realizes_granulars_e() {
    let Some(v) = venv() else { return };
    for ranks in [1, 2] {
        let run = |style: &str| {
            let vars = [("style", style.to_string()), ("dt", "1e-8".to_string())];
            run_deck(&v, "in.restitution", ranks, &vars)
        };
        let (g, d) = (run("granular"), run("dashpot"));
        eprintln!("in.restitution on {ranks} rank(s): granular {g:?}, dashpot {d:?}");
        assert_eq!(g["realized"], d["realized"], "realized e on {ranks} rank(s)");
        assert_eq!(g["vz1"], d["vz1"], "sphere 1's rebound on {ranks} rank(s)");
        assert!((num(&d, "realized") - 0.8).abs() < 1e-6, "{d:?}");
        assert!(num(&d, "gap") > 0.0, "the spheres are still in contact: {d:?}");
    }
}

/// in.pour.flatwall (two types: JKR + Mindlin + rolling + marshall, Hertz + linear_history +
/// rolling + marshall; a hertz/material wall), poured and settled.
#[test]
fn in_pour_flatwall_settles_as_with_granular() {
    let Some(v) = venv() else { return };
    let deck = Deck {
        file: "in.pour.flatwall",
        vars: &[("n", "200"), ("nsteps", "4000")],
        com: &[("xcom", 0.02), ("ycom", 0.02), ("zcom", 0.02)],
        seeds: &[],
    };
    deck_agrees(&v, &deck);
}

/// in.pour.drum (region walls: a rotating cylinder and its lids, tsuji damping, Mindlin),
/// filled and settled (the bed's height on the lid within 2 %, averaged over two pours: one
/// pour's partial monolayer moves by 2-3 % from seed to seed), then turned and rotated (the
/// centre of mass within 5 % of the drum's diameter of 30: an avalanche in progress, whose
/// place differs by as much between two pours of granular's own).
#[test]
fn in_pour_drum_turns_as_with_granular() {
    let Some(v) = venv() else { return };
    let deck = Deck {
        file: "in.pour.drum",
        vars: &[("n", "200"), ("fill", "8000"), ("spin", "2000")],
        com: &[
            ("nfill", 0.0),
            ("zfill", 0.02),
            ("xcom", -1.5),
            ("ycom", -1.5),
            ("zcom", -1.5),
        ],
        seeds: &["1234", "4321"],
    };
    deck_agrees(&v, &deck);
}

/// LAMMPS's examples/pour/in.pour (gran/hooke/history, a wall/gran hooke/history floor), poured
/// and then flowing down a chute.
#[test]
fn in_pour_chute_flows_as_with_granular() {
    let Some(v) = venv() else { return };
    let deck = Deck {
        file: "in.pour.chute",
        vars: &[("n", "300"), ("pour", "3000"), ("flow", "2000")],
        com: &[("xcom", 0.02), ("zcom", 0.02), ("vx", 0.02)],
        seeds: &[],
    };
    deck_agrees(&v, &deck);
}

/// in.pour.2d (gran/hertz/history, wall/gran hertz/history side walls and floor), poured and
/// settled in 2d.
#[test]
fn in_pour_2d_settles_as_with_granular() {
    let Some(v) = venv() else { return };
    let deck = Deck {
        file: "in.pour.2d",
        vars: &[("n", "300"), ("nsteps", "15000")],
        com: &[("xcom", 0.02), ("ycom", 0.02)],
        seeds: &[],
    };
    deck_agrees(&v, &deck);
}

/// The pair's slots walked and staged four at a time in AVX2 (`dashpot_simd_geom.cpp`, taken on
/// a CPU with AVX2) against the scalar walk and staging (`DASHPOT_LMP_SIMD=0`): in.pour.2d
/// (gran/hertz/history, poured into a dense pile), in.pour.chute (gran/hooke/history, a flowing
/// layer) and in.pour.flatwall (three bound models, an adhesive JKR type, rolling and twisting:
/// the vectorised walk with the scalar staging), each run on with its lowest atoms frozen (fix
/// freeze: the effective mass of a frozen body's contacts), end with the same positions,
/// velocities and spins, bit for bit.
#[test]
fn simd_staging_gives_the_scalar_bits() {
    let Some(v) = venv() else { return };
    let dir = lib_dir().join("lammps-simd");
    std::fs::create_dir_all(&dir).expect("simd dir");
    let decks: [(&str, &[(&str, &str)]); 3] = [
        ("in.pour.2d", &[("n", "300"), ("nsteps", "6000")]),
        (
            "in.pour.chute",
            &[("n", "300"), ("pour", "3000"), ("flow", "1000")],
        ),
        ("in.pour.flatwall", &[("n", "200"), ("nsteps", "3000")]),
    ];
    for (deck, vars) in decks {
        let dump = |simd: &str| -> String {
            let file = dir.join(format!("{deck}.simd{simd}.dump"));
            let wrapper = dir.join(format!("{deck}.simd{simd}.in"));
            let text = format!(
                "include {}\ngroup low id <= 30\nfix frozen low freeze\nrun 1000\n\
                 write_dump all custom {} id x y z vx vy vz omegax omegay omegaz \
                 modify sort id format float %.17g\n",
                lammps_dir().join(deck).display(),
                file.display()
            );
            std::fs::write(&wrapper, text).expect("write wrapper deck");
            let mut cmd = lmp_command(&v, 1);
            cmd.env("DASHPOT_LMP_SIMD", simd)
                .args(["-log", "none", "-in"])
                .arg(&wrapper)
                .arg("-var")
                .arg("plugin")
                .arg(plugin(&v))
                .args(["-var", "plugin_dir"])
                .arg(deps_dir())
                .args(["-var", "style", "dashpot"]);
            for (k, x) in vars {
                cmd.args(["-var", k, x]);
            }
            succeeded(
                &cmd.output().expect("run lmp"),
                &format!("{deck} DASHPOT_LMP_SIMD={simd}"),
            );
            std::fs::read_to_string(&file).expect("read dump")
        };
        let (simd, scalar) = (dump("1"), dump("0"));
        let atoms = scalar.lines().skip(9).count();
        assert!(atoms >= 200, "{deck}: {atoms} atoms in the dump");
        assert!(
            simd == scalar,
            "{deck}: the AVX2 staging's final state differs from the scalar one's"
        );
    }
}
