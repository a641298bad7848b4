//! The history springs' batch (four contacts at a time in AVX2 lanes where the CPU has them)
//! gives the per-contact form's bits for every spring kind, on every path: a fresh spring and a
//! held one, a spring with a normal part to turn or project, a velocity already tangent and one
//! not, sticking and sliding (a cap of zero, a spring that held nothing), a contact radius
//! shrinking (the rescaling variants) or growing, and a ragged last lane; and so do `rolling sds`
//! and `twisting marshall`; and the normal laws' force-and-context and reach batches.

use dashpot_granular::normal::{
    CoeffRestitution, DampingModel, Dmt, Hertz, Hooke, Jkr, MassVelocity, NormalModel, Tsuji, Velocity,
    Viscoelastic, FOURTHIRDS,
};
use dashpot_granular::normal_laws::GranNormalBound;
use dashpot_granular::rotation::Sds;
use dashpot_granular::rotation_laws::MarshallBound;
use dashpot_granular::tangential::Spring;
use dashpot_granular::tangential_laws::{kind, SpringBound};
use dashpot_sdk::{
    BoundContact, BoundRolling, BoundTangential, BoundTwisting, Contact, NormalBatch, NormalContext,
    TangentialBatch, TangentialContact, TwistingBatch, TwistingContact,
};
use std::f64::consts::PI;

/// `n` contacts with their history (`slots` a contact), drawn to cover every branch.
fn contacts(n: usize, slots: usize, seed: u64) -> (Vec<TangentialContact>, Vec<f64>) {
    let mut rnd = dashpot_testkit::uniform(seed);
    let (mut cs, mut hist) = (Vec::new(), Vec::new());
    for i in 0..n {
        let (th, ph) = (PI * rnd(), 2.0 * PI * rnd());
        let normal = [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()];
        let mut velocity = [rnd() - 0.5, rnd() - 0.5, rnd() - 0.5];
        if i % 3 == 0 {
            // already tangent (to rounding): the law keeps it as it is
            let vn = velocity.iter().zip(normal).map(|(v, n)| v * n).sum::<f64>();
            velocity = [0, 1, 2].map(|k| velocity[k] - vn * normal[k]);
        }
        let a = 1e-4 * (0.5 + rnd());
        let context = NormalContext {
            contact_radius: a,
            // a zero cap slides every spring; a small one some; a large one none
            cap_force: [0.0, 1e-3, 10.0][i % 3] * rnd(),
            damping: if i % 4 == 1 { 0.0 } else { 0.05 * rnd() },
        };
        cs.push(TangentialContact {
            normal,
            velocity,
            normal_force: context.cap_force,
            delta: 1e-6 * rnd(),
            mass: 1e-6 * (0.5 + rnd()),
            radius: 1e-3 * (0.5 + rnd()),
            context,
            dt: 1e-4,
        });
        // none held, or a spring with a normal part (to turn or project)
        for _ in 0..3 {
            hist.push(if i % 5 == 0 { 0.0 } else { 1e-4 * (rnd() - 0.5) });
        }
        if slots == 4 {
            // the contact radius of the last step: none, above or below this step's
            hist.push([0.0, 1.3 * a, 0.7 * a][i % 3]);
        }
    }
    (cs, hist)
}

/// Spring `law` of kind `kind` (`slots` history slots) in batches of several lengths against
/// its per-contact form.
fn check<L: BoundTangential>(law: L, kind: u8, slots: usize) {
    for n in [0, 1, 3, 4, 5, 7, 203] {
        let (cs, hist) = contacts(n, slots, 0x9e37_79b9_7f4a_7c15 ^ u64::from(kind));
        if n == 0 {
            continue;
        }
        let f = dashpot_testkit::batch_is_per_contact(
            &cs,
            &hist,
            slots,
            |c, h| law.force(c, h),
            |b| law.force_batch(b),
            &format!("kind {kind}, {n} contacts"),
        );
        if n == 203 {
            // the draw reaches both sides of the cap and springs that held nothing
            let (slid, stuck) = f.iter().zip(&cs).fold((0, 0), |(s, t), (f, c)| {
                let m = f.iter().map(|x| x * x).sum::<f64>().sqrt();
                let cap = 0.4 * c.context.cap_force;
                (
                    s + usize::from(m > 0.0 && (m - cap).abs() <= 1e-12 * cap),
                    t + usize::from(m < 0.999 * cap),
                )
            });
            assert!(
                slid > 10 && stuck > 10,
                "kind {kind}: {slid} sliding, {stuck} stuck"
            );
        }
    }
}

