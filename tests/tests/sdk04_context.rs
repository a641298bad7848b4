//! The normal context of sdk 0.4 through the real plugin libraries: what a normal law reports
//! per contact (contact radius, cap force, normal damping) reaches the tangential, rolling and
//! twisting laws that read it, bit for bit, through the host's handles and the DEM engine's
//! contact sets; laws that report none give the default; JKR reports its own contact radius,
//! against its closed form, positive past touching until rupture; bad contexts are errors that
//! name the contact.

use dashpot::dem::contacts::{ContactSet, Rotating};
use dashpot::laws::{EnergyOut, NormalLaw, RollingResistance, TwistingResistance};
use dashpot::Registry;
use dashpot_sdk::{
    Contact, ErrorKind, MaterialPair, NormalBatch, NormalContext, ParamValue, RollingBatch, TangentialBatch,
    TwistingBatch,
};
use dashpot_tests::{assert_same_bits, registry_with_context_fixture};
use std::f64::consts::PI;

fn materials() -> MaterialPair {
    MaterialPair::new(7.0e10, 2.7e10).unwrap()
}

/// `n` contacts of assorted geometry (more than a block of the sdk's checks), some apart.
struct Contacts {
    delta: Vec<f64>,
    rate: Vec<f64>,
    mass: Vec<f64>,
    radius: Vec<f64>,
    normal: Vec<[f64; 3]>,
}

fn contacts(n: usize) -> Contacts {
    let t = |i: usize| (i as f64 * 0.618_033_988_75).fract();
    Contacts {
        delta: (0..n).map(|i| 1.1e-5 * t(i) - 1e-6).collect(),
        rate: (0..n).map(|i| 0.4 * t(i + 7) - 0.2).collect(),
        mass: (0..n).map(|i| 1e-4 * (1.0 + t(i + 3))).collect(),
        radius: (0..n).map(|i| 1e-3 * (1.0 + 2.0 * t(i + 5))).collect(),
        normal: (0..n)
            .map(|i| {
                let a = 6.0 * t(i + 11);
                [a.cos(), a.sin(), 0.0]
            })
            .collect(),
    }
}

/// The context the fixture's `context-probe` reports for contact `i` on which its force is `f`.
fn probe_context(c: &Contacts, i: usize, f: f64) -> NormalContext {
    NormalContext {
        contact_radius: 3.0 * (c.radius[i] * c.delta[i].max(0.0)).sqrt() + c.radius[i] / 1000.0,
        cap_force: f + 0.5,
        damping: 7.0 * c.mass[i],
    }
}

/// The normal forces and contexts of `law` on `c` (memoryless).
fn forces_and_contexts(law: &dyn NormalLaw, c: &Contacts) -> (Vec<f64>, Vec<NormalContext>) {
    try_forces_and_contexts(law, c).unwrap()
}

/// [`forces_and_contexts`], or the law's refusal.
fn try_forces_and_contexts(
    law: &dyn NormalLaw,
    c: &Contacts,
) -> Result<(Vec<f64>, Vec<NormalContext>), dashpot_sdk::LawError> {
    let n = c.delta.len();
    let (mut f, mut x) = (vec![0.0; n], vec![NormalContext::default(); n]);
    let b = NormalBatch {
        delta: &c.delta,
        rate: &c.rate,
        mass: &c.mass,
        radius: &c.radius,
        slots: 0,
        history: &mut [],
        force: &mut f,
    };
    law.force_batch_context(b, None, &mut x, EnergyOut::none())?;
    Ok((f, x))
}

fn flat(x: &[NormalContext]) -> Vec<f64> {
    x.iter().flat_map(|c| c.to_array()).collect()
}

fn probe(reg: &Registry, nan_above: f64) -> impl NormalLaw {
    reg.contact(
        "context-probe",
        &[ParamValue::new("k", 3e4), ParamValue::new("nan_above", nan_above)],
    )
    .unwrap()
    .bind(&materials())
    .unwrap()
}

/// The tangential batch of `c` with normal forces `f` and contexts `x` into `out`.
fn tangential<'a>(
    c: &'a Contacts,
    f: &'a [f64],
    x: &'a [NormalContext],
    out: &'a mut [[f64; 3]],
) -> TangentialBatch<'a> {
    TangentialBatch {
        dt: 1e-6,
        normal: &c.normal,
        velocity: &c.normal,
        normal_force: f,
        delta: &c.delta,
        mass: &c.mass,
        radius: &c.radius,
        context: x,
        slots: 0,
        history: &mut [],
        force: out,
    }
}

