//! Soft-sphere DEM throughput, every contender measured in the same run:
//!
//! 1. `plugins`: 2,000 polydisperse disks (1.9–2 mm, E = 10⁸ Pa) settling under gravity on a
//!    floor, periodic sideways, HSD (ε = 0.5) + Mindlin (μ = 0.3) on one core: the plugins'
//!    batch calls against the same laws compiled into this benchmark (same checked trampoline),
//!    interleaved;
//! 2. `scaling`: cost per particle-step from 10³ to 10⁶ disks (one core), plugins, every size
//!    over the same stage of the same pile, the sizes timed in turn round by round, and the peak
//!    resident memory of the process while the piles (10⁶ disks among them) are held (VmHWM);
//! 3. `cores`: speed-up on two cores (10⁵ disks, one settled pile stepped alternately by one
//!    thread and by two, wall time): the ratio of the medians, and the median of the ratios
//!    block by block (each two-thread block against the one-thread block before it);
//! 4. `scaling3d`: the same as 2. for a 3D pile of polydisperse spheres (1.6–2.4 mm), periodic
//!    in x and y, on a floor, HSD + Mindlin through the plugins: 10³, 10⁴, 10⁵ and 10⁶ spheres,
//!    each made of copies of one 10³-sphere pile fallen and settling ([`common::tile3d`]), so
//!    every size steps the same stage; VmHWM with the 10⁶-sphere pile held;
//! 5. `plugins3d`: HSD + Mindlin + rolling `sds` (k = 10³ N/m, γ = 0.01 N·s/m, μ_r = 0.1)
//!    through the plugins against the same three laws compiled in, 4,000 spheres of that pile,
//!    one core, interleaved blocks, the median of the blocks' ratios;
//! 6. `energy`: the same 4,000 spheres and laws (plugins) with energy accounting on against
//!    off (`EngineConfig::energy`), interleaved blocks: the overhead as a fraction of a step;
//! 7. `species`: the same 4,000 spheres as one species against two species of the same
//!    material, alternating sphere by sphere, each pair of species and each species–floor pair
//!    under its own laws ([`SPECIES_LAWS`]: five classes of contacts instead of two),
//!    interleaved blocks: what species and per-pair laws cost;
//! 8. `checkpoint`: the time to write one checkpoint (`dem::checkpoint::write`, the whole
//!    state, atomically) of that pile and of 10⁵ spheres, as a share of a minute of run (a run
//!    checkpointing once a minute);
//! 9. `heat`: the same 4,000 spheres and laws (plugins) conducting heat (`heat-radius`, k = 40
//!    W/(m·K), temperatures 300/400 K, the floor at 350 K) against the same pile without heat,
//!    interleaved blocks: the cost of heat as a fraction of a step (target ≤ 15 %).
//!
//! One-core figures are thread CPU time (the machine is shared). Run: `cargo bench -p
//! dashpot-tests --bench dem [-- plugins | scaling | cores | scaling3d | plugins3d | energy |
//! species | checkpoint | heat]`
//! (sections by name; all by default).

mod common;

use common::{median, TileOrder};

use dashpot::dem::{Engine, Laws, Material, Rotation, SpeciesInfo, SpeciesLaws};
use dashpot::laws::{compiled, compiled_rolling, compiled_tangential};
use dashpot_hsd::Hsd;
use dashpot_mindlin::Mindlin;
use dashpot_rolling_sds::RollingSds;
use dashpot_sdk::{LawParams, MaterialPair, ParamValue, Params};
use dashpot_tests::registry_03;
use std::time::Instant;

const MAT: Material = Material {
    young: 1.0e8,
    poisson: 0.3,
    density: 7800.0,
    disk_mass: dashpot::dem::DiskMass::Sphere,
};

/// The rolling law of the 3D sections: `rolling-sds` with k (N/m), γ (N·s/m) and μ_r.
const ROLLING: [(&str, f64); 3] = [("k", 1.0e3), ("gamma", 0.01), ("mu", 0.1)];

/// The base of the 3D piles: 10³ spheres stepped this far from their lattice (0.088 s: fallen
/// onto the floor and still settling) before they are copied.
const BASE3D: usize = 1000;
const SETTLE3D: u64 = 40_000;

