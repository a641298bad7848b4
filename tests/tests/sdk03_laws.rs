//! The law kinds of sdk 0.3 against closed forms, through the real plugin libraries: adhesive
//! normal laws (JKR, DMT) with their reach, rolling and twisting laws, and the energy outputs.

use dashpot_sdk::abi::{ContactModelHandle, EnergyOut};
use dashpot_sdk::{
    LawError, MaterialPair, NormalBatch, ParamValue, RollingBatch, TwistingBatch, VectorBatch,
};
use dashpot_tests::registry_03;
use std::f64::consts::PI;

const E: f64 = 1.0e8;
const R: f64 = 1.0e-4;
const M: f64 = 1.0e-9;
const W: f64 = 0.05;

/// Named parameter values.
fn pv(p: &[(&str, f64)]) -> Vec<ParamValue> {
    p.iter().map(|&(n, v)| ParamValue::new(n, v)).collect()
}

fn materials() -> MaterialPair {
    MaterialPair::new(E, 4.0e7).unwrap()
}

/// One contact's step: (force, reach, power, elastic, energy written).
fn step(m: &ContactModelHandle, h: &mut [f64], delta: f64, rate: f64) -> (f64, f64, f64, f64, bool) {
    let (mut f, mut reach, mut p, mut e) = ([0.0], [f64::NAN], [f64::NAN], [f64::NAN]);
    let written = m
        .force_batch_with(
            NormalBatch {
                delta: &[delta],
                rate: &[rate],
                mass: &[M],
                radius: &[R],
                slots: h.len(),
                history: h,
                force: &mut f,
            },
            Some(&mut reach),
            EnergyOut {
                power: Some(&mut p),
                elastic: Some(&mut e),
            },
        )
        .unwrap();
    (f[0], reach[0], p[0], e[0], written)
}

/// One contact of a tangential or rolling law at overlap `d` (m), normal n̂ = z, velocity `v`
/// (m/s) and normal force `fnorm` (N) over `dt` (s), through `call` (the bound law's batch),
/// with both energy outputs: (force, power, elastic, energy written).
fn vector_step(
    call: impl FnOnce(VectorBatch<'_>, EnergyOut<'_>) -> Result<bool, LawError>,
    h: &mut [f64],
    (dt, v, fnorm, d): (f64, [f64; 3], f64, f64),
) -> ([f64; 3], f64, f64, bool) {
    let (mut f, mut p, mut e) = ([[0.0; 3]], [0.0], [0.0]);
    let written = call(
        VectorBatch {
            dt,
            normal: &[[0.0, 0.0, 1.0]],
            velocity: &[v],
            normal_force: &[fnorm],
            delta: &[d],
            mass: &[M],
            radius: &[R],
            context: &[],
            slots: h.len(),
            history: h,
            force: &mut f,
        },
        EnergyOut {
            power: Some(&mut p),
            elastic: Some(&mut e),
        },
    )
    .unwrap();
    (f[0], p[0], e[0], written)
}

/// A slow cycle of overlaps: from −δ0 up to δ1 and back down to −δ0, `n` steps each way, the
/// grid holding 0 exactly.
fn cycle(d0: f64, d1: f64, n: usize) -> Vec<f64> {
    let up: Vec<f64> = (0..=n).map(|i| -d0 + (d1 + d0) * i as f64 / n as f64).collect();
    let zero_at = up.iter().position(|d| *d >= 0.0).unwrap();
    let mut v = up.clone();
    v[zero_at] = 0.0;
    let down: Vec<f64> = v.iter().rev().skip(1).copied().collect();
    v.extend(down);
    v
}

fn jkr_delta_c() -> f64 {
    -0.75 * (PI * PI * W * W * R / (E * E)).cbrt()
}

