//! The two-body drivers pass the normal law's context (sdk 0.4) to the tangential and rolling
//! laws that read it, and the default context to those that do not: laws compiled into the test
//! record every contact they are called with, and each record's context is checked against
//! what the normal law reports at that contact.

use dashpot_core::collide::rolling::{roll, RollingSpec};
use dashpot_core::collide::{oblique, Body, Impact, Target};
use dashpot_core::laws::{compiled, compiled_rolling, compiled_tangential};
use dashpot_sdk::{
    BoundContact, BoundRolling, BoundTangential, Contact, ContactLaw, EndCriterion, LawError, LawParams,
    MaterialPair, NormalContext, ParamSpec, Params, RollingContact, RollingLaw, TangentialContact,
    TangentialLaw,
};
use std::sync::Mutex;

/// A Hertz spring F = K max(δ, 0)^{3/2} (K = 2e9 N/m^{3/2}) whose context is unlike the
/// default: a = 2 √(R max(δ, 0)), F_c = F + 1, η_n = 3 m.
#[derive(Clone, Copy)]
struct Spring;

impl LawParams for Spring {
    fn schema() -> Vec<ParamSpec> {
        Vec::new()
    }
    fn from_params(_: &Params) -> Result<Self, LawError> {
        Ok(Spring)
    }
}

impl ContactLaw for Spring {
    type Bound = Spring;
    const NAME: &'static str = "spring";
    const SUMMARY: &'static str = "test: Hertz spring with a context of its own";
    const DOC: &'static str = "F = K δ^{3/2}.";
    const END_CRITERION: EndCriterion = EndCriterion::Overlap;
    fn bind(&self, _: &MaterialPair) -> Result<Spring, LawError> {
        Ok(Spring)
    }
}

impl BoundContact for Spring {
    fn force(&self, c: Contact, _: &mut [f64]) -> f64 {
        2e9 * c.delta.max(0.0).powf(1.5)
    }
    fn context(&self, c: &Contact, _: &[f64], force: f64) -> NormalContext {
        spring_context(c.radius, c.delta, force, c.mass)
    }
}

fn spring_context(radius: f64, delta: f64, force: f64, mass: f64) -> NormalContext {
    NormalContext {
        contact_radius: 2.0 * (radius * delta.max(0.0)).sqrt(),
        cap_force: force + 1.0,
        damping: 3.0 * mass,
    }
}

/// What a recording law saw of one contact: R, δ, F_n, m and the context.
type Seen = (f64, f64, f64, f64, NormalContext);

/// A tangential or rolling law that records each contact it is called with; reads the context
/// when `R`. As a tangential law a capped linear spring (k = 1e5 N/m, μ = 0.5); as a rolling law
/// a constant resistance 0.2 F_n against the rolling velocity.
struct Recorder<const R: bool>;

impl<const R: bool> LawParams for Recorder<R> {
    fn schema() -> Vec<ParamSpec> {
        Vec::new()
    }
    fn from_params(_: &Params) -> Result<Self, LawError> {
        Ok(Recorder)
    }
}

#[derive(Default)]
struct Log(Mutex<Vec<Seen>>);

impl Log {
    fn seen(&self, radius: f64, delta: f64, fnorm: f64, mass: f64, x: NormalContext) {
        self.0.lock().unwrap().push((radius, delta, fnorm, mass, x));
    }
}

impl<const R: bool> TangentialLaw for Recorder<R> {
    type Bound = Log;
    const NAME: &'static str = "recorder";
    const SUMMARY: &'static str = "test: records its contacts";
    const DOC: &'static str = "A capped linear spring.";
    const READS_CONTEXT: bool = R;
    const HISTORY: &'static [dashpot_sdk::History] = &dashpot_sdk::History::TANGENTIAL_SPRING;
    fn bind(&self, _: &MaterialPair) -> Result<Log, LawError> {
        Ok(Log::default())
    }
}

impl<const R: bool> RollingLaw for Recorder<R> {
    type Bound = Log;
    const NAME: &'static str = "recorder-rolling";
    const SUMMARY: &'static str = "test: records its contacts";
    const DOC: &'static str = "A constant resistance.";
    const READS_CONTEXT: bool = R;
    fn bind(&self, _: &MaterialPair) -> Result<Log, LawError> {
        Ok(Log::default())
    }
}

impl BoundTangential for Log {
    fn force(&self, c: &TangentialContact, h: &mut [f64]) -> [f64; 3] {
        self.seen(c.radius, c.delta, c.normal_force, c.mass, c.context);
        let (k, cap) = (1e5, 0.5 * c.normal_force.max(0.0));
        let mut f = [0.0; 3];
        for a in 0..3 {
            h[a] += c.velocity[a] * c.dt;
            f[a] = -k * h[a];
        }
        let norm = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
        if norm > cap {
            for a in 0..3 {
                f[a] *= cap / norm;
                h[a] = -f[a] / k;
            }
        }
        f
    }
}

