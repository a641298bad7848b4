//! The normal and damping sub-models of LAMMPS's `pair_style granular`, as pure functions of a
//! contact's overlap δ (m), its rate δ̇ (m/s, > 0 approaching), effective mass m (kg) and radius
//! R (m), in LAMMPS's order of operations, so that the results are LAMMPS's to the bit.
//!
//! One contact's evaluation ([`evaluate`]) is LAMMPS's `GranularModel::calculate_forces` up to
//! the tangential model: the contact radius a, the elastic force F_ne (adhesion included), the
//! damping prefactor η_n, the total normal force F_n = F_ne + η_n δ̇ (clamped at 0 under
//! `limit_damping`), and the force the Coulomb caps of the other families scale with, F_c
//! (LAMMPS's `Fncrit`: |F_n|, or |F_ne + 2 F_pulloff| for the cohesive models).

use crate::cbrt::cbrt;
use std::f64::consts::PI;

/// 27 π² (LAMMPS's `PI27SQ`).
pub(crate) const PI27SQ: f64 = 266.47931882941265;
/// 3 √3.
pub(crate) const THREEROOT3: f64 = 5.196152422706632;
/// 6 √6.
pub(crate) const SIXROOT6: f64 = 14.696938456699067;
/// 1/√6.
pub(crate) const INVROOT6: f64 = 0.4082482904638631;
/// (3π²/16)^{1/3}: the JKR pull-off distance over (R γ²/E²)^{1/3}.
pub(crate) const JKRPREFIX: f64 = 1.2277228507842888;
/// 4/3 as LAMMPS writes it (`FOURTHIRDS`).
pub const FOURTHIRDS: f64 = 1.3333333333333333;
/// √(3/2) (coefficient of restitution damping of the non-Hookean models).
const ROOTTHREEBYTWO: f64 = 1.224744871391589;
/// 2 √(5/6) (the same).
const TWOROOTFIVEBYSIX: f64 = 1.8257418583505538;

/// Which lane form (`normal_avx2`) a normal or damping model has: [`lane::NONE`] for none.
pub mod lane {
    /// No lane form: contact by contact.
    pub const NONE: u8 = 0;
    /// `hooke`.
    pub const HOOKE: u8 = 1;
    /// `hertz`, `hertz/material`.
    pub const HERTZ: u8 = 2;
    /// `dmt`.
    pub const DMT: u8 = 3;
    /// `jkr`.
    pub const JKR: u8 = 4;
    /// damping `velocity`.
    pub const VELOCITY: u8 = 5;
    /// damping `mass_velocity`.
    pub const MASS_VELOCITY: u8 = 6;
    /// damping `viscoelastic`.
    pub const VISCOELASTIC: u8 = 7;
    /// damping `tsuji`, `coeff_restitution`: c √(max(0, m F_ne/δ)).
    pub const ROOT: u8 = 8;
}

/// A normal sub-model of LAMMPS bound to its constants: contact radius, elastic force, energy.
pub trait NormalModel: Copy + Send + Sync + 'static {
    /// Its lane form ([`lane`]).
    const LANE: u8 = lane::NONE;

    /// Its constants as its lane form reads them: k, E_eff (JKR) and γ (DMT, JKR).
    fn lane_constants(&self) -> [f64; 3] {
        [0.0; 3]
    }

    /// Whether the model is adhesive (LAMMPS's `cohesive_flag`: `dmt`, `jkr`): its cap force is
    /// |F_ne + 2 F_pulloff|, and LAMMPS refuses `tsuji`, `coeff_restitution` and
    /// `limit_damping` with it.
    const COHESIVE: bool;
    /// Whether it is LAMMPS's `hooke` (the `coeff_restitution` damping depends on it).
    const HOOKE: bool = false;

    /// The contact radius a (m) at overlap `delta` (m, may be < 0 for JKR) of a contact of
    /// effective radius `reff` (m): √(δ R) (LAMMPS computes dR = δ R first).
    #[inline(always)]
    fn contact_radius(&self, delta: f64, reff: f64) -> f64 {
        (delta * reff).sqrt()
    }

    /// The elastic force F_ne (N, > 0 repulsive, adhesion included) and the pull-off force
    /// F_pulloff (N, 0 for a non-cohesive model) at contact radius `a` (m) and overlap `delta`.
    fn elastic(&self, a: f64, delta: f64, reff: f64) -> (f64, f64);

    /// The elastic energy (J) the contact gives back when unloaded from overlap `delta` (contact
    /// radius `a`) to its end: ∫ F_ne dδ from the end of contact (δ = 0, or JKR's pull-off
    /// distance) to δ.
    fn elastic_energy(&self, a: f64, delta: f64, reff: f64) -> f64;

    /// How far beyond touching (m, ≥ 0) a formed contact still acts: 0 but for JKR.
    #[inline(always)]
    fn pulloff_distance(&self, _reff: f64) -> f64 {
        0.0
    }

    /// Whether the contact acts at overlap `delta` (LAMMPS's `touch`), given whether it acted
    /// at the last step (`touching`): δ > 0; JKR's formed contact down to its pull-off distance.
    #[inline(always)]
    fn touches(&self, delta: f64, reff: f64, touching: bool) -> bool {
        let _ = (reff, touching);
        delta > 0.0
    }
}

