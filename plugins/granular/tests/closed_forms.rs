//! The `gran-*` laws against closed forms: the linear oscillator's contact time and restitution
//! (`hooke` with `velocity` and `mass_velocity` damping), the restitution `coeff_restitution`
//! realizes at every speed (`hooke`, `hertz`, `hertz/material`), JKR's and DMT's pull-off
//! forces at LAMMPS's pull-off distance, a sphere launched sliding that ends rolling at 5/7 of
//! its speed, and the energy each law reports against the energy the bodies lose.

use dashpot_core::collide::{collide, Options, PairLaw};
use dashpot_core::laws::compiled;
use dashpot_granular::normal::{DampingModel, NormalModel};
use dashpot_granular::normal_laws::*;
use dashpot_granular::spring::{cross, dot, scale, sub, Ctx, ReadsContext};
use dashpot_granular::tangential_laws::*;
use dashpot_sdk::{
    BoundContact, Contact, ContactLaw, EndCriterion, LawParams, MaterialPair, ParamValue, TangentialContact,
    TangentialLaw,
};
use std::f64::consts::PI;

fn law<L: ContactLaw>(p: &[(&str, f64)]) -> L {
    let v: Vec<ParamValue> = p.iter().map(|(n, x)| ParamValue::new(n, *x)).collect();
    L::from_values(&v).expect("configure")
}

/// E_eff = 1e8/(2(1 − 0.3²)), G_eff = 1e8/(4 (2 − 0.3)(1 + 0.3)): LAMMPS's pair of two
/// E = 1e8 Pa, ν = 0.3 spheres.
fn mat() -> MaterialPair {
    MaterialPair {
        young: 1e8 / (2.0 * (1.0 - 0.09)),
        shear: 1e8 / (4.0 * 1.7 * 1.3),
    }
}

/// The head-on collision of law `L` at speed `v0`, effective mass `m` and radius `r`, ended as δ
/// returns to 0 (LAMMPS's end of a non-adhesive contact).
fn head_on<L: ContactLaw>(l: &L, m: f64, r: f64, v0: f64) -> (f64, f64) {
    let b = compiled(l, &mat()).expect("bind");
    let c = collide(
        &PairLaw::new(b, m, r),
        m,
        v0,
        EndCriterion::Overlap,
        &Options::default(),
    )
    .expect("collide");
    (c.restitution, c.contact_time)
}

#[test]
fn hooke_is_the_damped_linear_oscillator() {
    let (k, m, r) = (1e4, 1e-6, 3e-4);
    for (eta, l) in [
        (
            2e-3,
            head_on(&law::<GranHookeVelocity>(&[("k", k), ("damp", 2e-3)]), m, r, 0.3),
        ),
        (
            m * 1500.0,
            head_on(
                &law::<GranHookeMassVelocity>(&[("k", k), ("damp", 1500.0)]),
                m,
                r,
                0.3,
            ),
        ),
    ] {
        let w0 = (k / m).sqrt();
        let zeta = eta / (2.0 * (k * m).sqrt());
        let wd = w0 * (1.0 - zeta * zeta).sqrt();
        let (e, t) = l;
        assert!(
            (t - PI / wd).abs() < 1e-8 * t,
            "contact time {t} against {}",
            PI / wd
        );
        let e0 = (-zeta * PI / (1.0 - zeta * zeta).sqrt()).exp();
        assert!((e - e0).abs() < 1e-8, "restitution {e} against {e0}");
    }
}

