//! Heat conduction in the DEM engine (sdk 0.4), against closed forms and conservation: two
//! spheres held in contact relax under the engine's explicit Euler exactly as
//! ΔT_n = ΔT_0 (1 − dt/τ)^n, τ = 1/(H (1/C₁ + 1/C₂)); a sphere on an isothermal wall as
//! (1 − dt/τ)^n with τ = C/H_w, the wall's heat being the sphere's gain; under a wall at
//! T0 + A sin ωt its amplitude is A/√(1 + ω²τ²); a small pile conserves Σ C T to rounding, and
//! with a hot wall its books close (Σ C T − initial − wall heat = 0); heat never moves the
//! mechanics by a bit; a checkpoint resumes the temperatures bit for bit (and a checkpoint of
//! format 1 still reads); a pile stepped on one thread and on two has the same temperatures to
//! the bit; bad input is refused naming the key.
//!
//! "Held": the two spheres' normal law here is a contact without force (compiled into the
//! test), so the overlap, the contact radius and the conductance stay what they were set to,
//! exactly, as in the closed form.

use dashpot::cli::dem::scene_engine;
use dashpot::dem::heat::{HeatSetup, WallTemperature};
use dashpot::dem::scene::SceneFile;
use dashpot::dem::{Body, Engine, EngineConfig, Laws, Material, Rotation, Vec3, VecD, Wall};
use dashpot::laws::compiled;
use dashpot_sdk::{
    law_params, BoundContact, Contact, ContactLaw, EndCriterion, LawError, MaterialPair, ParamValue,
};
use dashpot_tests::registry_04;
use std::f64::consts::PI;

law_params! {
    /// A contact that holds without force: F = 0 at any overlap.
    #[derive(Clone, Copy)]
    pub struct Held;
}

impl ContactLaw for Held {
    type Bound = Held;
    const NAME: &'static str = "held";
    const SUMMARY: &'static str = "a contact without force";
    const DOC: &'static str = "F = 0.";
    const END_CRITERION: EndCriterion = EndCriterion::Overlap;
    fn bind(&self, _m: &MaterialPair) -> Result<Held, LawError> {
        Ok(*self)
    }
}

impl BoundContact for Held {
    fn force(&self, _c: Contact, _history: &mut [f64]) -> f64 {
        0.0
    }
}

const MAT: Material = Material {
    young: 1.0e8,
    poisson: 0.3,
    density: 7800.0,
    disk_mass: dashpot::dem::DiskMass::Sphere,
};
const SPECIFIC_HEAT: f64 = 500.0;
const K: f64 = 40.0;

/// Held contacts conducting through `heat-radius` (k = [`K`]).
fn held_laws() -> Laws {
    let reg = registry_04();
    let p = MAT.particle(1.0);
    let (pp, pw) = (
        MaterialPair::spheres(&p, &p).unwrap(),
        MaterialPair::wall(&p).unwrap(),
    );
    let heat = reg.heat("heat-radius", &[ParamValue::new("k", K)]).unwrap();
    Laws {
        pair: Box::new(compiled(&Held, &pp).unwrap()),
        wall: Box::new(compiled(&Held, &pw).unwrap()),
        pair_tangential: None,
        wall_tangential: None,
        rotation: Rotation {
            pair_heat: Some(Box::new(heat.bind(&pp).unwrap())),
            wall_heat: Some(Box::new(heat.bind(&pw).unwrap())),
            ..Rotation::default()
        },
    }
}

fn sphere(x: f64, z: f64, d: f64) -> Body<3> {
    Body {
        position: VecD::<3>::new(x, 0.0, z),
        velocity: VecD::<3>::zeros(),
        angular_velocity: Vec3::zeros(),
        diameter: d,
    }
}

/// A held run of `bodies` and `walls` at step `dt`, temperatures `t` and the walls' `tw`.
fn held(
    bodies: &[Body<3>],
    walls: Vec<Wall<3>>,
    dt: f64,
    t: Vec<f64>,
    tw: Vec<Option<WallTemperature>>,
) -> Engine<3> {
    let mut cfg = EngineConfig::<3>::new(MAT);
    cfg.gravity = VecD::<3>::zeros();
    cfg.dt = Some(dt);
    cfg.impact_speed = Some(1e-3);
    Engine::new(cfg, bodies, walls, held_laws())
        .unwrap()
        .with_heat(HeatSetup {
            temperature: t,
            specific_heat: vec![SPECIFIC_HEAT],
            walls: tw,
        })
        .unwrap()
}