/// LAMMPS `hooke k`: F_ne = k δ (k in N/m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hooke {
    /// Stiffness k (N/m).
    pub k: f64,
}

impl NormalModel for Hooke {
    const COHESIVE: bool = false;
    const HOOKE: bool = true;
    const LANE: u8 = lane::HOOKE;

    fn lane_constants(&self) -> [f64; 3] {
        [self.k, 0.0, 0.0]
    }

    #[inline(always)]
    fn elastic(&self, _a: f64, delta: f64, _reff: f64) -> (f64, f64) {
        (self.k * delta, 0.0)
    }

    #[inline(always)]
    fn elastic_energy(&self, _a: f64, delta: f64, _reff: f64) -> f64 {
        0.5 * self.k * delta * delta
    }
}

/// LAMMPS `hertz k` (k in N/m²) and `hertz/material E damp ν` (k = (4/3) E_eff): F_ne = k a δ,
/// a = √(δ R).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hertz {
    /// Stiffness k (N/m²).
    pub k: f64,
}

impl NormalModel for Hertz {
    const COHESIVE: bool = false;
    const LANE: u8 = lane::HERTZ;

    fn lane_constants(&self) -> [f64; 3] {
        [self.k, 0.0, 0.0]
    }

    #[inline(always)]
    fn elastic(&self, a: f64, delta: f64, _reff: f64) -> (f64, f64) {
        (self.k * a * delta, 0.0)
    }

    /// (2/5) k a δ², the integral of k √R δ^{3/2}.
    #[inline(always)]
    fn elastic_energy(&self, a: f64, delta: f64, _reff: f64) -> f64 {
        0.4 * self.k * a * delta * delta
    }
}

/// LAMMPS `dmt E damp ν γ`: F_ne = k a δ − 4π γ R, k = (4/3) E_eff, acting while δ > 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dmt {
    /// Stiffness k = (4/3) E_eff (Pa).
    pub k: f64,
    /// Surface energy γ (J/m², LAMMPS's `cohesion`).
    pub cohesion: f64,
}

impl NormalModel for Dmt {
    const COHESIVE: bool = true;
    const LANE: u8 = lane::DMT;

    fn lane_constants(&self) -> [f64; 3] {
        [self.k, 0.0, self.cohesion]
    }

    #[inline(always)]
    fn elastic(&self, a: f64, delta: f64, reff: f64) -> (f64, f64) {
        let pulloff = 4.0 * PI * self.cohesion * reff;
        (self.k * a * delta - pulloff, pulloff)
    }

    /// (2/5) k a δ² − 4π γ R δ: the work given back on unloading to δ = 0, where the contact ends
    /// (negative when adhesion dominates: separating then takes work).
    #[inline(always)]
    fn elastic_energy(&self, a: f64, delta: f64, reff: f64) -> f64 {
        0.4 * self.k * a * delta * delta - 4.0 * PI * self.cohesion * reff * delta
    }
}

/// LAMMPS `jkr E damp ν γ`: F_ne = k a³/R − 2π a² √(4γE/(π a)), k = (4/3) E_eff, with a the
/// JKR contact radius at δ; the contact forms at touch and ends at the pull-off distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jkr {
    /// Stiffness k = (4/3) E_eff (Pa).
    pub k: f64,
    /// Effective Young's modulus E_eff (Pa, LAMMPS's `Emix`).
    pub emix: f64,
    /// Surface energy γ (J/m², LAMMPS's `cohesion`).
    pub cohesion: f64,
}