fn rolling_params() -> Vec<ParamValue> {
    ROLLING.iter().map(|&(k, v)| ParamValue::new(k, v)).collect()
}

/// HSD + Mindlin (+ rolling sds with `rolling`) from the plugins.
fn plugin_laws(reg: &dashpot::Registry, rolling: bool) -> Laws {
    plugin_laws_with(reg, rolling, SPECIES_LAWS[0])
}

/// [`plugin_laws`] with HSD's restitution ε and Mindlin's μ `(eps, mu)`.
fn plugin_laws_with(reg: &dashpot::Registry, rolling: bool, (eps, mu): (f64, f64)) -> Laws {
    let laws = Laws::from_registry(
        reg,
        ("hsd", &[ParamValue::new("eps", eps)]),
        Some(("mindlin", &[ParamValue::new("mu", mu)])),
        &MAT,
    )
    .unwrap();
    if !rolling {
        return laws;
    }
    laws.with_rotation(reg, Some(("rolling-sds", &rolling_params())), None, &MAT)
        .unwrap()
}

/// The laws (HSD's ε, Mindlin's μ) of the `species` section's classes: a–a (and the pile of
/// one species), a–b, b–b; a–floor, b–floor. Each class its own: no two could share a batch.
const SPECIES_LAWS: [(f64, f64); 5] = [(0.5, 0.3), (0.55, 0.32), (0.6, 0.34), (0.5, 0.3), (0.45, 0.28)];

/// The same laws as [`plugin_laws`] compiled into this benchmark.
fn compiled_laws(rolling: bool) -> Laws {
    let p = MAT.particle(1.0);
    let (pp, pw) = (
        MaterialPair::spheres(&p, &p).unwrap(),
        MaterialPair::wall(&p).unwrap(),
    );
    let hsd = Hsd::with(0.5);
    let m = Mindlin::with(0.3, 0.0);
    let mut rotation = Rotation::default();
    if rolling {
        let sds: RollingSds = Params::resolve("rolling-sds", &RollingSds::schema(), &rolling_params())
            .and_then(|p| p.parse())
            .unwrap();
        rotation.pair_rolling = Some(Box::new(compiled_rolling(&sds, &pp).unwrap()));
        rotation.wall_rolling = Some(Box::new(compiled_rolling(&sds, &pw).unwrap()));
    }
    Laws {
        pair: Box::new(compiled(&hsd, &pp).unwrap()),
        wall: Box::new(compiled(&hsd, &pw).unwrap()),
        pair_tangential: Some(Box::new(compiled_tangential(&m, &pp).unwrap())),
        wall_tangential: Some(Box::new(compiled_tangential(&m, &pw).unwrap())),
        rotation,
    }
}

/// The benchmarks' pile ([`common::pile`]) of `n` disks with the first/last-step means.
fn pile(n: usize, laws: Laws) -> Engine<2> {
    common::pile(n, laws, MAT, true)
}

fn steps<const D: usize>(e: &mut Engine<D>, k: usize) -> f64 {
    let s = Instant::now();
    e.advance(k as u64).unwrap();
    s.elapsed().as_secs_f64()
}

/// Thread CPU seconds of `k` steps (one-thread pools: the work runs on this thread).
fn cpu_steps<const D: usize>(e: &mut Engine<D>, k: usize) -> f64 {
    let s = common::thread_cpu_seconds();
    e.advance(k as u64).unwrap();
    common::thread_cpu_seconds() - s
}

/// Thread CPU seconds of `k` steps held in the engine's memory order (`Engine::advance_held`).
fn held_steps<const D: usize>(e: &mut Engine<D>, k: usize) -> f64 {
    let s = common::thread_cpu_seconds();
    e.advance_held(k as u64).unwrap();
    common::thread_cpu_seconds() - s
}

/// Two contenders timed in interleaved blocks.
struct Pairs {
    /// CPU seconds of each block of `a` and of `b`, in the order run.
    ta: Vec<f64>,
    tb: Vec<f64>,
}

