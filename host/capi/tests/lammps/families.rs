//! `pair_style dashpot` with every family: rolling and twisting resistance (against LAMMPS's
//! `pair_style granular` and against closed forms), an adhesive normal law (JKR) whose contacts
//! act past touching across MPI ranks, and each contact's dissipated power.

use super::{assert_same, failing_deck, lib_dir, lmp, num, run_deck, succeeded, venv};
use std::f64::consts::PI;
use std::path::Path;

/// The rows `step value...` LAMMPS's thermo printed with `width` numbers each.
fn thermo_rows(venv: &Path, deck: &str, ranks: u32, vars: &[(&str, String)], width: usize) -> Vec<Vec<f64>> {
    let stdout = succeeded(&lmp(venv, deck, ranks, vars), &format!("{deck} {vars:?}"));
    let rows: Vec<Vec<f64>> = stdout
        .lines()
        .map(|l| {
            l.split_whitespace()
                .map(str::parse::<f64>)
                .collect::<Result<Vec<_>, _>>()
        })
        .filter_map(|r| r.ok().filter(|r| r.len() == width))
        .collect();
    assert!(rows.len() > 100, "{deck}: no thermo rows in\n{stdout}");
    rows
}

/// A polydisperse frictional pour (400 spheres of 4–8 mm, fix pour) with rolling resistance,
/// through `pair_style dashpot hsd ... tangential mindlin ... rolling sds k=KR gamma=GR mu=MUR`
/// and through `pair_style granular hertz/material ... damping coeff_restitution tangential
/// mindlin NULL 0 MU rolling sds KR GR MUR`: the same laws with the same numbers (HSD's α(ε) is
/// coeff_restitution's for Hertz; rolling sds is LAMMPS's, semantics and parameters). Fix pour
/// places the same spheres in both (checked: the same total volume); once their trajectories
/// part, each style settles its own random packing, whose centre-of-mass height scatters by
/// about 1 % from seed to seed, so the styles are compared on the mean over two seeds. Rolling
/// resistance raises that height by about 4 % here (the pile packs looser), more than the 2 %
/// allowed: a pair style that dropped the rolling torque would fail.
#[test]
fn a_rolling_pour_settles_to_pair_granulars_height_on_one_and_two_ranks() {
    let Some(v) = venv() else { return };
    let seeds = ["1111", "2222"];
    let mut mean = [0.0f64; 3]; // granular, dashpot 1 rank, dashpot 2 ranks
    for seed in seeds {
        let mut volume = None;
        for (k, (style, ranks, wall)) in [
            ("granular", 1, "fix"),
            ("dashpot", 1, "fix"),
            ("dashpot", 2, "pair"),
        ]
        .into_iter()
        .enumerate()
        {
            let vars: Vec<(&str, String)> = [
                ("n", "400"),
                ("L", "0.05"),
                ("tpour", "0.25"),
                ("tsettle", "0.12"),
                ("dt", "2e-5"),
                ("rolling", "sds"),
                ("kr", "1e4"),
                ("gr", "0.1"),
                ("mur", "1.0"),
                ("seed", seed),
                ("style", style),
                ("wall", wall),
            ]
            .iter()
            .map(|&(k, x)| (k, x.to_string()))
            .collect();
            let r = run_deck(&v, "in.pour", ranks, &vars);
            eprintln!("rolling pour, seed {seed}, {style} on {ranks} rank(s), wall {wall}: {r:?}");
            assert_eq!(num(&r, "atoms"), 400.0, "{r:?}");
            assert!(num(&r, "ke_per_atom") < 1e-7, "settled: {r:?}");
            let vol = num(&r, "volume");
            assert!(
                volume.is_none_or(|v0: f64| (vol - v0).abs() < 1e-12 * v0),
                "the same spheres: {r:?}"
            );
            volume = Some(vol);
            mean[k] += num(&r, "zcom") / seeds.len() as f64;
        }
    }
    eprintln!(
        "mean centre-of-mass height: granular {}, dashpot 1 rank {}, 2 ranks {}",
        mean[0], mean[1], mean[2]
    );
    for (k, ranks) in [(1, 1), (2, 2)] {
        let rel = mean[k] / mean[0] - 1.0;
        assert!(
            rel.abs() < 0.02,
            "dashpot on {ranks} rank(s): {} against granular {} ({rel:+.4})",
            mean[k],
            mean[0]
        );
    }
}