/// The single contact of `e` (pair or wall): its overlap and effective radius.
fn the_contact(e: &Engine<3>) -> (f64, f64) {
    let sets = e.pairs.chunks.iter().chain(&e.wall_contacts.chunks);
    let all: Vec<(f64, f64)> = sets
        .flat_map(|s| s.delta.iter().cloned().zip(s.radius.iter().cloned()))
        .collect();
    assert_eq!(all.len(), 1, "one contact");
    all[0]
}

#[test]
fn two_spheres_held_in_contact_relax_as_the_discrete_closed_form() {
    let (r1, r2, delta) = (1e-3, 1.5e-3, 2e-6);
    let bodies = [sphere(0.0, 0.0, 2.0 * r1), sphere(r1 + r2 - delta, 0.0, 2.0 * r2)];
    let m = |r: f64| 4.0 / 3.0 * PI * r.powi(3) * MAT.density;
    let (c1, c2) = (m(r1) * SPECIFIC_HEAT, m(r2) * SPECIFIC_HEAT);
    // the conductance of the engine's contact: 2 k √(R δ) at its overlap and radius
    let probe = held(&bodies, vec![], 1.0, vec![300.0, 350.0], vec![]);
    let (d, r) = the_contact(&probe);
    assert!((d - delta).abs() < 1e-15 && (r - r1 * r2 / (r1 + r2)).abs() < 1e-18);
    let h = 2.0 * K * (r * d).sqrt();
    let tau = 1.0 / (h * (1.0 / c1 + 1.0 / c2));
    let dt = tau / 50.0;
    let mut e = held(&bodies, vec![], dt, vec![300.0, 350.0], vec![]);
    let caps = e.heat_capacities().unwrap().to_vec();
    assert!((caps[0] - c1).abs() <= 1e-15 * c1 && (caps[1] - c2).abs() <= 1e-15 * c2);
    let ct0 = e.heat_books().unwrap().thermal;
    for n in 1..=200 {
        e.step().unwrap();
        let t = e.temperatures().unwrap();
        let want = 50.0 * (1.0 - dt / tau).powi(n);
        assert!(
            ((t[1] - t[0]) - want).abs() <= 1e-12 * 50.0,
            "step {n}: ΔT = {} vs {want}",
            t[1] - t[0]
        );
        let b = e.heat_books().unwrap();
        assert!(
            (b.thermal - ct0).abs() <= 1e-14 * ct0,
            "step {n}: Σ C T {} vs {ct0}",
            b.thermal
        );
        assert_eq!(b.wall_heat, 0.0);
        // the particles have not moved: the contact is the same
        assert_eq!(the_contact(&e).0.to_bits(), d.to_bits());
    }
    // relaxed to e^-4, towards (C₁T₁ + C₂T₂)/(C₁ + C₂); monotone: no stability warning
    let t = e.temperatures().unwrap();
    assert!(t[1] - t[0] < 0.02 * 50.0);
    assert!((t[0] - (300.0 * c1 + 350.0 * c2) / (c1 + c2)).abs() < 0.02 * 50.0);
    let b = e.heat_books().unwrap();
    assert!(b.warning().is_none(), "{:?}", b.warning());
    // C/ΣH of the smaller sphere: the limit met
    assert!((b.stability_limit - c1 / h).abs() <= 1e-12 * c1 / h);
    // a step past it is warned about, naming both
    let mut fast = held(&bodies, vec![], 1.5 * c1 / h, vec![300.0, 350.0], vec![]);
    fast.step().unwrap();
    let w = fast.heat_books().unwrap().warning().expect("a warning");
    assert!(w.contains("exceeds the thermal limit"), "{w}");
}

/// A sphere of radius `r` overlapping a floor by `delta`, at `t0`, the floor at `tw`.
fn on_a_floor(r: f64, delta: f64, dt: f64, t0: f64, tw: WallTemperature) -> Engine<3> {
    let floor = Wall::fixed(VecD::<3>::zeros(), VecD::<3>::new(0.0, 0.0, 1.0));
    held(
        &[sphere(0.0, r - delta, 2.0 * r)],
        vec![floor],
        dt,
        vec![t0],
        vec![Some(tw)],
    )
}

