//! The contact-law hot path over 10⁶ contacts, each contender measured side by side in one run:
//!
//! 1. HSD normal force with per-contact geometry (a polydisperse contact list: every contact its
//!    own effective mass and radius): the plugin's batch call against the same law compiled into
//!    this benchmark and called through the same checked trampoline;
//! 2. HSD + Mindlin with history (normal batch, then tangential batch with the springs of every
//!    contact): plugins against compiled in;
//! 3. normal-only HSD of sdk 0.2 (per-contact geometry) against sdk 0.1's bound-pair batch, the
//!    0.1 plugin built from the 0.1 sources of this repository and called exactly as a 0.1 host
//!    called it.
//!
//! Run: `cargo bench -p dashpot-tests --bench hsd_force`
//!
//! With `DASHPOT_BASELINE_PLUGINS=DIR` (a directory holding another build of the plugins of the
//! normal laws without history, HSD, LSD, Kuwabara–Kono, DMT, e.g. from an earlier commit),
//! section 1b races each build there against this one, on the 10⁶ contacts and in chunks of
//! 1,024 in cache: a same-run A/B of a change to a plugin or to the sdk's batch loop.
//! `DASHPOT_BENCH_SECTIONS=1,1b` runs only the sections listed.

mod common;

use common::thread_cpu_seconds;
use dashpot::laws::{compiled, compiled_tangential, EnergyOut, NormalLaw, TangentialForce};
use dashpot_hsd::Hsd;
use dashpot_mindlin::Mindlin;
use dashpot_sdk::{MaterialPair, NormalBatch, ParamValue, Particle, TangentialBatch};
use dashpot_tests::{assert_same_bits, full_registry, lib_in, plugin_file, registry_of, sdk01_registry};
use std::hint::black_box;

const N: usize = 1_000_000;
const REPS: usize = 21;
/// The contacts of one batch call as the DEM loop makes them (inputs just gathered, in cache).
const CHUNK: usize = 1024;
/// The chunks of CHUNK contacts in N.
const CHUNKS: usize = N / CHUNK;

fn time(f: &mut dyn FnMut()) -> f64 {
    let s = thread_cpu_seconds();
    f();
    thread_cpu_seconds() - s
}

/// Runs the contenders interleaved (A, B, A, B, ...) so that drifts in machine load hit all
/// alike; returns each one's minimum and median wall time (s).
fn race(contenders: &mut [&mut dyn FnMut()]) -> Vec<(f64, f64)> {
    for f in contenders.iter_mut() {
        f();
    }
    let mut t = vec![Vec::with_capacity(REPS); contenders.len()];
    for _ in 0..REPS {
        for (k, f) in contenders.iter_mut().enumerate() {
            t[k].push(time(*f));
        }
    }
    t.into_iter()
        .map(|mut v| {
            v.sort_by(f64::total_cmp);
            (v[0], v[REPS / 2])
        })
        .collect()
}

struct Contacts {
    delta: Vec<f64>,
    rate: Vec<f64>,
    mass: Vec<f64>,
    radius: Vec<f64>,
    normal: Vec<[f64; 3]>,
    velocity: Vec<[f64; 3]>,
}

fn contacts() -> Contacts {
    let mut rnd = common::xorshift_uniform(0x9e37_79b9_7f4a_7c15_u64);
    let mut c = Contacts {
        delta: Vec::with_capacity(N),
        rate: Vec::with_capacity(N),
        mass: Vec::with_capacity(N),
        radius: Vec::with_capacity(N),
        normal: Vec::with_capacity(N),
        velocity: Vec::with_capacity(N),
    };
    for _ in 0..N {
        // steel spheres of diameters 4-8 mm (a `fix pour ... diam range` packing)
        let (d1, d2) = (0.004 + 0.004 * rnd(), 0.004 + 0.004 * rnd());
        let (m1, m2) = (
            7800.0 * std::f64::consts::FRAC_PI_6 * d1 * d1 * d1,
            7800.0 * std::f64::consts::FRAC_PI_6 * d2 * d2 * d2,
        );
        c.radius.push(0.25 * d1 * d2 / (0.5 * (d1 + d2)));
        c.mass.push(m1 * m2 / (m1 + m2));
        c.delta.push(1e-5 * rnd());
        c.rate.push(2.0 * rnd() - 1.0);
        let (th, ph) = (std::f64::consts::PI * rnd(), 2.0 * std::f64::consts::PI * rnd());
        c.normal
            .push([th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()]);
        c.velocity.push([rnd() - 0.5, rnd() - 0.5, rnd() - 0.5]);
    }
    c
}