#[test]
fn every_kind_receives_exactly_the_context_the_normal_law_reported() {
    let reg = registry_with_context_fixture();
    let c = contacts(150);
    let n = c.delta.len();
    let (f, x) = forces_and_contexts(&probe(&reg, 1.0), &c);
    for i in 0..n {
        assert_eq!(x[i], probe_context(&c, i, f[i]), "contact {i}");
    }
    let m = materials();
    let echo = reg.tangential("context-echo", &[]).unwrap().bind(&m).unwrap();
    let rolling = reg
        .rolling("context-echo-rolling", &[])
        .unwrap()
        .bind(&m)
        .unwrap();
    let twisting = reg
        .twisting("context-echo-twisting", &[])
        .unwrap()
        .bind(&m)
        .unwrap();
    assert!(echo.reads_context() && rolling.reads_context() && twisting.reads_context());
    for name in ["mindlin", "linear-history", "context-echo-default"] {
        let info = &reg.find(name).unwrap().0.info;
        assert!(!info.reads_context, "{name}");
    }
    assert!(reg.find("context-echo").unwrap().0.info.reads_context);

    let mut out = vec![[0.0; 3]; n];
    echo.force_batch(tangential(&c, &f, &x, &mut out)).unwrap();
    assert_same_bits(out.as_flattened(), &flat(&x), |k| {
        format!("tangential, contact {}", k / 3)
    });
    let mut out = vec![[0.0; 3]; n];
    let b = tangential(&c, &f, &x, &mut out);
    let rb = RollingBatch {
        velocity: &c.normal,
        ..b
    };
    rolling.force_batch(rb, EnergyOut::none()).unwrap();
    assert_same_bits(out.as_flattened(), &flat(&x), |k| {
        format!("rolling, contact {}", k / 3)
    });
    let mut torque = vec![0.0; n];
    let tb = TwistingBatch {
        dt: 1e-6,
        normal: &c.normal,
        rate: &c.rate,
        normal_force: &f,
        delta: &c.delta,
        mass: &c.mass,
        radius: &c.radius,
        context: &x,
        slots: 0,
        history: &mut [],
        torque: &mut torque,
    };
    twisting.torque_batch(tb, EnergyOut::none()).unwrap();
    let a: Vec<f64> = x.iter().map(|x| x.contact_radius).collect();
    assert_same_bits(&torque, &a, |i| format!("twisting, contact {i}"));
}

/// A batch without contexts gives each contact the default one, built from its own radius,
/// overlap and normal force; so does a law that does not declare it reads them.
#[test]
fn without_contexts_each_contact_gets_its_default() {
    let reg = registry_with_context_fixture();
    let c = contacts(70);
    let n = c.delta.len();
    let f: Vec<f64> = (0..n).map(|i| 50.0 * c.delta[i]).collect();
    let want: Vec<NormalContext> = (0..n)
        .map(|i| NormalContext::hertzian(c.radius[i], c.delta[i], f[i]))
        .collect();
    for i in 0..n {
        let expected = NormalContext {
            contact_radius: (c.radius[i] * c.delta[i].max(0.0)).sqrt(),
            cap_force: f[i].max(0.0),
            damping: 0.0,
        };
        assert_eq!(want[i], expected);
    }
    for name in ["context-echo", "context-echo-default"] {
        let law = reg.tangential(name, &[]).unwrap().bind(&materials()).unwrap();
        let mut out = vec![[0.0; 3]; n];
        law.force_batch(tangential(&c, &f, &[], &mut out)).unwrap();
        assert_same_bits(out.as_flattened(), &flat(&want), |k| {
            format!("{name}, contact {}", k / 3)
        });
    }
}