#[test]
fn every_spring_batch_is_the_per_contact_form_bit_for_bit() {
    let spring = |k| Spring { k, xt: 0.7, mu: 0.4 };
    macro_rules! check {
        ($($kind:ident: $k:expr, $slots:expr;)*) => {$(
            check(SpringBound::<{ kind::$kind }>(spring($k)), kind::$kind, $slots);
        )*};
    }
    check! {
        LINEAR: 1e3, 3;
        MINDLIN: 1e7, 4;
        MINDLIN_RESCALE: 1e7, 4;
        MINDLIN_FORCE: 1e7, 4;
        MINDLIN_RESCALE_FORCE: 1e7, 4;
        CLASSIC_HOOKE: 1e3, 3;
        CLASSIC_HERTZ: 1e7, 4;
        CLASSIC_GRANULAR: 1e7, 4;
    }
}

/// Without the normal law's contexts (a host that passes none) the batch gives the
/// per-contact form's bits with each contact's default context.
#[test]
fn a_batch_without_contexts_is_the_per_contact_form() {
    let law = SpringBound::<{ kind::CLASSIC_HOOKE }>(Spring {
        k: 1e3,
        xt: 0.7,
        mu: 0.4,
    });
    let (mut cs, hist) = contacts(9, 3, 7);
    let mut h1 = hist.clone();
    let mut f1 = Vec::new();
    for (i, c) in cs.iter_mut().enumerate() {
        c.context = NormalContext::hertzian(c.radius, c.delta, c.normal_force);
        f1.push(law.force(c, &mut h1[3 * i..3 * i + 3]));
    }
    let col = |g: fn(&TangentialContact) -> f64| cs.iter().map(g).collect::<Vec<_>>();
    let (normal, velocity): (Vec<_>, Vec<_>) = cs.iter().map(|c| (c.normal, c.velocity)).unzip();
    let (fnorm, delta, mass, radius) = (
        col(|c| c.normal_force),
        col(|c| c.delta),
        col(|c| c.mass),
        col(|c| c.radius),
    );
    let (mut h2, mut f2) = (hist, vec![[0.0; 3]; cs.len()]);
    law.force_batch(TangentialBatch {
        dt: cs[0].dt,
        normal: &normal,
        velocity: &velocity,
        normal_force: &fnorm,
        delta: &delta,
        mass: &mass,
        radius: &radius,
        context: &[],
        slots: 3,
        history: &mut h2,
        force: &mut f2,
    });
    assert_eq!(f1, f2);
    assert_eq!(
        h1.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        h2.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
    );
    assert!(
        f1.iter().any(|f| f.iter().any(|&x| x != 0.0)),
        "some contacts carry a force"
    );
}

/// `rolling sds`'s batch is its per-contact form, bit for bit, stuck and sliding.
#[test]
fn rolling_sds_batch_is_the_per_contact_form_bit_for_bit() {
    let law = Sds {
        k: 1e3,
        gamma: 0.02,
        mu: 0.3,
    };
    for n in [1, 6, 203] {
        let (cs, hist) = contacts(n, 3, 0x51);
        dashpot_testkit::batch_is_per_contact(
            &cs,
            &hist,
            3,
            |c, h| BoundRolling::force(&law, c, h),
            |b| BoundRolling::force_batch(&law, b),
            &format!("rolling sds, {n} contacts"),
        );
    }
}

