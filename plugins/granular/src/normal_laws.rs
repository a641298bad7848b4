//! The normal laws `gran-NORMAL-DAMPING`: one generic law over LAMMPS's normal model (its
//! parameters and how it binds: [`NormalSpec`]) and damping model ([`DampingSpec`]); a macro
//! names each of the 21 combinations LAMMPS accepts.

use crate::calibrate::Calibrate;
use crate::docs::*;
use crate::normal::{
    evaluate, lane, CoeffRestitution, DampingModel, Dmt, Hertz, Hooke, Jkr, MassVelocity, NormalEval,
    NormalModel, Tsuji, Velocity, Viscoelastic, FOURTHIRDS,
};
use crate::spring::Ctx;
use dashpot_sdk::{
    BoundContact, CalibrationTarget, Coefficient, Contact, ContactLaw, EndCriterion, Energy, History,
    LawError, LawParams, MaterialPair, NormalBatch, Pair, ParamSpec, ParamValue, Params, Range,
};
use std::marker::PhantomData;

/// A LAMMPS normal model as a law sees it: its parameters besides `damp` (read from the
/// validated values), how it binds to the materials, and its history.
pub trait NormalSpec: Sized + Clone + Send + Sync + 'static {
    /// The bound kernel.
    type Model: NormalModel;
    /// The history the law keeps.
    const HISTORY: &'static [History] = &[];
    /// The schema, `damp` (the damping model's) placed where LAMMPS puts it.
    fn schema(damp: ParamSpec) -> Vec<ParamSpec>;
    /// The model's own parameters from validated values.
    fn read(p: &Params, law: &str) -> Result<Self, LawError>;
    /// The kernel bound to the materials.
    fn bind(&self, m: &MaterialPair) -> Self::Model;
    /// `limit_damping` (the cohesive models have none).
    fn limit(&self) -> bool {
        false
    }
}

/// The name of a law, for the parameter errors of a generic law.
pub trait LawName {
    /// The law's name.
    const NAME: &'static str;
}

/// A required parameter: its value, or an error naming it, its unit and its range.
pub(crate) fn required(p: &Params, law: &str, name: &str, what: &str) -> Result<f64, LawError> {
    p.get_opt(name)?.ok_or_else(|| {
        LawError::invalid_parameter(format!(
            "law '{law}' needs '{name}' ({what}): LAMMPS has no default for it"
        ))
    })
}

/// `limit_damping`: 0 or 1.
fn limit_spec() -> ParamSpec {
    ParamSpec::new(
        "limit_damping",
        "1",
        0.0,
        Range::closed(0.0, 1.0),
        "1: clamp a negative (attractive) total normal force to 0, LAMMPS's `limit_damping` keyword; 0: not",
    )
}

fn read_limit(p: &Params, law: &str) -> Result<bool, LawError> {
    match p.get("limit_damping")? {
        0.0 => Ok(false),
        1.0 => Ok(true),
        v => Err(LawError::invalid_parameter(format!(
            "parameter 'limit_damping' of law '{law}' = {v}: it must be 0 or 1"
        ))),
    }
}

/// A normal model whose stiffness is a parameter (`hooke k`, `hertz k`).
pub trait GivenStiffness: NormalModel {
    /// The unit of k.
    const UNIT: &'static str;
    /// The parameter's documentation.
    const DOC: &'static str;
    /// The model of stiffness `k`.
    fn with_k(k: f64) -> Self;
}

impl GivenStiffness for Hooke {
    const UNIT: &'static str = "N/m";
    const DOC: &'static str = "normal stiffness k (required): F = k δ";
    fn with_k(k: f64) -> Hooke {
        Hooke { k }
    }
}

impl GivenStiffness for Hertz {
    const UNIT: &'static str = "N/m^2";
    const DOC: &'static str = "normal stiffness k (required): F = k a δ";
    fn with_k(k: f64) -> Hertz {
        Hertz { k }
    }
}