/// Two JKR spheres pulled apart at a prescribed speed (`in.jkr`): the contact holds in tension
/// past touching, through its most tensile force −(3/2)π w R (to 1e-6), until the rupture
/// separation |δ_c| = (3/4)(π² w² R/E²)^{1/3} where dδ/da = 0 (within one step of the pull);
/// meanwhile the spheres cross from one MPI rank to the other, and 1 and 2 ranks agree to the
/// digit. The same holds for a sphere pulled off the `zplane` wall (R = d/2, E = E/(1 − ν²)).
/// LAMMPS's own JKR ends the contact earlier, at its pull-off distance 1.2277 (R γ²/E²)^{1/3}
/// (γ = w/2), the separation of the force minimum (load control), with the same most tensile
/// force.
#[test]
fn a_jkr_contact_holds_past_touching_until_its_rupture_separation_on_one_and_two_ranks() {
    let Some(v) = venv() else { return };
    let (w, radius, young, nu) = (0.5, 2.5e-3, 1.0e6, 0.3);
    let e_eff = young / (2.0 * (1.0 - nu * nu));
    let pulloff_force = 1.5 * PI * w * radius;
    let rupture = 0.75 * (PI * PI * w * w * radius / (e_eff * e_eff)).cbrt();
    let lammps_pulloff = 1.2277228507842888 * (radius * (w / 2.0) * (w / 2.0) / (e_eff * e_eff)).cbrt();
    let step = 1e-3 * 1e-5; // the pull's speed × dt (m)
                            // (most tensile force, last separation with a force, first without)
    let pull = |style: &str, ranks: u32, wall: &str| {
        let vars = [("style", style.to_string()), ("wall", wall.to_string())];
        let rows = thermo_rows(&v, "in.jkr", ranks, &vars, 3);
        let fmax = rows.iter().map(|r| r[2]).fold(f64::MIN, f64::max);
        let last = rows
            .iter()
            .filter(|r| r[2] != 0.0)
            .map(|r| r[1])
            .fold(f64::MIN, f64::max);
        let gone = rows
            .iter()
            .filter(|r| r[2] == 0.0 && r[1] > 0.0)
            .map(|r| r[1])
            .fold(f64::MAX, f64::min);
        // no gap: every sample between touching and the last force has a force
        assert!(
            rows.iter().all(|r| r[1] > last || r[2] != 0.0),
            "{style}: the contact dropped out before its last force"
        );
        (rows, fmax, last, gone)
    };
    let (one, fmax, last, gone) = pull("dashpot", 1, "0");
    eprintln!("dashpot jkr: max tension {fmax} N (3/2 pi w R = {pulloff_force}), breaks between {last} and {gone} m (|delta_c| = {rupture})");
    assert!(
        (fmax / pulloff_force - 1.0).abs() < 1e-6,
        "{fmax} against {pulloff_force}"
    );
    assert!(
        last <= rupture && rupture < gone && gone - last < 1.5 * step,
        "{last} {gone} {rupture}"
    );
    let (two, ..) = pull("dashpot", 2, "0");
    assert_eq!(one.len(), two.len());
    for (a, b) in one.iter().zip(&two) {
        assert!(
            (a[2] - b[2]).abs() <= 1e-12 * pulloff_force,
            "1 rank {a:?}, 2 ranks {b:?}"
        );
    }
    // the wall: the particle's own radius and the rigid wall's modulus
    let (e_wall, r_wall) = (young / (1.0 - nu * nu), 2.0 * radius);
    let (_, wmax, wlast, wgone) = pull("dashpot", 1, "1");
    let wall_rupture = 0.75 * (PI * PI * w * w * r_wall / (e_wall * e_wall)).cbrt();
    eprintln!("dashpot jkr on the wall: max tension {wmax} N, breaks between {wlast} and {wgone} m (|delta_c| = {wall_rupture})");
    assert!((wmax / (1.5 * PI * w * r_wall) - 1.0).abs() < 1e-6, "{wmax}");
    assert!(
        wlast <= wall_rupture && wall_rupture < wgone && wgone - wlast < 1.5 * step,
        "{wlast} {wgone}"
    );
    let (_, gmax, glast, ggone) = pull("granular", 1, "0");
    eprintln!("granular jkr: max tension {gmax} N, breaks between {glast} and {ggone} m (pull-off distance {lammps_pulloff})");
    assert!((gmax / pulloff_force - 1.0).abs() < 1e-4, "{gmax}");
    assert!(
        glast <= lammps_pulloff && lammps_pulloff < ggone,
        "{glast} {ggone} {lammps_pulloff}"
    );
}