/// `twisting marshall`'s batch is its per-contact form, bit for bit: twisting either way or not
/// at all, stuck and sliding, with a ragged last lane.
#[test]
fn twisting_marshall_batch_is_the_per_contact_form_bit_for_bit() {
    let law = MarshallBound(Spring {
        k: 1e7,
        xt: 0.7,
        mu: 0.4,
    });
    for n in [1, 5, 203] {
        let (cs, mut hist) = contacts(n, 4, 0x77);
        // slots θ and a_last of each contact from the drawn four
        hist = hist.chunks(4).flat_map(|h| [1e-2 * h[0], h[3]]).collect();
        let twist: Vec<TwistingContact> = cs
            .iter()
            .enumerate()
            .map(|(i, c)| TwistingContact {
                normal: c.normal,
                rate: [0.0, 30.0 * c.velocity[0], -5.0 * c.velocity[1]][i % 3],
                normal_force: c.normal_force,
                delta: c.delta,
                mass: c.mass,
                radius: c.radius,
                context: c.context,
                dt: c.dt,
            })
            .collect();
        let mut h1 = hist.clone();
        let t1: Vec<f64> = twist
            .iter()
            .enumerate()
            .map(|(i, c)| law.torque(c, &mut h1[2 * i..2 * i + 2]))
            .collect();
        let col = |g: fn(&TwistingContact) -> f64| twist.iter().map(g).collect::<Vec<_>>();
        let normal: Vec<[f64; 3]> = twist.iter().map(|c| c.normal).collect();
        let context: Vec<NormalContext> = twist.iter().map(|c| c.context).collect();
        let (rate, fnorm, delta, mass, radius) = (
            col(|c| c.rate),
            col(|c| c.normal_force),
            col(|c| c.delta),
            col(|c| c.mass),
            col(|c| c.radius),
        );
        let (mut h2, mut t2) = (hist, vec![0.0; n]);
        law.torque_batch(TwistingBatch {
            dt: twist[0].dt,
            normal: &normal,
            rate: &rate,
            normal_force: &fnorm,
            delta: &delta,
            mass: &mass,
            radius: &radius,
            context: &context,
            slots: 2,
            history: &mut h2,
            torque: &mut t2,
        });
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&t1), bits(&t2), "torques, {n} contacts");
        assert_eq!(bits(&h1), bits(&h2), "history, {n} contacts");
        if n == 203 {
            let slid = t1
                .iter()
                .zip(&twist)
                .filter(|(t, c)| {
                    **t != 0.0
                        && (t.abs() - 2.0 / 3.0 * 0.4 * c.context.contact_radius * c.context.cap_force).abs()
                            <= 1e-12 * t.abs()
                })
                .count();
            let stuck = t1.iter().filter(|t| **t != 0.0).count() - slid;
            assert!(slid > 10 && stuck > 10, "{slid} sliding, {stuck} stuck");
        }
    }
}

/// A normal law's force-and-context batch and its reach batch (four contacts at a time in
/// lanes where the CPU has them) give its per-contact forms' bits: pressed, touching, pulled
/// apart within and beyond JKR's pull-off distance, formed or not, approaching and receding.
fn normal_batch_is_per_contact<B: BoundContact>(law: &B, slots: usize, what: &str) {
    let mut rnd = dashpot_testkit::uniform(0xabcd_ef01);
    for n in [1, 3, 4, 9, 203] {
        let contacts: Vec<Contact> = (0..n)
            .map(|i| Contact {
                delta: [-3e-6, -1e-8, 0.0, 2e-6, 1e-9][i % 5] * (0.5 + rnd()),
                rate: 0.4 * (rnd() - 0.5),
                mass: 1e-7 * (0.5 + rnd()),
                radius: 2e-4 * (0.5 + rnd()),
            })
            .collect();
        let hist: Vec<f64> = (0..n * slots).map(|i| f64::from(u8::from(i % 3 != 0))).collect();
        let (mut h1, mut f1, mut x1) = (hist.clone(), vec![0.0; n], vec![NormalContext::default(); n]);
        for (i, c) in contacts.iter().enumerate() {
            (f1[i], x1[i]) = law.force_context(*c, &mut h1[i * slots..(i + 1) * slots]);
        }
        let col = |g: fn(&Contact) -> f64| contacts.iter().map(g).collect::<Vec<_>>();
        let (delta, rate, mass, radius) = (
            col(|c| c.delta),
            col(|c| c.rate),
            col(|c| c.mass),
            col(|c| c.radius),
        );
        let (mut h2, mut f2, mut x2) = (hist, vec![0.0; n], vec![NormalContext::default(); n]);
        let mut b = NormalBatch {
            delta: &delta,
            rate: &rate,
            mass: &mass,
            radius: &radius,
            slots,
            history: &mut h2,
            force: &mut f2,
        };
        law.force_context_batch(&mut b, &mut x2);
        let mut r2 = vec![0.0; n];
        law.reach_batch(&b, &mut r2);
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        let ctx = |x: &[NormalContext]| {
            x.iter()
                .flat_map(|c| c.to_array().map(f64::to_bits))
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&f1), bits(&f2), "forces, {what}, {n} contacts");
        assert_eq!(bits(&h1), bits(&h2), "history, {what}, {n} contacts");
        assert_eq!(ctx(&x1), ctx(&x2), "contexts, {what}, {n} contacts");
        let r1: Vec<f64> = contacts
            .iter()
            .enumerate()
            .map(|(i, c)| law.reach(c, &h1[i * slots..(i + 1) * slots]))
            .collect();
        assert_eq!(bits(&r1), bits(&r2), "reach, {what}, {n} contacts");
        if n == 203 {
            assert!(
                f1.iter().filter(|f| **f != 0.0).count() > 50,
                "{what}: contacts act"
            );
        }
    }
}