/// Prints two contenders' (min, median) times per contact, converted by `per`, and their ratio.
fn report(r: &[(f64, f64)], per: impl Fn(f64) -> f64, names: [&str; 2], ratio: &str, target: &str) {
    for (k, name) in names.iter().enumerate() {
        println!(
            "   {name:<22} {:7.3} | {:7.3} ns/contact",
            per(r[k].0),
            per(r[k].1)
        );
    }
    println!(
        "   ratio {ratio} (speed): {:.3} (min) | {:.3} (median){target}",
        r[0].0 / r[1].0,
        r[0].1 / r[1].1
    );
}

/// `law` on the first [`CHUNK`] contacts of `c`, [`CHUNKS`] times over (so that they stay in
/// cache), with the energy outputs given.
fn in_chunks(
    law: &dyn NormalLaw,
    c: &Contacts,
    o: &mut [f64],
    mut power: Option<&mut [f64]>,
    mut elastic: Option<&mut [f64]>,
) {
    for _ in 0..CHUNKS {
        let out = EnergyOut {
            power: power.as_deref_mut(),
            elastic: elastic.as_deref_mut(),
        };
        law.force_batch_with(normal_chunk(c, 0..CHUNK, &mut o[..CHUNK]), None, out)
            .expect("normal batch");
    }
}

/// The normal laws without history that section 1b races against another build: (library,
/// law).
const BASELINE_LAWS: [(&str, &str); 4] = [
    ("dashpot_hsd", "hsd"),
    ("dashpot_lsd", "lsd"),
    ("dashpot_kuwabara_kono", "kuwabara-kono"),
    ("dashpot_dmt", "dmt"),
];

/// Races two builds of a normal law (`laws`: baseline, this build) on the contacts `c`, whole
/// and in chunks of 1,024 already in cache, after checking that they give the same bits.
fn versus(
    c: &Contacts,
    laws: [&dyn NormalLaw; 2],
    (o1, o2): (&mut [f64], &mut [f64]),
    ns: impl Fn(f64) -> f64,
) {
    let [base, this] = laws;
    normal_step(base, c, o1);
    normal_step(this, c, o2);
    assert_same_bits(o1, o2, |i| format!("the force on contact {i}"));
    let r = race(&mut [&mut || normal_step(base, c, o1), &mut || normal_step(this, c, o2)]);
    report(&r, ns, ["baseline build", "this build"], "this / baseline", "");
    let r = race(&mut [&mut || in_chunks(base, c, o1, None, None), &mut || {
        in_chunks(this, c, o2, None, None)
    }]);
    println!("   the same, in chunks of {CHUNK} contacts already in cache");
    let per = |t: f64| t / (CHUNKS * CHUNK) as f64 * 1e9;
    report(&r, per, ["baseline build", "this build"], "this / baseline", "");
    let (mut p, mut e) = (
        [vec![0.0; CHUNK], vec![0.0; CHUNK]],
        [vec![0.0; CHUNK], vec![0.0; CHUNK]],
    );
    let [p1, p2] = &mut p;
    let [e1, e2] = &mut e;
    let r = race(
        &mut [&mut || in_chunks(base, c, o1, Some(p1), Some(e1)), &mut || {
            in_chunks(this, c, o2, Some(p2), Some(e2))
        }],
    );
    assert_same_bits(p1, p2, |i| format!("the power of contact {i}"));
    assert_same_bits(e1, e2, |i| format!("the elastic energy of contact {i}"));
    println!("   the same with the energy outputs");
    report(&r, per, ["baseline build", "this build"], "this / baseline", "");
}

/// Whether to run section `name`: every section unless `DASHPOT_BENCH_SECTIONS` lists some
/// (comma-separated, e.g. `1,1b`).
fn section(name: &str) -> bool {
    std::env::var("DASHPOT_BENCH_SECTIONS").map_or(true, |v| v.split(',').any(|s| s.trim() == name))
}

/// The normal batch (no history) of every contact of `c`, forces into `out`.
fn normal_step(law: &dyn NormalLaw, c: &Contacts, out: &mut [f64]) {
    law.force_batch(normal_chunk(c, 0..N, out)).expect("normal batch");
}

/// The normal batch (no history) of the contacts `range` of `c`, forces into `out`.
fn normal_chunk<'a>(c: &'a Contacts, range: std::ops::Range<usize>, out: &'a mut [f64]) -> NormalBatch<'a> {
    NormalBatch {
        delta: black_box(&c.delta[range.clone()]),
        rate: black_box(&c.rate[range.clone()]),
        mass: &c.mass[range.clone()],
        radius: &c.radius[range],
        slots: 0,
        history: &mut [],
        force: out,
    }
}

