//! The event-driven bed against exact invariants and closed forms, through the real plugins.

use dashpot::bed::{bed_particle, plugin_laws, Bed, BedConfig, Kind, LawChoice, Laws};
use dashpot::laws::PluginRestitution as BoundRestitutionHandle;
use dashpot_sdk::{LawError, ParamValue};
use dashpot_tests::seed_registry;

/// Restitution law `name` with `params`, bound to the paper's disks (2 mm, 3.27·10⁻⁵ kg).
fn paper_laws(name: &str, params: &[ParamValue]) -> Result<Laws<BoundRestitutionHandle>, LawError> {
    let law = LawChoice::new(name, params.to_vec());
    plugin_laws(&seed_registry(), &law, &bed_particle(0.002, 3.27e-5))
}

fn constant(r: f64) -> Laws<BoundRestitutionHandle> {
    paper_laws("constant", &[ParamValue::new("r", r)]).expect("constant law")
}

fn mcnamara_falcon() -> Laws<BoundRestitutionHandle> {
    paper_laws("mcnamara-falcon", &[]).expect("r(v)")
}

/// One disk in a tall box over a fixed floor (A = 0).
fn single(g: f64, headroom: f64) -> BedConfig {
    BedConfig {
        layers: 0.01, // N = n L/d = 1
        amplitude: 0.0,
        gravity: g,
        headroom,
        ..BedConfig::paper(0.01, 20.0)
    }
}

#[test]
fn elastic_disks_without_gravity_conserve_energy_over_a_million_events() {
    let cfg = BedConfig {
        gravity: 0.0,
        amplitude: 0.0, // the piston at rest
        ..BedConfig::paper(1.0, 20.0)
    };
    let mut bed = Bed::new(cfg, constant(1.0)).unwrap();
    let e0 = bed.kinetic_energy();
    bed.run_events(1_000_000).unwrap();
    assert_eq!(bed.counters.events, 1_000_000);
    let e1 = bed.kinetic_energy();
    assert!(
        ((e1 - e0) / e0).abs() < 1e-10,
        "relative energy drift {:e}",
        (e1 - e0) / e0
    );
    // both kinds of event occur: collisions and cell crossings
    assert!(bed.counters.disk_collisions > 10_000 && bed.counters.cell_crossings > 10_000);
    assert!(
        bed.counters.max_overlap <= 1e-9 * 0.002,
        "{:e}",
        bed.counters.max_overlap
    );
    assert!(bed.overlap_now() <= 1e-9 * 0.002);
}

#[test]
fn rough_disks_with_reversing_tangential_restitution_conserve_energy_with_rotation() {
    let cfg = BedConfig {
        gravity: 0.0,
        amplitude: 0.0,
        tangential: Some(1.0),
        ..BedConfig::paper(1.0, 20.0)
    };
    let mut bed = Bed::new(cfg, constant(1.0)).unwrap();
    let e0 = bed.kinetic_energy();
    bed.run_events(200_000).unwrap();
    let e1 = bed.kinetic_energy();
    assert!(((e1 - e0) / e0).abs() < 1e-11, "{:e}", (e1 - e0) / e0);
    assert!((0..bed.len()).any(|i| bed.spin(i).abs() > 1.0), "disks spin");
    assert!(bed.counters.max_overlap <= 1e-9 * 0.002);
    // r_t = 0 dissipates (the most)
    let mut bed = Bed::new(
        BedConfig {
            tangential: Some(0.0),
            ..cfg
        },
        constant(1.0),
    )
    .unwrap();
    // (a rough gas with r_t = 0 cools without end, its events ever sparser: a fixed time)
    bed.run_until(2.0, &mut |_| {}).unwrap();
    assert!(bed.kinetic_energy() < 0.9 * e0);
}

#[test]
fn smooth_limit_of_rough_disks_is_the_smooth_bed() {
    let cfg = BedConfig {
        tangential: Some(-1.0),
        ..BedConfig::paper(0.5, 25.0)
    };
    let mut a = Bed::new(cfg, mcnamara_falcon()).unwrap();
    let mut b = Bed::new(
        BedConfig {
            tangential: None,
            ..cfg
        },
        mcnamara_falcon(),
    )
    .unwrap();
    a.enable_log();
    b.enable_log();
    a.run_events(50_000).unwrap();
    b.run_events(50_000).unwrap();
    assert_eq!(a.log(), b.log());
    assert!((0..a.len()).all(|i| a.spin(i) == 0.0));
}