/// `hooke k` and `hertz k`: the stiffness and `limit_damping`.
#[derive(Debug, Clone, PartialEq)]
pub struct StiffnessSpec<M> {
    /// k (N/m for hooke, N/m² for hertz).
    pub k: f64,
    /// `limit_damping`.
    pub limit: bool,
    model: PhantomData<M>,
}

/// `hooke k`.
pub type HookeSpec = StiffnessSpec<Hooke>;
/// `hertz k`.
pub type HertzSpec = StiffnessSpec<Hertz>;

impl<M: GivenStiffness> NormalSpec for StiffnessSpec<M> {
    type Model = M;
    fn schema(damp: ParamSpec) -> Vec<ParamSpec> {
        vec![
            ParamSpec::derived("k", M::UNIT, Range::positive(), M::DOC),
            damp,
            limit_spec(),
        ]
    }
    fn read(p: &Params, law: &str) -> Result<Self, LawError> {
        Ok(StiffnessSpec {
            k: required(p, law, "k", &format!("{}, > 0", M::UNIT))?,
            limit: read_limit(p, law)?,
            model: PhantomData,
        })
    }
    fn bind(&self, _m: &MaterialPair) -> M {
        M::with_k(self.k)
    }
    fn limit(&self) -> bool {
        self.limit
    }
}

/// `hertz/material E damp ν`: k = (4/3) E_eff from the materials.
#[derive(Debug, Clone, PartialEq)]
pub struct HertzMaterialSpec {
    /// `limit_damping`.
    pub limit: bool,
}

impl NormalSpec for HertzMaterialSpec {
    type Model = Hertz;
    fn schema(damp: ParamSpec) -> Vec<ParamSpec> {
        vec![damp, limit_spec()]
    }
    fn read(p: &Params, law: &str) -> Result<Self, LawError> {
        Ok(HertzMaterialSpec {
            limit: read_limit(p, law)?,
        })
    }
    fn bind(&self, m: &MaterialPair) -> Hertz {
        Hertz {
            k: FOURTHIRDS * m.young,
        }
    }
    fn limit(&self) -> bool {
        self.limit
    }
}

/// The `cohesion` parameter of `dmt` and `jkr`.
fn cohesion_spec() -> ParamSpec {
    ParamSpec::derived(
        "cohesion",
        "J/m^2",
        Range::non_negative(),
        "surface energy γ (required), LAMMPS's `cohesion` (the work of adhesion is 2γ)",
    )
}

/// An adhesive normal model (`dmt`, `jkr`): bound to the materials and its surface energy.
pub trait Adhesive: NormalModel {
    /// The history the law keeps.
    const HISTORY: &'static [History];
    /// The model for materials `m` and surface energy `cohesion` (J/m²).
    fn with(m: &MaterialPair, cohesion: f64) -> Self;
}

impl Adhesive for Dmt {
    const HISTORY: &'static [History] = &[];
    fn with(m: &MaterialPair, cohesion: f64) -> Dmt {
        Dmt {
            k: FOURTHIRDS * m.young,
            cohesion,
        }
    }
}

impl Adhesive for Jkr {
    const HISTORY: &'static [History] = &[History::new(
        "touch",
        "1",
        "1 while the contact acts (from touch to the pull-off distance), else 0",
    )];
    fn with(m: &MaterialPair, cohesion: f64) -> Jkr {
        Jkr {
            k: FOURTHIRDS * m.young,
            emix: m.young,
            cohesion,
        }
    }
}

/// `dmt E damp ν γ` and `jkr E damp ν γ`: the surface energy.
#[derive(Debug, Clone, PartialEq)]
pub struct AdhesiveSpec<M> {
    /// γ (J/m²).
    pub cohesion: f64,
    model: PhantomData<M>,
}

/// `dmt E damp ν γ`.
pub type DmtSpec = AdhesiveSpec<Dmt>;
/// `jkr E damp ν γ`.
pub type JkrSpec = AdhesiveSpec<Jkr>;

