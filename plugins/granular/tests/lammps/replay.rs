//! The host's side of the exactness test: LAMMPS's contact geometry (what a host must compute
//! and pass to the `gran-*` laws for LAMMPS's forces), the laws composed at one contact, and a
//! replay of a dumped run that compares every step's force and torques.

use super::{half_step, Atom};
use dashpot_granular::normal::{DampingModel, NormalModel};
use dashpot_granular::normal_laws::GranNormalBound;
use dashpot_granular::spring::{cross, dot, scale, sub, Ctx, ReadsContext, SpringStep};
use dashpot_sdk::{
    BoundContact, Contact, ContactLaw, MaterialPair, ParamValue, RollingContact, RollingLaw,
    TangentialContact, TangentialLaw, TwistingContact, TwistingLaw,
};

type NormalFn = Box<dyn Fn(Contact, &mut [f64]) -> (f64, Ctx)>;
type VectorFn<C> = Box<dyn Fn(&Ctx, &C, &mut [f64]) -> ([f64; 3], SpringStep)>;
type TwistFn = Box<dyn Fn(&Ctx, &TwistingContact, &mut [f64]) -> (f64, SpringStep)>;

/// A family's law with the history slots it keeps.
pub struct Law<F> {
    f: F,
    slots: usize,
}

fn values(params: &[(&str, f64)]) -> Vec<ParamValue> {
    params.iter().map(|(n, v)| ParamValue::new(n, *v)).collect()
}

/// The normal law `L` with `params`, bound to `m`: its force and the context it reports.
pub fn normal<L, M, D>(params: &[(&str, f64)], m: &MaterialPair) -> Law<NormalFn>
where
    L: ContactLaw<Bound = GranNormalBound<M, D>>,
    M: NormalModel,
    D: DampingModel,
{
    let b = L::from_values(&values(params))
        .expect("configure")
        .bind(m)
        .expect("bind");
    Law {
        f: Box::new(move |c, h| {
            let f = b.force(c, h);
            (f, b.context(&c, h, f))
        }),
        slots: L::HISTORY.len(),
    }
}

/// Declares the constructor `$f` of a law of kind `$trait` read through its context: the law
/// with `params`, bound to `m`. Each call also goes through the sdk's trait (`$bound::$call`,
/// the context in the contact, as a host passes it) and checks the same bits and history.
macro_rules! motion_law {
    ($f:ident, $trait:ident, $bound:ident::$call:ident, $contact:ty, $out:ty, $fn:ty) => {
        #[doc = concat!("The ", stringify!($trait), " `L` with `params`, bound to `m`.")]
        pub fn $f<L>(params: &[(&str, f64)], m: &MaterialPair) -> Law<$fn>
        where
            L: $trait,
            L::Bound: ReadsContext<$contact, Out = $out> + dashpot_sdk::$bound,
        {
            assert!(L::READS_CONTEXT, "{} reads the normal context", L::NAME);
            let b = L::from_values(&values(params))
                .expect("configure")
                .bind(m)
                .expect("bind");
            Law {
                f: Box::new(move |x, c, h| {
                    let mut through_sdk = h.to_vec();
                    let o = dashpot_sdk::$bound::$call(&b, c, &mut through_sdk);
                    let out = b.eval(x, c, h);
                    assert!(
                        o == out.0 && through_sdk == h,
                        "the sdk trait and the kernel differ"
                    );
                    out
                }),
                slots: L::HISTORY.len(),
            }
        }
    };
}

motion_law!(
    tangential,
    TangentialLaw,
    BoundTangential::force,
    TangentialContact,
    [f64; 3],
    VectorFn<TangentialContact>
);
motion_law!(
    rolling,
    RollingLaw,
    BoundRolling::force,
    RollingContact,
    [f64; 3],
    VectorFn<RollingContact>
);
motion_law!(
    twisting,
    TwistingLaw,
    BoundTwisting::torque,
    TwistingContact,
    f64,
    TwistFn
);