impl Pairs {
    /// `blocks` blocks of `k` steps of `a` and of `b`, interleaved (a, b, a, b, ...) so that
    /// the machine's drift falls on both alike.
    fn run<const D: usize>(a: &mut Engine<D>, b: &mut Engine<D>, blocks: usize, k: usize) -> Pairs {
        let (mut ta, mut tb) = (Vec::new(), Vec::new());
        for _ in 0..blocks {
            ta.push(cpu_steps(a, k));
            tb.push(cpu_steps(b, k));
        }
        Pairs { ta, tb }
    }

    /// Each pair's time of `b` over its time of `a`, sorted.
    fn ratios(&self) -> Vec<f64> {
        let mut r: Vec<f64> = self.ta.iter().zip(&self.tb).map(|(a, b)| b / a).collect();
        r.sort_by(f64::total_cmp);
        r
    }

    /// Prints what `a` costs more than `b` a step (`on` and `off` name them), `work`
    /// particle-steps a block, `contacts` in the pile: the median of the blocks' ratios, the
    /// spread of the ratios and the ratio of the medians.
    fn print_cost(&self, what: &str, on: &str, off: &str, work: usize, contacts: usize, target: &str) {
        let r = self.ratios();
        let ps = |t: &[f64]| work as f64 / median(t);
        println!(
            "{what}, 1 core: {on} {:.3e} particle-steps/s, {off} {:.3e}; cost of a step {:+.1} % median of the blocks' ratios ({:+.1} to {:+.1} %), {:+.1} % of the medians ({} interleaved blocks; {contacts} contacts)   target {target}",
            ps(&self.ta),
            ps(&self.tb),
            100.0 * (1.0 / median(&r) - 1.0),
            100.0 * (1.0 / r[r.len() - 1] - 1.0),
            100.0 * (1.0 / r[0] - 1.0),
            100.0 * (median(&self.ta) / median(&self.tb) - 1.0),
            self.ta.len()
        );
    }

    /// Prints the plugins' speed (`a`) against the laws compiled in (`b`), `work` particle-steps
    /// a block, and checks that both followed the same trajectory.
    fn plugins_against_compiled<const D: usize>(
        &self,
        what: &str,
        work: usize,
        a: &Engine<D>,
        b: &Engine<D>,
    ) {
        let ps = |t: &[f64]| work as f64 / median(t);
        println!(
            "{what}, 1 core: plugins {:.3e} particle-steps/s, compiled in {:.3e}; ratio plugins/compiled = {} ({} interleaved blocks of {} steps; {} contacts, dt = {:.3e} s)",
            ps(&self.ta),
            ps(&self.tb),
            self.summary(),
            self.ta.len(),
            work / a.p.len(),
            a.contacts(),
            a.dt()
        );
        assert!(
            (a.p.pos[0] - b.p.pos[0]).norm() < 1e-9,
            "both runs follow the same trajectory"
        );
    }

