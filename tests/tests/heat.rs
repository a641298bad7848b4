//! Heat conduction (sdk 0.4) through the real plugin libraries, against closed forms: two
//! spheres in static contact relax as ΔT_n = ΔT_0 (1 − dt/τ)^n under explicit Euler (LAMMPS's
//! `fix heat/flow`), τ = 1/(H (1/C₁ + 1/C₂)); Q_ij = −Q_ji exactly; Σ C T conserved to rounding;
//! a sphere on an isothermal wall relaxes with τ = C/H_w, and under a sinusoidal wall its
//! amplitude is A/√(1 + ω²τ²), its lag atan(ωτ); a chain of N spheres decays by its modes
//! λ_k = (4H/C) sin²(kπ/2N); with Hertzian contacts H ∝ F^(1/3) (`heat-radius`) and F^(2/3)
//! (`heat-area`); JKR's contact conducts past touching; bad input is an error naming it.

use dashpot::laws::{EnergyOut, Heat, HeatConduction, ModelHandle};
use dashpot::Registry;
use dashpot_sdk::{
    ErrorKind, HeatBatch, HeatFlow, LawKind, MaterialPair, NormalBatch, NormalContext, ParamValue,
};
use dashpot_tests::registry_04;
use std::f64::consts::PI;

fn materials() -> MaterialPair {
    MaterialPair::new(7.0e10, 2.7e10).unwrap()
}

/// Heat law `name` with parameter `p` = `v`, bound to [`materials`].
fn law(reg: &Registry, name: &str, p: &str, v: f64) -> ModelHandle<Heat> {
    reg.heat(name, &[ParamValue::new(p, v)])
        .unwrap()
        .bind(&materials())
        .unwrap()
}

/// The flows of `law` on contacts of temperatures `t` (`[T_i, T_j]`, K), overlaps `delta` (m)
/// and effective radii `radius` (m), with the normal law's `context` (empty: the defaults).
fn eval(
    law: &impl HeatConduction,
    t: &[[f64; 2]],
    delta: &[f64],
    radius: &[f64],
    context: &[NormalContext],
) -> Vec<HeatFlow> {
    let n = t.len();
    let fnorm = vec![0.0; n];
    let mut flow = vec![HeatFlow::default(); n];
    law.heat_batch(HeatBatch {
        dt: 1e-5,
        temperature: t,
        normal_force: &fnorm,
        delta,
        radius,
        context,
        slots: 0,
        history: &mut [],
        flow: &mut flow,
    })
    .unwrap();
    flow
}

/// Heat capacity C = m c (J/K) of a sphere of radius `r` (m): steel, 7800 kg/m³, 500 J/(kg·K).
fn capacity(r: f64) -> f64 {
    7800.0 * 4.0 / 3.0 * PI * r.powi(3) * 500.0
}

#[test]
fn the_heat_laws_are_listed_with_their_units_and_read_the_context() {
    let reg = registry_04();
    for (name, p, unit) in [
        ("heat-radius", "k", "W/(m·K)"),
        ("heat-area", "h", "W/(m²·K)"),
        ("heat-radius-corrected", "k", "W/(m·K)"),
    ] {
        let info = &reg.find(name).unwrap().0.info;
        assert_eq!(info.kind, LawKind::Heat, "{name}");
        assert!(info.reads_context, "{name}");
        assert!(info.history.is_empty(), "{name}");
        let spec = info.params.iter().find(|s| s.name == p).unwrap();
        assert_eq!(spec.unit, unit, "{name}");
        // no default magnitude: the law refuses to run without it, naming it
        let e = reg
            .heat(name, &[])
            .err()
            .expect("refused without its coefficient");
        assert!(e.to_string().contains(&format!("{p} (W/")), "{name}: {e}");
    }
    assert_eq!(
        reg.names_of(LawKind::Heat),
        "heat-radius, heat-area, heat-radius-corrected"
    );
    // a heat law is not a contact law, and the other way round
    let e = reg
        .contact("heat-area", &[ParamValue::new("h", 1.0)])
        .err()
        .unwrap();
    assert!(e.to_string().contains("is a heat law"), "{e}");
    let e = reg.heat("hsd", &[]).err().unwrap();
    assert!(e.to_string().contains("heat laws loaded: heat-radius"), "{e}");
}