/// An adhesive contact that reaches past its pair's neighbour cutoff (`in.reach`: two formed
/// JKR contacts, the cutoff d + 5 µm given by `pair_style dashpot CUTOFF` or pair_coeff's
/// `cutoff` keyword, the reach 10–20 µm) would drop out of the neighbour list while it still
/// pulls: LAMMPS stops, non-zero, with pair dashpot's error naming the law, the reach (the
/// law's closed form: |δ_c| = (3/4)(π² w² R/E²)^{1/3} for dashpot's jkr, LAMMPS's pull-off
/// distance (3π²/16)^{1/3} (R γ²/E²)^{1/3}, γ = w/2, for gran-jkr), the cutoff and both radii.
/// With a cutoff that covers the reach the same deck runs.
#[test]
fn an_adhesive_contact_reaching_past_the_cutoff_stops_lammps_naming_law_reach_cutoff_and_radii() {
    let Some(v) = venv() else { return };
    let (w, radius, young, nu, d) = (0.5, 2.5e-3, 1.0e6, 0.3, 0.01);
    let e_eff = young / (2.0 * (1.0 - nu * nu));
    let jkr = 0.75 * (PI * PI * w * w * radius / (e_eff * e_eff)).cbrt();
    let gran = (3.0 * PI * PI / 16.0).cbrt() * (radius * (w / 2.0) * (w / 2.0) / (e_eff * e_eff)).cbrt();
    for (syntax, law, reach) in [
        ("dashpot", "jkr", jkr),
        ("granular", "gran-jkr-viscoelastic", gran),
    ] {
        // the reach lies between the too short cutoff and the long enough one
        assert!(reach > 5e-6 && reach < 1e-4, "{syntax}: reach {reach}");
        let text = failing_deck(&v, "in.reach", &[("syntax", syntax), ("beyond", "5e-6")]);
        let line = text
            .lines()
            .find(|l| l.contains("ERROR") && l.contains("beyond touching"))
            .unwrap_or_else(|| panic!("{syntax}: no reach error in\n{text}"));
        eprintln!("{syntax}: {line}");
        assert!(
            line.contains("pair dashpot") && line.contains(&format!("law '{law}'")),
            "{line}"
        );
        // the numbers of "reaches R beyond touching, past the neighbour cutoff (C for radii A and B)"
        let after = |needle: &str| -> f64 {
            let at = line
                .find(needle)
                .unwrap_or_else(|| panic!("'{needle}' in {line}"));
            let rest = &line[at + needle.len()..];
            let word = rest
                .split(|ch: char| ch.is_whitespace() || ch == ')' || ch == ':')
                .next();
            word.and_then(|t| t.parse().ok())
                .unwrap_or_else(|| panic!("a number after '{needle}' in {line}"))
        };
        let (got_reach, cut, needed) = (after("reaches "), after("neighbour cutoff ("), after("at least "));
        let radii = &line[line.find("for radii ").unwrap_or_else(|| panic!("{line}")) + 10..];
        let radii: Vec<f64> = radii
            .split(')')
            .next()
            .unwrap_or_default()
            .split(" and ")
            .filter_map(|t| t.trim().parse().ok())
            .collect();
        let [a, b] = radii[..] else {
            panic!("two radii in {line}")
        };
        assert!(
            (got_reach / reach - 1.0).abs() < 1e-9,
            "reach {got_reach} vs {reach}: {line}"
        );
        assert!((cut / (d + 5e-6) - 1.0).abs() < 1e-12, "cutoff {cut}: {line}");
        assert!(a == 0.5 * d && b == 0.5 * d, "radii {a} {b}: {line}");
        assert!(a + b + got_reach > cut, "{line}");
        assert!((needed / (a + b + got_reach) - 1.0).abs() < 1e-12, "{line}");
        // no crash: LAMMPS's own error exit, not a signal
        assert!(
            !text.contains("Segmentation") && !text.contains("signal"),
            "{text}"
        );
        let r = run_deck(
            &v,
            "in.reach",
            1,
            &[("syntax", syntax.into()), ("beyond", "1e-4".into())],
        );
        assert_eq!(num(&r, "atoms"), 2.0, "{syntax}: {r:?}");
    }
}