#[test]
fn a_sphere_on_an_isothermal_wall_relaxes_with_tau_c_over_h() {
    let (r, delta, t0, tw): (f64, f64, f64, f64) = (1e-3, 1e-6, 350.0, 280.0);
    let c = 4.0 / 3.0 * PI * r.powi(3) * MAT.density * SPECIFIC_HEAT;
    let probe = on_a_floor(r, delta, 1.0, t0, WallTemperature::Fixed(tw));
    let (d, reff) = the_contact(&probe);
    assert_eq!(reff, r, "R_eff = R against a wall");
    let hw = 2.0 * K * (r * d).sqrt();
    let tau = c / hw;
    let dt = tau / 40.0;
    let mut e = on_a_floor(r, delta, dt, t0, WallTemperature::Fixed(tw));
    for n in 1..=300 {
        e.step().unwrap();
        let t = e.temperatures().unwrap()[0];
        let want = tw + (t0 - tw) * (1.0 - dt / tau).powi(n);
        assert!((t - want).abs() <= 1e-12 * (t0 - tw), "step {n}: {t} vs {want}");
        // the heat the wall gave is what the sphere gained
        let b = e.heat_books().unwrap();
        assert!(
            (b.wall_heat - c * (t - t0)).abs() <= 1e-12 * c * (t0 - tw),
            "step {n}"
        );
        assert!(
            b.balance.abs() <= 1e-12 * c * t0,
            "step {n}: balance {}",
            b.balance
        );
    }
    // a wall without a temperature does not conduct
    let floor = Wall::fixed(VecD::<3>::zeros(), VecD::<3>::new(0.0, 0.0, 1.0));
    let mut off = held(
        &[sphere(0.0, r - delta, 2.0 * r)],
        vec![floor],
        dt,
        vec![t0],
        vec![None],
    );
    off.advance(50).unwrap();
    assert_eq!(off.temperatures().unwrap()[0], t0);
    assert_eq!(off.heat_books().unwrap().wall_heat, 0.0);
}

#[test]
fn under_a_sinusoidal_wall_the_amplitude_is_a_over_sqrt_one_plus_omega_tau_squared() {
    let (r, delta): (f64, f64) = (1e-3, 1e-6);
    let c = 4.0 / 3.0 * PI * r.powi(3) * MAT.density * SPECIFIC_HEAT;
    let probe = on_a_floor(r, delta, 1.0, 300.0, WallTemperature::Fixed(300.0));
    let (d, _) = the_contact(&probe);
    let tau = c / (2.0 * K * (r * d).sqrt());
    for wt in [0.5, 2.0] {
        let omega = wt / tau;
        let (mean, amp) = (300.0, 20.0);
        let wall = WallTemperature::Sine {
            mean,
            amplitude: amp,
            frequency: omega / (2.0 * PI),
        };
        let period = 2.0 * PI / omega;
        // 400 steps a period
        let dt = period / 400.0;
        let mut e = on_a_floor(r, delta, dt, mean, wall);
        // past the transient (e^-15 of it left), then one period's extremes
        let k = e.steps_to(15.0 * tau + 3.0 * period, u64::MAX);
        e.advance(k).unwrap();
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for _ in 0..400 {
            e.step().unwrap();
            let t = e.temperatures().unwrap()[0];
            (lo, hi) = (lo.min(t), hi.max(t));
        }
        let got = 0.5 * (hi - lo);
        // explicit Euler's steady response, T_{n+1} = T_n + (dt/τ)(T_w(t_{n+1}) − T_n): the
        // gain (dt/τ)/|e^{iω dt} − 1 + dt/τ| exactly (to the sampling of the extremes,
        // 1 − cos(π/400) = 3e-5), and the continuous A/√(1 + ω²τ²) as dt → 0
        let (x, wd) = (dt / tau, omega * dt);
        let discrete = amp * x / ((wd.cos() - 1.0 + x).powi(2) + wd.sin().powi(2)).sqrt();
        assert!(
            (got / discrete - 1.0).abs() < 1e-4,
            "ωτ = {wt}: amplitude {got} vs {discrete}"
        );
        let want = amp / (1.0 + wt * wt).sqrt();
        assert!(
            (got / want - 1.0).abs() < 5e-3,
            "ωτ = {wt}: amplitude {got} vs {want}"
        );
        assert!(e.heat_books().unwrap().balance.abs() <= 1e-12 * c * mean);
    }
}