/// The tangential batch of the contacts `range` of `c` (their normal forces `fnorm`, history
/// `hist`, forces `out`), with the energy outputs `energy` asks for.
fn tangential_range(
    law: &dyn TangentialForce,
    c: &Contacts,
    range: std::ops::Range<usize>,
    (fnorm, hist, out): (&[f64], &mut [f64], &mut [[f64; 3]]),
    energy: EnergyOut<'_>,
) {
    law.force_batch_with(
        TangentialBatch {
            dt: 1e-7,
            normal: &c.normal[range.clone()],
            velocity: black_box(&c.velocity[range.clone()]),
            normal_force: fnorm,
            delta: &c.delta[range.clone()],
            mass: &c.mass[range.clone()],
            radius: &c.radius[range],
            context: &[],
            slots: hist.len() / out.len(),
            history: hist,
            force: out,
        },
        energy,
    )
    .expect("tangential batch");
}

fn tangential_step(
    law: &dyn TangentialForce,
    c: &Contacts,
    fnorm: &[f64],
    hist: &mut [f64],
    out: &mut [[f64; 3]],
) {
    tangential_range(law, c, 0..out.len(), (fnorm, hist, out), EnergyOut::none());
}

fn main() {
    let steel = Particle {
        diameter: 0.006,
        density: 7800.0,
        young: 2.0e11,
        poisson: 0.3,
    };
    let mat = MaterialPair::spheres(&steel, &steel).expect("materials");
    let c = contacts();
    let reg = full_registry();
    let hsd_p = reg
        .contact("hsd", &[ParamValue::new("eps", 0.54)])
        .expect("hsd")
        .bind(&mat)
        .expect("bind");
    let hsd_s = compiled(&Hsd::with(0.54), &mat).expect("bind");
    let mind_p = reg
        .tangential("mindlin", &[ParamValue::new("mu", 0.3)])
        .expect("mindlin")
        .bind(&mat)
        .expect("bind");
    let mind_s = compiled_tangential(&Mindlin::with(0.3, 0.0), &mat).expect("bind");

    // the two forms compute the same bits
    let (mut f1, mut f2) = (vec![0.0; N], vec![0.0; N]);
    normal_step(&hsd_p, &c, &mut f1);
    normal_step(&hsd_s, &c, &mut f2);
    assert_same_bits(&f1, &f2, |i| format!("HSD's force on contact {i}"));

    println!("Contact laws over {N} contacts (steel, diameters 4-8 mm, each contact its own m and r), {REPS} interleaved runs (min | median)");
    let ns = |t: f64| t / N as f64 * 1e9;
    let ns_chunked = |t: f64| t / (CHUNKS * CHUNK) as f64 * 1e9;

    // 1. HSD normal, per-contact geometry
    let (mut o1, mut o2) = (vec![0.0; N], vec![0.0; N]);
    if section("1") {
        let r = race(&mut [&mut || normal_step(&hsd_s, &c, &mut o1), &mut || {
            normal_step(&hsd_p, &c, &mut o2)
        }]);
        println!("1. HSD normal force, per-contact geometry");
        report(
            &r,
            ns,
            ["compiled in", "plugin batch call"],
            "plugin / compiled",
            "",
        );
    }

    // 1b. this build of the normal laws without history against another one (a same-run A/B)
    if let Some(dir) = std::env::var_os("DASHPOT_BASELINE_PLUGINS").filter(|_| section("1b")) {
        for (lib, name) in BASELINE_LAWS {
            let file = lib_in(std::path::Path::new(&dir), lib);
            if !file.exists() {
                continue;
            }
            let bind = |file| {
                registry_of(vec![file])
                    .contact(name, &[])
                    .expect("the law")
                    .bind(&mat)
                    .expect("bind")
            };
            let (base, this) = (bind(file.clone()), bind(plugin_file(lib)));
            println!(
                "1b. {name} normal force: this build against the one in {}",
                file.display()
            );
            versus(&c, [&base, &this], (&mut o1, &mut o2), ns);
        }
    }

    // 2. HSD + Mindlin with history
    let slots = mind_p.history_slots();
    if section("2") {
        let (mut hs, mut hp) = (vec![0.0; slots * N], vec![0.0; slots * N]);
        let (mut ts, mut tp) = (vec![[0.0; 3]; N], vec![[0.0; 3]; N]);
        let (mut ns_, mut np_) = (vec![0.0; N], vec![0.0; N]);
        let r = race(&mut [
            &mut || {
                normal_step(&hsd_s, &c, &mut ns_);
                tangential_step(&mind_s, &c, &ns_, &mut hs, &mut ts);
            },
            &mut || {
                normal_step(&hsd_p, &c, &mut np_);
                tangential_step(&mind_p, &c, &np_, &mut hp, &mut tp);
            },
        ]);
        // after the same calls in the same order, the springs are the same bits
        assert_same_bits(&hs, &hp, |k| format!("Mindlin's spring of contact {}", k / slots));
        println!("2. HSD + Mindlin (μ = 0.3) with history: normal batch, then tangential batch");
        report(
            &r,
            ns,
            ["compiled in", "plugin batch calls"],
            "plugin / compiled",
            "   target >= 0.95",
        );
    }

    // 2b. the same plugins with the energy outputs on and off, in chunks of CHUNK contacts in
    // cache as the DEM loop calls them: what the accounting costs the laws
    if section("2b") {
        let mut h = [vec![0.0; slots * CHUNK], vec![0.0; slots * CHUNK]];
        let (mut fa, mut fb) = (vec![[0.0; 3]; CHUNK], vec![[0.0; 3]; CHUNK]);
        let (mut p, mut e) = (vec![0.0; CHUNK], vec![0.0; CHUNK]);
        let (mut pt, mut et) = (vec![0.0; CHUNK], vec![0.0; CHUNK]);
        let (mut na, mut nb) = (vec![0.0; CHUNK], vec![0.0; CHUNK]);
        let [ha, hb] = &mut h;
        let r = race(&mut [
            &mut || {
                for k in 0..CHUNKS {
                    let range = k * CHUNK..(k + 1) * CHUNK;
                    let nbatch = normal_chunk(&c, range.clone(), &mut na);
                    hsd_p.force_batch(nbatch).expect("normal batch");
                    tangential_range(&mind_p, &c, range, (&na, &mut *ha, &mut fa), EnergyOut::none());
                }
            },
            &mut || {
                for k in 0..CHUNKS {
                    let range = k * CHUNK..(k + 1) * CHUNK;
                    let nbatch = normal_chunk(&c, range.clone(), &mut nb);
                    let out = EnergyOut {
                        power: Some(&mut p),
                        elastic: Some(&mut e),
                    };
                    hsd_p.force_batch_with(nbatch, None, out).expect("normal batch");
                    let out = EnergyOut {
                        power: Some(&mut pt),
                        elastic: Some(&mut et),
                    };
                    tangential_range(&mind_p, &c, range, (&nb, &mut *hb, &mut fb), out);
                }
            },
        ]);
        assert_eq!(fa, fb, "the energy outputs change no force");
        println!("2b. HSD + Mindlin plugins in chunks of {CHUNK} in cache: energy outputs off against on");
        report(&r, ns_chunked, ["energy off", "energy on"], "off / on", "");
    }

    // 3. sdk 0.2 per-contact geometry against sdk 0.1's bound-pair batch
    if !section("3") && !section("4") {
        return;
    }
    match sdk01_registry("release") {
        None => println!("3. skipped: the sdk 0.1 sources are not in this checkout's history"),
        Some(old) => {
            let m01 = old
                .contact("hsd", &[ParamValue::new("eps", 0.54)])
                .expect("0.1 hsd")
                .bind(&mat)
                .expect("bind");
            let (mut o3, mut o4) = (vec![0.0; N], vec![0.0; N]);
            let r = race(&mut [
                &mut || {
                    m01.v1_bound_pair_batch(
                        c.mass[0],
                        c.radius[0],
                        black_box(&c.delta),
                        black_box(&c.rate),
                        &mut o3,
                    )
                    .expect("a 0.1 law")
                    .expect("0.1 batch")
                },
                &mut || normal_step(&hsd_p, &c, &mut o4),
            ]);
            println!("3. HSD normal force: sdk 0.2 per-contact geometry vs sdk 0.1 bound-pair batch (both plugins)");
            report(
                &r,
                ns,
                ["0.1 bound to one pair", "0.2 per-contact m, r"],
                "0.2 / 0.1",
                "   target >= 0.9",
            );

            // 4. the same two calls as a DEM loop makes them: chunks of CHUNK contacts whose
            // inputs were just gathered (in cache), so the law's cost is measured, not DRAM's
            let (d, v) = (&c.delta[..CHUNK], &c.rate[..CHUNK]);
            let (mut o5, mut o6) = (vec![0.0; CHUNK], vec![0.0; CHUNK]);
            let r = race(&mut [
                &mut || {
                    for _ in 0..CHUNKS {
                        m01.v1_bound_pair_batch(c.mass[0], c.radius[0], black_box(d), black_box(v), &mut o5)
                            .expect("a 0.1 law")
                            .expect("0.1 batch");
                    }
                },
                &mut || {
                    for _ in 0..CHUNKS {
                        hsd_p
                            .force_batch(normal_chunk(&c, 0..CHUNK, &mut o6))
                            .expect("normal batch");
                    }
                },
            ]);
            println!(
                "4. the same, in chunks of {CHUNK} contacts already in cache (as the DEM loop calls it)"
            );
            report(
                &r,
                ns_chunked,
                ["0.1 bound to one pair", "0.2 per-contact m, r"],
                "0.2 / 0.1",
                "   target >= 0.9",
            );
        }
    }
}