/// A sphere on the `zplane` wall against rolling or twisting resistance (`in.rotation`), at the
/// law's cap: rolling without slip under `rolling sds` it decelerates at (5/7) μ_r g and stops
/// after 7 v0²/(10 μ_r g); spinning about the vertical its spin falls at μ m g / I under
/// `twisting sds` and at (2/3) μ_t a m g / I under `twisting marshall`, a = √(r δ). Checked at
/// half the closed-form stopping time (and the rolling stop) to 0.5 %: the cap builds up over
/// the first steps.
#[test]
fn rolling_and_twisting_resistance_on_the_wall_meet_their_closed_forms() {
    let Some(v) = venv() else { return };
    let run = |vars: &[(&str, &str)]| {
        let vars: Vec<(&str, String)> = vars.iter().map(|&(k, x)| (k, x.to_string())).collect();
        let r = run_deck(&v, "in.rotation", 1, &vars);
        eprintln!("{vars:?}: {r:?}");
        r
    };
    let (mu_r, v0, g) = (0.1, 0.1, 9.81);
    let r = run(&[
        ("family", "rolling"),
        ("law", "sds"),
        ("k", "1000"),
        ("mu", "0.1"),
    ]);
    let v_half = v0 - 5.0 / 7.0 * mu_r * g * num(&r, "t");
    assert!((num(&r, "vx") / v_half - 1.0).abs() < 5e-3, "{r:?}: v = {v_half}");
    // rolling without slip: v = omega r
    assert!(
        (num(&r, "wy") * 0.005 / num(&r, "vx") - 1.0).abs() < 5e-3,
        "{r:?}"
    );
    let r = run(&[
        ("family", "rolling"),
        ("law", "sds"),
        ("k", "1000"),
        ("mu", "0.1"),
        ("frac", "1.3"),
    ]);
    let stop = 7.0 * v0 * v0 / (10.0 * mu_r * g);
    assert!(
        (num(&r, "x") / stop - 1.0).abs() < 5e-3,
        "{r:?}: stops after {stop} m"
    );
    for (law, k, mu, w0) in [("sds", "1e-3", "1e-4", "10"), ("marshall", "1e6", "0.5", "1")] {
        let r = run(&[
            ("family", "twisting"),
            ("law", law),
            ("k", k),
            ("mu", mu),
            ("w0", w0),
        ]);
        let half = 0.5 * num(&r, "w0");
        assert!(
            (num(&r, "wz") / half - 1.0).abs() < 5e-3,
            "twisting {law}: {r:?}, expected {half}"
        );
    }
}

/// Each contact's dissipated power, by family, through `compute pair/local` (`energy=1`,
/// `in.energy`: two spinning spheres in an oblique collision): the normal dashpot's never
/// negative, each family's sum over the run positive where the family acts, and it closes the
/// energy balance — while the spheres touch, the kinetic energy lost equals the power integrated
/// over the steps plus the elastic energy stored — to 0.5 % of the energy lost with normal,
/// rolling and twisting laws whose own accounting is exact (HSD, rolling and twisting sds), to
/// 5 % with Mindlin friction in a grazing, sliding impact (Mindlin's stiffness 8 G a changes
/// with the overlap, so its spring's energy changes without work; the DEM engine's balance has
/// the same bound).
#[test]
fn each_contacts_dissipated_power_is_positive_and_closes_the_energy_balance() {
    let Some(v) = venv() else { return };
    let mindlin = "tangential mindlin mu=0.3 rolling sds k=200 gamma=0.02 mu=0.02 twisting sds k=2e-4 gamma=1e-7 mu=2e-5";
    let grazing = [
        ("x0", "0.0032"),
        ("y0", "0.004"),
        ("wz1", "200"),
        ("others", mindlin),
    ];
    for (vars, tolerance, families) in [
        (&[][..], 5e-3, [true, false, true, true]),
        (&grazing[..], 0.05, [true; 4]),
    ] {
        let vars: Vec<(&str, String)> = vars.iter().map(|&(k, x)| (k, x.to_string())).collect();
        // step, kinetic energy, power (total, normal, tangential, rolling, twisting), elastic
        let rows = thermo_rows(&v, "in.energy", 1, &vars, 8);
        let dt = 2e-6;
        let e0 = rows[0][1];
        let (mut dissipated, mut by_family, mut worst) = (0.0, [0.0f64; 4], 0.0f64);
        for pair in rows.windows(2) {
            let (a, b) = (&pair[0], &pair[1]);
            // the normal dashpot's power and the elastic energy are never negative; a spring's
            // power may be on a step where its stiffness or its cap stores energy no force paid
            // for (its sum over the run is checked below)
            for q in 2..8 {
                assert!(b[q].is_finite(), "{vars:?}: step {b:?}");
            }
            assert!(b[3] >= 0.0 && b[7] >= 0.0, "{vars:?}: step {b:?}");
            // the total is the families' sum (to rounding of their magnitudes: a step's total may
            // be negative)
            let scale = b[3..7].iter().map(|x| x.abs()).sum::<f64>();
            assert!(
                (b[2] - b[3..7].iter().sum::<f64>()).abs() <= 1e-12 * scale.max(1e-30),
                "{b:?}"
            );
            dissipated += 0.5 * (a[2] + b[2]) * dt;
            for f in 0..4 {
                by_family[f] += 0.5 * (a[3 + f] + b[3 + f]) * dt;
            }
            if b[2] > 0.0 || b[7] > 0.0 {
                worst = worst.max((e0 - b[1] - dissipated - b[7]).abs());
            }
        }
        let lost = e0 - rows.last().expect("rows")[1];
        eprintln!("{vars:?}: lost {lost:e} J, dissipated {dissipated:e} J {by_family:?}, worst residual {worst:e} J");
        assert!(lost > 0.1 * e0, "{lost} of {e0}");
        assert!(
            worst < tolerance * lost,
            "residual {worst:e} J of {lost:e} J lost"
        );
        for (f, &on) in families.iter().enumerate() {
            assert_eq!(by_family[f] > 0.0, on, "family {f}: {by_family:?}");
        }
    }
}