#[test]
fn the_same_seed_gives_the_same_event_sequence() {
    let cfg = BedConfig::paper(1.5, 25.0);
    let run = |seed: u64| {
        let mut bed = Bed::new(BedConfig { seed, ..cfg }, mcnamara_falcon()).unwrap();
        bed.enable_log();
        bed.run_until(0.4, &mut |_| {}).unwrap();
        assert!(bed.counters.max_overlap <= 1e-9 * 0.002);
        bed.log().to_vec()
    };
    let (a, b, c) = (run(7), run(7), run(8));
    assert!(a.len() > 10_000);
    assert_eq!(a, b, "same seed, same events, bit for bit");
    assert_ne!(a, c, "another seed, another run");
}

#[test]
fn a_disk_bouncing_on_a_fixed_floor_follows_the_analytic_heights() {
    let (g, r, h) = (9.8, 0.8, 0.05);
    let mut bed = Bed::new(single(g, 0.2), constant(r)).unwrap();
    bed.enable_log();
    let rad = 0.001;
    bed.set_state(&[(0.1, rad + h)], &[(0.0, 0.0)]).unwrap();
    let v0 = (2.0 * g * h).sqrt();
    let t1 = (2.0 * h / g).sqrt();
    // the bounces accumulate at t* = t1 (1 + 2r/(1 − r)); stop well before
    bed.run_until(t1 * (1.0 + 2.0 * r * (1.0 - r.powi(25)) / (1.0 - r)), &mut |_| {})
        .unwrap();
    let hits: Vec<_> = bed.log().iter().filter(|e| e.kind == Kind::Piston).collect();
    assert!(hits.len() >= 25, "{} bounces", hits.len());
    let mut t_expect = t1;
    for (k, e) in hits.iter().take(25).enumerate() {
        let v = v0 * r.powi(k as i32);
        assert!((e.speed - v).abs() < 1e-12 * v0, "bounce {k}: {} vs {v}", e.speed);
        assert!(
            (e.t - t_expect).abs() < 1e-12,
            "bounce {k} at {} vs {t_expect}",
            e.t
        );
        assert_eq!(e.r, r);
        // rebound height h_k = (r v)²/(2g) = r^(2k+2) h
        let hk = (r * e.speed).powi(2) / (2.0 * g);
        assert!((hk - h * r.powi(2 * k as i32 + 2)).abs() < 1e-12 * h);
        t_expect += 2.0 * r * v / g;
    }
    assert!(bed.counters.max_overlap <= 1e-9 * 0.002);
}

#[test]
fn the_lid_receives_m_one_plus_r_times_the_normal_speed() {
    let (r, v) = (0.8, 1.3);
    let mut bed = Bed::new(single(0.0, 0.015), constant(r)).unwrap();
    bed.set_state(&[(0.05, 0.01)], &[(0.4, v)]).unwrap();
    bed.start_window();
    let lid = bed.lid();
    // reaches the lid at (lid − R − y)/v; stop before it comes back down to the floor
    bed.run_until((lid - 0.001 - 0.01) / v + 0.001, &mut |_| {})
        .unwrap();
    assert_eq!(bed.window.lid_collisions, 1);
    let expect = 3.27e-5 * (1.0 + r) * v;
    assert!((bed.window.lid_impulse - expect).abs() < 1e-15 * expect);
    let (_, _, vx, vy) = bed.state_at(0, bed.now());
    assert!((vy + r * v).abs() < 1e-14 && vx == 0.4);
    assert!(bed.counters.max_overlap <= 1e-9 * 0.002);
}

#[test]
fn the_paper_bed_never_overlaps_and_measures_positive_observables() {
    let mut bed = Bed::new(BedConfig::paper(3.0, 30.0), mcnamara_falcon()).unwrap();
    // no missed collision: no pair ever found overlapping, period after period
    for k in 1..=5 {
        bed.run_until(k as f64 / 30.0, &mut |_| {}).unwrap();
        assert!(bed.overlap_now() <= 1e-9 * 0.002, "{:e}", bed.overlap_now());
    }
    let rep = bed.run_protocol(0.0, 10.0, &mut |_| {}).unwrap();
    assert!(rep.max_overlap <= 1e-9 * 0.002, "{:e}", rep.max_overlap);
    assert!(bed.overlap_now() <= 1e-9 * 0.002);
    assert!(rep.pressure > 0.0 && rep.temperature > 0.0 && rep.lid_collision_rate > 0.0);
    // P = Nc ΔI / L by definition
    let di = rep.mean_impulse.expect("disks hit the lid");
    assert!((rep.pressure - rep.lid_collision_rate * di / 0.2).abs() < 1e-12 * rep.pressure);
    assert_eq!(rep.disks, 300);
    assert_eq!(rep.tc_firings, 0);
}