/// Normal laws that report no context of their own (every law but JKR and the fixture) give
/// the default for their force: the Hertzian radius, max(F, 0) and no damping.
#[test]
fn laws_without_a_context_of_their_own_give_the_default() {
    let reg = registry_with_context_fixture();
    let c = contacts(90);
    for (name, params) in [
        ("hsd", vec![ParamValue::new("eps", 0.5)]),
        ("lsd", vec![ParamValue::new("eps", 0.5)]),
        ("kuwabara-kono", vec![]),
        ("dmt", vec![]),
    ] {
        let law = reg.contact(name, &params).unwrap().bind(&materials()).unwrap();
        let (f, x) = forces_and_contexts(&law, &c);
        for i in 0..f.len() {
            let contact = Contact {
                delta: c.delta[i],
                rate: c.rate[i],
                mass: c.mass[i],
                radius: c.radius[i],
            };
            assert_eq!(
                x[i],
                NormalContext::default_for(&contact, f[i]),
                "{name} contact {i}"
            );
        }
    }
}

/// JKR's contact radius a solves δ = a²/R − √(2π w a/E) on the stable branch, stays positive
/// past touching (δ < 0) until rupture at δ_c = −(3/4)(π² w² R/E²)^{1/3}, and is 0 after; its
/// cap force is F_e(a) + 3π w R > 0 and its damping α(ε) √((4/3) E a m).
#[test]
fn jkr_reports_its_own_contact_radius_past_touching_until_rupture() {
    let reg = registry_with_context_fixture();
    let (w, eps) = (0.1, 0.8);
    let m = materials();
    let law = reg
        .contact("jkr", &[ParamValue::new("w", w), ParamValue::new("eps", eps)])
        .unwrap()
        .bind(&m)
        .unwrap();
    let (e, r, mass) = (m.young, 1e-3, 1e-4);
    let delta_c = -0.75 * (PI * PI * w * w * r / (e * e)).cbrt();
    let alpha = dashpot_sdk::physics::tsuji_alpha(eps);
    let mut h = [0.0];
    let (mut past_touching, mut broke) = (0, false);
    // approach to δ = 3 |δ_c|, then pull apart to 1.5 δ_c
    let (steps, top) = (400, -3.0 * delta_c);
    for s in 0..=steps {
        let t = s as f64 / steps as f64;
        let delta = if t < 0.3 {
            top * t / 0.3
        } else {
            top + (1.5 * delta_c - top) * (t - 0.3) / 0.7
        };
        let (mut f, mut x) = ([0.0], [NormalContext::default()]);
        let b = NormalBatch {
            delta: &[delta],
            rate: &[-0.01],
            mass: &[mass],
            radius: &[r],
            slots: 1,
            history: &mut h,
            force: &mut f,
        };
        law.force_batch_context(b, None, &mut x, EnergyOut::none())
            .unwrap();
        let x = x[0];
        if delta < delta_c {
            broke = true;
        }
        if broke {
            assert_eq!(
                (h[0], x),
                (0.0, NormalContext::default()),
                "after rupture, δ = {delta:e}"
            );
            continue;
        }
        let a = x.contact_radius;
        assert!(a > 0.0, "δ = {delta:e}: a = {a:e}");
        let back = a * a / r - (2.0 * PI * w * a / e).sqrt();
        assert!(
            (back - delta).abs() <= 1e-9 * delta_c.abs(),
            "δ = {delta:e}: δ(a) = {back:e}"
        );
        let fe = 4.0 * e * a * a * a / (3.0 * r) - (8.0 * PI * w * e * a * a * a).sqrt();
        let cap = fe + 3.0 * PI * w * r;
        assert!(
            (x.cap_force - cap).abs() <= 1e-12 * cap,
            "{} vs {cap}",
            x.cap_force
        );
        assert!(x.cap_force > 1.5 * PI * w * r * (1.0 - 1e-12));
        let damping = alpha * (4.0 / 3.0 * e * a * mass).sqrt();
        assert!((x.damping - damping).abs() <= 1e-12 * damping);
        past_touching += usize::from(delta < 0.0);
    }
    assert!(broke && past_touching > 30, "{past_touching} steps past touching");
}