    /// The speed ratio of `a` over `b`: "R median of the blocks' ratios (lo-hi), R of the
    /// medians".
    fn summary(&self) -> String {
        let r = self.ratios();
        format!(
            "{:.3} median of the blocks' ratios ({:.3}-{:.3}), {:.3} of the medians",
            median(&r),
            r[0],
            r[r.len() - 1],
            median(&self.tb) / median(&self.ta)
        )
    }
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

fn print_vm_hwm(what: &str) {
    if let Some(kib) = vm_hwm_kib() {
        println!(
            "peak resident memory of the process, {what}: {:.2} GiB",
            kib as f64 / 1048576.0
        );
    }
}

/// Scaling, one core: the piles of each size (`piles[s]`: several of `sizes[s]` particles where
/// one is too small to time) stepped in turn, `rounds` rounds of `k` steps, so that every
/// size's window spans the same stretch of the machine's time (its speed drifts by ±20 % over
/// tens of seconds, which timing one size after another turned into ratios). Thread CPU time;
/// per size the best round, the median round and the whole window (the cost a run pays, list
/// builds included), and the spread of each over the sizes. `window` names the stage stepped.
fn scaling<const D: usize>(
    one: &rayon::ThreadPool,
    sizes: &[usize],
    piles: &mut [Vec<Engine<D>>],
    rounds: usize,
    k: usize,
    window: &str,
) {
    let (mut costs, mut medians, mut wholes) = (Vec::new(), Vec::new(), Vec::new());
    let builds0: Vec<u64> = piles
        .iter()
        .map(|ps| ps.iter().map(|e| e.rebuilds()).sum())
        .collect();
    let mut times = vec![Vec::new(); sizes.len()];
    // the rounds keep each pile in the engine's memory order (`advance_held`, as a long run
    // or the Python scene's blocks do); the permutations into it and out, which every
    // `advance` call pays, timed apart
    let cross = |e: &mut Engine<D>, into: bool| {
        let c = common::thread_cpu_seconds();
        if into {
            e.advance_held(0).unwrap();
        } else {
            e.to_user_order();
        }
        common::thread_cpu_seconds() - c
    };
    let reordered: Vec<bool> = piles
        .iter()
        .map(|ps| ps.iter().any(|e| (0..e.p.len()).any(|k| e.user_index(k) != k)))
        .collect();
    let mut crossing: Vec<f64> = one.install(|| {
        piles
            .iter_mut()
            .map(|ps| ps.iter_mut().map(|e| cross(e, true)).sum())
            .collect()
    });
    for _ in 0..rounds {
        for (s, ps) in piles.iter_mut().enumerate() {
            let t: f64 = one.install(|| ps.iter_mut().map(|e| held_steps(e, k)).sum());
            times[s].push(t / (ps.len() as f64 * sizes[s] as f64 * k as f64));
        }
    }
    one.install(|| {
        for (c, ps) in crossing.iter_mut().zip(piles.iter_mut()) {
            *c += ps.iter_mut().map(|e| cross(e, false)).sum::<f64>();
        }
    });
    let kind = if D == 2 { "disk" } else { "sphere" };
    for (s, ps) in piles.iter().enumerate() {
        let n = sizes[s];
        let whole = times[s].iter().sum::<f64>() / rounds as f64;
        let best = times[s].iter().cloned().fold(f64::INFINITY, f64::min);
        let med = median(&times[s]);
        let builds: u64 = ps.iter().map(|e| e.rebuilds()).sum::<u64>() - builds0[s];
        let per = ps.iter().map(|e| e.contacts()).sum::<usize>() as f64 / (ps.len() * n) as f64;
        println!(
            "n = {n:>8}: {:.1} ns per particle-step over {window} ({} pile(s); {builds} list builds in the window); rounds of {k} steps: best {:.1}, median {:.1}; {per:.3} contacts per {kind}",
            whole * 1e9,
            ps.len(),
            best * 1e9,
            med * 1e9,
        );
        if reordered[s] {
            println!(
                "  reordered by the engine; its memory order crossed into and out of (once per `advance` call): {:.1} ns per particle",
                crossing[s] / (ps.len() * n) as f64 * 1e9
            );
        }
        costs.push(best);
        medians.push(med);
        wholes.push(whole);
    }
    let spread = |v: &[f64]| {
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &c| (a.min(c), b.max(c)));
        hi / lo
    };
    println!(
        "cost per particle-step, max/min over the sizes: {:.2} (whole windows), {:.2} (median rounds), {:.2} (best rounds)   target <= 1.5",
        spread(&wholes),
        spread(&medians),
        spread(&costs)
    );
}

/// The base of the 3D piles ([`BASE3D`] spheres, [`SETTLE3D`] steps from the lattice) with
/// `laws`, stepped on `one`.
fn base3d(one: &rayon::ThreadPool, laws: Laws) -> Engine<3> {
    one.install(|| {
        let mut e = common::pile3d(BASE3D, laws, MAT);
        let t = cpu_steps(&mut e, SETTLE3D as usize);
        println!(
            "3D base pile: {BASE3D} spheres stepped {SETTLE3D} steps ({:.3} s simulated, dt = {:.3e} s) in {t:.1} CPU s; {} contacts, centre of mass {:.3} mm high",
            e.time(),
            e.dt(),
            e.contacts(),
            common::com_height(&e) * 1e3
        );
        e
    })
}