#[test]
fn conductances_are_lammps_radius_and_area_models() {
    let reg = registry_04();
    let (k, h) = (2.5, 3.0e4);
    let radius = [6e-4, 1e-3, 2e-3, 5e-4];
    let delta = [1e-6, 3e-7, 0.0, -1e-7];
    let t = [[300.0, 350.0], [400.0, 310.0], [300.0, 301.0], [300.0, 500.0]];
    let rad = eval(&law(&reg, "heat-radius", "k", k), &t, &delta, &radius, &[]);
    let area = eval(&law(&reg, "heat-area", "h", h), &t, &delta, &radius, &[]);
    for i in 0..4 {
        // the default context: a = √(R max(δ, 0)), as LAMMPS's hooke, hertz and dmt
        let a = (radius[i] * delta[i].max(0.0)).sqrt();
        let dt = t[i][1] - t[i][0];
        assert_eq!(rad[i].conductance, 2.0 * k * a, "contact {i}");
        assert_eq!(rad[i].heat, 2.0 * k * a * dt, "contact {i}");
        assert_eq!(area[i].conductance, h * PI * a * a, "contact {i}");
        assert_eq!(area[i].heat, h * PI * a * a * dt, "contact {i}");
    }
    // apart: no conduction
    assert_eq!((rad[3].heat, area[3].heat), (0.0, 0.0));
    // the normal law's own contact radius when it reports one
    let x = [NormalContext {
        contact_radius: 1e-4,
        cap_force: 1.0,
        damping: 0.0,
    }];
    let f = eval(
        &law(&reg, "heat-radius", "k", k),
        &t[..1],
        &delta[..1],
        &radius[..1],
        &x,
    );
    assert_eq!(f[0].conductance, 2.0 * k * 1e-4);
}

#[test]
fn two_spheres_relax_as_the_discrete_closed_form_and_conserve_heat() {
    let reg = registry_04();
    let (r1, r2) = (1e-3, 1.5e-3);
    let (c1, c2) = (capacity(r1), capacity(r2));
    let reff = r1 * r2 / (r1 + r2);
    let delta = 1e-6;
    for heat in [
        law(&reg, "heat-radius", "k", 40.0),
        law(&reg, "heat-area", "h", 1e6),
    ] {
        let (mut t1, mut t2) = (300.0, 350.0);
        let h = eval(&heat, &[[t1, t2]], &[delta], &[reff], &[])[0].conductance;
        let tau = 1.0 / (h * (1.0 / c1 + 1.0 / c2));
        let dt = tau / 50.0;
        let (dt0, ct0) = (t2 - t1, c1 * t1 + c2 * t2);
        for n in 1..=200 {
            // both orders in one batch: Q_ij = −Q_ji exactly
            let f = eval(&heat, &[[t1, t2], [t2, t1]], &[delta; 2], &[reff; 2], &[]);
            assert_eq!(
                f[1].heat.to_bits(),
                (-f[0].heat).to_bits(),
                "{} step {n}",
                heat.name()
            );
            assert_eq!(f[1].conductance.to_bits(), f[0].conductance.to_bits());
            // LAMMPS's fix heat/flow: T += dt Q / C, explicit Euler
            t1 += dt * f[0].heat / c1;
            t2 -= dt * f[0].heat / c2;
            let want = dt0 * (1.0 - dt / tau).powi(n);
            assert!(
                ((t2 - t1) - want).abs() <= 1e-12 * dt0,
                "{} step {n}: ΔT = {} vs {want}",
                heat.name(),
                t2 - t1
            );
            let ct = c1 * t1 + c2 * t2;
            assert!(
                (ct - ct0).abs() <= 1e-14 * ct0,
                "{} step {n}: Σ C T {ct} vs {ct0}",
                heat.name()
            );
        }
        // it has relaxed to e^-4 of the start, towards (C₁T₁ + C₂T₂)/(C₁ + C₂)
        assert!((t2 - t1) < 0.02 * dt0);
        assert!((t1 - ct0 / (c1 + c2)).abs() < 0.02 * dt0);
    }
}

#[test]
fn a_sphere_on_an_isothermal_wall_relaxes_with_tau_c_over_h() {
    let reg = registry_04();
    let r = 1e-3;
    let c = capacity(r);
    // against a flat wall R_eff = R; the wall's temperature is the partner's
    let (delta, tw) = (2e-6, 280.0);
    let heat = law(&reg, "heat-area", "h", 5e5);
    let hw = eval(&heat, &[[0.0, 1.0]], &[delta], &[r], &[])[0].conductance;
    let tau = c / hw;
    let dt = tau / 40.0;
    let (t0, mut t, mut wall) = (350.0, 350.0, 0.0);
    for n in 1..=300 {
        let q = eval(&heat, &[[t, tw]], &[delta], &[r], &[])[0].heat;
        t += dt * q / c;
        wall -= dt * q;
        let want = tw + (t0 - tw) * (1.0 - dt / tau).powi(n);
        assert!((t - want).abs() <= 1e-12 * (t0 - tw), "step {n}: {t} vs {want}");
        // the heat the wall gave is what the sphere gained
        assert!((c * (t - t0) + wall).abs() <= 1e-12 * c * (t0 - tw));
    }
}