impl Jkr {
    /// The JKR contact radius a (m) at dR = δ R (m²): the closed-form root of
    /// δ = a²/R − 2 √(π γ a/E) (LAMMPS's `calculate_contact_radius`, same operations).
    #[inline(always)]
    pub fn radius_at(&self, reff: f64, dr: f64) -> f64 {
        let (coh, e) = (self.cohesion, self.emix);
        let r2 = reff * reff;
        let dr2 = dr * dr;
        let t0 = coh * coh * r2 * r2 * e;
        let t1 = PI27SQ * t0;
        let t2 = 8.0 * dr * dr2 * e * e * e;
        let t3 = 4.0 * dr2 * e;
        let sqrt1 = lmax(0.0, t0 * (t1 + 2.0 * t2));
        let t4 = cbrt(t1 + t2 + THREEROOT3 * PI * sqrt1.sqrt());
        let t5 = t3 / t4 + t4 / e;
        let sqrt2 = lmax(0.0, 2.0 * dr + t5);
        let t6 = sqrt2.sqrt();
        let sqrt3 = lmax(0.0, 4.0 * dr - t5 + SIXROOT6 * coh * PI * r2 / (e * t6));
        INVROOT6 * (t6 + sqrt3.sqrt())
    }

    /// W(a) = ∫ F_ne dδ along the JKR curve (J, up to a constant): 8E a⁵/(15R²) −
    /// (8/(3R)) √(πγE) a^{7/2} + 2πγ a².
    fn work(&self, a: f64, reff: f64) -> f64 {
        let e = self.emix;
        let s = (PI * self.cohesion * e).sqrt();
        8.0 * e * a.powi(5) / (15.0 * reff * reff) - 8.0 / (3.0 * reff) * s * a.powf(3.5)
            + 2.0 * PI * self.cohesion * a * a
    }
}

impl NormalModel for Jkr {
    const COHESIVE: bool = true;
    const LANE: u8 = lane::JKR;

    fn lane_constants(&self) -> [f64; 3] {
        [self.k, self.emix, self.cohesion]
    }

    #[inline(always)]
    fn contact_radius(&self, delta: f64, reff: f64) -> f64 {
        self.radius_at(reff, delta * reff)
    }

    #[inline(always)]
    fn elastic(&self, a: f64, _delta: f64, reff: f64) -> (f64, f64) {
        let a2 = a * a;
        let fne =
            self.k * a * a2 / reff - 2.0 * PI * a2 * (4.0 * self.cohesion * self.emix / (PI * a)).sqrt();
        (fne, 3.0 * PI * self.cohesion * reff)
    }

    /// W(a) − W(a_t), a_t the contact radius at touch (δ = 0), where the contact forms: nothing
    /// appears as it forms, the energy integrates the force, and at the pull-off distance it holds
    /// the cycle's adhesion hysteresis W(a_po) − W(a_t), which a host books as dissipated when the
    /// contact ends (as for dashpot's own `jkr`).
    fn elastic_energy(&self, a: f64, _delta: f64, reff: f64) -> f64 {
        let touch = self.radius_at(reff, 0.0);
        self.work(a, reff) - self.work(touch, reff)
    }

    /// (3π²/16)^{1/3} (R γ²/E²)^{1/3} (LAMMPS's `pulloff_distance`): where the tensile force is
    /// largest, −3π γ R = −(3/2) π w R (w = 2γ).
    #[inline(always)]
    fn pulloff_distance(&self, reff: f64) -> f64 {
        if reff <= 0.0 {
            return 0.0;
        }
        JKRPREFIX * cbrt(reff * self.cohesion * self.cohesion / (self.emix * self.emix))
    }

    #[inline(always)]
    fn touches(&self, delta: f64, reff: f64, touching: bool) -> bool {
        // an overlapping contact acts either way: the pull-off distance (a cube root) is
        // needed only for a formed contact pulled apart beyond touching
        delta > 0.0 || (touching && delta > -self.pulloff_distance(reff))
    }
}