/// A small 3D pile settling on a floor (`hsd` + `mindlin`), hot and cold halves, with a heat
/// law (`heat` tables) or none; the floor's `temperature` line.
fn pile(heat: &str, floor_temperature: &str) -> String {
    format!(
        r#"
dimension = 3
gravity = [0.0, 0.0, -9.81]
duration = 1.0
impact_speed = 0.5
[law]
name = "hsd"
params = {{ eps = 0.6 }}
[tangential]
name = "mindlin"
params = {{ mu = 0.3 }}
{heat}
[material]
young = 1.0e7
poisson = 0.3
density = 2500.0
heat_capacity = 800.0
[[wall]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
{floor_temperature}
[box]
lo = [0.0, 0.0, 0.0]
hi = [0.012, 0.012, 0.05]
periodic = [true, true, false]
[[generate]]
count = 40
diameter = [0.0018, 0.0022]
lo = [0.0, 0.0, 0.0]
hi = [0.012, 0.012, 0.006]
seed = 3
speed = 0.3
temperature = 400.0
[[generate]]
count = 40
diameter = [0.0018, 0.0022]
lo = [0.0, 0.0, 0.006]
hi = [0.012, 0.012, 0.012]
seed = 4
speed = 0.3
temperature = 300.0
"#
    )
}

const HEAT: &str = "[heat]\nname = \"heat-area\"\nparams = { h = 1.0e6 }\n";

fn scene_run(text: &str) -> Engine<3> {
    let reg = registry_04();
    let file = SceneFile::parse(text).unwrap();
    let scene = file.scene::<3>().unwrap();
    scene_engine(&reg, &file, &scene).unwrap().0
}

#[test]
fn a_pile_conserves_heat_and_its_books_close_with_a_hot_floor() {
    // insulated: Σ C T conserved to rounding while heat flows from the hot half
    let mut e = scene_run(&pile(HEAT, ""));
    let t0 = e.temperatures().unwrap().to_vec();
    let ct0 = e.heat_books().unwrap().thermal;
    e.advance(20_000).unwrap();
    let b = e.heat_books().unwrap();
    assert!(
        e.contacts() > 40,
        "the pile is in contact ({} at t = {} s, dt = {} s)",
        e.contacts(),
        e.time(),
        e.dt()
    );
    assert!(
        (b.thermal - ct0).abs() <= 1e-13 * ct0,
        "Σ C T {} vs {ct0}",
        b.thermal
    );
    assert_eq!(b.wall_heat, 0.0);
    let t = e.temperatures().unwrap();
    let moved = t.iter().zip(&t0).filter(|(a, b)| a != b).count();
    assert!(
        moved > 40,
        "heat flowed through the contacts ({moved} particles changed)"
    );
    let (lo, hi) = t
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
    assert!(
        lo >= 300.0 - 1e-9 && hi <= 400.0 + 1e-9,
        "no temperature outside the start's range: {lo} .. {hi}"
    );
    // the same pile on a floor at 500 K: the floor gives heat, the books close
    let mut e = scene_run(&pile(HEAT, "temperature = 500.0"));
    e.advance(20_000).unwrap();
    let b = e.heat_books().unwrap();
    assert!(b.wall_heat > 0.0, "the hot floor gave heat ({})", b.wall_heat);
    assert!(b.balance.abs() <= 1e-13 * b.thermal, "balance {}", b.balance);
    // the books in --json's state
    let v = e.state_json();
    assert_eq!(v["heat"]["wall_heat"], serde_json::json!(b.wall_heat));
    assert_eq!(
        v["particles"][0]["temperature"],
        serde_json::json!(e.temperatures().unwrap()[0])
    );
}

#[test]
fn heat_does_not_move_the_mechanics_by_a_bit() {
    let mut with = scene_run(&pile(HEAT, "temperature = 500.0"));
    let mut without = scene_run(&pile("", ""));
    assert!(without.temperatures().is_none() && without.heat_books().is_none());
    for _ in 0..3 {
        with.advance(400).unwrap();
        without.advance(400).unwrap();
        for (a, b) in [(&with.p.pos, &without.p.pos), (&with.p.vel, &without.p.vel)] {
            for (x, y) in a.iter().zip(b.iter()) {
                for k in 0..3 {
                    assert_eq!(x[k].to_bits(), y[k].to_bits());
                }
            }
        }
        assert_eq!(with.p.omega.len(), without.p.omega.len());
        assert!(with
            .p
            .omega
            .iter()
            .zip(&without.p.omega)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!(
            with.dissipated.map(f64::to_bits),
            without.dissipated.map(f64::to_bits)
        );
    }
}

/// A pile of 1,200 spheres (a 3D pile of 1,024 or more steps in parallel, in small chunks),
/// hot below and cold above, on a floor at 350 K, with `heat-radius`.
fn big_pile() -> String {
    pile(
        "[heat]\nname = \"heat-radius\"\nparams = { k = 40.0 }\n",
        "temperature = 350.0",
    )
    .replace("hi = [0.012, 0.012, 0.05]", "hi = [0.03, 0.03, 0.06]")
    .replace("count = 40", "count = 600")
    .replace("hi = [0.012, 0.012, 0.006]", "hi = [0.03, 0.03, 0.012]")
    .replace("lo = [0.0, 0.0, 0.006]", "lo = [0.0, 0.0, 0.012]")
    .replace("hi = [0.012, 0.012, 0.012]", "hi = [0.03, 0.03, 0.024]")
}

#[test]
fn a_heated_pile_has_the_same_temperatures_to_the_bit_on_one_thread_and_two() {
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build();
        pool.expect("a thread pool").install(|| {
            let mut e = scene_run(&big_pile());
            // single steps (each pass in parallel on two threads), then blocks
            for _ in 0..300 {
                e.step().unwrap();
            }
            e.advance(20_000).unwrap();
            e
        })
    };
    let (a, b) = (run(1), run(2));
    assert!(a.p.len() >= 1024, "{} spheres", a.p.len());
    assert!(a.contacts() > 300, "the pile is in contact ({})", a.contacts());
    let (ta, tb) = (a.temperatures().unwrap(), b.temperatures().unwrap());
    let moved = ta.iter().filter(|&&t| t != 300.0 && t != 400.0).count();
    assert!(moved > 300, "heat flowed ({moved} particles changed)");
    assert!(ta.iter().zip(tb).all(|(x, y)| x.to_bits() == y.to_bits()));
    assert_eq!(a.heat_books(), b.heat_books());
    assert!(a.heat_books().unwrap().wall_heat != 0.0, "the floor conducted");
    assert!(a.p.pos.iter().zip(&b.p.pos).all(|(x, y)| x == y));
}

/// `e`'s state, of the scene `text`, written as a checkpoint into a scratch directory.
fn checkpointed(text: &str, e: &Engine<3>) -> (tempfile::TempDir, std::path::PathBuf) {
    use dashpot::dem::checkpoint::{self, Checkpoint, Header};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("run.dpck");
    let ck = Checkpoint::<3> {
        scene: text.to_string(),
        laws: String::new(),
        energy_initial: 0.0,
        frames: 0,
        engine: e.save_state(),
    };
    let header = Header {
        dimension: 3,
        scene_hash: 1,
    };
    checkpoint::write(&path, header, &ck).unwrap();
    (dir, path)
}

/// The engine state of the checkpoint `path`.
fn read_back(path: &std::path::Path) -> dashpot::dem::integrator::EngineState<3> {
    use dashpot::dem::checkpoint;
    let (_, payload) = checkpoint::read_raw(path).unwrap();
    checkpoint::decode::<3>(path, &payload).unwrap().engine
}

#[test]
fn a_checkpoint_resumes_the_temperatures_bit_for_bit() {
    let text = pile(
        HEAT,
        "temperature = { mean = 400.0, amplitude = 50.0, frequency = 20.0 }",
    );
    let mut a = scene_run(&text);
    a.advance(15_000).unwrap();
    let (_dir, path) = checkpointed(&text, &a);
    a.advance(3000).unwrap();
    let mut b = scene_run(&text);
    b.restore_state(read_back(&path)).unwrap();
    b.advance(3000).unwrap();
    let (ta, tb) = (a.temperatures().unwrap(), b.temperatures().unwrap());
    assert!(ta.iter().zip(tb).all(|(x, y)| x.to_bits() == y.to_bits()));
    assert_eq!(a.heat_books(), b.heat_books());
    assert!(a.heat_books().unwrap().wall_heat != 0.0, "the floor conducted");
    // a state without temperatures does not fit a run with heat, and the other way round
    let plain = scene_run(&pile("", ""));
    let e = b.restore_state(plain.save_state()).unwrap_err().to_string();
    assert!(e.contains("no temperatures"), "{e}");
    let mut plain = plain;
    let e = plain.restore_state(a.save_state()).unwrap_err().to_string();
    assert!(e.contains("holds temperatures"), "{e}");
}

#[test]
fn a_checkpoint_of_format_one_reads_as_a_run_without_heat() {
    use dashpot::dem::checkpoint::HEADER_LEN;
    let text = pile("", "");
    let mut a = scene_run(&text);
    a.advance(300).unwrap();
    let (_dir, path) = checkpointed(&text, &a);
    // format 1 is format 2 without the last byte (the temperatures' `None`)
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(*bytes.last().unwrap(), 0);
    let payload = &bytes[HEADER_LEN..bytes.len() - 1];
    let mut old = bytes[..HEADER_LEN].to_vec();
    old[8..12].copy_from_slice(&1u32.to_le_bytes());
    old[20..28].copy_from_slice(&(payload.len() as u64).to_le_bytes());
    old[28..32].copy_from_slice(&crc32(payload).to_le_bytes());
    old.extend_from_slice(payload);
    std::fs::write(&path, &old).unwrap();
    let back = read_back(&path);
    a.advance(200).unwrap();
    let mut b = scene_run(&text);
    b.restore_state(back).unwrap();
    b.advance(200).unwrap();
    assert!(a.p.pos.iter().zip(&b.p.pos).all(|(x, y)| x == y));
}

/// CRC-32 (IEEE), bit by bit.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= b as u32;
        for _ in 0..8 {
            c = if c & 1 != 0 {
                (c >> 1) ^ 0xEDB8_8320
            } else {
                c >> 1
            };
        }
    }
    !c
}