/// LAMMPS's materials of two spheres of one type (`E`, `ν`): E_eff = 1/((1 − ν²)/E +
/// (1 − ν²)/E), G_eff = 1/(2(2 − ν)(1 + ν)/E + 2(2 − ν)(1 + ν)/E), LAMMPS's operations.
pub fn pair_materials(e: f64, nu: f64) -> MaterialPair {
    let fe = (1.0 - nu * nu) / e;
    let fg = 2.0 * (2.0 - nu) * (1.0 + nu) / e;
    MaterialPair {
        young: 1.0 / (fe + fe),
        shear: 1.0 / (fg + fg),
    }
}

/// LAMMPS's materials of a sphere (`E`, `ν`) and `fix wall/gran`'s wall: a wall of the same
/// material, E_eff = E/(2(1 − ν²)), G_eff = E/(4(2 − ν)(1 + ν)).
pub fn wall_materials(e: f64, nu: f64) -> MaterialPair {
    MaterialPair {
        young: e / (2.0 * (1.0 - nu * nu)),
        shear: e / (4.0 * (2.0 - nu) * (1.0 + nu)),
    }
}

/// The laws of one contact, as `pair_style granular` composes its sub-models.
pub struct Model {
    /// The normal law.
    pub normal: Law<NormalFn>,
    /// The tangential law.
    pub tangential: Law<VectorFn<TangentialContact>>,
    /// The rolling law, if any.
    pub rolling: Option<Law<VectorFn<RollingContact>>>,
    /// The twisting law, if any.
    pub twisting: Option<Law<TwistFn>>,
    /// Torque arms R_i, R_j (the classic pair styles) instead of R − δ/2.
    pub classic_arms: bool,
}

/// The per-contact state of a replay.
#[derive(Default)]
struct History {
    normal: Vec<f64>,
    tangential: Vec<f64>,
    rolling: Vec<f64>,
    twisting: Vec<f64>,
}

impl History {
    fn new(m: &Model) -> History {
        History {
            normal: vec![0.0; m.normal.slots],
            tangential: vec![0.0; m.tangential.slots],
            rolling: vec![0.0; m.rolling.as_ref().map_or(0, |l| l.slots)],
            twisting: vec![0.0; m.twisting.as_ref().map_or(0, |l| l.slots)],
        }
    }
}

/// How a replay went: contact steps, worst relative differences of the force and of the
/// torques, and the steps where each family's spring slid (or stuck).
#[derive(Debug, Default, Clone, Copy)]
pub struct Outcome {
    /// Steps in contact.
    pub contact: usize,
    /// max |F − F_lammps|/|F_lammps|.
    pub force: f64,
    /// max |τ − τ_lammps|/|τ_lammps| over both bodies.
    pub torque: f64,
    /// Steps where the tangential force was capped / not.
    pub slid: [usize; 2],
    /// The same for rolling.
    pub rolled: [usize; 2],
    /// The same for twisting.
    pub twisted: [usize; 2],
}

fn rel(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = sub(a, b);
    let n = dot(b, b).sqrt();
    if n == 0.0 {
        if dot(d, d) == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    } else {
        dot(d, d).sqrt() / n
    }
}

fn count(c: &mut [usize; 2], slid: bool) {
    c[usize::from(!slid)] += 1;
}