impl<M: Adhesive> NormalSpec for AdhesiveSpec<M> {
    type Model = M;
    const HISTORY: &'static [History] = M::HISTORY;
    fn schema(damp: ParamSpec) -> Vec<ParamSpec> {
        vec![damp, cohesion_spec()]
    }
    fn read(p: &Params, law: &str) -> Result<Self, LawError> {
        Ok(AdhesiveSpec {
            cohesion: required(p, law, "cohesion", "J/m^2, >= 0")?,
            model: PhantomData,
        })
    }
    fn bind(&self, m: &MaterialPair) -> M {
        M::with(m, self.cohesion)
    }
}

/// A LAMMPS damping model as a law sees it: its `damp` parameter.
pub trait DampingSpec: DampingModel {
    /// The `damp` parameter: unit, range, default and meaning for this model.
    fn damp() -> ParamSpec;
}

impl DampingSpec for Velocity {
    fn damp() -> ParamSpec {
        ParamSpec::new(
            "damp",
            "N*s/m",
            0.0,
            Range::non_negative(),
            "normal damping η_n = damp",
        )
    }
}
impl DampingSpec for MassVelocity {
    fn damp() -> ParamSpec {
        ParamSpec::new(
            "damp",
            "1/s",
            0.0,
            Range::non_negative(),
            "normal damping η_n = damp m",
        )
    }
}
impl DampingSpec for Viscoelastic {
    fn damp() -> ParamSpec {
        ParamSpec::new(
            "damp",
            "1/(m*s)",
            0.0,
            Range::non_negative(),
            "normal damping η_n = damp m a",
        )
    }
}
impl DampingSpec for Tsuji {
    fn damp() -> ParamSpec {
        ParamSpec::new(
            "damp",
            "1",
            1.0,
            Range::closed(0.0, 1.0),
            "restitution e of the Tsuji damping η_n = α(e) √(m F/δ) (1: nearly undamped)",
        )
    }
}
impl DampingSpec for CoeffRestitution {
    fn damp() -> ParamSpec {
        ParamSpec::new(
            "damp",
            "1",
            1.0,
            Range::open_closed(0.0, 1.0),
            "restitution e the damping realizes (1: undamped)",
        )
    }
}

/// A `gran-NORMAL-DAMPING` law, configured: the normal model's parameters, `damp`, and the
/// damping model `D`.
#[derive(Debug, Clone, PartialEq)]
pub struct GranNormal<S, D> {
    /// The normal model's own parameters.
    pub spec: S,
    /// `damp`: the damping coefficient, or the restitution e for `tsuji` and
    /// `coeff_restitution`.
    pub damp: f64,
    damping: PhantomData<D>,
}

impl<S, D> GranNormal<S, D> {
    /// The law of normal parameters `spec` and damping parameter `damp`.
    pub fn new(spec: S, damp: f64) -> Self {
        GranNormal {
            spec,
            damp,
            damping: PhantomData,
        }
    }
}

impl<S: NormalSpec, D: DampingSpec> LawParams for GranNormal<S, D>
where
    Self: LawName,
{
    fn schema() -> Vec<ParamSpec> {
        S::schema(D::damp())
    }
    fn from_params(p: &Params) -> Result<Self, LawError> {
        Ok(GranNormal::new(
            S::read(p, <Self as LawName>::NAME)?,
            p.get("damp")?,
        ))
    }
}

/// A `gran-*` normal law bound to a pair of materials.
#[derive(Debug, Clone, Copy)]
pub struct GranNormalBound<M, D> {
    /// The normal model's kernel.
    pub model: M,
    /// The damping coefficient ([`DampingModel::coefficient`]).
    pub coef: f64,
    /// `limit_damping`.
    pub limit: bool,
    damping: PhantomData<D>,
}

