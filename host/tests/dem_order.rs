//! The engine's memory order (`EngineConfig::sort_from`, `sort_period`): the engine renumbers
//! its particles along a space-filling curve, every per-particle array and the contacts'
//! histories with them, and nothing of it shows: a run reordered often is the run never
//! reordered, particle by particle in the user's numbering, up to the rounding of the order in
//! which a particle's contact forces are summed; the same bit for bit on one thread and two;
//! errors name the user's particle.
//!
//! The piles are dense and frictional (Mindlin's tangential spring and a rolling resistance, whose
//! histories are vectors: a pair seen from the wrong partner would get its springs reversed)
//! and span several chunks of contacts, so that pairs cross chunks in both orders.

use dashpot::dem::{
    Body, DemError, DiskMass, Domain, Engine, EngineConfig, Laws, Material, Rotation, Vec3, VecD, Wall,
};
use dashpot::laws::{compiled, compiled_rolling, compiled_tangential};
use dashpot_hsd::Hsd;
use dashpot_mindlin::Mindlin;
use dashpot_rolling_sds::RollingSds;
use dashpot_sdk::{LawParams, MaterialPair, ParamValue, Params};

const DIAM: f64 = 0.002;

const MAT: Material = Material {
    young: 1.0e8,
    poisson: 0.3,
    density: 7800.0,
    disk_mass: DiskMass::Disk,
};

/// HSD (ε = 0.8), with Mindlin (μ = 0.5) and a rolling resistance (`rolling-sds`: k = 10³ N/m,
/// γ = 0.01 N·s/m, μ_r = 0.1; its history a vector too) when `friction`.
fn laws(friction: bool) -> Laws {
    let p = MAT.particle(1.0);
    let (pp, pw) = (
        MaterialPair::spheres(&p, &p).unwrap(),
        MaterialPair::wall(&p).unwrap(),
    );
    let (hsd, f) = (Hsd::with(0.8), Mindlin::with(0.5, 0.0));
    Laws {
        pair: Box::new(compiled(&hsd, &pp).unwrap()),
        wall: Box::new(compiled(&hsd, &pw).unwrap()),
        pair_tangential: friction.then(|| Box::new(compiled_tangential(&f, &pp).unwrap()) as _),
        wall_tangential: friction.then(|| Box::new(compiled_tangential(&f, &pw).unwrap()) as _),
        rotation: if friction {
            rolling(&pp, &pw)
        } else {
            Rotation::default()
        },
    }
}

/// `rolling-sds` between particles (`pp`) and against walls (`pw`).
fn rolling(pp: &MaterialPair, pw: &MaterialPair) -> Rotation {
    let params: Vec<ParamValue> = [("k", 1.0e3), ("gamma", 0.01), ("mu", 0.1)]
        .iter()
        .map(|&(k, v)| ParamValue::new(k, v))
        .collect();
    let sds: RollingSds = Params::resolve("rolling-sds", &RollingSds::schema(), &params)
        .and_then(|p| p.parse())
        .unwrap();
    Rotation {
        pair_rolling: Some(Box::new(compiled_rolling(&sds, pp).unwrap())),
        wall_rolling: Some(Box::new(compiled_rolling(&sds, pw).unwrap())),
        ..Rotation::default()
    }
}

/// A dense lattice of `cols` columns (along every axis but the last) and `layers` layers, the
/// particles numbered in an order scrambled from the lattice's (so that the engine's order
/// differs from the user's everywhere), spacing 0.99 of the largest diameter, random
/// directions at 0.2 m/s, diameters in [0.97, 1] × `DIAM`; periodic sideways, a floor below,
/// gravity, reordered from 0 particles on every `period` steps (`None`: never); frictional.
fn lattice<const D: usize>(cols: usize, layers: usize, period: Option<u64>) -> Engine<D> {
    lattice_with::<D>(cols, layers, period, true)
}

/// [`lattice`], frictional (Mindlin, rolling resistance) when `friction`.
fn lattice_with<const D: usize>(
    cols: usize,
    layers: usize,
    period: Option<u64>,
    friction: bool,
) -> Engine<D> {
    let a = 0.99 * DIAM;
    // numbers spread over [0, 1): the m-th multiple of the golden ratio, modulo 1
    let spread = |m: usize| (m as f64 * 0.618_033_988_749_895).fract();
    let n = cols.pow(D as u32 - 1) * layers;
    let mut bodies: Vec<(usize, Body<D>)> = (0..n)
        .map(|k| {
            let mut x = VecD::<D>::zeros();
            let mut v = VecD::<D>::zeros();
            let mut r = k;
            for c in 0..D {
                let m = if c + 1 < D { cols } else { layers };
                x[c] = ((r % m) as f64 + 0.5) * a;
                r /= m;
                v[c] = 0.2 * (2.0 * spread(D * k + c + 1) - 1.0);
            }
            let d = DIAM * (0.97 + 0.03 * spread(7 * k + 3));
            let b = Body {
                position: x,
                velocity: v,
                angular_velocity: Vec3::zeros(),
                diameter: d,
            };
            // (n is 2^a 5^b here: 7919 is prime to it, so the keys are a permutation)
            ((7919 * k) % n, b)
        })
        .collect();
    bodies.sort_by_key(|p| p.0);
    let bodies: Vec<Body<D>> = bodies.into_iter().map(|(_, b)| b).collect();
    let mut cfg = EngineConfig::<D>::new(MAT);
    cfg.impact_speed = Some(1.0);
    cfg.gravity[D - 1] = -9.81;
    cfg.energy = true;
    cfg.sort_from = if period.is_some() { 0 } else { usize::MAX };
    cfg.sort_period = period.unwrap_or(1);
    let mut hi = VecD::<D>::repeat(cols as f64 * a);
    hi[D - 1] = layers as f64 * a + 1.0;
    let mut periodic = [true; D];
    periodic[D - 1] = false;
    cfg.domain = Domain {
        lo: VecD::<D>::zeros(),
        hi,
        periodic,
        bounded: false,
    };
    let mut up = VecD::<D>::zeros();
    up[D - 1] = 1.0;
    let floor = Wall::fixed(VecD::<D>::zeros(), up);
    Engine::new(cfg, &bodies, vec![floor], laws(friction)).unwrap()
}