#[test]
fn jkr_pull_off_force_reach_and_rupture() {
    let reg = registry_03();
    let law = reg.contact("jkr", &[ParamValue::new("w", W)]).unwrap();
    let m = law.bind(&materials()).unwrap();
    assert_eq!(m.history_slots(), 1);
    let dc = jkr_delta_c();
    let a0 = (9.0 * PI * W * R * R / (2.0 * E)).cbrt();
    let path = cycle(2.0 * dc.abs(), 20.0 * a0 * a0 / R, 200_000);
    let mut h = [0.0];
    let (mut fmin, mut touched, mut broken) = (f64::INFINITY, false, false);
    let (mut work, mut prev): (f64, Option<(f64, f64)>) = (0.0, None);
    let mut e_top = 0.0;
    let mut past_touch = 0;
    for (i, &d) in path.iter().enumerate() {
        let unloading = i > path.len() / 2;
        let rate = if unloading { -1e-3 } else { 1e-3 };
        let (f, reach, p, e, written) = step(&m, &mut h, d, rate);
        assert!(written, "jkr accounts for energy");
        assert_eq!(p, 0.0, "undamped: no dissipation");
        touched |= d >= 0.0;
        if !touched {
            // the contact forms only at touch
            assert_eq!((f, reach), (0.0, 0.0), "before touch at δ = {d:e}");
            continue;
        }
        if broken {
            assert_eq!((f, reach, h[0]), (0.0, 0.0, 0.0), "after rupture at δ = {d:e}");
            continue;
        }
        if d < dc {
            // the contact ends at its documented separation
            assert!(
                unloading && f == 0.0 && reach == 0.0 && h[0] == 0.0,
                "rupture at δ = {d:e}"
            );
            broken = true;
            continue;
        }
        assert!(
            (reach / dc.abs() - 1.0).abs() < 1e-12,
            "reach {reach} vs |δ_c| {}",
            dc.abs()
        );
        if unloading && d < 0.0 {
            past_touch += 1;
            assert!(f < 0.0, "tensile past touching at δ = {d:e}: {f}");
        }
        fmin = fmin.min(f);
        if unloading && d >= 0.0 {
            if let Some((dp, fp)) = prev {
                work += 0.5 * (f + fp) * (dp - d);
            }
            prev = Some((d, f));
            if e_top == 0.0 {
                e_top = e;
            }
        }
    }
    assert!(broken && past_touch > 1000);
    let want = -1.5 * PI * W * R;
    assert!(
        (fmin / want - 1.0).abs() < 1e-6,
        "most tensile force {fmin} vs −(3/2)π w R = {want}"
    );
    // the elastic energy at the top is the work given back on unloading to touch
    assert!(
        (work / e_top - 1.0).abs() < 1e-4,
        "∫F dδ = {work} vs elastic {e_top}"
    );
    // at the separation itself the force is −(5/6) π w R
    let mut h = [1.0];
    let (f, ..) = step(&m, &mut h, dc, 0.0);
    assert!((f / (-5.0 / 6.0 * PI * W * R) - 1.0).abs() < 1e-3, "F(δ_c) = {f}");
}

#[test]
fn dmt_pull_off_is_two_pi_w_r_and_the_contact_ends_at_touch() {
    let reg = registry_03();
    let m = reg
        .contact("dmt", &[ParamValue::new("w", W)])
        .unwrap()
        .bind(&materials())
        .unwrap();
    let mut fmin = f64::INFINITY;
    let k = 4.0 / 3.0 * E * R.sqrt();
    for d in cycle(1e-8, 1e-6, 20_000) {
        let (f, reach, p, e, written) = step(&m, &mut [], d, 0.0);
        assert!(written && reach == 0.0 && p == 0.0);
        if d < 0.0 {
            assert_eq!((f, e), (0.0, 0.0));
        } else {
            let want = k * d.powf(1.5) - 2.0 * PI * W * R;
            assert!((f - want).abs() <= 1e-12 * want.abs().max(2.0 * PI * W * R));
            // Hertz's energy and the constant adhesive force's potential: the integral of F
            let stored = 0.4 * k * d.powf(2.5) - 2.0 * PI * W * R * d;
            assert!(
                (e - stored).abs() <= 1e-12 * (0.4 * k * d.powf(2.5)).max(2.0 * PI * W * R * d).max(1e-300)
            );
        }
        fmin = fmin.min(f);
    }
    let want = -2.0 * PI * W * R;
    assert!((fmin / want - 1.0).abs() < 1e-6, "{fmin} vs {want}");
}