impl<M: NormalModel, D: DampingModel> GranNormalBound<M, D> {
    /// The kernel `model` with damping coefficient `coef` and `limit_damping` flag `limit`.
    pub fn new(model: M, coef: f64, limit: bool) -> Self {
        GranNormalBound {
            model,
            coef,
            limit,
            damping: PhantomData,
        }
    }

    /// Whether contact `c` acts, its history (JKR's `touch`) updated.
    #[inline(always)]
    fn touches(&self, c: &Contact, history: &mut [f64]) -> bool {
        let touching = history.first().is_some_and(|&t| t != 0.0);
        let t = self.model.touches(c.delta, c.radius, touching);
        if let Some(h) = history.first_mut() {
            *h = f64::from(u8::from(t));
        }
        t
    }

    /// The whole evaluation at contact `c` (whether it acts is the caller's).
    #[inline(always)]
    pub fn eval(&self, c: &Contact) -> NormalEval {
        evaluate::<M, D>(
            &self.model,
            self.coef,
            self.limit,
            c.delta,
            c.rate,
            c.mass,
            c.radius,
        )
    }

    /// Whether contact `c` acts with `history` as the last force call left it.
    #[inline(always)]
    fn acting(&self, c: &Contact, history: &[f64]) -> bool {
        match history.first() {
            Some(&t) => t != 0.0,
            None => c.delta > 0.0,
        }
    }
}

impl<M: NormalModel, D: DampingModel> BoundContact for GranNormalBound<M, D> {
    /// What the law tells the other laws of contact `c` after a force call that left `history`
    /// and returned `force`: the contact radius, LAMMPS's `Fncrit` and `damp_prefactor` (zero
    /// when the contact does not act).
    fn context(&self, c: &Contact, history: &[f64], force: f64) -> Ctx {
        if !self.acting(c, history) {
            return Ctx::default();
        }
        let e = self.eval(c);
        Ctx {
            contact_radius: e.contact_radius,
            cap_force: if M::COHESIVE { e.cap } else { force.abs() },
            damping: e.damping,
        }
    }

    #[inline(always)]
    fn force(&self, c: Contact, history: &mut [f64]) -> f64 {
        if !self.touches(&c, history) {
            return 0.0;
        }
        self.eval(&c).force
    }

    /// The context is the force's own evaluation (JKR's contact radius is a cube root): one
    /// evaluation for both, the bits of `force` then `context`.
    const CONTEXT_WITH_FORCE: bool = true;

    #[inline(always)]
    fn force_context(&self, c: Contact, history: &mut [f64]) -> (f64, Ctx) {
        if !self.touches(&c, history) {
            return (0.0, Ctx::default());
        }
        let e = self.eval(&c);
        let ctx = Ctx {
            contact_radius: e.contact_radius,
            cap_force: if M::COHESIVE { e.cap } else { e.force.abs() },
            damping: e.damping,
        };
        (e.force, ctx)
    }

    /// On an x86-64 CPU with AVX2, four contacts at a time in explicit lanes (`normal_avx2`,
    /// the per-contact form's bits), the last `n % 4` one at a time.
    #[inline(always)]
    fn force_context_batch(&self, b: &mut NormalBatch<'_>, out: &mut [Ctx]) {
        let mut from = 0;
        #[cfg(target_arch = "x86_64")]
        if M::LANE != lane::NONE
            && D::LANE != lane::NONE
            && b.force.len() >= 4
            && dashpot_sdk::simd::available()
        {
            let [k, emix, cohesion] = self.model.lane_constants();
            let m = crate::normal_avx2::Consts { k, emix, cohesion };
            // SAFETY: the CPU has AVX2 (checked just above); the lanes check the lengths
            from = unsafe { crate::normal_avx2::force_context::<M, D>(&m, self.coef, self.limit, b, out) };
        }
        let slots = b.slots;
        for (i, x) in out.iter_mut().enumerate().skip(from) {
            let c = b.contact(i);
            (b.force[i], *x) = self.force_context(c, &mut b.history[i * slots..(i + 1) * slots]);
        }
    }