#[test]
fn chattering_on_the_floor_ends_at_the_analytic_time_and_the_disk_rests_without_overlap() {
    // one disk dropped on a fixed floor with constant r: infinitely many bounces accumulate at
    // t* = t1 (1 + 2r/(1 − r)) (Luck & Mehta's chattering); then it rests on the floor
    let (g, r, h): (f64, f64, f64) = (9.8, 0.8, 0.05);
    let t1 = (2.0 * h / g).sqrt();
    let t_star = t1 * (1.0 + 2.0 * r / (1.0 - r));
    let mut bed = Bed::new(single(g, 0.2), constant(r)).unwrap();
    bed.enable_log();
    bed.set_state(&[(0.1, 0.001 + h)], &[(0.0, 0.0)]).unwrap();
    bed.run_until(2.0 * t_star, &mut |_| {}).unwrap();
    assert!(bed.riding(0) && bed.counters.rides == 1);
    let last = bed.log().iter().rev().find(|e| e.kind == Kind::Piston).unwrap();
    // the chattering left over below the riding speed lasts < 2 v_ride / (g (1 − r))
    let v_ride = 1e-6 * (g * 0.002).sqrt();
    assert!(last.t <= t_star && t_star - last.t < 2.0 * v_ride / (g * (1.0 - r)) + 1e-12);
    let (_, y, vx, vy) = bed.state_at(0, bed.now());
    assert!((y - 0.001).abs() < 1e-15 && vx == 0.0 && vy == 0.0, "{y} {vy}");
    assert!(bed.counters.max_overlap <= 1e-9 * 0.002 && bed.overlap_now() <= 1e-9 * 0.002);
    // with TC (t_c = 1 ms) the bounces shorter than t_c are elastic: the disk keeps bouncing
    let mut bed = Bed::new(
        BedConfig {
            tc: Some(1e-3),
            ..single(g, 0.2)
        },
        constant(r),
    )
    .unwrap();
    bed.set_state(&[(0.1, 0.001 + h)], &[(0.0, 0.0)]).unwrap();
    bed.run_until(2.0 * t_star, &mut |_| {}).unwrap();
    let rep = bed.report(1.0);
    assert!(
        rep.tc_firings > 0 && rep.tc_share > 0.5 && rep.counters.rides == 0,
        "{rep:?}"
    );
    assert!(rep.max_overlap <= 1e-9 * 0.002);
}

#[test]
fn a_disk_at_rest_on_the_piston_rides_until_it_decelerates_faster_than_g() {
    // at t = 0 the piston is at its lowest, at rest, accelerating up at 16 A f² = 160 m/s²:
    // a disk put on it at rest rides with it and flies off at t0 = 1/(4f), when the piston
    // starts decelerating at 160 m/s² > g, with the piston's peak speed V = 4Af upward
    let f = 20.0;
    let cfg = BedConfig {
        layers: 0.01,
        headroom: 0.2,
        ..BedConfig::paper(0.01, f)
    };
    let mut bed = Bed::new(cfg, constant(0.8)).unwrap();
    let z0 = bed.piston().state(0.0).z;
    assert!((z0 + 0.0125).abs() < 1e-15);
    bed.set_state(&[(0.1, z0 + 0.001)], &[(0.0, 0.0)]).unwrap();
    bed.start_window();
    let t0 = 0.25 / f;
    bed.run_until(0.999 * t0, &mut |_| {}).unwrap();
    assert!(bed.riding(0));
    let p = bed.piston().state(bed.now());
    let (_, y, _, vy) = bed.state_at(0, bed.now());
    assert!((y - p.z - 0.001).abs() < 1e-15 && (vy - p.v).abs() < 1e-12);
    let tf = t0 + 1e-4;
    bed.run_until(tf, &mut |_| {}).unwrap();
    assert!(!bed.riding(0));
    let v = 4.0 * 0.025 * f;
    let (_, y, _, vy) = bed.state_at(0, tf);
    assert!((vy - (v - 9.8 * 1e-4)).abs() < 1e-12, "{vy}");
    assert!((y - (0.001 + v * 1e-4 - 4.9e-8)).abs() < 1e-15, "{y}");
    // the piston gave it the momentum m (V + g t0), over the ride
    let j = bed.window.piston_impulse;
    assert!((j - 3.27e-5 * (v + 9.8 * t0)).abs() < 1e-15, "{j:e}");
    assert!(bed.counters.max_overlap <= 1e-9 * 0.002);
}

