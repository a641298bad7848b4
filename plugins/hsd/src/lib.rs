//! Hertz spring with Tsuji damping (HSD): F = K δ^{3/2} + α(ε) √(mK) δ^{1/4} δ̇
//! (Antypov & Elliott 2011, eqs. 9–11, 17).

use dashpot_sdk::{
    BoundContact, CalibrationTarget, Coefficient, Contact, ContactLaw, EndCriterion, Energy, EnergyBatch,
    LawError, MaterialPair, NormalBatch, Pair, ParamValue, Params, Range,
};

/// The exact Tsuji damping factor α(ε) = −√5 ln ε / √(ln²ε + π²) (Antypov & Elliott eq. 17).
pub fn alpha(eps: f64) -> f64 {
    dashpot_sdk::physics::tsuji_alpha(eps)
}

dashpot_sdk::law_params! {
    /// The configured law: restitution `eps`.
    #[derive(Debug, Clone)]
    pub struct Hsd {
        /// coefficient of restitution (contact ends when δ returns to 0)
        eps: f64 { unit: "1", default: 0.54, range: Range::open_closed(0.0, 1.0) },
    }
}

impl Hsd {
    /// The law with restitution `eps` ∈ (0, 1].
    pub fn with(eps: f64) -> Hsd {
        Hsd { eps }
    }
}

/// HSD bound to a pair of materials. Per contact of effective mass m and radius r:
/// K = (4/3) E √r, so K δ^{3/2} = a √(rδ) δ and α √(mK) δ^{1/4} = b √(m √(rδ)), with the
/// constants a = (4/3) E and b = α √((4/3) E): two square roots per contact, as when bound to
/// one pair.
#[derive(Debug, Clone)]
pub struct HsdBound {
    /// (4/3) E_eff (Pa).
    pub a: f64,
    /// α √((4/3) E_eff) (√Pa).
    pub b: f64,
    young: f64,
    alpha: f64,
}

impl ContactLaw for Hsd {
    type Bound = HsdBound;
    const NAME: &'static str = "hsd";
    const SUMMARY: &'static str =
        "Hertz + Tsuji damping: F = K δ^{3/2} + α(ε)√(mK) δ^{1/4} δ̇, exact α(ε) of Antypov & Elliott eq. 17";
    const DOC: &'static str = "Hertzian spring-dashpot (HSD) normal force \
        F = K δ^{3/2} + α(ε) √(m K) δ^{1/4} δ̇ for δ ≥ 0, 0 for δ < 0, with K = (4/3) E_eff √r_eff \
        (eq. 9), m the effective mass and α(ε) = −√5 ln ε / √(ln²ε + π²) (Antypov & Elliott 2011, \
        eq. 17). Its phase trajectory is that of the linear spring-dashpot with k = (2/3) E_eff d \
        mapped by δ_H/d = (5/4)^{2/5} (δ_L/d)^{4/5} (eq. 19), so a collision ending when δ returns \
        to 0 has restitution exactly ε at every impact speed, and its contact time scales as \
        v0^{-1/5}. Calibration in closed form: ε sets eps (the stiffness is the pair's E_eff).";
    const END_CRITERION: EndCriterion = EndCriterion::Overlap;

    fn bind(&self, materials: &MaterialPair) -> Result<HsdBound, LawError> {
        let a = 4.0 / 3.0 * materials.young;
        let alpha = alpha(self.eps);
        Ok(HsdBound {
            a,
            b: alpha * a.sqrt(),
            young: materials.young,
            alpha,
        })
    }

    fn calibrate(
        target: &CalibrationTarget,
        _pair: &Pair,
        _fixed: &Params,
    ) -> Result<Option<Vec<ParamValue>>, LawError> {
        // ε alone has a closed form; a contact time needs the integrator (τ ∝ v0^{-1/5}).
        if target.end != EndCriterion::Overlap || target.contact_time.is_some() {
            return Ok(None);
        }
        Ok(Some(vec![ParamValue::new("eps", target.restitution)]))
    }
}

impl HsdBound {
    /// The spring K δ^{3/2} (N), the dashpot α√(mK) δ^{1/4} δ̇ (N) and the spring's energy
    /// (2/5) K δ^{5/2} (J) at overlap `delta` (m), rate `rate` (m/s), effective mass `mass` (kg)
    /// and radius `radius` (m).
    #[inline(always)]
    fn terms(&self, delta: f64, rate: f64, mass: f64, radius: f64) -> (f64, f64, f64) {
        let d = delta.max(0.0);
        let s1 = (radius * d).sqrt();
        let s2 = (mass * s1).sqrt();
        (self.a * s1 * d, self.b * s2 * rate, 0.4 * self.a * s1 * d * d)
    }
}

impl BoundContact for HsdBound {
    /// Two square roots and a few products, no branch: the sdk evaluates HSD eight contacts at a
    /// time between the checks of the next ones.
    const STRAIGHT_LINE: bool = true;

    #[inline(always)]
    fn force(&self, c: Contact, _history: &mut [f64]) -> f64 {
        let (spring, dashpot, _) = self.terms(c.delta, c.rate, c.mass, c.radius);
        spring + dashpot
    }