/// C's `MAX(a, b)`: `a > b ? a : b`.
#[inline(always)]
pub(crate) fn lmax(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// C's `MIN(a, b)`: `a < b ? a : b`.
#[inline(always)]
pub(crate) fn lmin(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

/// x^n by squaring, as LAMMPS's `MathSpecial::powint` (n ≥ 0).
fn powint(x: f64, n: u32) -> f64 {
    if n == 0 {
        return 1.0;
    }
    if x == 0.0 {
        return 0.0;
    }
    let (mut yy, mut ww, mut nn) = (1.0, x, n);
    while nn != 0 {
        if nn & 1 == 1 {
            yy *= ww;
        }
        nn >>= 1;
        ww *= ww;
    }
    yy
}

/// A damping sub-model of LAMMPS: its coefficient (from the `damp` parameter, once) and its
/// prefactor η_n (N·s/m) at a contact; the damping force is η_n δ̇.
pub trait DampingModel: Copy + Send + Sync + 'static {
    /// Its lane form ([`lane`]).
    const LANE: u8 = lane::NONE;

    /// Whether LAMMPS refuses it with a cohesive normal model (`allow_cohesion = 0`).
    const REFUSES_COHESION: bool = false;

    /// The coefficient LAMMPS derives from the normal model's `damp` (`init`): `damp` itself,
    /// or the Tsuji and restitution factors; `hooke` says whether the normal model is `hooke`.
    fn coefficient(damp: f64, hooke: bool) -> f64 {
        let _ = hooke;
        damp
    }

    /// The prefactor η_n (N·s/m) from the coefficient `c`, effective mass `meff` (kg), contact
    /// radius `a` (m), elastic force `fnormal` (N) and overlap `delta` (m).
    fn prefactor(c: f64, meff: f64, a: f64, fnormal: f64, delta: f64) -> f64;
}

/// LAMMPS `damping velocity`: η_n = damp (N·s/m).
#[derive(Debug, Clone, Copy)]
pub struct Velocity;
/// LAMMPS `damping mass_velocity`: η_n = damp m (damp in 1/s).
#[derive(Debug, Clone, Copy)]
pub struct MassVelocity;
/// LAMMPS `damping viscoelastic` (its default): η_n = damp m a (damp in 1/(m·s)).
#[derive(Debug, Clone, Copy)]
pub struct Viscoelastic;
/// LAMMPS `damping tsuji`: η_n = α(e) √(m F_ne/δ), α the fit of Marshall (2009, eq. 53) to
/// Tsuji's damping, `damp` = e the restitution.
#[derive(Debug, Clone, Copy)]
pub struct Tsuji;
/// LAMMPS `damping coeff_restitution`: η_n = β(e) √(m F_ne/δ), β = −2 ln e/√(π² + ln² e) for
/// `hooke`, −√5 ln e/√(π² + ln² e) otherwise: the restitution e at every impact speed.
#[derive(Debug, Clone, Copy)]
pub struct CoeffRestitution;

impl DampingModel for Velocity {
    const LANE: u8 = lane::VELOCITY;

    #[inline(always)]
    fn prefactor(c: f64, _meff: f64, _a: f64, _fnormal: f64, _delta: f64) -> f64 {
        c
    }
}

impl DampingModel for MassVelocity {
    const LANE: u8 = lane::MASS_VELOCITY;

    #[inline(always)]
    fn prefactor(c: f64, meff: f64, _a: f64, _fnormal: f64, _delta: f64) -> f64 {
        c * meff
    }
}

impl DampingModel for Viscoelastic {
    const LANE: u8 = lane::VISCOELASTIC;

    #[inline(always)]
    fn prefactor(c: f64, meff: f64, a: f64, _fnormal: f64, _delta: f64) -> f64 {
        c * meff * a
    }
}

/// √(max(0, m F/δ)) for δ > 0, else 0: the stiffness-based factor of `tsuji` and
/// `coeff_restitution`.
#[inline(always)]
fn tsuji_root(meff: f64, fnormal: f64, delta: f64) -> f64 {
    let s = if delta > 0.0 {
        lmax(0.0, meff * fnormal / delta)
    } else {
        0.0
    };
    s.sqrt()
}

impl DampingModel for Tsuji {
    const REFUSES_COHESION: bool = true;
    const LANE: u8 = lane::ROOT;

    fn coefficient(e: f64, _hooke: bool) -> f64 {
        let mut d = 1.2728 - 4.2783 * e + 11.087 * (e * e);
        d += -22.348 * (e * e * e) + 27.467 * powint(e, 4);
        d += -18.022 * powint(e, 5) + 4.8218 * powint(e, 6);
        d
    }

    #[inline(always)]
    fn prefactor(c: f64, meff: f64, _a: f64, fnormal: f64, delta: f64) -> f64 {
        c * tsuji_root(meff, fnormal, delta)
    }
}

impl DampingModel for CoeffRestitution {
    const REFUSES_COHESION: bool = true;
    const LANE: u8 = lane::ROOT;

    fn coefficient(e: f64, hooke: bool) -> f64 {
        let l = e.ln();
        if hooke {
            -2.0 * l / (PI * PI + l * l).sqrt()
        } else {
            -ROOTTHREEBYTWO * TWOROOTFIVEBYSIX * l / (PI * PI + l * l).sqrt()
        }
    }

    #[inline(always)]
    fn prefactor(c: f64, meff: f64, _a: f64, fnormal: f64, delta: f64) -> f64 {
        c * tsuji_root(meff, fnormal, delta)
    }
}

/// What the normal and damping models give at one contact, and the other families read.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NormalEval {
    /// Contact radius a (m).
    pub contact_radius: f64,
    /// Elastic force F_ne (N), adhesion included (LAMMPS's `Fnormal`).
    pub elastic: f64,
    /// Pull-off force F_pulloff (N; 0 for a non-cohesive model).
    pub pulloff: f64,
    /// Damping prefactor η_n (N·s/m, LAMMPS's `damp_prefactor`).
    pub damping: f64,
    /// Total normal force F_n = F_ne + η_n δ̇ (N, > 0 repulsive), 0 where `limit_damping` clamps it.
    pub force: f64,
    /// The cap force F_c (N, LAMMPS's `Fncrit`).
    pub cap: f64,
}