#[test]
fn every_normal_batch_is_the_per_contact_form_bit_for_bit() {
    let e = 5e7;
    let k = FOURTHIRDS * e;
    let jkr = Jkr {
        k,
        emix: e,
        cohesion: 0.05,
    };
    let dmt = Dmt { k, cohesion: 0.05 };
    let hertz = Hertz { k };
    let hooke = Hooke { k: 1e3 };
    let ts = Tsuji::coefficient(0.7, false);
    let cr = CoeffRestitution::coefficient(0.7, false);
    macro_rules! check {
        ($($model:ident $m:ident, $damping:ident $c:expr, $limit:expr, $slots:expr;)*) => {$(
            normal_batch_is_per_contact(
                &GranNormalBound::<$model, $damping>::new($m, $c, $limit),
                $slots,
                concat!(stringify!($model), " ", stringify!($damping)),
            );
        )*};
    }
    check! {
        Jkr jkr, Viscoelastic 0.3, false, 1;
        Jkr jkr, Velocity 1e-3, false, 1;
        Jkr jkr, MassVelocity 30.0, false, 1;
        Dmt dmt, MassVelocity 50.0, false, 0;
        Hertz hertz, Viscoelastic 0.3, true, 0;
        Hertz hertz, Tsuji ts, true, 0;
        Hertz hertz, CoeffRestitution cr, false, 0;
        Hooke hooke, MassVelocity 50.0, false, 0;
        Hooke hooke, CoeffRestitution 0.5, true, 0;
    }
}

/// The lanes' cube root is the per-contact one, bit for bit, across the range and at its ends.
#[test]
fn lane_cube_roots_are_the_per_contact_ones() {
    let mut rnd = dashpot_testkit::uniform(3);
    let jkr = Jkr {
        k: 1.0,
        emix: 1.0,
        cohesion: 1.0,
    };
    let law = GranNormalBound::<Jkr, Velocity>::new(jkr, 0.0, false);
    // the reach is the pull-off distance, a cube root of R γ²/E² = R: radii across the range,
    // every 7th beyond the lanes' range (then lane by lane)
    let n = 400;
    let radius: Vec<f64> = (0..n)
        .map(|i| {
            if i % 7 == 3 {
                1e-305 * (1.0 + rnd())
            } else {
                10f64.powf(600.0 * (rnd() - 0.5))
            }
        })
        .collect();
    let zeros = vec![0.0; n];
    let (mut h, mut f) = (vec![1.0; n], vec![0.0; n]);
    let b = NormalBatch {
        delta: &zeros,
        rate: &zeros,
        mass: &zeros,
        radius: &radius,
        slots: 1,
        history: &mut h,
        force: &mut f,
    };
    let mut r = vec![0.0; n];
    law.reach_batch(&b, &mut r);
    for (i, (&x, &y)) in radius.iter().zip(&r).enumerate() {
        assert_eq!(
            y.to_bits(),
            jkr.pulloff_distance(x).to_bits(),
            "radius {x:e} ({i})"
        );
    }
}
