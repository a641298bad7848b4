//! HSD force over 10⁶ pairs: the plugin's batch call and per-pair call against the same law
//! compiled statically into this benchmark, measured side by side in one run.
//!
//! Run: `cargo bench -p dashpot-tests --bench hsd_force`

use dashpot_hsd::Hsd;
use dashpot_sdk::{BoundContact, ContactLaw, Pair, ParamValue, Particle};
use dashpot_tests::seed_registry;
use std::hint::black_box;
use std::time::Instant;

const N: usize = 1_000_000;
const REPS: usize = 21;

fn time(f: &mut dyn FnMut()) -> f64 {
    let s = Instant::now();
    f();
    s.elapsed().as_secs_f64()
}

/// Runs the contenders interleaved (A, B, C, A, B, C, ...) so that drifts in machine load hit
/// all alike, and returns each one's minimum and median wall time (s).
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

fn main() {
    let pair = Pair::spheres(&Particle::MCC, &Particle::MCC).expect("pair");
    // Overlaps up to 1e-4 m (1 % of d) and rates of either sign: a realistic DEM contact list.
    let mut x = 0x9e37_79b9_7f4a_7c15_u64;
    let mut rnd = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64
    };
    let delta: Vec<f64> = (0..N).map(|_| 1e-4 * rnd()).collect();
    let rate: Vec<f64> = (0..N).map(|_| 2.0 * rnd() - 1.0).collect();
    let mut out = vec![0.0; N];

    // The same law, compiled into this binary, and loaded from libdashpot_hsd.so.
    let stat = Hsd::with(0.54).bind(&pair).expect("bind");
    let reg = seed_registry();
    let plug = reg
        .contact("hsd", &[ParamValue::new("eps", 0.54)])
        .expect("law")
        .bind(&pair)
        .expect("bind");

    let mut reference = vec![0.0; N];
    stat.force_batch(&delta, &rate, &mut reference);
    plug.force_batch(&delta, &rate, &mut out).expect("batch");
    assert!(
        out.iter()
            .zip(&reference)
            .all(|(a, b)| a.to_bits() == b.to_bits()),
        "plugin and static forces differ"
    );

    let mut o1 = vec![0.0; N];
    let mut o2 = vec![0.0; N];
    let mut o3 = vec![0.0; N];
    let r = race(&mut [
        &mut || stat.force_batch(black_box(&delta), black_box(&rate), black_box(&mut o1)),
        &mut || {
            plug.force_batch(black_box(&delta), black_box(&rate), black_box(&mut o2))
                .expect("batch")
        },
        &mut || {
            for i in 0..N {
                o3[i] = plug
                    .force(black_box(delta[i]), black_box(rate[i]))
                    .expect("force");
            }
            black_box(&o3);
        },
    ]);
    let ns = |t: f64| t / N as f64 * 1e9;
    println!("HSD normal force over {N} pairs, {REPS} interleaved runs (min | median)");
    for (name, (tmin, tmed)) in [
        "static (compiled in)",
        "plugin batch call",
        "plugin per-pair call",
    ]
    .iter()
    .zip(&r)
    {
        println!("  {name:<22} {:7.3} | {:7.3} ns/pair", ns(*tmin), ns(*tmed));
    }
    println!(
        "  speed ratio plugin batch / static:    {:.3} (min) | {:.3} (median)   target >= 0.95",
        r[0].0 / r[1].0,
        r[0].1 / r[1].1
    );
    println!(
        "  speed ratio plugin per-pair / static: {:.3} (min) | {:.3} (median)",
        r[0].0 / r[2].0,
        r[0].1 / r[2].1
    );
}