#[test]
fn under_a_sinusoidal_wall_the_amplitude_is_a_over_sqrt_1_plus_omega_tau_squared() {
    let reg = registry_04();
    let r = 1e-3;
    let c = capacity(r);
    let delta = 2e-6;
    let heat = law(&reg, "heat-radius", "k", 50.0);
    let hw = eval(&heat, &[[0.0, 1.0]], &[delta], &[r], &[])[0].conductance;
    let tau = c / hw;
    for omega_tau in [0.5, 2.0] {
        let (amp, omega) = (10.0, omega_tau / tau);
        let period = 2.0 * PI / omega;
        let steps_per_period = 20_000;
        let dt = period / steps_per_period as f64;
        let mut t = 0.0;
        // 12 periods: the transient e^(−t/τ) is gone (t > 18 τ), then fit the last two
        let (mut s, mut co) = (0.0, 0.0);
        for n in 0..12 * steps_per_period {
            let time = n as f64 * dt;
            if n >= 10 * steps_per_period {
                s += t * (omega * time).sin();
                co += t * (omega * time).cos();
            }
            let tw = amp * (omega * time).sin();
            t += dt * eval(&heat, &[[t, tw]], &[delta], &[r], &[])[0].heat / c;
        }
        let (b, cc) = (s / steps_per_period as f64, co / steps_per_period as f64);
        let got = (b * b + cc * cc).sqrt();
        let want = amp / (1.0 + omega_tau * omega_tau).sqrt();
        assert!(
            (got / want - 1.0).abs() < 2e-3,
            "ωτ = {omega_tau}: amplitude {got} vs {want}"
        );
        let lag = (-cc).atan2(b);
        assert!(
            (lag - omega_tau.atan()).abs() < 2e-3,
            "ωτ = {omega_tau}: lag {lag} vs {}",
            omega_tau.atan()
        );
    }
}

#[test]
fn a_chain_of_spheres_decays_by_its_modes() {
    let reg = registry_04();
    let n = 7;
    let r = 1e-3;
    let c = capacity(r);
    let delta = 1e-6;
    let heat = law(&reg, "heat-radius", "k", 30.0);
    // identical spheres: R_eff = R/2 for every contact, the same H
    let h = eval(&heat, &[[0.0, 1.0]], &[delta], &[r / 2.0], &[])[0].conductance;
    let dt = 0.2 * c / h;
    for k in 1..n {
        let mode = |j: usize| (k as f64 * PI * (j as f64 + 0.5) / n as f64).cos();
        let lambda = 4.0 * h / c * (k as f64 * PI / (2 * n) as f64).sin().powi(2);
        let mut t: Vec<f64> = (0..n).map(|j| 300.0 + mode(j)).collect();
        for step in 1..=100 {
            let pairs: Vec<[f64; 2]> = (0..n - 1).map(|j| [t[j], t[j + 1]]).collect();
            let f = eval(&heat, &pairs, &vec![delta; n - 1], &vec![r / 2.0; n - 1], &[]);
            for (j, q) in f.iter().enumerate() {
                t[j] += dt * q.heat / c;
                t[j + 1] -= dt * q.heat / c;
            }
            let g = (1.0 - dt * lambda).powi(step);
            for (j, tj) in t.iter().enumerate() {
                assert!(
                    (tj - 300.0 - g * mode(j)).abs() < 1e-12,
                    "mode {k} step {step} sphere {j}"
                );
            }
        }
    }
}

#[test]
fn with_hertzian_contacts_h_scales_as_f_one_third_or_two_thirds() {
    let reg = registry_04();
    let m = materials();
    let hertz = reg.contact("hsd", &[]).unwrap().bind(&m).unwrap();
    let r = 1e-3;
    // δ ×4 gives F ×8 in Hertz's F ∝ δ^(3/2)
    let delta = [1e-6, 4e-6];
    let (mut f, mut x) = ([0.0; 2], [NormalContext::default(); 2]);
    let b = NormalBatch {
        delta: &delta,
        rate: &[0.0; 2],
        mass: &[1e-4; 2],
        radius: &[r; 2],
        slots: 0,
        history: &mut [],
        force: &mut f,
    };
    hertz
        .force_batch_context(b, None, &mut x, EnergyOut::none())
        .unwrap();
    assert!((f[1] / f[0] - 8.0).abs() < 1e-12, "F ratio {}", f[1] / f[0]);
    let t = [[300.0, 310.0]; 2];
    for (name, p, ratio) in [("heat-radius", "k", 2.0), ("heat-area", "h", 4.0)] {
        let q = eval(&law(&reg, name, p, 7.0), &t, &delta, &[r; 2], &x);
        let got = q[1].conductance / q[0].conductance;
        assert!(
            (got - ratio).abs() < 1e-12,
            "{name}: H(8F)/H(F) = {got}, want {ratio}"
        );
    }
}

