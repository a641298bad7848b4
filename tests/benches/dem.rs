//! Soft-sphere DEM throughput, every contender measured in the same run:
//!
//! 1. 2,000 polydisperse disks (1.9–2 mm, E = 10⁸ Pa) settling under gravity on a floor,
//!    periodic sideways, HSD (ε = 0.5) + Mindlin (μ = 0.3) on one core: the plugins' batch calls
//!    against the same laws compiled into this benchmark (same checked trampoline), interleaved;
//! 2. cost per particle-step from 10³ to 10⁶ disks (one core), plugins, every size over the same
//!    stage of the same pile, the sizes timed in turn round by round;
//! 3. speed-up on two cores (10⁵ disks, one settled pile stepped alternately by one thread and
//!    by two, wall time): the ratio of the medians, and the median of the ratios block by block
//!    (each two-thread block against the one-thread block before it);
//! 4. peak resident memory of the process while the piles of 2. (10⁶ disks among them) are
//!    held (VmHWM).
//!
//! One-core figures are thread CPU time (the machine is shared). Run: `cargo bench -p
//! dashpot-tests --bench dem [-- plugins | scaling | cores]` (sections by name; all by default).

mod common;

use dashpot::dem::{Engine, Laws, Material};
use dashpot::laws::{compiled, compiled_tangential};
use dashpot_hsd::Hsd;
use dashpot_mindlin::Mindlin;
use dashpot_sdk::{MaterialPair, ParamValue};
use dashpot_tests::full_registry;
use std::time::Instant;

const MAT: Material = Material {
    young: 1.0e8,
    poisson: 0.3,
    density: 7800.0,
    disk_mass: dashpot::dem::DiskMass::Sphere,
};

fn plugin_laws(reg: &dashpot::Registry) -> Laws {
    Laws::from_registry(
        reg,
        ("hsd", &[ParamValue::new("eps", 0.5)]),
        Some(("mindlin", &[ParamValue::new("mu", 0.3)])),
        &MAT,
    )
    .unwrap()
}

fn compiled_laws() -> Laws {
    let p = MAT.particle(1.0);
    let (pp, pw) = (
        MaterialPair::spheres(&p, &p).unwrap(),
        MaterialPair::wall(&p).unwrap(),
    );
    let hsd = Hsd::with(0.5);
    let m = Mindlin::with(0.3, 0.0);
    Laws {
        pair: Box::new(compiled(&hsd, &pp).unwrap()),
        wall: Box::new(compiled(&hsd, &pw).unwrap()),
        pair_tangential: Some(Box::new(compiled_tangential(&m, &pp).unwrap())),
        wall_tangential: Some(Box::new(compiled_tangential(&m, &pw).unwrap())),
        rotation: Default::default(),
    }
}

/// The benchmarks' pile ([`common::pile`]) of `n` disks with the first/last-step means.
fn pile(n: usize, laws: Laws) -> Engine<2> {
    common::pile(n, laws, MAT, true)
}

fn steps(e: &mut Engine<2>, k: usize) -> f64 {
    let s = Instant::now();
    e.advance(k as u64).unwrap();
    s.elapsed().as_secs_f64()
}

/// Thread CPU seconds of `k` steps (one-thread pools: the work runs on this thread).
fn cpu_steps(e: &mut Engine<2>, k: usize) -> f64 {
    let s = common::thread_cpu_seconds();
    e.advance(k as u64).unwrap();
    common::thread_cpu_seconds() - s
}

/// The CPU times (s) of `blocks` blocks of `k` steps of `a` and of `b`, interleaved (a, b, a, b,
/// ...) so that drift of the machine falls on both alike; each list sorted.
fn interleaved(a: &mut Engine<2>, b: &mut Engine<2>, blocks: usize, k: usize) -> (Vec<f64>, Vec<f64>) {
    let (mut ta, mut tb) = (Vec::new(), Vec::new());
    for _ in 0..blocks {
        ta.push(cpu_steps(a, k));
        tb.push(cpu_steps(b, k));
    }
    ta.sort_by(f64::total_cmp);
    tb.sort_by(f64::total_cmp);
    (ta, tb)
}

/// The speed ratio of `a` over `b` from their sorted [`interleaved`] times: "R median, R best".
fn ratios(ta: &[f64], tb: &[f64]) -> String {
    let m = ta.len() / 2;
    format!("{:.3} median, {:.3} best", tb[m] / ta[m], tb[0] / ta[0])
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}

fn vm_hwm_kib() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let l = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    l.split_whitespace().nth(1)?.parse().ok()
}

