//! What the tangential, rolling and twisting kernels share: the contact context they read, the
//! vector helpers in LAMMPS's order of operations, and the energy of one step of a
//! spring–dashpot–slider.

use dashpot_sdk::Energy;

/// What a contact's normal law tells its other laws (LAMMPS's `contact_radius`, `Fncrit` and
/// `damp_prefactor`): the sdk 0.4 normal context.
pub type Ctx = dashpot_sdk::NormalContext;

/// a · b.
#[inline(always)]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// |a|.
#[inline(always)]
pub fn len(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// s a.
#[inline(always)]
pub fn scale(s: f64, a: [f64; 3]) -> [f64; 3] {
    [s * a[0], s * a[1], s * a[2]]
}

/// a + b.
#[inline(always)]
pub fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// a − b.
#[inline(always)]
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// a × b.
#[inline(always)]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// (10⁻¹³)²: a velocity whose normal part is below 10⁻¹³ of its length is tangent to rounding.
const TANGENT_EPS2: f64 = 1e-26;

/// The part of `v` in the plane normal to the unit vector `n`: v − (v·n) n, or `v` itself when
/// it is already tangent to rounding (its normal part below 10⁻¹³ |v|), so that a host passing
/// LAMMPS's own tangential velocity v_tr gets LAMMPS's bits.
#[inline(always)]
pub fn tangential(v: [f64; 3], n: [f64; 3]) -> [f64; 3] {
    let vn = dot(v, n);
    if vn * vn <= TANGENT_EPS2 * dot(v, v) {
        v
    } else {
        sub(v, scale(vn, n))
    }
}

/// `v` turned into the plane normal to `n` at its length (LAMMPS's `rotate_rescale_vec`): the
/// projection, rescaled to |v| (0 if the projection vanishes).
#[inline(always)]
pub fn rotate_rescale(v: [f64; 3], n: [f64; 3]) -> [f64; 3] {
    let rsht = dot(v, n);
    let mag = len(v);
    let p = sub(v, scale(rsht, n));
    let pm = len(p);
    let s = if pm > 0.0 { mag / pm } else { 0.0 };
    scale(s, p)
}

/// Three history slots as a vector.
#[inline(always)]
pub fn vec3(h: &[f64]) -> [f64; 3] {
    [h[0], h[1], h[2]]
}

/// One step of a spring–dashpot–slider as its energy accounting sees it: the spring as the
/// previous step left it (`xi_before`, stiffness `k_before`), the spring the step advanced from
/// (`xi_start`: turned, rescaled or projected, at the stiffness `k` of this step), the spring it
/// left (`xi_after`), the dashpot `eta` and the velocity `v` the spring advanced with, the force
/// `force` the law returned and whether it was capped (`slid`). A displacement spring in m, N/m,
/// N·s/m, m/s and N; a twist as `[θ, 0, 0]` in rad, N·m/rad, N·m·s/rad, rad/s and N·m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpringStep {
    /// Stiffness at the previous step.
    pub k_before: f64,
    /// The spring the previous step left.
    pub xi_before: [f64; 3],
    /// Stiffness at this step.
    pub k: f64,
    /// The spring this step advanced from.
    pub xi_start: [f64; 3],
    /// The spring this step left.
    pub xi_after: [f64; 3],
    /// Dashpot of this step.
    pub eta: f64,
    /// Velocity the spring advanced with.
    pub v: [f64; 3],
    /// The force (or torque) returned.
    pub force: [f64; 3],
    /// Whether the force was capped.
    pub slid: bool,
}

impl SpringStep {
    /// The step of stiffness `k` = [previous step's, this step's], springs `xi` = [the previous
    /// step's, the start of this one, its end], dashpot `eta`, velocity `v`, returning `force`,
    /// capped or not (`slid`).
    #[inline(always)]
    pub fn new(
        k: [f64; 2],
        xi: [[f64; 3]; 3],
        eta: f64,
        v: [f64; 3],
        force: [f64; 3],
        slid: bool,
    ) -> SpringStep {
        SpringStep {
            k_before: k[0],
            xi_before: xi[0],
            k: k[1],
            xi_start: xi[1],
            xi_after: xi[2],
            eta,
            v,
            force,
            slid,
        }
    }