#[test]
fn coeff_restitution_realizes_its_restitution_at_every_speed() {
    let (m, r) = (1e-6, 3e-4);
    for e in [0.3, 0.7, 0.95] {
        for v0 in [0.01, 0.3, 3.0] {
            let got = [
                head_on(
                    &law::<GranHookeCoeffRestitution>(&[("k", 1e4), ("damp", e)]),
                    m,
                    r,
                    v0,
                )
                .0,
                head_on(
                    &law::<GranHertzCoeffRestitution>(&[("k", 1e8), ("damp", e)]),
                    m,
                    r,
                    v0,
                )
                .0,
                head_on(
                    &law::<GranHertzMaterialCoeffRestitution>(&[("damp", e)]),
                    m,
                    r,
                    v0,
                )
                .0,
            ];
            for g in got {
                assert!((g - e).abs() < 1e-7, "e = {e}, v0 = {v0}: {g}");
            }
        }
    }
}

/// A normal law's force at overlap `delta` at rest, for a contact that acts there.
fn formed_force<M: NormalModel, D: DampingModel>(b: &GranNormalBound<M, D>, delta: f64, r: f64) -> f64 {
    b.eval(&Contact {
        delta,
        rate: 0.0,
        mass: 1e-6,
        radius: r,
    })
    .force
}

#[test]
fn jkr_pulls_off_at_three_halves_pi_w_r_at_lammps_pulloff_distance() {
    let (gamma, r) = (0.05, 2.7e-4);
    let b = law::<GranJkrVelocity>(&[("damp", 0.0), ("cohesion", gamma)])
        .bind(&mat())
        .unwrap();
    let po = b.model.pulloff_distance(r);
    let w = 2.0 * gamma;
    let f_po = formed_force(&b, -po, r);
    assert!((f_po + 1.5 * PI * w * r).abs() < 1e-10 * f_po.abs(), "{f_po}");
    // the largest tension: F ≥ F(−δ_po) on the whole branch, F(0+) repulsive beyond it
    for i in 0..=400 {
        let d = -po + i as f64 * 2.0 * po / 400.0;
        assert!(formed_force(&b, d, r) >= f_po * (1.0 + 1e-12), "{d}");
    }
    // the contact acts down to the pull-off distance, and reaches it
    let c = Contact {
        delta: -0.999 * po,
        rate: 0.0,
        mass: 1e-6,
        radius: r,
    };
    assert_eq!(b.reach(&c, &[1.0]), po);
    let mut h = [1.0];
    assert!(b.force(c, &mut h) < 0.0 && h[0] == 1.0);
    assert_eq!(
        b.force(
            Contact {
                delta: -1.001 * po,
                ..c
            },
            &mut h
        ),
        0.0
    );
    assert_eq!(h[0], 0.0, "broken");
    assert_eq!(
        b.force(
            Contact {
                delta: -0.5 * po,
                ..c
            },
            &mut h
        ),
        0.0,
        "no force before touching again"
    );
    // DMT: the elastic Hertz force less 4π γ R = 2π w R, from touch
    let d = law::<GranDmtVelocity>(&[("damp", 0.0), ("cohesion", gamma)])
        .bind(&mat())
        .unwrap();
    assert!((formed_force(&d, 1e-300, r) + 2.0 * PI * w * r).abs() < 1e-12);
}