#[test]
fn elastic_energy_is_the_integral_of_the_force_and_damped_power_is_force_times_rate() {
    let reg = registry_03();
    let k = 4.0 / 3.0 * E * R.sqrt();
    // undamped Hertz (hsd at ε = 1): no power, elastic (2/5) K δ^{5/2}
    let hsd = reg
        .contact("hsd", &[ParamValue::new("eps", 1.0)])
        .unwrap()
        .bind(&materials())
        .unwrap();
    let (mut work, mut prev) = (0.0, 0.0);
    let n = 10_000;
    for i in 0..=n {
        let d = 1e-6 * i as f64 / n as f64;
        let (f, reach, p, e, written) = step(&hsd, &mut [], d, 0.3);
        assert!(written && reach == 0.0);
        assert_eq!(p, 0.0);
        let want = 0.4 * k * d.powf(2.5);
        assert!((e - want).abs() <= 1e-12 * want.max(1e-300), "{e} vs {want}");
        if i > 0 {
            work += 0.5 * (f + prev) * 1e-6 / n as f64;
            if i == n {
                assert!((work / e - 1.0).abs() < 1e-6, "∫F dδ {work} vs {e}");
            }
        }
        prev = f;
    }
    // damped laws: power = (F(δ, δ̇) − F(δ, 0)) δ̇
    for (name, params) in [
        ("hsd", vec![ParamValue::new("eps", 0.5)]),
        ("lsd", vec![ParamValue::new("eps", 0.5)]),
        ("kuwabara-kono", vec![ParamValue::new("A", 2e-6)]),
        ("jkr", vec![ParamValue::new("w", W), ParamValue::new("eps", 0.5)]),
        ("dmt", vec![ParamValue::new("w", W), ParamValue::new("eps", 0.5)]),
    ] {
        let m = reg.contact(name, &params).unwrap().bind(&materials()).unwrap();
        let slots = m.history_slots();
        for d in [1e-8, 3e-7, 1e-6] {
            for rate in [-0.7, 0.2, 1.5] {
                let (f, _, p, _, written) = step(&m, &mut vec![0.0; slots], d, rate);
                let (f0, ..) = step(&m, &mut vec![0.0; slots], d, 0.0);
                assert!(written, "{name}");
                let want = (f - f0) * rate;
                assert!(
                    p >= 0.0 && (p - want).abs() <= 1e-9 * want.abs(),
                    "{name} {d} {rate}: {p} vs {want}"
                );
            }
        }
    }
}

/// Plastic laws: along a load–unload–reload path, the work done on the contact equals the
/// elastic energy stored plus the energy dissipated (∫ power dt), to the path's resolution.
#[test]
fn plastic_laws_close_their_energy_balance() {
    let reg = registry_03();
    for (name, params) in [
        ("thornton", vec![ParamValue::new("py", 3e6)]),
        ("walton-braun", vec![]),
    ] {
        let m = reg.contact(name, &params).unwrap().bind(&materials()).unwrap();
        let mut h = vec![0.0; m.history_slots()];
        let dt = 1e-6;
        let n = 40_000;
        let (mut work, mut dissipated, mut f_prev, mut d_prev) = (0.0, 0.0, 0.0, 0.0);
        let mut p_prev = 0.0;
        let mut e_last = 0.0;
        let mut peak = 0.0f64;
        for i in 1..=n {
            let s = i as f64 / n as f64;
            // up to 1 µm, down to 0.3 µm, up to 1.5 µm
            let d = if s < 0.4 {
                2.5e-6 * s
            } else if s < 0.6 {
                1e-6 - 3.5e-6 * (s - 0.4)
            } else {
                0.3e-6 + 3e-6 * (s - 0.6)
            };
            let rate = (d - d_prev) / dt;
            let (f, _, p, e, written) = step(&m, &mut h, d, rate);
            assert!(written && p >= 0.0 && e >= 0.0, "{name}");
            work += 0.5 * (f + f_prev) * (d - d_prev);
            dissipated += 0.5 * (p + p_prev) * dt;
            (f_prev, d_prev, p_prev, e_last) = (f, d, p, e);
            peak = peak.max(work);
        }
        assert!(
            dissipated > 0.05 * peak,
            "{name} dissipates: {dissipated} of {peak}"
        );
        let gap = work - e_last - dissipated;
        assert!(
            gap.abs() < 2e-3 * peak,
            "{name}: work {work} = elastic {e_last} + dissipated {dissipated}?"
        );
    }
}