/// A normal law reporting a non-finite context, a context given with a bad field, and a
/// context array of the wrong length are errors that name the contact or the lengths.
#[test]
fn bad_contexts_are_errors_naming_the_contact() {
    let reg = registry_with_context_fixture();
    let c = contacts(5);
    let law = probe(&reg, 5e-6);
    let e = try_forces_and_contexts(&law, &c).unwrap_err();
    let first = c.delta.iter().position(|&d| d > 5e-6).unwrap();
    assert_eq!(e.kind, ErrorKind::NonFinite);
    assert!(
        e.message
            .contains(&format!("returned a non-finite context on contact {first}")),
        "{}",
        e.message
    );
    let (f, mut x) = forces_and_contexts(&probe(&reg, 1.0), &c);
    x[2].damping = f64::NAN;
    let echo = reg
        .tangential("context-echo", &[])
        .unwrap()
        .bind(&materials())
        .unwrap();
    let mut out = vec![[0.0; 3]; 5];
    let e = echo.force_batch(tangential(&c, &f, &x, &mut out)).unwrap_err();
    assert!(
        e.message.contains("input context[2]") && e.message.contains("≥ 0"),
        "{}",
        e.message
    );
    x[2].damping = -1.0;
    let e = echo.force_batch(tangential(&c, &f, &x, &mut out)).unwrap_err();
    assert!(e.message.contains("input context[2]"), "{}", e.message);
    let e = echo
        .force_batch(tangential(&c, &f, &x[..4], &mut out))
        .unwrap_err();
    assert!(
        e.message.contains("context has 4 values for 5 contacts"),
        "{}",
        e.message
    );
}

/// A DEM contact set of `c`, every contact a pair (0, 1 + i), with room for rotation laws.
fn contact_set(c: &Contacts) -> ContactSet {
    let n = c.delta.len();
    let mut s = ContactSet::new(0, 0).with_rotation(Some(0), Some(0));
    s.i = vec![0; n];
    s.j = (1..=n as u32).collect();
    s.delta = c.delta.clone();
    s.rate = c.rate.clone();
    s.mass = c.mass.clone();
    s.radius = c.radius.clone();
    s.normal = c.normal.clone();
    s.vrel = c.normal.clone();
    s.fnorm = vec![0.0; n];
    s.ftan = vec![[0.0; 3]; n];
    s.fresh = vec![false; n];
    s.last = vec![false; n];
    s.vroll = c.normal.clone();
    s.twist = c.rate.clone();
    s.froll = vec![[0.0; 3]; n];
    s.mtwist = vec![0.0; n];
    s
}

/// The DEM engine's contact sets compute the normal law's contexts when a law of the contact's
/// motion reads them and pass them to every such law; otherwise they compute none and the laws
/// see the defaults.
#[test]
fn the_dem_contact_sets_pass_the_contexts_to_the_laws_that_read_them() {
    let reg = registry_with_context_fixture();
    let m = materials();
    let c = contacts(300);
    let n = c.delta.len();
    let normal = probe(&reg, 1.0);
    let echo = reg.tangential("context-echo", &[]).unwrap().bind(&m).unwrap();
    let rolling = reg
        .rolling("context-echo-rolling", &[])
        .unwrap()
        .bind(&m)
        .unwrap();
    let twisting = reg
        .twisting("context-echo-twisting", &[])
        .unwrap()
        .bind(&m)
        .unwrap();
    let mut s = contact_set(&c);
    let rotation = Rotating {
        rolling: Some(&rolling),
        twisting: Some(&twisting),
        context: false,
    };
    s.evaluate(&normal, Some(&echo), rotation, 1e-6, false).unwrap();
    let want: Vec<NormalContext> = (0..n).map(|i| probe_context(&c, i, s.fnorm[i])).collect();
    assert_same_bits(s.ftan.as_flattened(), &flat(&want), |k| {
        format!("tangential, contact {}", k / 3)
    });
    assert_same_bits(s.froll.as_flattened(), &flat(&want), |k| {
        format!("rolling, contact {}", k / 3)
    });
    let a: Vec<f64> = want.iter().map(|x| x.contact_radius).collect();
    assert_same_bits(&s.mtwist, &a, |i| format!("twisting, contact {i}"));

    // no law reads the contexts: none is computed, the law sees each contact's default
    let plain = reg
        .tangential("context-echo-default", &[])
        .unwrap()
        .bind(&m)
        .unwrap();
    let mut s = contact_set(&c);
    s.evaluate(&normal, Some(&plain), Rotating::default(), 1e-6, false)
        .unwrap();
    assert!(s.context.is_empty());
    let want: Vec<NormalContext> = (0..n)
        .map(|i| NormalContext::hertzian(c.radius[i], c.delta[i], s.fnorm[i]))
        .collect();
    assert_same_bits(s.ftan.as_flattened(), &flat(&want), |k| {
        format!("default, contact {}", k / 3)
    });
}