    /// JKR's on an x86-64 CPU with AVX2 four contacts at a time (`normal_avx2`, the same bits).
    #[inline(always)]
    fn reach_batch(&self, b: &NormalBatch<'_>, out: &mut [f64]) {
        let mut from = 0;
        #[cfg(target_arch = "x86_64")]
        if M::LANE == lane::JKR && out.len() >= 4 && dashpot_sdk::simd::available() {
            let [k, emix, cohesion] = self.model.lane_constants();
            let m = crate::normal_avx2::Consts { k, emix, cohesion };
            // SAFETY: the CPU has AVX2 (checked just above); the lanes check the lengths
            from = unsafe { crate::normal_avx2::jkr_reach(&m, b, out) };
        }
        let slots = b.slots;
        for (i, x) in out.iter_mut().enumerate().skip(from) {
            *x = self.reach(&b.contact(i), &b.history[i * slots..(i + 1) * slots]);
        }
    }

    fn coefficients(&self, _mass: f64, radius: f64) -> Vec<Coefficient> {
        let mut c = vec![Coefficient::new(
            "damp_coefficient",
            "-",
            self.coef,
            "the coefficient LAMMPS derives from damp (tsuji: α(e), coeff_restitution: β(e), else damp)",
        )];
        let po = self.model.pulloff_distance(radius);
        if po > 0.0 {
            c.push(Coefficient::new(
                "pulloff_distance",
                "m",
                po,
                "how far beyond touching a formed contact acts (LAMMPS's JKR pull-off distance)",
            ));
        }
        c
    }

    fn reach(&self, c: &Contact, history: &[f64]) -> f64 {
        if self.acting(c, history) {
            self.model.pulloff_distance(c.radius)
        } else {
            0.0
        }
    }

    fn energy(&self, c: &Contact, history: &[f64], force: f64) -> Option<Energy> {
        if !self.acting(c, history) {
            return Some(Energy::default());
        }
        let e = self.eval(c);
        Some(Energy {
            power: (force - e.elastic) * c.rate,
            elastic: self.model.elastic_energy(e.contact_radius, c.delta, c.radius),
        })
    }
}

/// Declares the `gran-*` normal laws: type name, law name, normal spec, damping model, and the
/// documentation macros of both.
macro_rules! normal_laws {
    ($($ty:ident = $name:literal, $spec:ident, $damping:ident, $ndoc:ident, $ddoc:ident, $summary:literal;)*) => {$(
        #[doc = concat!("The law `", $name, "`: ", $summary, ".")]
        pub type $ty = GranNormal<$spec, $damping>;

        impl LawName for GranNormal<$spec, $damping> {
            const NAME: &'static str = $name;
        }

        impl ContactLaw for GranNormal<$spec, $damping> {
            type Bound = GranNormalBound<<$spec as NormalSpec>::Model, $damping>;
            const NAME: &'static str = $name;
            const SUMMARY: &'static str = $summary;
            const DOC: &'static str = concat!($ndoc!(), $ddoc!(), normal_common_doc!());
            const END_CRITERION: EndCriterion = EndCriterion::Overlap;
            const HISTORY: &'static [History] = <$spec as NormalSpec>::HISTORY;

            fn calibrate(t: &CalibrationTarget, pair: &Pair, fixed: &Params) -> Result<Option<Vec<ParamValue>>, LawError> {
                <Self as Calibrate>::closed_form(t, pair, fixed)
            }

            fn bind(&self, m: &MaterialPair) -> Result<Self::Bound, LawError> {
                let model = self.spec.bind(m);
                let coef = <$damping as DampingModel>::coefficient(self.damp, <<$spec as NormalSpec>::Model as NormalModel>::HOOKE);
                Ok(GranNormalBound::new(model, coef, self.spec.limit()))
            }
        }
    )*};
}