/// Whether two runs' states (positions, velocities, spins) are the same bit for bit (no NaN
/// here, and no signed zero a step could tell apart).
fn same_state<const D: usize>(a: &Engine<D>, b: &Engine<D>) -> bool {
    a.p.pos == b.p.pos && a.p.vel == b.p.vel && a.p.omega == b.p.omega
}

/// Runs the lattice reordered every 7 steps and never, `steps` steps in blocks of 9 (the
/// energy accounted), and compares them particle by particle.
fn same_run_in_any_order<const D: usize>(cols: usize, layers: usize, steps: u64) {
    let run = |period: Option<u64>| {
        let mut e = lattice::<D>(cols, layers, period);
        let radii = e.p.radius.clone();
        let mut done = 0;
        while done < steps {
            let k = (steps - done).min(9);
            e.advance(k).unwrap();
            done += k;
            // between the calls, the arrays are in the user's numbering
            assert_eq!(e.p.radius, radii, "radii stay with their particles");
        }
        e
    };
    let (a, b) = (run(Some(7)), run(None));
    let n = a.p.len();
    let moved = (0..n).filter(|&k| a.user_index(k) != k).count();
    println!(
        "{D}D: {n} particles, {} pair and {} wall contacts; {moved} of them numbered otherwise by the engine",
        a.pairs.len(),
        a.wall_contacts.len()
    );
    assert!(moved > n / 2, "the engine reordered the particles");
    assert!(a.pairs.chunks.len() >= 2 && a.pairs.len() > n / 2);
    assert_eq!(b.user_index(7), 7);
    let (mut dx, mut dv, mut dw) = (0.0f64, 0.0f64, 0.0f64);
    for k in 0..n {
        dx = dx.max((a.p.pos[k] - b.p.pos[k]).norm());
        dv = dv.max((a.p.vel[k] - b.p.vel[k]).norm());
        dw = dw.max((a.p.angular_velocity(k) - b.p.angular_velocity(k)).norm());
    }
    let vmax = b.p.vel.iter().map(|v| v.norm()).fold(0.0, f64::max);
    let wmax = (0..n).map(|k| b.p.angular_velocity(k).norm()).fold(0.0, f64::max);
    println!("largest differences: position {dx:.2e} m, velocity {dv:.2e} of {vmax:.2e} m/s, spin {dw:.2e} of {wmax:.2e} rad/s");
    // rounding in the sums of the contact forces, grown over the steps: far below any physics
    assert!(dx < 1e-9 * DIAM, "positions differ by {dx:e} m");
    assert!(dv < 1e-7 * vmax, "velocities differ by {dv:e} m/s");
    assert!(dw < 1e-7 * wmax, "spins differ by {dw:e} rad/s");
    assert_eq!(a.pairs.len(), b.pairs.len(), "the same contacts");
    assert_eq!(a.wall_contacts.len(), b.wall_contacts.len());
    assert_eq!(a.pair_episodes, b.pair_episodes, "the same contacts formed");
    let (ea, eb) = (a.energy().total(), b.energy().total());
    assert!((ea - eb).abs() <= 1e-10 * ea.abs(), "energy {ea} against {eb}");
    let (ia, ib) = (a.wall_impulse[0], b.wall_impulse[0]);
    assert!(
        (ia - ib).norm() <= 1e-9 * ib.norm(),
        "floor impulse {ia:?} against {ib:?}"
    );
    // the springs' history followed its contacts: the friction work is the same
    let (da, db) = (a.dissipated[0], b.dissipated[0]);
    assert!(!b.unreported[0] && db > 0.0, "HSD reports its dissipation");
    assert!((da - db).abs() <= 1e-9 * db, "dissipated {da} against {db} J");
    let tq = |e: &Engine<D>| (0..n).map(|k| e.p.torque(k).norm()).sum::<f64>();
    assert!(
        tq(&b) > 0.0 && (tq(&a) - tq(&b)).abs() <= 1e-7 * tq(&b),
        "torques {} against {}",
        tq(&a),
        tq(&b)
    );
}