impl BoundRolling for Log {
    fn force(&self, c: &RollingContact, _: &mut [f64]) -> [f64; 3] {
        self.seen(c.radius, c.delta, c.normal_force, c.mass, c.context);
        let v = c.velocity;
        let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if speed == 0.0 {
            return [0.0; 3];
        }
        let s = -0.2 * c.normal_force.max(0.0) / speed;
        [s * v[0], s * v[1], s * v[2]]
    }
}

/// Every recorded context is the normal law's at that contact (when `reads`), else the default.
fn check(log: &Log, reads: bool, what: &str) -> usize {
    let seen = log.0.lock().unwrap();
    for &(r, d, f, m, x) in seen.iter() {
        let want = if reads {
            spring_context(r, d, f, m)
        } else {
            NormalContext::hertzian(r, d, f)
        };
        assert_eq!(x, want, "{what}: R {r:e}, δ {d:e}, F {f:e}");
    }
    seen.len()
}

fn materials() -> MaterialPair {
    MaterialPair::new(7e10, 2.7e10).unwrap()
}

#[test]
fn the_oblique_driver_passes_the_context_to_a_tangential_law_that_reads_it() {
    let normal = compiled(&Spring, &materials()).unwrap();
    let particle = Body::solid_sphere(1e-3, 2.5e-3);
    let impact = Impact {
        speed: 0.5,
        angle: 0.6,
        spin: 0.0,
        end: EndCriterion::Overlap,
        steps: 400,
    };
    for target in [Target::Wall, Target::Sphere(particle)] {
        let reading = compiled_tangential(&Recorder::<true>, &materials()).unwrap();
        oblique(&normal, Some(&reading), &particle, &target, &impact).unwrap();
        assert!(check(reading.law(), true, "oblique, reading") > 300);
        let plain = compiled_tangential(&Recorder::<false>, &materials()).unwrap();
        oblique(&normal, Some(&plain), &particle, &target, &impact).unwrap();
        assert!(check(plain.law(), false, "oblique, not reading") > 300);
    }
}

#[test]
fn the_rolling_driver_passes_the_context_to_the_laws_that_read_it() {
    let normal = compiled(&Spring, &materials()).unwrap();
    let spec = RollingSpec {
        mass: 1e-3,
        radius: 2.5e-3,
        inertia: 0.4 * 1e-3 * 2.5e-3 * 2.5e-3,
        v0: 0.01,
        gravity: 9.81,
        steps: 40,
    };
    // the contexts are computed when either law reads them, and then both receive them
    for (t_reads, r_reads) in [(true, false), (false, true), (false, false)] {
        let (t, r) = match (t_reads, r_reads) {
            (true, false) => (
                Box::new(compiled_tangential(&Recorder::<true>, &materials()).unwrap()) as Box<dyn Recorded>,
                Box::new(compiled_rolling(&Recorder::<false>, &materials()).unwrap()) as Box<dyn Recorded>,
            ),
            (false, true) => (
                Box::new(compiled_tangential(&Recorder::<false>, &materials()).unwrap()) as Box<dyn Recorded>,
                Box::new(compiled_rolling(&Recorder::<true>, &materials()).unwrap()) as Box<dyn Recorded>,
            ),
            _ => (
                Box::new(compiled_tangential(&Recorder::<false>, &materials()).unwrap()) as Box<dyn Recorded>,
                Box::new(compiled_rolling(&Recorder::<false>, &materials()).unwrap()) as Box<dyn Recorded>,
            ),
        };
        roll(&normal, t.tangential(), r.rolling(), &spec, 0).unwrap();
        let any = t_reads || r_reads;
        assert!(check(t.log(), any, "rolling driver, tangential") > 100);
        assert!(check(r.log(), any, "rolling driver, rolling") > 100);
    }
}

/// A compiled recorder of either kind, as the drivers take it.
trait Recorded {
    fn log(&self) -> &Log;
    fn tangential(&self) -> &dyn dashpot_core::laws::TangentialForce {
        unreachable!("not a tangential law")
    }
    fn rolling(&self) -> &dyn dashpot_core::laws::RollingResistance {
        unreachable!("not a rolling law")
    }
}

impl Recorded for dashpot_sdk::abi::StaticModel<dashpot_sdk::abi::Tangential, Log> {
    fn log(&self) -> &Log {
        self.law()
    }
    fn tangential(&self) -> &dyn dashpot_core::laws::TangentialForce {
        self
    }
}

impl Recorded for dashpot_sdk::abi::StaticModel<dashpot_sdk::abi::Rolling, Log> {
    fn log(&self) -> &Log {
        self.law()
    }
    fn rolling(&self) -> &dyn dashpot_core::laws::RollingResistance {
        self
    }
}