#[test]
fn bad_heat_input_is_refused_naming_the_key() {
    let refused = |text: &str| -> String {
        match SceneFile::parse(text).and_then(|f| f.scene::<3>()) {
            Ok(_) => panic!("accepted"),
            Err(e) => e.to_string(),
        }
    };
    let ok = pile(HEAT, "");
    let m = refused(&ok.replace("heat_capacity = 800.0\n", ""));
    assert!(m.contains("[material].heat_capacity is missing"), "{m}");
    let m = refused(&ok.replace("heat_capacity = 800.0", "heat_capacity = -1.0"));
    assert!(m.contains("heat_capacity = -1") && m.contains("> 0"), "{m}");
    let m = refused(&ok.replace("temperature = 300.0\n", ""));
    assert!(m.contains("generate[1].temperature is missing"), "{m}");
    let m = refused(&ok.replace("temperature = 300.0", "temperature = -3.0"));
    assert!(
        m.contains("generate[1].temperature = -3 K") && m.contains(">= 0"),
        "{m}"
    );
    let m = refused(&pile(
        HEAT,
        "temperature = { mean = 10.0, amplitude = 20.0, frequency = 1.0 }",
    ));
    assert!(
        m.contains("wall[0].temperature") && m.contains("|amplitude| <= mean"),
        "{m}"
    );
    let m = refused(&pile(HEAT, "temperature = \"hot\""));
    assert!(m.contains("a temperature (K) or a table"), "{m}");
    // an unknown heat law, and a contact law given as one
    let reg = registry_04();
    for (law, want) in [("heat-radus", "heat-radius"), ("hsd", "heat laws loaded")] {
        let text = pile(&format!("[heat]\nname = \"{law}\"\n"), "");
        let file = SceneFile::parse(&text).unwrap();
        let scene = file.scene::<3>().unwrap();
        let e = scene_engine(&reg, &file, &scene).err().unwrap();
        assert!(format!("{e:#}").contains(want), "{e:#}");
    }
    // without [heat], temperatures are not needed
    let plain = pile("", "")
        .replace("heat_capacity = 800.0\n", "")
        .replace("temperature = 300.0\n", "");
    assert!(SceneFile::parse(&plain)
        .unwrap()
        .scene::<3>()
        .unwrap()
        .heat
        .is_none());
}