/// One contact's normal force as LAMMPS computes it: model `n` with damping `D` of coefficient
/// `c` ([`DampingModel::coefficient`]) and `limit_damping` flag `limit`, at overlap `delta` (m),
/// rate `rate` (m/s, > 0 approaching; LAMMPS's −v_nn), effective mass `meff` (kg) and radius
/// `reff` (m). The caller decides that the contact is active (δ > 0, or JKR's formed contact).
#[inline(always)]
pub fn evaluate<N: NormalModel, D: DampingModel>(
    n: &N,
    c: f64,
    limit: bool,
    delta: f64,
    rate: f64,
    meff: f64,
    reff: f64,
) -> NormalEval {
    let a = n.contact_radius(delta, reff);
    let (fne, pulloff) = n.elastic(a, delta, reff);
    let damping = D::prefactor(c, meff, a, fne, delta);
    let mut force = fne + damping * rate;
    if limit && force < 0.0 {
        force = 0.0;
    }
    let cap = if N::COHESIVE {
        (fne + 2.0 * pulloff).abs()
    } else {
        force.abs()
    };
    NormalEval {
        contact_radius: a,
        elastic: fne,
        pulloff,
        damping,
        force,
        cap,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn powint_is_repeated_squaring_and_agrees_with_powi_to_rounding() {
        for x in [0.0, 0.3, 0.9, 1.0, 1.7] {
            for n in 0..7 {
                let p = powint(x, n);
                assert!(
                    (p - x.powi(n as i32)).abs() <= 4.0 * f64::EPSILON * p.abs(),
                    "{x}^{n}"
                );
            }
        }
    }

    #[test]
    fn tsuji_fit_is_nearly_undamped_at_one_and_restitution_damping_vanishes_there() {
        assert!(Tsuji::coefficient(1.0, false).abs() < 1e-3);
        assert_eq!(CoeffRestitution::coefficient(1.0, true), 0.0);
        // the non-Hookean factor is √5 times the Hookean ζ (Antypov & Elliott's α(ε) = √5 ζ(ε))
        let e = 0.6;
        let r = CoeffRestitution::coefficient(e, false) / CoeffRestitution::coefficient(e, true);
        assert!((r - 0.5 * 5f64.sqrt()).abs() < 1e-15, "{r}");
    }

    #[test]
    fn jkr_radius_solves_the_jkr_overlap_relation() {
        let j = Jkr {
            k: FOURTHIRDS * 5e7,
            emix: 5e7,
            cohesion: 0.05,
        };
        let r = 2.7e-4;
        let po = j.pulloff_distance(r);
        for delta in [-po, -0.5 * po, 0.0, 3e-7, 4e-6] {
            let a = j.contact_radius(delta, r);
            let d = a * a / r - 2.0 * (PI * j.cohesion * a / j.emix).sqrt();
            assert!((d - delta).abs() < 1e-12 * r, "{delta}: {d}");
        }
    }
}