    /// The step's energy over `dt` (s): elastic k |ξ_after|²/2 (J); power (W) the energy taken
    /// from the bodies' motion and from the spring, per second: W/dt − (E_after − E_before)/dt,
    /// with W the work the bodies did on the contact. Stuck (ξ_after = ξ_start + v dt), that is
    /// η |v|² − (k |ξ_start|²/2 − E_before)/dt: the dashpot, less the energy the changes of the
    /// spring at fixed motion put into it (a growing stiffness, Mindlin's rescaling, LAMMPS's
    /// reset holding the dashpot's share), which no force paid for and which can make the power
    /// negative. Sliding: W = −(F_start + F)·v dt/2 with F_start = −k ξ_start − η v, the force
    /// averaged over the step. A step of no length dissipates nothing.
    #[inline(always)]
    pub fn energy(&self, dt: f64) -> Energy {
        let elastic = 0.5 * self.k * dot(self.xi_after, self.xi_after);
        let before = 0.5 * self.k_before * dot(self.xi_before, self.xi_before);
        if dt <= 0.0 || dt.is_nan() {
            return Energy { power: 0.0, elastic };
        }
        let power = if self.slid {
            let start = sub(scale(-self.k, self.xi_start), scale(self.eta, self.v));
            -0.5 * dot(add(start, self.force), self.v) - (elastic - before) / dt
        } else {
            let start = 0.5 * self.k * dot(self.xi_start, self.xi_start);
            self.eta * dot(self.v, self.v) - (start - before) / dt
        };
        Energy { power, elastic }
    }
}

/// A bound law that reads its contact's normal context (tangential, rolling, twisting): its
/// output with the context given explicitly. The sdk traits' methods call it with the context
/// the host passes.
pub trait ReadsContext<C> {
    /// The output: a force (N) or a torque (N·m).
    type Out: Copy;
    /// The output on contact `c` under context `ctx`, its history `h` advanced, and the step as
    /// its energy sees it.
    fn eval(&self, ctx: &Ctx, c: &C, h: &mut [f64]) -> (Self::Out, SpringStep);
}

/// Implements a kind's sdk trait for a bound law through [`ReadsContext`], with the context
/// the host passes in the contact.
macro_rules! through_context {
    ($trait:ident, $ty:ty, $contact:ty, $out:ty, $call:ident, $energy_call:ident $(, $more:item)*) => {
        impl $trait for $ty {
            $($more)*

            #[inline(always)]
            fn $call(&self, c: &$contact, h: &mut [f64]) -> $out {
                self.eval(&c.context, c, h).0
            }
            #[inline(always)]
            fn $energy_call(&self, c: &$contact, h: &mut [f64]) -> ($out, Option<dashpot_sdk::Energy>) {
                let (o, s) = self.eval(&c.context, c, h);
                (o, Some(s.energy(c.dt)))
            }
        }
    };
}
pub(crate) use through_context;

/// `each_from!(b, from, out, |c, h| output)`: `b.out[i]` = the output on contact `i` of batch
/// `b` (a tangential, rolling or twisting batch; its context the one the host passed, or the
/// default), its history `h` advanced, for the contacts `from..`: the per-contact form, for the
/// contacts the lanes leave (the last `n % 4`) or every contact of a batch that takes none.
macro_rules! each_from {
    ($b:ident, $from:expr, $out:ident, |$c:ident, $h:ident| $eval:expr) => {{
        let slots = $b.slots;
        for i in $from..$b.$out.len() {
            let $c = &$b.contact(i);
            let $h = &mut $b.history[i * slots..(i + 1) * slots];
            $b.$out[i] = $eval;
        }
    }};
}
pub(crate) use each_from;
