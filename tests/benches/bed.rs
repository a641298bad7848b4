//! The vibrated bed at n = 3, f = 30 Hz, g = 9.8 m/s², r(v), N = 300: CPU seconds per simulated
//! second with the restitution law loaded as a plugin and compiled in, side by side in one run;
//! then against the independent C reference `edref` (built here from its source, found in
//! `$DASHPOT_EDREF` or `../shared/peers/edref` beside the workspace; skipped with a reason when
//! absent) on the same case and protocol, 300 measured periods after 50: 7 pairs, the order of
//! the two contenders alternating from pair to pair, the ratio the median of the pairs' ratios.
//!
//! Run: `cargo bench -p dashpot-tests --bench bed`; `cargo bench -p dashpot-tests --bench bed --
//! once [PERIODS]` runs dashpot's side of the edref protocol alone, once (for instruction counts
//! under callgrind, of the bench binary `target/release/deps/bed-*`).

use dashpot::bed::{bed_particle, plugin_laws, Bed, BedConfig, Compiled, LawChoice, Laws, Restitution};
use dashpot_mcnamara_falcon::McNamaraFalcon;
use dashpot_tests::seed_registry;

const REPS: usize = 7;
/// Transient before timing (s of simulated time) and timed span (s).
const TRANSIENT: f64 = 1.0;
const SPAN: f64 = 6.0;

/// CPU time (s) of this thread, from the kernel's thread CPU clock (exact to the ns at the
/// call, unlike /proc's tick-updated counters); None where the clock is missing.
fn cpu_seconds() -> Option<f64> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec into the valid pointer we pass.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    (rc == 0).then_some(ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9)
}

struct Run {
    cpu: f64,
    wall: f64,
    events: u64,
    collisions: u64,
    pressure: f64,
}