/// `tiles` copies of `base` as one pile numbered in `order`, with `laws` (energy accounting on
/// with `energy`).
fn tiled3d(base: &Engine<3>, tiles: [usize; 2], order: TileOrder, laws: Laws, energy: bool) -> Engine<3> {
    let (bodies, side, top) = common::tile3d(base, BASE3D, tiles, order);
    common::pile3d_engine(&bodies, side, top, laws, MAT, energy)
}

/// `tiles` copies of `base` as two species of the same material (sphere k of species k mod 2),
/// each pair of species and each species–floor pair under its own laws: `laws(SPECIES_LAWS[c])`
/// for class c (a–a, a–b, b–b between spheres; a–floor, b–floor).
fn tiled3d_species(base: &Engine<3>, tiles: [usize; 2], laws: impl Fn((f64, f64)) -> Laws) -> Engine<3> {
    let (bodies, side, top) = common::tile3d(base, BASE3D, tiles, TileOrder::Lattice);
    let (cfg, walls) = common::pile3d_config(side, top, MAT, false);
    let mut table = SpeciesLaws::single(laws(SPECIES_LAWS[0]), MAT);
    let class = |c: usize| SpeciesLaws::single(laws(SPECIES_LAWS[c]), MAT);
    let info = |name: &str| SpeciesInfo {
        name: name.into(),
        material: MAT,
    };
    table.species = vec![info("a"), info("b")];
    table.pair.extend([1, 2].into_iter().flat_map(|c| class(c).pair));
    table.wall = [3, 4].into_iter().flat_map(|c| class(c).wall).collect();
    table.pair_class = vec![0, 1, 1, 2];
    table.pair_labels = vec!["a–a".into(), "a–b".into(), "b–b".into()];
    table.wall_class = vec![0, 1];
    table.wall_labels = vec!["a–floor".into(), "b–floor".into()];
    let species: Vec<u8> = (0..bodies.len()).map(|k| (k % 2) as u8).collect();
    Engine::with_species(cfg, &bodies, &species, walls, table).expect("the two-species pile")
}

/// CPU seconds (this thread) to write the checkpoint of `e` to `path`, the median of `n`.
fn checkpoint_seconds(e: &Engine<3>, path: &std::path::Path, n: usize) -> (f64, u64) {
    use dashpot::dem::checkpoint::{self, Checkpoint, Header};
    let mut t = Vec::new();
    for _ in 0..n {
        let t0 = std::time::Instant::now();
        let ck = Checkpoint {
            scene: String::new(),
            laws: String::new(),
            energy_initial: 0.0,
            frames: 0,
            engine: e.save_state(),
        };
        let header = Header {
            dimension: 3,
            scene_hash: 0,
        };
        checkpoint::write(path, header, &ck).expect("the checkpoint is written");
        t.push(t0.elapsed().as_secs_f64());
    }
    let bytes = std::fs::metadata(path).map(|m| m.len()).unwrap_or(0);
    (median(&t), bytes)
}

