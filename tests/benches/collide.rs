//! Collisions per CPU second through the plugins (HSD and Kuwabara–Kono) at the tolerance that
//! meets the accuracy target (realized restitution within 1e-9 of eps for HSD), the same with the
//! laws compiled in, and, side by side in the same run, SciPy's `solve_ivp(method="DOP853")`.
//!
//! Run: `DASHPOT_PYTHON=/path/to/venv/bin/python cargo bench -p dashpot-tests --bench collide`
//! (the venv needs scipy and numpy: see tests/benches/collide_scipy.py). Without
//! DASHPOT_PYTHON it tries `python3`, and reports if SciPy is missing.

mod common;

use dashpot::collide::{collide, ContactForce, Options, PairLaw};
use dashpot::laws::compiled;
use dashpot_sdk::{EndCriterion, MaterialPair, Pair, ParamValue, Particle};
use dashpot_tests::seed_registry;
use std::process::Command;

const RTOL: f64 = 1e-9;

struct Case {
    eps: f64,
    v0: f64,
}

fn cases(n: usize) -> Vec<Case> {
    let mut rnd = common::xorshift_uniform(0x2545_f491_4f6c_dd1d_u64);
    (0..n)
        .map(|_| Case {
            eps: 0.01 + 0.98 * rnd(),
            v0: 10f64.powf(-3.0 + 4.0 * rnd()),
        })
        .collect()
}

/// Runs all cases (law bound per case, as a calibration loop would), returns (collisions per CPU
/// second, worst |ε − eps|).
fn measure<C: ContactForce>(
    cases: &[Case],
    mass: f64,
    end: EndCriterion,
    make: impl Fn(f64) -> C,
    check: bool,
) -> (f64, f64) {
    let opt = Options {
        rtol: RTOL,
        ..Options::default()
    };
    let laws: Vec<C> = cases.iter().map(|c| make(c.eps)).collect();
    let mut worst: f64 = 0.0;
    let t = common::process_cpu_seconds();
    for (c, law) in cases.iter().zip(&laws) {
        let r = collide(law, mass, c.v0, end, &opt).expect("collision");
        if check {
            worst = worst.max((r.restitution - c.eps).abs());
        }
    }
    let dt = common::process_cpu_seconds() - t;
    (cases.len() as f64 / dt, worst)
}

fn main() {
    let pair = Pair::spheres(&Particle::MCC, &Particle::MCC).expect("pair");
    let mat = MaterialPair::spheres(&Particle::MCC, &Particle::MCC).expect("materials");
    let reg = seed_registry();
    let cs = cases(20_000);

    let (hsd_plugin, hsd_err) = measure(
        &cs,
        pair.mass,
        EndCriterion::Overlap,
        |e| {
            PairLaw::bind(
                &reg.contact("hsd", &[ParamValue::new("eps", e)]).expect("law"),
                &pair,
                Particle::MCC.poisson,
            )
            .expect("bind")
        },
        true,
    );
    let (hsd_static, _) = measure(
        &cs,
        pair.mass,
        EndCriterion::Overlap,
        |e| {
            PairLaw::new(
                compiled(&dashpot_hsd::Hsd::with(e), &mat).expect("bind"),
                pair.mass,
                pair.radius,
            )
        },
        false,
    );
    // KK: A chosen so that ε spans roughly the same range; restitution is not a parameter here
    let (kk_plugin, _) = measure(
        &cs,
        pair.mass,
        EndCriterion::Force,
        |e| {
            PairLaw::bind(
                &reg.contact("kuwabara-kono", &[ParamValue::new("A", 1e-5 * (1.0 - e))])
                    .expect("law"),
                &pair,
                Particle::MCC.poisson,
            )
            .expect("bind")
        },
        false,
    );
    let (kk_static, _) = measure(
        &cs,
        pair.mass,
        EndCriterion::Force,
        |e| {
            PairLaw::new(
                compiled(&dashpot_kuwabara_kono::KuwabaraKono::with(1e-5 * (1.0 - e)), &mat).expect("bind"),
                pair.mass,
                pair.radius,
            )
        },
        false,
    );

    println!("Two-body collisions, MCC spheres, eps in [0.01, 0.99], v0 in [1e-3, 10] m/s, rtol {RTOL:e}, one core");
    println!("  HSD through the plugin      {hsd_plugin:10.0} collisions/CPU s   worst |ε − eps| = {hsd_err:.1e} (target ≤ 1e-9)");
    println!(
        "  HSD compiled in             {hsd_static:10.0} collisions/CPU s   (plugin/static speed {:.3})",
        hsd_plugin / hsd_static
    );
    println!("  KK  through the plugin      {kk_plugin:10.0} collisions/CPU s   (end: force)");
    println!(
        "  KK  compiled in             {kk_static:10.0} collisions/CPU s   (plugin/static speed {:.3})",
        kk_plugin / kk_static
    );

    let python = std::env::var("DASHPOT_PYTHON").unwrap_or_else(|_| "python3".into());
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/collide_scipy.py");
    // SciPy at the reference tolerance (1e-10, where its ε error is ~1e-9) and at ours.
    for (label, rtol) in [("accuracy-matched", 1e-10), ("same rtol", RTOL)] {
        match Command::new(&python)
            .arg(&script)
            .args(["--rtol", &rtol.to_string(), "--seconds", "10"])
            .output()
        {
            Ok(o) if o.status.success() => {
                let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("scipy json");
                let rate = v["collisions_per_second"].as_f64().unwrap_or(f64::NAN);
                println!(
                    "  SciPy DOP853 rtol {rtol:e}     {rate:10.1} collisions/CPU s   worst |ε − eps| = {:.1e} ({} collisions)",
                    v["max_eps_error"].as_f64().unwrap_or(f64::NAN),
                    v["collisions"]
                );
                println!(
                    "  speed ratio dashpot HSD plugin / SciPy ({label}): {:.0}x   (target >= 1000x)",
                    hsd_plugin / rate
                );
            }
            Ok(o) => {
                println!(
                    "  SciPy baseline not run ({python} failed: {}); install it as described in {}",
                    String::from_utf8_lossy(&o.stderr).lines().last().unwrap_or(""),
                    script.display()
                );
                break;
            }
            Err(e) => {
                println!("  SciPy baseline not run: cannot start {python}: {e}");
                break;
            }
        }
    }
}