/// One contact of sphere i with sphere j (or the wall: `wall`), LAMMPS's geometry: returns the
/// force on i and the torques on i and j, or `None` out of contact.
#[allow(clippy::too_many_arguments)]
fn contact(
    m: &Model,
    h: &mut History,
    o: &mut Outcome,
    (xi, vi, wi, ri, mi): ([f64; 3], [f64; 3], [f64; 3], f64, f64),
    (xj, vj, wj, rj, mj): ([f64; 3], [f64; 3], [f64; 3], f64, f64),
    wall: bool,
    dt: f64,
) -> Option<([f64; 3], [f64; 3], [f64; 3])> {
    let dx = sub(xi, xj);
    let rsq = dot(dx, dx);
    let (radsum, reff, meff) = if wall {
        (ri, ri, mi)
    } else {
        (ri + rj, ri * rj / (ri + rj), mi * mj / (mi + mj))
    };
    let r = rsq.sqrt();
    let delta = radsum - r;
    let n = scale(1.0 / r, dx);
    let vr = sub(vi, vj);
    let vnnr = dot(vr, n);
    let vt = sub(vr, scale(vnnr, n));
    let wr = [
        ri * wi[0] + rj * wj[0],
        ri * wi[1] + rj * wj[1],
        ri * wi[2] + rj * wj[2],
    ];
    let vtr = sub(vt, cross(wr, n));
    let c = Contact {
        delta,
        rate: -vnnr,
        mass: meff,
        radius: reff,
    };
    let (fn_, ctx) = (m.normal.f)(c, &mut h.normal);
    let touching = ctx != Ctx::default() || fn_ != 0.0;
    if !touching {
        // out of contact: LAMMPS drops the contact's history
        *h = History::new(m);
        return None;
    }
    o.contact += 1;
    let tc = TangentialContact {
        context: ctx,
        normal: n,
        velocity: vtr,
        normal_force: fn_,
        delta,
        mass: meff,
        radius: reff,
        dt,
    };
    let (fs, s) = (m.tangential.f)(&ctx, &tc, &mut h.tangential);
    count(&mut o.slid, s.slid);
    let force = [fn_ * n[0] + fs[0], fn_ * n[1] + fs[1], fn_ * n[2] + fs[2]];
    let t = scale(-1.0, cross(n, fs));
    let (arm_i, arm_j) = if m.classic_arms || wall {
        (ri, rj)
    } else {
        (ri - 0.5 * delta, rj - 0.5 * delta)
    };
    let (mut ti, mut tj) = (scale(arm_i, t), scale(arm_j, t));
    let relrot = sub(wi, wj);
    if let Some(l) = &m.rolling {
        let rc = TangentialContact {
            velocity: scale(reff, cross(relrot, n)),
            ..tc
        };
        let (fr, s) = (l.f)(&ctx, &rc, &mut h.rolling);
        count(&mut o.rolled, s.slid);
        let tr = scale(reff, cross(n, fr));
        ti = [ti[0] + tr[0], ti[1] + tr[1], ti[2] + tr[2]];
        tj = sub(tj, tr);
    }
    if let Some(l) = &m.twisting {
        let wc = TwistingContact {
            context: ctx,
            normal: n,
            rate: dot(relrot, n),
            normal_force: fn_,
            delta,
            mass: meff,
            radius: reff,
            dt,
        };
        let (mt, s) = (l.f)(&ctx, &wc, &mut h.twisting);
        count(&mut o.twisted, s.slid);
        let tw = scale(mt, n);
        ti = [ti[0] + tw[0], ti[1] + tw[1], ti[2] + tw[2]];
        tj = sub(tj, tw);
    }
    Some((force, ti, tj))
}

/// Replays a two-sphere run (`wall`: one sphere against the wall z = 0) under the laws `m`,
/// step by step from LAMMPS's own half-step state, and compares each step's force and torques
/// with LAMMPS's.
pub fn replay(steps: &[Vec<Atom>], m: &Model, dt: f64, wall: bool) -> Outcome {
    let mut h = History::new(m);
    let mut o = Outcome::default();
    for w in steps.windows(2) {
        let (now, next) = (&w[0], &w[1]);
        let (xi, vi, wi) = half_step(&now[0], &next[0], dt);
        let i = (xi, vi, wi, now[0].radius, now[0].mass);
        let j = if wall {
            ([xi[0], xi[1], 0.0], [0.0; 3], [0.0; 3], 0.0, 0.0)
        } else {
            let (xj, vj, wj) = half_step(&now[1], &next[1], dt);
            (xj, vj, wj, now[1].radius, now[1].mass)
        };
        match contact(m, &mut h, &mut o, i, j, wall, dt) {
            None => assert_eq!(
                next[0].fc, [0.0; 3],
                "LAMMPS has a contact force where the laws have none"
            ),
            Some((f, ti, tj)) => {
                o.force = o.force.max(rel(f, next[0].fc));
                o.torque = o.torque.max(rel(ti, next[0].t));
                if !wall {
                    o.torque = o.torque.max(rel(tj, next[1].t));
                }
            }
        }
    }
    o
}