fn main() {
    // `cargo bench --bench dem -- [plugins] [scaling] [cores] [scaling3d] [plugins3d] [energy]`:
    // the named sections only
    let only: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with('-')).collect();
    let run = |name: &str| only.is_empty() || only.iter().any(|a| a == name);
    // every plugin of the workspace (`rolling-sds` among them)
    let reg = registry_03();
    let one = pool(1);

    // 1. plugins vs compiled in, 2,000 settling disks, one core, interleaved blocks
    if run("plugins") {
        one.install(|| {
            let mut a = pile(2000, plugin_laws(&reg, false));
            let mut b = pile(2000, compiled_laws(false));
            // settle first: contacts everywhere
            steps(&mut a, 5000);
            steps(&mut b, 5000);
            let ab = Pairs::run(&mut a, &mut b, 7, 500);
            ab.plugins_against_compiled("2000 disks, HSD + Mindlin", 2000 * 500, &a, &b);
            let ps = |t: f64| 2000.0 * 500.0 / t;

            // what the first/last-step means cost: the same pile with the plain step-end rule,
            // both from the start and settled as long (a pile gains contacts as it settles)
            let mut a = pile(2000, plugin_laws(&reg, false));
            let mut c = common::pile(2000, plugin_laws(&reg, false), MAT, false);
            steps(&mut a, 5000);
            steps(&mut c, 5000);
            let ac = Pairs::run(&mut a, &mut c, 7, 500);
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
                ps(median(&ac.ta)),
                ps(median(&ac.tb)),
                ac.summary(),
                a.contacts(),
                c.contacts(),
                a.rebuilds(),
                c.rebuilds()
            );
        });
    }

    // 2. scaling, one core: every size steps through the same stage of the same pile (steps
    // 300..400 from the lattice, so the same contacts per disk), the smaller sizes as several
    // piles (15 of 10³, 10 of 10⁴) so that each size's block is long enough to time; 4 rounds
    // of 25 steps
    if run("scaling") {
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
                            let mut e = pile(n, plugin_laws(&reg, false));
                            cpu_steps(&mut e, 300);
                            e
                        })
                        .collect()
                })
                .collect()
        });
        scaling(&one, &sizes, &mut piles, 4, 25, "steps 300..400");
        print_vm_hwm("every pile above held at once (the 10^6 one among them)");
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
        let mut e = two.install(|| pile(n, plugin_laws(&reg, false)));
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

    // 4. scaling in 3D, one core: 10³, 10⁴, 10⁵, 10⁶ spheres, each size copies of one base pile
    // (1 × 1, 5 × 2, 10 × 10, 40 × 25 of them), so every size steps the same stage; the smaller
    // sizes as several piles; the first 20 steps (the contacts' history forming afresh) untimed,
    // then 4 rounds of 10 steps. The spheres numbered first as a pile generated at the full
    // size would be (the figure), then copy by copy (what the memory order costs)
    if run("scaling3d") {
        let base = base3d(&one, plugin_laws(&reg, false));
        let tiles = [[1, 1], [5, 2], [10, 10], [40, 25]];
        let sizes: Vec<usize> = tiles.iter().map(|[x, y]| BASE3D * x * y).collect();
        for order in [TileOrder::Lattice, TileOrder::Copies] {
            let mut piles: Vec<Vec<Engine<3>>> = one.install(|| {
                tiles
                    .iter()
                    .zip(&sizes)
                    .map(|(&t, &n)| {
                        (0..(100_000 / n).clamp(1, 15))
                            .map(|_| {
                                let mut e = tiled3d(&base, t, order, plugin_laws(&reg, false), false);
                                cpu_steps(&mut e, 20);
                                e
                            })
                            .collect()
                    })
                    .collect()
            });
            println!(
                "spheres numbered {}:",
                match order {
                    TileOrder::Lattice => "as the lattice of the whole pile",
                    TileOrder::Copies => "copy by copy",
                }
            );
            let window = format!(
                "steps {}..{} of the base pile (20..60 after the copy)",
                SETTLE3D + 20,
                SETTLE3D + 60
            );
            scaling(&one, &sizes, &mut piles, 4, 10, &window);
            if order == TileOrder::Lattice {
                print_vm_hwm(
                    "every 3D pile above held at once (the 10^6-sphere one among them)   target <= 4 GiB",
                );
            }
        }
    }

    // 5. plugins vs compiled in, 3D, HSD + Mindlin + rolling sds: 4,000 spheres (2 × 2 copies of
    // the base pile), one core, interleaved blocks
    // 6. energy accounting on vs off: the same pile and laws (plugins)
    if run("plugins3d") || run("energy") || run("species") || run("checkpoint") || run("heat") {
        let base = base3d(&one, plugin_laws(&reg, true));
        let n = 4 * BASE3D;
        const BLOCKS: usize = 21;
        const K: usize = 400;
        let contest = |a: &mut Engine<3>, b: &mut Engine<3>| {
            one.install(|| {
                // the contacts' history formed again after the copy
                steps(a, 500);
                steps(b, 500);
                Pairs::run(a, b, BLOCKS, K)
            })
        };
        if run("plugins3d") {
            let mut a = tiled3d(&base, [2, 2], TileOrder::Lattice, plugin_laws(&reg, true), false);
            let mut b = tiled3d(&base, [2, 2], TileOrder::Lattice, compiled_laws(true), false);
            let ab = contest(&mut a, &mut b);
            ab.plugins_against_compiled("4000 spheres, HSD + Mindlin + rolling sds", n * K, &a, &b);
            println!("  target >= 0.95");
        }
        if run("energy") {
            let mut a = tiled3d(&base, [2, 2], TileOrder::Lattice, plugin_laws(&reg, true), true);
            let mut b = tiled3d(&base, [2, 2], TileOrder::Lattice, plugin_laws(&reg, true), false);
            let ab = contest(&mut a, &mut b);
            let what = format!("{n} spheres, HSD + Mindlin + rolling sds (plugins), blocks of {K} steps");
            ab.print_cost(
                &what,
                "energy accounting on",
                "off",
                n * K,
                a.contacts(),
                "<= 10 %",
            );
            println!(
                "  dissipated since the copy (J): normal {:.3e}, tangential {:.3e}, rolling {:.3e}, twisting {:.3e}",
                a.dissipated[0], a.dissipated[1], a.dissipated[2], a.dissipated[3]
            );
            assert_eq!(
                a.p.pos[0], b.p.pos[0],
                "the accounting does not change the trajectory"
            );
        }
        if run("species") {
            let mut a = tiled3d_species(&base, [2, 2], |l| plugin_laws_with(&reg, true, l));
            let mut b = tiled3d(&base, [2, 2], TileOrder::Lattice, plugin_laws(&reg, true), false);
            let ab = contest(&mut a, &mut b);
            let what = format!("{n} spheres, HSD + Mindlin + rolling sds (plugins), blocks of {K} steps");
            let (on, off) = ("two species with laws per pair", "one species");
            ab.print_cost(&what, on, off, n * K, a.contacts(), "<= 5 %");
        }
        if run("checkpoint") {
            let dir = std::env::temp_dir().join(format!("dashpot-bench-{}", std::process::id()));
            std::fs::create_dir_all(&dir).expect("a temporary directory");
            let path = dir.join("bench.dpck");
            for tiles in [[2, 2], [10, 10]] {
                let mut e = tiled3d(&base, tiles, TileOrder::Lattice, plugin_laws(&reg, true), false);
                let step = one.install(|| cpu_steps(&mut e, 100)) / 100.0;
                let (t, bytes) = checkpoint_seconds(&e, &path, 5);
                println!(
                    "{} spheres ({} contacts): a checkpoint of {:.1} MB written in {:.3} s (median of 5, wall) = {:.0} steps ({:.2e} s a step); at one a minute {:.3} % of the run   target <= 2 %",
                    e.p.len(),
                    e.contacts(),
                    bytes as f64 / 1e6,
                    t,
                    t / step,
                    step,
                    100.0 * t / 60.0
                );
            }
            let _ = std::fs::remove_dir_all(&dir);
        }
        if run("heat") {
            let reg = dashpot_tests::registry_04();
            let hot = plugin_laws(&reg, true)
                .with_heat(&reg, ("heat-radius", &[ParamValue::new("k", 40.0)]), &MAT)
                .unwrap();
            let a = tiled3d(&base, [2, 2], TileOrder::Lattice, hot, true);
            let setup = dashpot::dem::heat::HeatSetup {
                temperature: (0..a.p.len())
                    .map(|i| if i % 2 == 0 { 300.0 } else { 400.0 })
                    .collect(),
                specific_heat: vec![500.0],
                walls: vec![Some(dashpot::dem::heat::WallTemperature::Fixed(350.0)); a.walls.len()],
            };
            let mut a = a.with_heat(setup).unwrap();
            let mut b = tiled3d(&base, [2, 2], TileOrder::Lattice, plugin_laws(&reg, true), true);
            let ab = contest(&mut a, &mut b);
            let books = a.heat_books().unwrap();
            let what = format!("{n} spheres, HSD + Mindlin + rolling sds (plugins), blocks of {K} steps");
            ab.print_cost(&what, "heat-radius on", "off", n * K, a.contacts(), "<= 15 %");
            println!(
                "  thermal books: Σ m c T {:.6e} J, the floor gave {:.3e} J, balance {:.1e} J; smallest m c/ΣH {:.3e} s (dt {:.3e} s)",
                books.thermal, books.wall_heat, books.balance, books.stability_limit, books.dt
            );
            assert_eq!(a.p.pos[0], b.p.pos[0], "heat does not change the trajectory");
        }
    }
}