#[test]
fn tangential_energy_is_the_springs_and_the_slip_power() {
    let reg = registry_03();
    let mat = materials();
    let m = reg
        .tangential("mindlin", &[ParamValue::new("mu", 0.3)])
        .unwrap()
        .bind(&mat)
        .unwrap();
    let (d, fnorm, v) = (1e-6, 2e-3, 0.01);
    // ξ, the stiffness of the last call, the dashpot's share of the last force
    let mut h = [0.0; 7];
    let kt = 8.0 * mat.shear * (R * d).sqrt();
    let mut e_prev = 0.0;
    for i in 0..400 {
        let x_prev = h[0];
        let (f, p, e, written) = vector_step(
            |b, e| m.force_batch_with(b, e),
            &mut h,
            (1e-7, [v, 0.0, 0.0], fnorm, d),
        );
        assert!(written);
        let xi2 = h[0] * h[0] + h[1] * h[1] + h[2] * h[2];
        assert!((e - 0.5 * kt * xi2).abs() <= 1e-12 * e.max(1e-300), "step {i}");
        if f[0].abs() < 0.3 * fnorm * (1.0 - 1e-9) {
            // the spring's work over the step, all stored: nothing dissipated but rounding
            assert!(
                p.abs() <= 1e-12 * f[0].abs() * v,
                "undamped spring holding, step {i}: {p}"
            );
        } else {
            // the work of the force averaged over the step (the spring's −k_t ξ before it, the
            // capped force after), less what the spring stored: μ F_n v once it slides steadily
            let expect = -0.5 * (f[0] - kt * x_prev) * v - (e - e_prev) / 1e-7;
            assert!((p - expect).abs() < 1e-12, "sliding power, step {i}");
            if i > 200 {
                assert!(
                    (p - 0.3 * fnorm * v).abs() < 1e-12,
                    "steady sliding power μ F_n v, step {i}"
                );
            }
        }
        e_prev = e;
    }
}