normal_laws! {
    GranHookeVelocity = "gran-hooke-velocity", HookeSpec, Velocity, hooke_doc, velocity_doc,
        "LAMMPS hooke + damping velocity: F = k δ + η δ̇";
    GranHookeMassVelocity = "gran-hooke-mass-velocity", HookeSpec, MassVelocity, hooke_doc, mass_velocity_doc,
        "LAMMPS hooke + damping mass_velocity (classic gran/hooke): F = k δ + damp m δ̇";
    GranHookeViscoelastic = "gran-hooke-viscoelastic", HookeSpec, Viscoelastic, hooke_doc, viscoelastic_doc,
        "LAMMPS hooke + damping viscoelastic: F = k δ + damp m a δ̇";
    GranHookeTsuji = "gran-hooke-tsuji", HookeSpec, Tsuji, hooke_doc, tsuji_doc,
        "LAMMPS hooke + damping tsuji: F = k δ + α(e) √(m k) δ̇";
    GranHookeCoeffRestitution = "gran-hooke-coeff-restitution", HookeSpec, CoeffRestitution, hooke_doc, coeff_restitution_doc,
        "LAMMPS hooke + damping coeff_restitution: restitution e exactly";
    GranHertzVelocity = "gran-hertz-velocity", HertzSpec, Velocity, hertz_doc, velocity_doc,
        "LAMMPS hertz + damping velocity: F = k a δ + η δ̇";
    GranHertzMassVelocity = "gran-hertz-mass-velocity", HertzSpec, MassVelocity, hertz_doc, mass_velocity_doc,
        "LAMMPS hertz + damping mass_velocity: F = k a δ + damp m δ̇";
    GranHertzViscoelastic = "gran-hertz-viscoelastic", HertzSpec, Viscoelastic, hertz_doc, viscoelastic_doc,
        "LAMMPS hertz + damping viscoelastic (classic gran/hertz/history): F = k a δ + damp m a δ̇";
    GranHertzTsuji = "gran-hertz-tsuji", HertzSpec, Tsuji, hertz_doc, tsuji_doc,
        "LAMMPS hertz + damping tsuji: F = k a δ + α(e) √(m k a) δ̇";
    GranHertzCoeffRestitution = "gran-hertz-coeff-restitution", HertzSpec, CoeffRestitution, hertz_doc, coeff_restitution_doc,
        "LAMMPS hertz + damping coeff_restitution: restitution e at every speed";
    GranHertzMaterialVelocity = "gran-hertz-material-velocity", HertzMaterialSpec, Velocity, hertz_material_doc, velocity_doc,
        "LAMMPS hertz/material + damping velocity: F = (4/3) E a δ + η δ̇";
    GranHertzMaterialMassVelocity = "gran-hertz-material-mass-velocity", HertzMaterialSpec, MassVelocity, hertz_material_doc, mass_velocity_doc,
        "LAMMPS hertz/material + damping mass_velocity: F = (4/3) E a δ + damp m δ̇";
    GranHertzMaterialViscoelastic = "gran-hertz-material-viscoelastic", HertzMaterialSpec, Viscoelastic, hertz_material_doc, viscoelastic_doc,
        "LAMMPS hertz/material + damping viscoelastic: F = (4/3) E a δ + damp m a δ̇";
    GranHertzMaterialTsuji = "gran-hertz-material-tsuji", HertzMaterialSpec, Tsuji, hertz_material_doc, tsuji_doc,
        "LAMMPS hertz/material + damping tsuji: F = (4/3) E a δ + α(e) √(m (4/3) E a) δ̇";
    GranHertzMaterialCoeffRestitution = "gran-hertz-material-coeff-restitution", HertzMaterialSpec, CoeffRestitution, hertz_material_doc, coeff_restitution_doc,
        "LAMMPS hertz/material + damping coeff_restitution: restitution e at every speed";
    GranDmtVelocity = "gran-dmt-velocity", DmtSpec, Velocity, dmt_doc, velocity_doc,
        "LAMMPS dmt + damping velocity: F = (4/3) E a δ − 4π γ R + η δ̇";
    GranDmtMassVelocity = "gran-dmt-mass-velocity", DmtSpec, MassVelocity, dmt_doc, mass_velocity_doc,
        "LAMMPS dmt + damping mass_velocity: F = (4/3) E a δ − 4π γ R + damp m δ̇";
    GranDmtViscoelastic = "gran-dmt-viscoelastic", DmtSpec, Viscoelastic, dmt_doc, viscoelastic_doc,
        "LAMMPS dmt + damping viscoelastic: F = (4/3) E a δ − 4π γ R + damp m a δ̇";
    GranJkrVelocity = "gran-jkr-velocity", JkrSpec, Velocity, jkr_doc, velocity_doc,
        "LAMMPS jkr + damping velocity: JKR adhesion to LAMMPS's pull-off distance, + η δ̇";
    GranJkrMassVelocity = "gran-jkr-mass-velocity", JkrSpec, MassVelocity, jkr_doc, mass_velocity_doc,
        "LAMMPS jkr + damping mass_velocity: JKR adhesion to LAMMPS's pull-off distance, + damp m δ̇";
    GranJkrViscoelastic = "gran-jkr-viscoelastic", JkrSpec, Viscoelastic, jkr_doc, viscoelastic_doc,
        "LAMMPS jkr + damping viscoelastic: JKR adhesion to LAMMPS's pull-off distance, + damp m a δ̇";
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `force_context` gives the bits of `force` then `context`, and the same history: pressed,
    /// touching, pulled apart within and beyond JKR's pull-off distance, formed or not.
    fn same_bits<M: NormalModel, D: DampingModel>(law: GranNormalBound<M, D>, slots: usize) {
        let mut acting = 0;
        for delta in [-1e-6, -1e-8, 0.0, 1e-9, 3e-7, 4e-6] {
            for rate in [-0.3, 0.0, 0.2] {
                for formed in [0.0, 1.0] {
                    let c = Contact {
                        delta,
                        rate,
                        mass: 1.1e-7,
                        radius: 2.7e-4,
                    };
                    let (mut h1, mut h2) = (vec![formed; slots], vec![formed; slots]);
                    let f = law.force(c, &mut h1);
                    let x = law.context(&c, &h1, f);
                    let (g, y) = law.force_context(c, &mut h2);
                    assert_eq!(f.to_bits(), g.to_bits(), "force at delta = {delta:e}");
                    assert_eq!(x.to_array().map(f64::to_bits), y.to_array().map(f64::to_bits));
                    assert_eq!(h1, h2);
                    acting += usize::from(f != 0.0);
                }
            }
        }
        assert!(acting > 0, "some contacts act");
    }

    #[test]
    fn force_context_is_force_then_context_to_the_bit() {
        let e = 5e7;
        let jkr = Jkr {
            k: FOURTHIRDS * e,
            emix: e,
            cohesion: 0.05,
        };
        same_bits(GranNormalBound::<Jkr, Viscoelastic>::new(jkr, 0.3, false), 1);
        same_bits(GranNormalBound::<Jkr, Velocity>::new(jkr, 1e-3, false), 1);
        let hertz = Hertz { k: FOURTHIRDS * e };
        let tsuji = Tsuji::coefficient(0.7, false);
        same_bits(GranNormalBound::<Hertz, Tsuji>::new(hertz, tsuji, true), 0);
        let dmt = Dmt {
            k: FOURTHIRDS * e,
            cohesion: 0.05,
        };
        same_bits(GranNormalBound::<Dmt, MassVelocity>::new(dmt, 50.0, false), 0);
        same_bits(
            GranNormalBound::<Hooke, CoeffRestitution>::new(Hooke { k: 1e3 }, 0.5, false),
            0,
        );
    }
}