fn run<R: Restitution>(laws: Laws<R>) -> Run {
    let cfg = BedConfig::paper(3.0, 30.0);
    let mut bed = Bed::new(cfg, laws).expect("bed");
    bed.run_until(TRANSIENT, &mut |_| {}).expect("transient");
    bed.start_window();
    let (e0, c0) = (bed.counters.events, bed.counters.collisions);
    let cpu0 = cpu_seconds().unwrap_or(f64::NAN);
    let t0 = std::time::Instant::now();
    bed.run_until(TRANSIENT + SPAN, &mut |_| {}).expect("run");
    let wall = t0.elapsed().as_secs_f64();
    let cpu = cpu_seconds().map(|c| c - cpu0).unwrap_or(wall);
    assert!(cpu.is_finite(), "no CPU clock");
    let rep = bed.report(wall);
    Run {
        cpu,
        wall,
        events: bed.counters.events - e0,
        collisions: bed.counters.collisions - c0,
        pressure: rep.pressure,
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The C reference's source directory, or why there is none.
fn edref_dir() -> Result<std::path::PathBuf, String> {
    dashpot_tests::dir_holding(
        "DASHPOT_EDREF",
        || Ok(dashpot_tests::workspace_root().join("../shared/peers/edref")),
        "edref.c",
        "edref.c in",
        "set DASHPOT_EDREF to the reference's directory",
    )
}

/// Builds edref with the flags of its Makefile (gcc -O2 -std=c11) into target/edref/.
fn build_edref(dir: &std::path::Path) -> Result<std::path::PathBuf, String> {
    let out = dashpot_tests::workspace_root().join("target/edref");
    std::fs::create_dir_all(&out).map_err(|e| e.to_string())?;
    let exe = out.join("edref");
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let st = std::process::Command::new(&cc)
        .args(["-O2", "-std=c11", "-o"])
        .arg(&exe)
        .arg(dir.join("edref.c"))
        .arg("-lm")
        .status()
        .map_err(|e| format!("cannot run {cc}: {e}"))?;
    if st.success() {
        Ok(exe)
    } else {
        Err(format!("{cc} failed to build edref ({st})"))
    }
}

/// One edref run of the case: (CPU s per simulated s over the measured periods, P).
fn run_edref(exe: &std::path::Path) -> (f64, f64) {
    let o = std::process::Command::new(exe)
        .args([
            "n=3",
            "f=30",
            "g=9.8",
            "law=mf",
            "cycles=300",
            "trans=50",
            "seed=1",
            "tc=0",
        ])
        .output()
        .expect("edref runs");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("edref prints JSON");
    assert_eq!(v["aborted"], 0, "edref aborted: {v}");
    let cpu = v["cpu_s"].as_f64().expect("cpu_s");
    (cpu / (PERIODS / 30.0), v["P"].as_f64().expect("P"))
}

/// Measured periods of the edref protocol (after 50 periods of transient).
const PERIODS: f64 = 300.0;

/// One dashpot run of the same case: (CPU s per simulated s over the `periods` measured
/// periods, P).
fn run_protocol<R: Restitution>(laws: Laws<R>, periods: f64) -> (f64, f64) {
    let mut bed = Bed::new(BedConfig::paper(3.0, 30.0), laws).expect("bed");
    bed.run_until(50.0 / 30.0, &mut |_| {}).expect("transient");
    bed.start_window();
    let cpu0 = cpu_seconds().expect("thread CPU clock");
    bed.run_until((50.0 + periods) / 30.0, &mut |_| {}).expect("run");
    let cpu = cpu_seconds().expect("thread CPU clock") - cpu0;
    (cpu / (periods / 30.0), bed.report(1.0).pressure)
}

fn versus_edref(plugin: &Laws<dashpot::laws::PluginRestitution>) {
    let exe = match edref_dir().and_then(|d| build_edref(&d)) {
        Ok(e) => e,
        Err(why) => {
            println!("edref comparison skipped: {why}");
            return;
        }
    };
    const R: usize = 7;
    let (mut ours, mut theirs, mut pairs) = (Vec::new(), Vec::new(), Vec::new());
    let (mut p_ours, mut p_theirs) = (0.0, 0.0);
    for k in 0..R {
        // alternate which contender goes first, so that neither always follows the other
        let mut one = |edref_now: bool| {
            if edref_now {
                let (c, p) = run_edref(&exe);
                theirs.push(c);
                p_theirs = p;
            } else {
                let (c, p) = run_protocol(
                    Laws {
                        disk: &plugin.disk,
                        wall: &plugin.wall,
                    },
                    PERIODS,
                );
                ours.push(c);
                p_ours = p;
            }
        };
        one(k % 2 == 0);
        one(k % 2 == 1);
        pairs.push(theirs[k] / ours[k]);
    }
    let (mo, mt) = (median(ours.clone()), median(theirs.clone()));
    let mino = ours.iter().cloned().fold(f64::INFINITY, f64::min);
    let mint = theirs.iter().cloned().fold(f64::INFINITY, f64::min);
    let shown: Vec<String> = pairs.iter().map(|r| format!("{r:.2}")).collect();
    println!(
        "against edref (C, gcc -O2), n = 3, f = 30 Hz, g = 9.8, r(v), {PERIODS} periods after 50, seed 1, {R} alternating pairs (min | median)"
    );
    println!("  edref    {mint:.4} | {mt:.4} CPU s per simulated s   P = {p_theirs:.4} N/m");
    println!("  dashpot  {mino:.4} | {mo:.4} CPU s per simulated s   P = {p_ours:.4} N/m (plugin law, all guards on)");
    println!(
        "  speed ratio dashpot / edref: {:.2}x (median of pairs; pairs {})   min/min {:.2}x   target >= 1.6x",
        median(pairs.clone()),
        shown.join(", "),
        mint / mino
    );
}

/// `-- once [PERIODS]`: one dashpot run of the edref protocol's 50 + PERIODS periods alone (300
/// by default), for instruction counts under callgrind:
/// `valgrind --tool=callgrind target/release/deps/bed-* once 300`.
fn once(plugin: &Laws<dashpot::laws::PluginRestitution>, periods: f64) {
    let laws = Laws {
        disk: &plugin.disk,
        wall: &plugin.wall,
    };
    let mut bed = Bed::new(BedConfig::paper(3.0, 30.0), laws).expect("bed");
    bed.run_until((50.0 + periods) / 30.0, &mut |_| {}).expect("run");
    // the event count and the final time's kinetic energy to the last bit: a change that keeps
    // the physics keeps them
    println!(
        "dashpot {} periods: {} events, kinetic energy {:e} J",
        50.0 + periods,
        bed.counters.events,
        bed.kinetic_energy()
    );
}

fn main() {
    let reg = seed_registry();
    let plugin = plugin_laws(
        &reg,
        &LawChoice::new("mcnamara-falcon", Vec::new()),
        &bed_particle(0.002, 3.27e-5),
    )
    .expect("plugin");
    let args: Vec<String> = std::env::args().collect();
    if let Some(k) = args.iter().position(|a| a == "once") {
        let periods = match args.get(k + 1) {
            Some(p) => p.parse().expect("once PERIODS: a number of periods"),
            None => PERIODS,
        };
        return once(&plugin, periods);
    }
    let law = McNamaraFalcon { r0: 0.95, vy: 0.3 };
    let stat = Laws {
        disk: Compiled(law),
        wall: Compiled(law),
    };
    let mut p = Vec::new();
    let mut s = Vec::new();
    for _ in 0..REPS {
        p.push(run(Laws {
            disk: &plugin.disk,
            wall: &plugin.wall,
        }));
        s.push(run(Laws {
            disk: &stat.disk,
            wall: &stat.wall,
        }));
    }
    // the same law through both paths: the same trajectory, bit for bit
    assert_eq!(p[0].events, s[0].events, "plugin and static runs differ");
    assert_eq!(p[0].pressure.to_bits(), s[0].pressure.to_bits());
    let per = |v: &[Run], f: &dyn Fn(&Run) -> f64| -> (f64, f64) {
        let x: Vec<f64> = v.iter().map(f).collect();
        (x.iter().cloned().fold(f64::INFINITY, f64::min), median(x))
    };
    let cpu_p = per(&p, &|r| r.cpu / SPAN);
    let cpu_s = per(&s, &|r| r.cpu / SPAN);
    let wall_p = per(&p, &|r| r.wall / SPAN);
    let wall_s = per(&s, &|r| r.wall / SPAN);
    let r0 = &s[0];
    println!(
        "vibrated bed n = 3, f = 30 Hz, g = 9.8, r(v), N = 300: {SPAN} s simulated after {TRANSIENT} s, {REPS} interleaved runs (min | median)"
    );
    println!(
        "  events per simulated second {:.0}, collisions {:.0} ({:.0} % of events)",
        r0.events as f64 / SPAN,
        r0.collisions as f64 / SPAN,
        100.0 * r0.collisions as f64 / r0.events as f64
    );
    println!(
        "  static (compiled in)  {:.4} | {:.4} CPU s per simulated s ({:.4} | {:.4} wall)",
        cpu_s.0, cpu_s.1, wall_s.0, wall_s.1
    );
    println!(
        "  plugin                {:.4} | {:.4} CPU s per simulated s ({:.4} | {:.4} wall)",
        cpu_p.0, cpu_p.1, wall_p.0, wall_p.1
    );
    println!(
        "  plugin cost (CPU): {:+.2} % (min) | {:+.2} % (median)   target <= 5 %",
        100.0 * (cpu_p.0 / cpu_s.0 - 1.0),
        100.0 * (cpu_p.1 / cpu_s.1 - 1.0)
    );
    println!(
        "  collisions per CPU second: {:.3e} (plugin, median) | {:.3e} (static, median)",
        r0.collisions as f64 / (cpu_p.1 * SPAN),
        r0.collisions as f64 / (cpu_s.1 * SPAN)
    );
    versus_edref(&plugin);
}