#[test]
fn rolling_sds_is_capped_at_mu_fn_and_stores_k_xi_squared_over_two() {
    let reg = registry_03();
    let (k, gamma, mu, fnorm, v, dt) = (1e3, 0.5, 0.1, 2.0, 0.01, 1e-4);
    let m = reg
        .rolling("rolling-sds", &pv(&[("k", k), ("gamma", gamma), ("mu", mu)]))
        .unwrap()
        .bind(&materials())
        .unwrap();
    // ξ, the dashpot's share of the last force
    let mut h = [0.0; 6];
    let mut capped = false;
    let c = gamma / dt;
    let mut e_prev = 0.0;
    for i in 1..=3000 {
        let (before, fd) = (h[1], h[4]);
        let (f, p, e, written) = vector_step(|b, e| m.batch(b, e), &mut h, (dt, [0.0, v, 0.0], fnorm, 1e-6));
        assert!(written);
        let mag = f[1].abs();
        let xi = h[1];
        let e_before = std::mem::replace(&mut e_prev, e);
        assert!((e - 0.5 * k * xi * xi).abs() <= 1e-12 * e.max(1e-300));
        let trial = k * v * dt * i as f64 + gamma * v;
        if (trial - mu * fnorm).abs() < 1e-9 {
            continue; // at the cap itself, holding and sliding coincide
        }
        if trial <= mu * fnorm && !capped {
            assert!((f[1] + trial).abs() <= 1e-12 * trial, "spring–dashpot, step {i}");
            // the dashpot's γ v² (half of it on the first step: its force rose from 0)
            let want = if i == 1 { 0.5 } else { 1.0 } * gamma * v * v;
            assert!(
                (p - want).abs() < 1e-12 * want,
                "dashpot power, step {i}: {p} vs {want}"
            );
        } else {
            capped = true;
            assert!(
                (mag - mu * fnorm).abs() <= 1e-12 * mu * fnorm,
                "capped at μ F_n, step {i}"
            );
            // the spring ∥ dashpot element carries the capped force: −k ξ − (γ/dt)(ξ − ξ_before)
            // = F, the rest of v dt slips; the spring tends to μ F_n/k, never holding the
            // dashpot's share (LAMMPS's reset (μ F_n − γ v)/k would)
            let want = (c * before + mu * fnorm) / (k + c);
            assert!(
                (xi - want).abs() <= 1e-15 * want,
                "spring, step {i}: {xi} vs {want}"
            );
            // the work of the force before the step (its spring and dashpot shares) and after
            // it over the step, less what the spring stored
            let expect = -0.5 * (-k * before + fd + f[1]) * v - (e - e_before) / dt;
            assert!(
                (p - expect).abs() < 1e-12 * mu * fnorm * v,
                "sliding power, step {i}: {p} vs {expect}"
            );
            assert!(p > 0.0, "step {i}: {p}");
        }
        assert_eq!([f[0], f[2]], [0.0, 0.0]);
    }
    assert!(capped);
    // a steady slide: the spring at μ F_n/k, the power μ F_n v
    assert!((h[1] - mu * fnorm / k).abs() < 1e-12 * mu * fnorm / k);
}

/// A twisting batch of one contact at twisting rate `w` (rad/s), normal force `fnorm` (N),
/// overlap `d` (m) and effective mass `mass` (kg), with the energy outputs `energy`.
fn twist_batch(
    m: &dashpot_sdk::abi::ModelHandle<dashpot_sdk::abi::Twisting>,
    h: &mut [f64],
    (w, fnorm, d, mass): (f64, f64, f64, f64),
    torque: &mut [f64; 1],
    energy: EnergyOut<'_>,
) -> Result<bool, LawError> {
    m.batch(
        TwistingBatch {
            dt: 1e-4,
            normal: &[[0.0, 0.0, 1.0]],
            rate: &[w],
            normal_force: &[fnorm],
            delta: &[d],
            mass: &[mass],
            radius: &[R],
            context: &[],
            slots: h.len(),
            history: h,
            torque,
        },
        energy,
    )
}

/// One contact's twisting step with both energy outputs: (torque, power, elastic).
fn twist(
    m: &dashpot_sdk::abi::ModelHandle<dashpot_sdk::abi::Twisting>,
    h: &mut [f64],
    w: f64,
    fnorm: f64,
    d: f64,
) -> (f64, f64, f64) {
    let (mut t, mut p, mut e) = ([0.0], [0.0], [0.0]);
    let energy = EnergyOut {
        power: Some(&mut p),
        elastic: Some(&mut e),
    };
    assert!(twist_batch(m, h, (w, fnorm, d, M), &mut t, energy).unwrap());
    (t[0], p[0], e[0])
}