#[test]
fn the_piston_carries_the_lid_pressure_plus_the_weight_within_its_standard_error() {
    // McNamara & Falcon: the time-averaged pressure on the lower wall is P + N m g / L
    let mut bed = Bed::new(BedConfig::paper(1.0, 30.0), mcnamara_falcon()).unwrap();
    let rep = bed.run_protocol(5.0, 40.0, &mut |_| {}).unwrap();
    let expect = rep.pressure + 100.0 * 3.27e-5 * 9.8 / 0.2;
    let se = (rep.piston_pressure_stderr.unwrap().powi(2) + rep.pressure_stderr.unwrap().powi(2)).sqrt();
    assert!(
        (rep.piston_pressure - expect).abs() < 4.0 * se,
        "{} vs {expect} ± {se}",
        rep.piston_pressure
    );
    assert!(se < 0.05 * expect);
}

#[test]
fn the_standard_errors_match_the_spread_of_independent_seeds() {
    // 8 seeds of a short run: the spread of P across seeds against the batch-means standard
    // error each run reports; an honest error bar agrees within a factor of 2
    let runs: Vec<_> = (1..=8u64)
        .map(|seed| {
            let mut bed = Bed::new(
                BedConfig {
                    seed,
                    ..BedConfig::paper(1.0, 30.0)
                },
                mcnamara_falcon(),
            )
            .unwrap();
            bed.run_protocol(10.0, 60.0, &mut |_| {}).unwrap()
        })
        .collect();
    let p: Vec<f64> = runs.iter().map(|r| r.pressure).collect();
    let mean = p.iter().sum::<f64>() / 8.0;
    let sd = (p.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / 7.0).sqrt();
    let se = runs.iter().map(|r| r.pressure_stderr.unwrap()).sum::<f64>() / 8.0;
    assert!(sd / se > 0.5 && sd / se < 2.0, "spread {sd:e}, reported {se:e}");
    // and the mean of the seeds, as --seeds reports it, carries their spread over √8
    let c = dashpot::bed::BedReport::combine(&runs).unwrap();
    assert!(
        (c.pressure - mean).abs() < 1e-15 && (c.pressure_stderr.unwrap() - sd / 8f64.sqrt()).abs() < 1e-15
    );
}

#[test]
fn tc_makes_a_share_of_collisions_elastic_in_one_layer_with_constant_r() {
    let cfg = BedConfig {
        gravity: 0.0,
        tc: Some(1e-5),
        ..BedConfig::paper(1.0, 30.0)
    };
    let mut bed = Bed::new(cfg, constant(0.7)).unwrap();
    let rep = bed.run_protocol(2.0, 3.0, &mut |_| {}).unwrap();
    assert!(
        rep.tc_firings > 0 && rep.tc_share > 0.0 && rep.tc_share < 1.0,
        "{rep:?}"
    );
    assert!(rep.max_overlap <= 1e-9 * 0.002, "{:e}", rep.max_overlap);
}

#[test]
fn bad_input_is_a_clear_error() {
    let laws = || constant(0.9);
    let msg = |cfg: BedConfig| match Bed::new(cfg, laws()) {
        Ok(_) => panic!("accepted {cfg:?}"),
        Err(e) => e.to_string(),
    };
    let p = BedConfig::paper(1.0, 20.0);
    assert!(msg(BedConfig { layers: -1.0, ..p }).contains("layers n = -1"));
    assert!(msg(BedConfig { freq: 0.0, ..p }).contains("f must be > 0"));
    assert!(msg(BedConfig { freq: -5.0, ..p }).contains("f = -5 Hz"));
    assert!(msg(BedConfig { width: 0.004, ..p }).contains("box is too small"));
    assert!(msg(BedConfig {
        headroom: -0.0015,
        ..p
    })
    .contains("box is too small"));
    assert!(msg(BedConfig {
        layers: 40.0,
        headroom: -0.07,
        ..p
    })
    .contains("box is too small"));
    assert!(msg(BedConfig {
        tangential: Some(1.5),
        ..p
    })
    .contains("[-1, 1]"));
    let e = paper_laws("no-such-law", &[]).err().unwrap().to_string();
    assert!(e.contains("no-such-law") && e.contains("mcnamara-falcon"), "{e}");
    let e = paper_laws("hsd", &[]).err().unwrap().to_string();
    assert!(e.contains("restitution law is needed"), "{e}");
}
