//! LAMMPS's own granular decks through `pair_style dashpot` by one word: the switch itself
//! (`examples/lammps/switch.sh`, no LAMMPS needed), and the setups of LAMMPS's example decks
//! (`in.restitution`, `in.pour.flatwall`, `in.pour.drum`, `in.pour.chute`, `in.pour.2d`) run
//! short with `pair_style granular` and with `pair_style dashpot`, on 1 and 2 ranks.

use super::{lammps_dir, lib_dir};
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
    let dir = lib_dir().join("lammps-switch");
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
    let text = String::from_utf8_lossy(&out.stdout);
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