#[test]
fn twisting_laws_follow_their_formulas() {
    let reg = registry_03();
    let (k, gamma, mu, fnorm, w, dt) = (2e-3, 1e-6, 5e-5, 3.0, 0.4, 1e-4);
    let sds = reg
        .twisting("twisting-sds", &pv(&[("k", k), ("gamma", gamma), ("mu", mu)]))
        .unwrap()
        .bind(&materials())
        .unwrap();
    // θ, the dashpot's share of the last torque
    let mut h = [0.0; 2];
    let mut capped = false;
    let mut e_prev = 0.0;
    let c = gamma / dt;
    for i in 1..=2000 {
        let (before, md) = (h[0], h[1]);
        let (t, p, e) = twist(&sds, &mut h, w, fnorm, 1e-6);
        let theta = w * dt * i as f64;
        let trial = k * theta + gamma * w;
        if trial <= mu * fnorm && !capped {
            assert!((t + trial).abs() <= 1e-12 * trial && (h[0] - theta).abs() <= 1e-12 * theta);
            // γ ω² (half of it on the first step: the dashpot's torque rose from 0)
            let want = if i == 1 { 0.5 } else { 1.0 } * gamma * w * w;
            assert!((p - want).abs() <= 1e-9 * want, "step {i}: {p} vs {want}");
        } else {
            capped = true;
            // the spring ∥ dashpot element carries the critical torque, the rest slips
            let want = (c * before + mu * fnorm) / (k + c);
            assert!((t + mu * fnorm).abs() <= 1e-15 && (h[0] - want).abs() < 1e-12 * want);
            // the work of the torque before the step (spring and dashpot) and after it, less
            // what the spring stored
            let expect = -0.5 * (-k * before + md + t) * w - (e - e_prev) / dt;
            assert!(
                (p - expect).abs() <= 1e-9 * mu * fnorm * w,
                "step {i}: {p} vs {expect}"
            );
            assert!(p > 0.0, "step {i}: {p}");
        }
        assert!((e - 0.5 * k * h[0] * h[0]).abs() <= 1e-12 * e.max(1e-300));
        e_prev = e;
    }
    assert!(capped);
    // Marshall: k = k_t a²/2, γ = γ_t a²/2, M_c = (2/3) μ_t a |F_n|, a = √(R δ)
    let (kt, gt, mut_, d) = (1e5, 2e-2, 0.4, 1e-6);
    let marshall = reg
        .twisting(
            "twisting-marshall",
            &pv(&[("kt", kt), ("gammat", gt), ("mu_t", mut_)]),
        )
        .unwrap()
        .bind(&materials())
        .unwrap();
    let a = (R * d).sqrt();
    let (kw, gw, mc) = (0.5 * kt * a * a, 0.5 * gt * a * a, 2.0 / 3.0 * mut_ * a * fnorm);
    let mut h = [0.0; 3];
    let (t, _, _) = twist(&marshall, &mut h, w, fnorm, d);
    let want = -kw * w * dt - gw * w;
    assert!(
        want.abs() < mc && (t - want).abs() <= 1e-12 * want.abs(),
        "{t} vs {want}"
    );
    assert_eq!(h[1], kw, "the stiffness of the last call, kept");
    let mut h = [0.0; 3];
    let (t, _, _) = twist(&marshall, &mut h, 1e6, fnorm, d);
    assert!(
        (t + mc).abs() <= 1e-12 * mc,
        "capped at (2/3) μ_t a F_n: {t} vs {mc}"
    );
    let mut h = [0.3, kw, 0.0];
    let (t, p, e) = twist(&marshall, &mut h, w, fnorm, -1e-9);
    assert_eq!((t, h[0], e), (0.0, 0.0, 0.0), "out of contact the twist resets");
    // what the spring stored is dissipated, with its torque's work over half the step
    let dropped = 0.5 * kw * 0.3 * w + 0.5 * kw * 0.3 * 0.3 / dt;
    assert!((p - dropped).abs() <= 1e-12 * dropped, "{p} vs {dropped}");
    // a grown contact keeps the spring's torque (incremental stiffness), a shrunk one its angle
    for (k_before, theta) in [(0.5 * kw, 0.15), (2.0 * kw, 0.3)] {
        let mut h = [0.3, k_before, 0.0];
        twist(&marshall, &mut h, 0.0, fnorm, d);
        assert!((h[0] - theta).abs() <= 1e-12, "{k_before}: θ = {}", h[0]);
    }
}