/// `f` run on a pool of `threads` threads.
fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build();
    pool.expect("a thread pool").install(f)
}

#[test]
fn a_reordered_2d_run_is_the_same_run_in_the_users_numbering() {
    // 64 × 80 disks: 3 chunks of contacts
    same_run_in_any_order::<2>(64, 80, 120);
}

#[test]
fn a_reordered_3d_run_is_the_same_run_in_the_users_numbering() {
    // 16 × 16 × 20 spheres: 3 chunks of contacts
    same_run_in_any_order::<3>(16, 20, 60);
}

/// Reordered every few steps, a run is the same bit for bit on one thread and two, and
/// stepped one by one or in blocks.
#[test]
fn a_reordered_run_is_the_same_bit_for_bit_on_one_thread_and_two() {
    let run = |threads: usize, block: u64| -> Engine<2> {
        on_threads(threads, || {
            let mut e = lattice::<2>(64, 80, Some(5));
            for _ in 0..(40 / block) {
                e.advance(block).unwrap();
            }
            e
        })
    };
    let a = run(1, 1);
    assert!(same_state(&a, &run(2, 1)), "one thread and two part");
    assert!(same_state(&a, &run(2, 8)), "single steps and blocks part");
}

/// A 3D pile of small chunks (2,880 spheres: 15 chunks of 192, each particle's shares summed
/// nearest chunk first) is the same bit for bit on one, two and three threads, stepped one by
/// one or in blocks, reordered every few steps or never (then numbered in a scrambled order:
/// a chunk's partners lie in every other chunk, and whole ranges are heads).
#[test]
fn a_3d_pile_of_small_chunks_is_the_same_bit_for_bit_on_any_threads() {
    for period in [Some(5), None] {
        let run = |threads: usize, block: u64| -> Engine<3> {
            on_threads(threads, || {
                let mut e = lattice::<3>(12, 20, period);
                for _ in 0..(40 / block) {
                    e.advance(block).unwrap();
                }
                e
            })
        };
        let a = run(1, 1);
        assert!(a.pairs.len() > 2000, "{} pair contacts", a.pairs.len());
        for (threads, block) in [(2, 1), (2, 8), (3, 8)] {
            assert!(
                same_state(&a, &run(threads, block)),
                "period {period:?}: one thread and {threads} (blocks of {block}) part"
            );
        }
    }
}

/// An error names the user's particle, not the engine's.
#[test]
fn an_error_names_the_users_particle() {
    let mut e = lattice::<2>(64, 80, Some(5));
    e.advance(12).unwrap();
    let k = (0..e.p.len()).find(|&k| e.user_index(k) != k).unwrap();
    let u = e.user_index(k);
    e.p.vel[u].x = f64::NAN;
    match e.step() {
        Err(DemError::NonFinite { i, .. }) if i == u => {}
        other => panic!("expected a non-finite state of {u}, got {other:?}"),
    }
}

/// Each particle's share of the dissipated power (W) is reported under the user's number
/// (frictionless: HSD reports its power, so every family is accounted).
#[test]
fn power_shares_are_reported_under_the_users_numbers() {
    let run = |period: Option<u64>| {
        let mut e = lattice_with::<3>(16, 20, period, false);
        e.advance(40).unwrap();
        e
    };
    let (a, b) = (run(Some(7)), run(None));
    let (pa, pb) = (a.particle_power().unwrap(), b.particle_power().unwrap());
    let scale = pb.iter().map(|w| w.abs()).fold(0.0, f64::max);
    let dp = pa.iter().zip(&pb).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    println!("power shares differ by {dp:.2e} W at most, of {scale:.2e} W");
    assert!(
        scale > 0.0 && dp <= 1e-7 * scale,
        "power shares differ by {dp:e} W of {scale:e} W"
    );
}

/// A 3D pile of small chunks (2,880 spheres) steps as one pass over the particles, its list
/// going stale mid-pass now and then: the same bits as the plain two passes (a fresh list and
/// every force at each step, forced by invalidating the list) on one, two and three threads.
#[test]
fn a_3d_pile_of_small_chunks_steps_as_two_passes_would() {
    let run = |threads: usize, two_passes: bool| -> Engine<3> {
        on_threads(threads, || {
            let mut e = lattice::<3>(12, 20, None);
            // 1 m/s: the list goes stale every few dozen steps
            e.p.vel.iter_mut().for_each(|v| *v *= 5.0);
            if two_passes {
                for _ in 0..480 {
                    e.invalidate_neighbours();
                    e.step().unwrap();
                }
            } else {
                e.advance(480).unwrap();
            }
            e
        })
    };
    let reference = run(1, true);
    assert_eq!(reference.rebuilds(), 481);
    for threads in [1, 2, 3] {
        let e = run(threads, false);
        println!("{threads} thread(s): {} list builds in 480 steps", e.rebuilds());
        assert!(e.rebuilds() >= 3, "the run must cross stale lists");
        assert!(
            same_state(&e, &reference),
            "{threads} thread(s): one pass and two part"
        );
    }
}