fn main() {
    // `cargo bench --bench dem -- [plugins] [scaling] [cores]`: the named sections only
    let only: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with('-')).collect();
    let run = |name: &str| only.is_empty() || only.iter().any(|a| a == name);
    let reg = full_registry();
    let one = pool(1);

    // 1. plugins vs compiled in, 2,000 settling disks, one core, interleaved blocks
    if run("plugins") {
        one.install(|| {
        let mut a = pile(2000, plugin_laws(&reg));
        let mut b = pile(2000, compiled_laws());
        // settle first: contacts everywhere
        steps(&mut a, 5000);
        steps(&mut b, 5000);
        let (ta, tb) = interleaved(&mut a, &mut b, 7, 500);
        let ps = |t: f64| 2000.0 * 500.0 / t;
        println!(
            "2000 disks, HSD + Mindlin, 1 core: plugins {:.3e} particle-steps/s, compiled in {:.3e}; ratio plugins/compiled = {} (7 interleaved blocks of 500 steps; {} contacts, dt = {:.3e} s)",
            ps(ta[3]),
            ps(tb[3]),
            ratios(&ta, &tb),
            a.contacts(),
            a.dt()
        );
        assert!((a.p.pos[0] - b.p.pos[0]).norm() < 1e-9, "both runs follow the same trajectory");

        // what the first/last-step means cost: the same pile with the plain step-end rule, both
        // from the start and settled as long (a pile gains contacts as it settles)
        let mut a = pile(2000, plugin_laws(&reg));
        let mut c = common::pile(2000, plugin_laws(&reg), MAT, false);
        steps(&mut a, 5000);
        steps(&mut c, 5000);
        let (ta, tc) = interleaved(&mut a, &mut c, 7, 500);
        let (mut formed, mut last, mut total) = (0usize, 0usize, 0usize);
        for _ in 0..200 {
            a.step().unwrap();
            formed += a.pairs.formed();
            last += a.pairs.predicted_last();
            total += a.pairs.len();
        }
        println!(
            "  per step: {:.1} pair contacts, {:.1} first touches, {:.1} predicted last steps; {} listed pairs, {} neighbour builds in {} steps",
            total as f64 / 200.0,
            formed as f64 / 200.0,
            last as f64 / 200.0,
            a.listed_pairs(),
            a.rebuilds(),
            a.steps()
        );
        println!(
            "2000 disks, plugins: with the first/last-step means {:.3e} particle-steps/s, without {:.3e}; ratio with/without = {} ({} and {} contacts, {} and {} neighbour rebuilds)",
            ps(ta[3]),
            ps(tc[3]),
            ratios(&ta, &tc),
            a.contacts(),
            c.contacts(),
            a.rebuilds(),
            c.rebuilds()
        );
    });
    }

    // 2. scaling, one core: every size steps through the same stage of the same pile (steps
    // 300..400 from the lattice, so the same contacts per disk), the smaller sizes as several
    // piles (15 of 10³, 10 of 10⁴) so that each size's block is long enough to time. The sizes
    // are timed in turn, round by round (4 rounds of 25 steps), so that every size's window
    // spans the same stretch of the machine's time: this machine's speed drifts by ±20 % over
    // tens of seconds, which timing one size after another turned into ratios. Thread CPU
    // time; per size the best round, the median round and the whole window (the cost a run
    // pays, list builds included).
    if run("scaling") {
        let (mut costs, mut medians, mut wholes) = (Vec::new(), Vec::new(), Vec::new());
        // DASHPOT_BENCH_SIZES="100000 1000000": other sizes (for profiling one of them)
        let sizes: Vec<usize> = std::env::var("DASHPOT_BENCH_SIZES")
            .ok()
            .map(|s| s.split_whitespace().filter_map(|w| w.parse().ok()).collect())
            .unwrap_or_else(|| vec![1_000, 10_000, 100_000, 1_000_000]);
        let mut piles: Vec<Vec<Engine<2>>> = one.install(|| {
            sizes
                .iter()
                .map(|&n| {
                    (0..(100_000 / n).clamp(1, 15))
                        .map(|_| {
                            let mut e = pile(n, plugin_laws(&reg));
                            cpu_steps(&mut e, 300);
                            e
                        })
                        .collect()
                })
                .collect()
        });
        let builds0: Vec<u64> = piles
            .iter()
            .map(|ps| ps.iter().map(|e| e.rebuilds()).sum())
            .collect();
        let mut rounds = vec![Vec::new(); sizes.len()];
        for _ in 0..4 {
            for (s, ps) in piles.iter_mut().enumerate() {
                let n = sizes[s];
                let t: f64 = one.install(|| ps.iter_mut().map(|e| cpu_steps(e, 25)).sum());
                rounds[s].push(t / (ps.len() as f64 * n as f64 * 25.0));
            }
        }
        for (s, ps) in piles.iter().enumerate() {
            let n = sizes[s];
            let whole = rounds[s].iter().sum::<f64>() / 4.0;
            let mut rs = rounds[s].clone();
            rs.sort_by(f64::total_cmp);
            let (best, median) = (rs[0], 0.5 * (rs[1] + rs[2]));
            let builds: u64 = ps.iter().map(|e| e.rebuilds()).sum::<u64>() - builds0[s];
            let per = ps.iter().map(|e| e.contacts()).sum::<usize>() as f64 / (ps.len() * n) as f64;
            println!(
                "n = {n:>8}: {:.1} ns per particle-step over steps 300..400 ({} pile(s); {builds} list builds in the window); rounds of 25 steps: best {:.1}, median {:.1}; {per:.3} contacts per disk",
                whole * 1e9,
                ps.len(),
                best * 1e9,
                median * 1e9,
            );
            costs.push(best);
            medians.push(median);
            wholes.push(whole);
        }
        let spread = |v: &[f64]| {
            let (lo, hi) = v
                .iter()
                .fold((f64::INFINITY, 0.0f64), |(a, b), &c| (a.min(c), b.max(c)));
            hi / lo
        };
        println!(
            "cost per particle-step, max/min over the sizes: {:.2} (whole windows), {:.2} (median rounds), {:.2} (best rounds)",
            spread(&wholes),
            spread(&medians),
            spread(&costs)
        );
        drop(piles);
        if let Some(kib) = vm_hwm_kib() {
            println!(
                "peak resident memory of the process, every pile above held at once (the 10^6 one among them): {:.2} GiB",
                kib as f64 / 1048576.0
            );
        }
    }

    // 3. two cores: one pile of 10⁵ disks, settled until its contacts are the work of a step,
    // then stepped in blocks alternately by one thread and by two (the same engine, so both
    // sides step the same disks with the same contacts)
    if run("cores") {
        let two = pool(2);
        // DASHPOT_BENCH_CORES_N: another size (the speed-up where the pile fits in cache, say)
        let n: usize = std::env::var("DASHPOT_BENCH_CORES_N")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(100_000);
        let settle: usize = std::env::var("DASHPOT_BENCH_SETTLE")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(2000);
        let mut e = two.install(|| pile(n, plugin_laws(&reg)));
        two.install(|| steps(&mut e, settle));
        // 15 blocks of each: the machine's noise over a block (~0.1-0.2 s) is the error here
        const BLOCKS: usize = 15;
        let (mut t1, mut t2) = (Vec::new(), Vec::new());
        let (mut cpu2, mut wall2) = (0.0, 0.0);
        let (c0, b0) = (e.contacts(), e.rebuilds());
        for _ in 0..BLOCKS {
            t1.push(one.install(|| steps(&mut e, 40)));
            let c = common::process_cpu_seconds();
            let w = two.install(|| steps(&mut e, 40));
            cpu2 += common::process_cpu_seconds() - c;
            wall2 += w;
            t2.push(w);
        }
        // each 2-thread block against the 1-thread block just before it: the machine's drift
        // over the run (±20 % over tens of seconds) cancels within a pair
        let m = BLOCKS / 2;
        let mut paired: Vec<f64> = t1.iter().zip(&t2).map(|(a, b)| a / b).collect();
        paired.sort_by(f64::total_cmp);
        t1.sort_by(f64::total_cmp);
        t2.sort_by(f64::total_cmp);
        println!(
            "n = {n}: 1 core {:.3e} particle-steps/s, 2 cores {:.3e}; speed-up {:.2} median, {:.2} best; block by block {:.2} median ({:.2}-{:.2} the middle half) ({BLOCKS} interleaved blocks of 40 steps of one pile settled {settle} steps; {c0} -> {} contacts)",
            n as f64 * 40.0 / t1[m],
            n as f64 * 40.0 / t2[m],
            t1[m] / t2[m],
            t1[0] / t2[0],
            paired[m],
            paired[BLOCKS / 4],
            paired[BLOCKS - 1 - BLOCKS / 4],
            e.contacts()
        );
        println!(
            "  cores the 2-thread blocks used (process CPU s / wall s, the waits spinning): {:.2}; {} neighbour-list builds in the {} steps",
            cpu2 / wall2,
            e.rebuilds() - b0,
            BLOCKS * 80
        );
    }
}