#[test]
fn rolling_epsd_caps_the_torque_at_mu_r_r_fn() {
    let reg = registry_03();
    let (kt, mu, fnorm, v, dt) = (1e3, 0.2, 1.5, 0.02, 1e-4);
    let m = reg
        .rolling("rolling-epsd", &pv(&[("kt", kt), ("mu_r", mu), ("eta", 0.3)]))
        .unwrap()
        .bind(&materials())
        .unwrap();
    let gamma = 2.0 * 0.3 * (1.4 * M * kt).sqrt();
    // ξ, the dashpot's share of the last force
    let mut h = [0.0; 6];
    let mut capped = false;
    for i in 1..=2000 {
        let (f, ..) = vector_step(|b, e| m.batch(b, e), &mut h, (dt, [v, 0.0, 0.0], fnorm, 1e-6));
        let spring = kt * v * dt * i as f64;
        if spring <= mu * fnorm && !capped {
            assert!((f[0] + spring + gamma * v).abs() <= 1e-12 * (spring + gamma * v));
        } else {
            capped = true;
            // the torque R |F_r| is μ_r R F_n: the force is μ_r F_n, no damping while mobilized
            assert!(
                (f[0] + mu * fnorm).abs() <= 1e-12 * mu * fnorm,
                "step {i}: {:?}",
                f
            );
        }
    }
    assert!(capped);
}

/// The new kinds' inputs are checked in the plugin like the old ones': a bad value is an error
/// naming the law, the array, the contact and the value, before anything is computed.
#[test]
fn bad_inputs_of_the_new_kinds_are_named() {
    let reg = registry_03();
    let rolling = reg
        .rolling("rolling-sds", &[])
        .unwrap()
        .bind(&materials())
        .unwrap();
    let mut h = [0.0; 12];
    let mut f = [[7.0; 3]; 2];
    let e = rolling
        .batch(
            RollingBatch {
                dt: 1e-4,
                normal: &[[0.0, 0.0, 1.0]; 2],
                velocity: &[[0.0; 3], [0.0, f64::NAN, 0.0]],
                normal_force: &[1.0; 2],
                delta: &[1e-6; 2],
                mass: &[M; 2],
                radius: &[R; 2],
                context: &[],
                slots: 6,
                history: &mut h,
                force: &mut f,
            },
            EnergyOut::none(),
        )
        .unwrap_err();
    assert!(
        e.message.contains("rolling law 'rolling-sds': input velocity[1]") && e.message.contains("NaN"),
        "{}",
        e.message
    );
    let twisting = reg
        .twisting("twisting-sds", &[])
        .unwrap()
        .bind(&materials())
        .unwrap();
    let mut h = [0.0; 2];
    let e = twist_batch(
        &twisting,
        &mut h,
        (1.0, 1.0, 1e-6, 0.0),
        &mut [0.0],
        EnergyOut::none(),
    )
    .unwrap_err();
    assert!(
        e.message
            .contains("twisting law 'twisting-sds': input mass[0] = 0 must be finite and > 0 (kg)"),
        "{}",
        e.message
    );
    // energy outputs of the wrong length are refused
    let mut p = [0.0; 2];
    let energy = EnergyOut {
        power: Some(&mut p),
        elastic: None,
    };
    let e = twist_batch(&twisting, &mut h, (1.0, 1.0, 1e-6, M), &mut [0.0], energy).unwrap_err();
    assert!(
        e.message
            .contains("energy outputs must have one value per contact (1)"),
        "{}",
        e.message
    );
    // a law of one kind is not another's
    let e = reg.rolling("twisting-sds", &[]).err().expect("refused");
    assert!(
        e.message
            .contains("is a twisting law, but a rolling law is needed"),
        "{}",
        e.message
    );
}