/// The rolling and twisting springs of a long contact drifting across the boundary between two
/// MPI ranks (`in.twospheres` with both families) travel with the atoms as the tangential one
/// does: 1 and 2 ranks give the same trajectory (to 1e-9), and so does a run stopped mid-contact,
/// written to a restart file and read back on 2 ranks with the pair style's laws taken from the
/// file (to 1e-6, LAMMPS's own restart effect). The families change the spins by far more.
#[test]
fn rolling_and_twisting_springs_cross_ranks_and_survive_a_restart_file() {
    let Some(v) = venv() else { return };
    let more = (
        "more",
        "rolling sds k=20 gamma=0.001 mu=0.05 twisting sds k=1e-5 gamma=1e-9 mu=2e-5".to_string(),
    );
    let plain = run_deck(&v, "in.twospheres", 1, &[]);
    let one = run_deck(&v, "in.twospheres", 1, std::slice::from_ref(&more));
    let two = run_deck(&v, "in.twospheres", 2, std::slice::from_ref(&more));
    let dir = lib_dir().join("lammps-restart-rotation");
    std::fs::create_dir_all(&dir).expect("restart dir");
    let vars = [
        more,
        ("restart", "1".into()),
        ("restart_dir", dir.display().to_string()),
        ("repeat_pair", "0".into()),
    ];
    let restarted = run_deck(&v, "in.twospheres", 2, &vars);
    eprintln!("plain {plain:?}\nwith rolling and twisting: 1 rank {one:?}\n2 ranks {two:?}\nrestarted {restarted:?}");
    assert!(
        (num(&one, "w1") / num(&plain, "w1") - 1.0).abs() > 0.1,
        "{one:?} {plain:?}"
    );
    for k in ["x1", "y1", "z1", "vx1", "vy1", "vz1", "vx2", "vy2", "w1", "w3"] {
        assert_same(k, &one, &two, 1e-9, "on 1 and 2 ranks");
        assert_same(k, &one, &restarted, 1e-6, "straight and restarted");
    }
}

/// Bad input for the new families stops LAMMPS with a clear message: a law of another kind
/// after `rolling`, a family given twice, a parameter out of range.
#[test]
fn pair_dashpot_reports_family_errors() {
    let Some(v) = venv() else { return };
    let text = failing_deck(&v, "in.energy", &[("others", "rolling hsd")]);
    assert!(
        text.contains("creating the rolling law") && text.contains("contact law"),
        "{text}"
    );
    let text = failing_deck(
        &v,
        "in.energy",
        &[("others", "twisting sds k=1 twisting sds k=2")],
    );
    assert!(
        text.contains("'twisting' must be followed by one twisting law name, once"),
        "{text}"
    );
    let text = failing_deck(&v, "in.energy", &[("others", "rolling sds k=-1")]);
    assert!(
        text.contains("creating the rolling law") && text.contains("= -1 is out of range"),
        "{text}"
    );
}