#[test]
fn jkr_contacts_conduct_past_touching_until_rupture() {
    let reg = registry_04();
    let m = materials();
    // strong adhesion: a pull-off distance of ~1e-7 m
    let jkr = reg
        .contact("jkr", &[ParamValue::new("w", 10.0)])
        .unwrap()
        .bind(&m)
        .unwrap();
    let heat = law(&reg, "heat-radius", "k", 10.0);
    let r = 1e-3;
    let mut history = vec![0.0; jkr.history_slots()];
    // load, then pull apart in small steps until JKR lets go
    let mut path: Vec<f64> = (0..=10).map(|i| 1e-7 * i as f64).collect();
    path.extend((0..600).map(|i| 1e-7 - 1e-9 * i as f64));
    let (mut conducted_apart, mut ruptured) = (false, false);
    for d in path {
        let (mut f, mut x) = ([0.0], [NormalContext::default()]);
        let b = NormalBatch {
            delta: &[d],
            rate: &[0.0],
            mass: &[1e-4],
            radius: &[r],
            slots: history.len(),
            history: &mut history,
            force: &mut f,
        };
        jkr.force_batch_context(b, None, &mut x, EnergyOut::none())
            .unwrap();
        let q = eval(&heat, &[[300.0, 310.0]], &[d], &[r], &x)[0];
        assert_eq!(q.conductance, 20.0 * x[0].contact_radius);
        if d < 0.0 && !ruptured {
            if q.heat > 0.0 {
                conducted_apart = true;
            } else {
                ruptured = true;
            }
        } else if ruptured {
            assert_eq!(q.heat, 0.0, "no conduction after rupture (δ = {d:e})");
        }
    }
    assert!(
        conducted_apart && ruptured,
        "apart {conducted_apart}, ruptured {ruptured}"
    );
}

#[test]
fn the_corrected_law_is_heat_radius_with_the_real_contact_radius() {
    let reg = registry_04();
    let m = materials();
    let (k, t, delta, r) = (3.0, [[300.0, 320.0]], [1e-6], [1e-3]);
    let plain = eval(&law(&reg, "heat-radius", "k", k), &t, &delta, &r, &[])[0];
    let corrected = |young_real: f64, x: Option<f64>| {
        let mut p = vec![ParamValue::new("k", k), ParamValue::new("young_real", young_real)];
        p.extend(x.map(|x| ParamValue::new("exponent", x)));
        let l = reg.heat("heat-radius-corrected", &p).unwrap().bind(&m).unwrap();
        eval(&l, &t, &delta, &r, &[])[0]
    };
    // real = simulated modulus: heat-radius to the bit
    assert_eq!(corrected(m.young, None), plain);
    // 8× stiffer real particles: a real contact radius half as large at equal force
    let c = corrected(8.0 * m.young, None);
    assert!((c.conductance / plain.conductance - 0.5).abs() < 1e-14);
    // equal impact speed: the exponent 1/5
    let c = corrected(32.0 * m.young, Some(0.2));
    assert!((c.conductance / plain.conductance - 0.5).abs() < 1e-14);
}

#[test]
fn bad_input_is_an_error_naming_the_contact() {
    let reg = registry_04();
    let heat = law(&reg, "heat-area", "h", 1.0);
    let n = 70;
    let mut t = vec![[300.0, 310.0]; n];
    t[66][1] = f64::NAN;
    let (fnorm, delta, radius) = (vec![1.0; n], vec![1e-6; n], vec![1e-3; n]);
    let mut flow = vec![HeatFlow::default(); n];
    let call = |t: &[[f64; 2]], radius: &[f64], x: &[NormalContext], flow: &mut [HeatFlow]| {
        heat.heat_batch(HeatBatch {
            dt: 1e-6,
            temperature: t,
            normal_force: &fnorm,
            delta: &delta,
            radius,
            context: x,
            slots: 0,
            history: &mut [],
            flow,
        })
    };
    let e = call(&t, &radius, &[], &mut flow).unwrap_err();
    assert_eq!(e.kind, ErrorKind::NonFinite);
    assert!(e.to_string().contains("temperature[66]"), "{e}");
    t[66][1] = 310.0;
    let mut bad_r = radius.clone();
    bad_r[3] = 0.0;
    let e = call(&t, &bad_r, &[], &mut flow).unwrap_err();
    assert!(e.to_string().contains("radius[3] = 0"), "{e}");
    let mut x = vec![NormalContext::default(); n];
    x[5].contact_radius = -1.0;
    let e = call(&t, &radius, &x, &mut flow).unwrap_err();
    assert!(e.to_string().contains("context[5]"), "{e}");
    let e = call(&t[..3], &radius, &[], &mut flow).unwrap_err();
    assert!(e.to_string().contains("disagree in length"), "{e}");
    call(&t, &radius, &[], &mut flow).unwrap();
    assert!(flow.iter().all(|f| f.heat > 0.0));
}