/// A sphere (mass m, radius R) resting on the wall z = 0 under gravity g, launched sliding at
/// v0 along x without spin, integrated by velocity Verlet with the normal law `n` and the
/// tangential law `t` composed as LAMMPS composes them (`fix wall/gran`'s geometry): returns
/// v_x and R ω_y after `steps` steps of `dt`.
fn slide_to_roll<T: ReadsContext<TangentialContact, Out = [f64; 3]>>(
    n: &impl Fn(Contact, &mut [f64]) -> (f64, Ctx),
    t: &T,
    slots: usize,
) -> (f64, f64) {
    let (r, m, g, v0, dt) = (5e-4, 1.3e-6, 9.81, 0.01, 1e-6);
    let inertia = 0.4 * m * r * r;
    // rest: F(δ) = m g
    let (mut lo, mut hi) = (0.0, 1e-5);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        let f = n(
            Contact {
                delta: mid,
                rate: 0.0,
                mass: m,
                radius: r,
            },
            &mut [],
        )
        .0;
        if f < m * g {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let (mut x, mut v, mut w) = ([0.0, 0.0, r - lo], [v0, 0.0, 0.0], [0.0; 3]);
    let (mut f, mut tq) = ([0.0, 0.0, -m * g], [0.0; 3]);
    let mut h = vec![0.0; slots];
    for _ in 0..20_000 {
        for k in 0..3 {
            v[k] += 0.5 * dt * f[k] / m;
            x[k] += dt * v[k];
            w[k] += 0.5 * dt * tq[k] / inertia;
        }
        let nrm = [0.0, 0.0, 1.0];
        let delta = r - x[2];
        let c = Contact {
            delta,
            rate: -v[2],
            mass: m,
            radius: r,
        };
        let (fn_, ctx) = n(c, &mut []);
        let vt = [v[0], v[1], 0.0];
        let vtr = sub(vt, cross(scale(r, w), nrm));
        let tc = TangentialContact {
            context: ctx,
            normal: nrm,
            velocity: vtr,
            normal_force: fn_,
            delta,
            mass: m,
            radius: r,
            dt,
        };
        let (fs, _) = t.eval(&ctx, &tc, &mut h);
        f = [fs[0], fs[1], fn_ - m * g];
        tq = scale(-r, cross(nrm, fs));
        for k in 0..3 {
            v[k] += 0.5 * dt * f[k] / m;
            w[k] += 0.5 * dt * tq[k] / inertia;
        }
    }
    (v[0] / v0, r * w[1] / v0)
}

#[test]
fn a_sphere_launched_sliding_ends_rolling_at_five_sevenths() {
    let wall = MaterialPair {
        young: 1e8 / (2.0 * 0.91),
        shear: 1e8 / (4.0 * 1.7 * 1.3),
    };
    let b = law::<GranHertzMaterialViscoelastic>(&[("damp", 3e7)])
        .bind(&wall)
        .unwrap();
    let normal = |c: Contact, h: &mut [f64]| {
        let f = b.force(c, h);
        (f, b.context(&c, h, f))
    };
    let p = |kt: Option<f64>| -> Vec<ParamValue> {
        let mut v = vec![ParamValue::new("xt", 1.0), ParamValue::new("mu", 0.3)];
        v.extend(kt.map(|k| ParamValue::new("kt", k)));
        v
    };
    let rolls = |name: &str, (v, rw): (f64, f64)| {
        eprintln!("{name}: v/v0 = {v}, R ω/v0 = {rw}");
        assert!((v - 5.0 / 7.0).abs() < 2e-3, "{name}: v/v0 = {v}");
        assert!(
            (rw - v).abs() < 2e-3,
            "{name}: rolling without slip, R ω/v0 = {rw}"
        );
    };
    rolls("gran-mindlin", roll_with::<GranMindlin>(&normal, &p(None), &wall));
    rolls(
        "gran-linear-history",
        roll_with::<GranLinearHistory>(&normal, &p(Some(500.0)), &wall),
    );
    rolls(
        "gran-mindlin-rescale-force",
        roll_with::<GranMindlinRescaleForce>(&normal, &p(None), &wall),
    );
    rolls(
        "gran-linear-history-classic",
        roll_with::<GranLinearHistoryClassic>(&normal, &p(Some(500.0)), &wall),
    );
}

/// [`slide_to_roll`] with the tangential law `T` of `params`, bound to `m`.
fn roll_with<T>(
    n: &impl Fn(Contact, &mut [f64]) -> (f64, Ctx),
    params: &[ParamValue],
    m: &MaterialPair,
) -> (f64, f64)
where
    T: TangentialLaw,
    T::Bound: ReadsContext<TangentialContact, Out = [f64; 3]>,
{
    let t = T::from_values(params).unwrap().bind(m).unwrap();
    slide_to_roll(n, &t, T::HISTORY.len())
}

/// The energy a normal law reports over a collision integrated by velocity Verlet: the
/// dissipated work ∫ power dt and the elastic energy held at the end of contact (JKR's
/// hysteresis, none for the others) are the kinetic energy lost.
fn energy_balance<L: ContactLaw>(l: &L, v0: f64)
where
    L::Bound: BoundContact,
{
    let b = l.bind(&mat()).unwrap();
    let (m, r, dt) = (1e-6, 3e-4, 2e-9);
    let mut h = vec![0.0; L::HISTORY.len()];
    let (mut d, mut u, mut f) = (0.0, v0, 0.0);
    let (mut dissipated, mut touched) = (0.0, false);
    let mut last = None;
    for _ in 0..2_000_000 {
        u -= 0.5 * dt * f / m;
        d += dt * u;
        let c = Contact {
            delta: d,
            rate: u,
            mass: m,
            radius: r,
        };
        let (fnew, e) = b.force_energy(c, &mut h);
        let e = e.expect("energy");
        if fnew != 0.0 || e.elastic != 0.0 {
            touched = true;
            dissipated += e.power * dt;
            last = Some(e.elastic);
        } else if touched {
            break;
        }
        f = fnew;
        u -= 0.5 * dt * f / m;
    }
    let lost = 0.5 * m * (v0 * v0 - u * u);
    // elastic energy is measured from touch: every contact starts with none; a JKR contact,
    // acting past touching, ends at the pull-off distance holding its cycle's adhesion
    // hysteresis (> 0, which a host books as dissipated as the contact ends), every other with
    // none
    let held = last.expect("the contact acted");
    if L::NAME.contains("jkr") {
        assert!(
            held > 1e-3 * lost,
            "{}: held at pull-off {held}, lost {lost}",
            L::NAME
        );
    } else {
        assert!(
            held.abs() < 1e-3 * lost.max(1e-30) + 1e-18,
            "{}: elastic at the end {held}",
            L::NAME
        );
    }
    assert!(
        (dissipated + held - lost).abs() < 2e-3 * 0.5 * m * v0 * v0,
        "{}: dissipated {dissipated}, held {held}, lost {lost}",
        L::NAME
    );
}

#[test]
fn normal_laws_account_the_energy_the_bodies_lose() {
    energy_balance(&law::<GranHookeVelocity>(&[("k", 1e4), ("damp", 2e-3)]), 0.3);
    energy_balance(&law::<GranHertzTsuji>(&[("k", 1e8), ("damp", 0.5)]), 0.3);
    energy_balance(
        &law::<GranHertzMaterialViscoelastic>(&[("damp", 3e7), ("limit_damping", 1.0)]),
        0.3,
    );
    energy_balance(
        &law::<GranDmtViscoelastic>(&[("damp", 3e7), ("cohesion", 0.05)]),
        0.3,
    );
    energy_balance(
        &law::<GranJkrMassVelocity>(&[("damp", 100.0), ("cohesion", 0.05)]),
        0.3,
    );
}

#[test]
fn a_stuck_linear_spring_dissipates_nothing_and_mindlin_reports_the_energy_its_growing_stiffness_adds() {
    let (n, dt) = ([0.0, 0.0, 1.0], 1e-7);
    let ctx = |delta: f64| Ctx {
        contact_radius: (3e-4 * delta).sqrt(),
        cap_force: 1.0,
        damping: 0.0,
    };
    let tc = |delta: f64, vx: f64| TangentialContact {
        context: ctx(delta),
        normal: n,
        velocity: [vx, 0.0, 0.0],
        normal_force: 1.0,
        delta,
        mass: 1e-6,
        radius: 3e-4,
        dt,
    };
    let p = [
        ParamValue::new("kt", 3e3),
        ParamValue::new("xt", 0.0),
        ParamValue::new("mu", 1.0),
    ];
    let lin = GranLinearHistory::from_values(&p).unwrap().bind(&mat()).unwrap();
    let min = GranMindlin::from_values(&p[1..]).unwrap().bind(&mat()).unwrap();
    let (mut hl, mut hm) = ([0.0; 3], [0.0; 4]);
    let (mut work_l, mut work_m, mut neg) = (0.0, 0.0, 0);
    // load the spring and the overlap, then unload both back
    for i in 0..2000 {
        let vx = if i < 1000 { 1e-3 } else { -1e-3 };
        let delta = 1e-6 * (1.0 + (i.min(2000 - i) as f64) / 1000.0);
        let (_, s) = lin.eval(&ctx(delta), &tc(delta, vx), &mut hl);
        work_l += s.energy(dt).power * dt;
        let (_, s) = min.eval(&ctx(delta), &tc(delta, vx), &mut hm);
        let e = s.energy(dt);
        neg += usize::from(e.power < 0.0);
        work_m += e.power * dt;
        assert!(!s.slid);
    }
    assert!(work_l.abs() < 1e-16, "{work_l}");
    assert!(dot(hl, hl).sqrt() < 1e-12, "back to rest");
    // LAMMPS's incremental Mindlin spring stores energy as a grows on loading (negative
    // power) and loses it as a shrinks: the law reports both
    assert!(neg > 900, "{neg} steps of negative power");
    assert!(work_m.abs() > 0.0);
}

/// Calibrates law `L` to restitution `e` (and contact time `tau`) with the values `fixed`, then
/// collides it: the realized restitution and contact time.
fn calibrated<L: ContactLaw>(e: f64, tau: Option<f64>, fixed: &[(&str, f64)], m: f64, r: f64) -> (f64, f64) {
    let target = dashpot_sdk::CalibrationTarget {
        restitution: e,
        contact_time: tau,
        impact_speed: None,
        end: EndCriterion::Overlap,
    };
    let pair = dashpot_sdk::Pair::new(m, r, mat().young).unwrap();
    let fixed: Vec<ParamValue> = fixed.iter().map(|(n, x)| ParamValue::new(n, *x)).collect();
    let p = dashpot_sdk::Params::resolve(L::NAME, &L::schema(), &fixed).unwrap();
    let mut found = L::calibrate(&target, &pair, &p).unwrap().expect("a closed form");
    found.extend(fixed);
    head_on(&L::from_values(&found).unwrap(), m, r, 0.4)
}

#[test]
fn hookean_laws_calibrate_to_a_restitution_and_a_contact_time_in_closed_form() {
    let (m, r, e, tau) = (1e-6, 3e-4, 0.55, 4e-5);
    for (got_e, got_t) in [
        calibrated::<GranHookeVelocity>(e, Some(tau), &[], m, r),
        calibrated::<GranHookeMassVelocity>(e, Some(tau), &[], m, r),
        calibrated::<GranHookeCoeffRestitution>(e, Some(tau), &[], m, r),
    ] {
        assert!(
            (got_e - e).abs() < 1e-8 && (got_t - tau).abs() < 1e-8 * tau,
            "{got_e} {got_t}"
        );
    }
    // a given stiffness: the restitution alone
    let (got_e, _) = calibrated::<GranHookeVelocity>(e, None, &[("k", 2e4)], m, r);
    assert!((got_e - e).abs() < 1e-8, "{got_e}");
    let (got_e, _) = calibrated::<GranHertzMaterialCoeffRestitution>(e, None, &[], m, r);
    assert!((got_e - e).abs() < 1e-7, "{got_e}");
    // no closed form for a Hertzian contact with velocity damping
    let pair = dashpot_sdk::Pair::new(m, r, mat().young).unwrap();
    let p = dashpot_sdk::Params::resolve("x", &GranHertzVelocity::schema(), &[ParamValue::new("k", 1e8)])
        .unwrap();
    let t = dashpot_sdk::CalibrationTarget {
        restitution: e,
        contact_time: None,
        impact_speed: None,
        end: EndCriterion::Overlap,
    };
    assert!(GranHertzVelocity::calibrate(&t, &pair, &p).unwrap().is_none());
}