    /// Elastic (2/5) K δ^{5/2} (J); power: the damping force α√(mK) δ^{1/4} δ̇ times δ̇ (W).
    #[inline(always)]
    fn energy(&self, c: &Contact, _history: &[f64], _force: f64) -> Option<Energy> {
        let (_, dashpot, elastic) = self.terms(c.delta, c.rate, c.mass, c.radius);
        Some(Energy {
            power: dashpot * c.rate,
            elastic,
        })
    }

    /// The forces with their energy, over plain arrays (a loop the compiler vectorises).
    #[inline(always)]
    fn force_batch_energy(&self, b: NormalBatch<'_>, out: EnergyBatch<'_>) -> bool {
        let n = b.force.len();
        let (d, v, m, r) = (&b.delta[..n], &b.rate[..n], &b.mass[..n], &b.radius[..n]);
        let (p, e) = (&mut out.power[..n], &mut out.elastic[..n]);
        for i in 0..n {
            let (spring, dashpot, elastic) = self.terms(d[i], v[i], m[i], r[i]);
            b.force[i] = spring + dashpot;
            p[i] = dashpot * v[i];
            e[i] = elastic;
        }
        true
    }

    fn coefficients(&self, mass: f64, radius: f64) -> Vec<Coefficient> {
        let k = 4.0 / 3.0 * self.young * radius.sqrt();
        vec![
            Coefficient::new("K", "N/m^(3/2)", k, "Hertz stiffness (4/3) E_eff √r_eff (eq. 9)"),
            Coefficient::new("m", "kg", mass, "effective mass"),
            Coefficient::new(
                "alpha",
                "1",
                self.alpha,
                "Tsuji factor −√5 ln ε/√(ln²ε+π²) (eq. 17)",
            ),
            Coefficient::new(
                "c",
                "N·s/m^(5/4)",
                self.alpha * (mass * k).sqrt(),
                "damping coefficient α√(mK) (eq. 10)",
            ),
            Coefficient::new("Omega0", "1/(s·m^(1/4))", (k / mass).sqrt(), "√(K/m) (eq. 11)"),
        ]
    }
}

dashpot_sdk::export_laws!(contact: [Hsd]);

#[cfg(test)]
mod tests {
    use super::*;
    use dashpot_sdk::abi::{EnergyOut, Normal, NormalCall, StaticModel};
    use dashpot_sdk::NormalBatch;
    use dashpot_testkit::{uniform, STEEL_6MM};

    /// The batch through the sdk's checked trampoline (the pipelined loop for its full blocks of
    /// 64, the plain one for the rest; the AVX2 build when the CPU has it) gives, bit for bit,
    /// the closed form as HSD evaluates it contact by contact, d = max(δ, 0), s1 = √(r d),
    /// s2 = √(m s1), F = a s1 d + b s2 δ̇, its power b s2 δ̇² and elastic energy (2/5) a s1 d²,
    /// on batches of every length around the block size, polydisperse, overlaps of both signs.
    #[test]
    fn the_batch_is_the_closed_form_bit_for_bit() {
        let mat = MaterialPair::spheres(&STEEL_6MM, &STEEL_6MM).expect("materials");
        let model = StaticModel::<Normal, HsdBound>::bind(&Hsd::with(0.54), &mat).expect("bind");
        let law = Hsd::with(0.54).bind(&mat).expect("bind");
        let mut rnd = uniform(0x9e37_79b9_7f4a_7c15_u64);
        for n in [1, 63, 64, 65, 127, 128, 640, 1000, 1024 + 7] {
            let delta: Vec<f64> = (0..n).map(|_| 1.2e-5 * rnd() - 2e-6).collect();
            let rate: Vec<f64> = (0..n).map(|_| 2.0 * rnd() - 1.0).collect();
            let mass: Vec<f64> = (0..n).map(|_| 1e-4 + 1e-3 * rnd()).collect();
            let radius: Vec<f64> = (0..n).map(|_| 1e-3 + 4e-3 * rnd()).collect();
            for energy in [false, true] {
                let (mut f, mut p, mut e) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
                let call = NormalCall {
                    batch: NormalBatch {
                        delta: &delta,
                        rate: &rate,
                        mass: &mass,
                        radius: &radius,
                        slots: 0,
                        history: &mut [],
                        force: &mut f,
                    },
                    reach: None,
                    context: None,
                };
                let out = if energy {
                    EnergyOut {
                        power: Some(&mut p),
                        elastic: Some(&mut e),
                    }
                } else {
                    EnergyOut::none()
                };
                assert_eq!(model.batch(call, out).expect("batch"), energy);
                for i in 0..n {
                    let d = delta[i].max(0.0);
                    let s1 = (radius[i] * d).sqrt();
                    let s2 = (mass[i] * s1).sqrt();
                    let want = law.a * s1 * d + law.b * s2 * rate[i];
                    assert_eq!(f[i].to_bits(), want.to_bits(), "n {n}, contact {i}");
                    let c = Contact {
                        delta: delta[i],
                        rate: rate[i],
                        mass: mass[i],
                        radius: radius[i],
                    };
                    assert_eq!(law.force(c, &mut []).to_bits(), want.to_bits());
                    if energy {
                        let power = law.b * s2 * rate[i] * rate[i];
                        let elastic = 0.4 * law.a * s1 * d * d;
                        assert_eq!(p[i].to_bits(), power.to_bits(), "n {n}, power {i}");
                        assert_eq!(e[i].to_bits(), elastic.to_bits(), "n {n}, elastic {i}");
                    }
                }
            }
        }
    }
}
