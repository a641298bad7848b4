//! Species and per-pair laws in the DEM engine: in one scene of two species (glass beads and a
//! cohesive powder) and a wall of its own material, a head-on collision of each pair realises
//! that pair's law bound to that pair's materials, as the two-body driver says: HSD's ε for
//! glass–glass, Kuwabara–Kono's restitution for powder–powder, JKR sticking below its critical
//! speed (and rebounding above it) for glass–powder, and Kuwabara–Kono against the wall's own
//! material for glass–wall. A mixed pile closes its energy books class by class; bad pair
//! tables are refused naming the pair.

use dashpot::cli::dem::scene_engine;
use dashpot::collide::{collide, Options, PairLaw};
use dashpot::dem::scene::SceneFile;
use dashpot::dem::Engine;
use dashpot_sdk::{EndCriterion, MaterialPair, Pair, ParamValue, Particle};
use dashpot_tests::registry_03;

const GLASS: Particle = Particle {
    diameter: 0.002,
    density: 2500.0,
    young: 1.0e8,
    poisson: 0.25,
};

const POWDER: Particle = Particle {
    diameter: 0.0015,
    density: 1200.0,
    young: 5.0e7,
    poisson: 0.3,
};

/// The wall's own material (Pa, ratio).
const WALL: (f64, f64) = (2.0e8, 0.3);

/// JKR's work of adhesion between glass and powder (J/m²).
const W: f64 = 0.05;

/// The species and pair tables of the scene, and a default law (HSD, ε = 0.9) for the pairs
/// not named (powder against the wall).
fn tables() -> String {
    format!(
        r#"
dimension = 3
duration = 0.004
impact_speed = 1.0
[law]
name = "hsd"
params = {{ eps = 0.9 }}
[[species]]
name = "glass"
young = {gy:e}
poisson = {gn}
density = {gd}
[[species]]
name = "powder"
young = {py:e}
poisson = {pn}
density = {pd}
[[pair]]
species = ["glass", "glass"]
[pair.law]
name = "hsd"
params = {{ eps = 0.7 }}
[pair.tangential]
name = "mindlin"
params = {{ mu = 0.3 }}
[[pair]]
species = "powder"
[pair.law]
name = "kuwabara-kono"
params = {{ A = 5e-6 }}
[[pair]]
species = ["powder", "glass"]
[pair.law]
name = "jkr"
params = {{ w = {W} }}
[[pair]]
species = "glass"
wall = "floor"
[pair.law]
name = "kuwabara-kono"
params = {{ A = 3e-6 }}
[[wall]]
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
material = {{ young = {wy:e}, poisson = {wn} }}
"#,
        gy = GLASS.young,
        gn = GLASS.poisson,
        gd = GLASS.density,
        py = POWDER.young,
        pn = POWDER.poisson,
        pd = POWDER.density,
        wy = WALL.0,
        wn = WALL.1,
    )
}

/// A particle table: species, position (m), velocity (m/s).
fn particle(species: &str, d: f64, x: [f64; 3], v: [f64; 3]) -> String {
    format!("[[particle]]\nspecies = \"{species}\"\ndiameter = {d}\nposition = {x:?}\nvelocity = {v:?}\n")
}

/// Two particles of species `a`, `b` on the line y = `y`, z = 20 mm, approaching head on at
/// the relative speed `v` (m/s), 1 µm apart.
fn head_on(a: (&str, f64), b: (&str, f64), y: f64, v: f64) -> String {
    let gap = 1e-6;
    let xa = -0.5 * a.1 - 0.5 * gap;
    let xb = 0.5 * b.1 + 0.5 * gap;
    particle(a.0, a.1, [xa, y, 0.02], [0.5 * v, 0.0, 0.0])
        + &particle(b.0, b.1, [xb, y, 0.02], [-0.5 * v, 0.0, 0.0])
}

/// The engine of `text`.
fn engine(text: &str) -> Engine<3> {
    let reg = registry_03();
    let file = SceneFile::parse(text).unwrap();
    let scene = file.scene::<3>().unwrap();
    scene_engine(&reg, &file, &scene).unwrap().0
}

/// The two-body driver's collision of law `name` (`params`) bound to `mp`, effective mass
/// `m` (kg) and radius `r` (m), at `v` (m/s), ended at zero overlap as the engine ends it.
fn driver(name: &str, params: &[ParamValue], mp: &MaterialPair, m: f64, r: f64, v: f64) -> (f64, bool) {
    let reg = registry_03();
    let law = reg.contact(name, params).unwrap().bind(mp).unwrap();
    let c = collide(
        &PairLaw::new(law, m, r),
        m,
        v,
        EndCriterion::Overlap,
        &Options::default(),
    )
    .unwrap();
    (c.restitution, c.stuck)
}

/// JKR's critical speed between glass and powder (m/s), by bisection on the two-body driver.
fn jkr_critical_speed() -> f64 {
    let pair = Pair::spheres(&GLASS, &POWDER).unwrap();
    let mp = MaterialPair::spheres(&GLASS, &POWDER).unwrap();
    let w = [ParamValue::new("w", W)];
    let (mut lo, mut hi) = (1e-6f64, 1.0f64);
    while hi / lo > 1.0 + 1e-4 {
        let mid = (lo * hi).sqrt();
        if driver("jkr", &w, &mp, pair.mass, pair.radius, mid).1 {
            lo = mid
        } else {
            hi = mid
        }
    }
    hi
}

#[test]
fn each_pair_of_species_and_the_species_wall_pair_realise_their_own_laws() {
    let vc = jkr_critical_speed();
    let (dg, dp) = (GLASS.diameter, POWDER.diameter);
    let v = 0.5;
    let mut text = tables();
    text += &head_on(("glass", dg), ("glass", dg), 0.0, v);
    text += &head_on(("powder", dp), ("powder", dp), 0.01, v);
    text += &head_on(("glass", dg), ("powder", dp), 0.02, 0.5 * vc);
    text += &head_on(("glass", dg), ("powder", dp), 0.03, 2.0 * vc);
    // a glass bead falling on the floor (no gravity: at v), far from the others
    text += &particle("glass", dg, [0.0, 0.04, 0.5 * dg + 1e-6], [0.0, 0.0, -v]);
    let mut e = engine(&text);
    let before = e.p.vel.clone();
    while e.time() < 0.004 {
        e.step().unwrap();
    }
    // the sticking pair is the one contact left (an elastic JKR contact: it keeps vibrating)
    assert_eq!(
        e.pairs.len(),
        1,
        "only the slow glass–powder pair stays in contact"
    );
    let stuck = e.pairs.chunks.iter().find(|s| !s.is_empty()).unwrap();
    assert_eq!((stuck.i[0], stuck.j[0]), (4, 5), "the slow glass–powder pair");
    assert_eq!(e.wall_contacts.len(), 0);
    let rel = |a: usize, b: usize, vel: &[dashpot::dem::VecD<3>]| vel[b][0] - vel[a][0];
    let restitution = |a: usize| -rel(a, a + 1, &e.p.vel) / rel(a, a + 1, &before);
    // glass–glass: HSD at ε = 0.7 (not the default's 0.9)
    let eg = restitution(0);
    assert!(
        (eg - 0.7).abs() < 1e-3,
        "glass–glass restitution {eg}, HSD's ε = 0.7"
    );
    // powder–powder: Kuwabara–Kono bound to powder's moduli, as the two-body driver says
    let pp = Pair::spheres(&POWDER, &POWDER).unwrap();
    let a = [ParamValue::new("A", 5e-6)];
    let mp = MaterialPair::spheres(&POWDER, &POWDER).unwrap();
    let want = driver("kuwabara-kono", &a, &mp, pp.mass, pp.radius, v).0;
    let ep = restitution(2);
    assert!(
        (ep - want).abs() < 1e-3,
        "powder–powder restitution {ep}, the driver's {want}"
    );
    assert!(want < 0.97, "Kuwabara–Kono dissipates here ({want})");
    // glass–powder below the critical speed: stuck together (above), their centre of mass
    // moving on as before
    let momentum = |vel: &[dashpot::dem::VecD<3>]| vel[4] * e.p.mass[4] + vel[5] * e.p.mass[5];
    let (p0, p1) = (momentum(&before), momentum(&e.p.vel));
    let scale = e.p.mass[4] * before[4].norm();
    assert!(
        (p1 - p0).norm() < 1e-9 * scale,
        "the stuck pair's momentum is kept: {p0} then {p1}"
    );
    // above it: JKR's restitution for the mixed pair (glass against powder: E_eff of both)
    let gp = Pair::spheres(&GLASS, &POWDER).unwrap();
    let mgp = MaterialPair::spheres(&GLASS, &POWDER).unwrap();
    let (want, stuck) = driver(
        "jkr",
        &[ParamValue::new("w", W)],
        &mgp,
        gp.mass,
        gp.radius,
        2.0 * vc,
    );
    assert!(!stuck);
    let ej = restitution(6);
    assert!(
        (ej / want - 1.0).abs() < 0.01,
        "glass–powder at 2 v_c: restitution {ej}, the driver's {want}"
    );
    // glass on the floor: Kuwabara–Kono bound to glass and the wall's own material
    let mw = MaterialPair::spheres(
        &GLASS,
        &Particle {
            diameter: 1.0,
            density: 1.0,
            young: WALL.0,
            poisson: WALL.1,
        },
    )
    .unwrap();
    let (m, r) = (GLASS.mass(), GLASS.radius());
    let a = [ParamValue::new("A", 3e-6)];
    let want = driver("kuwabara-kono", &a, &mw, m, r, v).0;
    let ew = -e.p.vel[8][2] / before[8][2];
    eprintln!("restitution: glass–glass {eg} (HSD ε 0.7), powder–powder {ep}, glass–powder at 2 v_c {ej} (v_c = {vc:e} m/s), glass–floor {ew} (driver {want})");
    assert!(
        (ew - want).abs() < 1e-3,
        "glass–floor restitution {ew}, the driver's {want}"
    );
    // (a rigid floor would give another: the wall's material is what the law was bound to)
    let rigid = driver("kuwabara-kono", &a, &MaterialPair::wall(&GLASS).unwrap(), m, r, v).0;
    assert!(
        (rigid - want).abs() > 5e-3,
        "rigid {rigid} against the wall's material {want}"
    );
}

/// A pile of both species poured on the floor, every pair with its own laws (friction with
/// history on some, rolling resistance on one): the energy books close as in a one-species
/// pile, and every class's contacts are counted.
#[test]
fn a_mixed_pile_closes_its_energy_books_class_by_class() {
    let text = format!(
        r#"{}
gravity = [0.0, 0.0, -9.81]
[[pair]]
species = "powder"
wall = 0
[pair.law]
name = "hsd"
params = {{ eps = 0.6 }}
[pair.tangential]
name = "linear-history"
params = {{ mu = 0.4 }}
[pair.rolling]
name = "rolling-sds"
params = {{ k = 100.0, mu = 0.1 }}
[[generate]]
count = 150
diameter = [0.0018, 0.0022]
lo = [-0.006, -0.006, 0.001]
hi = [0.006, 0.006, 0.03]
species = "glass"
seed = 3
[[generate]]
count = 150
diameter = [0.0014, 0.0016]
lo = [-0.006, -0.006, 0.031]
hi = [0.006, 0.006, 0.05]
species = "powder"
seed = 4
"#,
        tables().replace("duration = 0.004", "duration = 0.12").replace(
            "name = \"jkr\"\nparams = { w = 0.05 }",
            "name = \"hsd\"\nparams = { eps = 0.5 }"
        ),
    );
    let mut text = text.replace("gravity = [0.0, 0.0, -9.81]\n", "");
    text = text.replacen(
        "dimension = 3\n",
        "dimension = 3\ngravity = [0.0, 0.0, -9.81]\n",
        1,
    );
    // four side walls keep the pile together
    for (p, n) in [
        ("[-0.0065, 0.0, 0.0]", "[1.0, 0.0, 0.0]"),
        ("[0.0065, 0.0, 0.0]", "[-1.0, 0.0, 0.0]"),
        ("[0.0, -0.0065, 0.0]", "[0.0, 1.0, 0.0]"),
        ("[0.0, 0.0065, 0.0]", "[0.0, -1.0, 0.0]"),
    ] {
        text += &format!("[[wall]]\npoint = {p}\nnormal = {n}\n");
    }
    let reg = registry_03();
    let file = SceneFile::parse(&text).unwrap();
    let scene = file.scene::<3>().unwrap();
    assert!(
        scene.plan.pair.len() >= 3 && scene.plan.wall.len() >= 3,
        "{:?}",
        scene.plan.json()
    );
    let (mut e, e0) = scene_engine(&reg, &file, &scene).unwrap();
    let mut seen = [false; 2];
    while e.time() < 0.12 {
        e.advance(200).unwrap();
        for s in e.pairs.chunks.iter() {
            if !s.is_empty() {
                seen[usize::from(s.slots_t > 0)] = true;
            }
        }
    }
    assert!(
        seen[0] && seen[1],
        "contacts with and without a tangential history: {seen:?}, {} pairs, {} wall contacts, t = {}",
        e.pairs.len(),
        e.wall_contacts.len(),
        e.time()
    );
    let en = e.energy().total() + e.elastic().iter().sum::<f64>();
    let lost: f64 = e.dissipated.iter().sum();
    assert!(e.unreported.iter().all(|u| !u));
    assert!(
        lost > 0.0 && e.dissipated.iter().all(|&d| d >= 0.0),
        "{:?}",
        e.dissipated
    );
    let residual = e0 - en - lost;
    assert!(
        residual.abs() < 1e-3 * lost,
        "books: E0 {e0}, now {en}, dissipated {lost}: residual {residual}"
    );
}

/// A mixed 3D pile of small chunks (1,024 spheres of two species drawn at random, three pair
/// classes and two wall classes, each with its own laws), stepped in parallel: the same bit for
/// bit on one thread and two, whatever the threads did (the chunks, and so the order in which
/// each particle's forces are summed, are a function of the pile and its classes alone).
#[test]
fn a_mixed_pile_is_the_same_bit_for_bit_on_one_thread_and_two() {
    let text = tables()
        .replace("impact_speed = 1.0", "impact_speed = 3.0")
        .replace(
            "name = \"jkr\"\nparams = { w = 0.05 }",
            "name = \"hsd\"\nparams = { eps = 0.5 }",
        )
        + r#"
[[generate]]
count = 1024
diameter = [0.0020, 0.0022]
lo = [-0.0095, -0.0095, 0.0]
hi = [0.0095, 0.0095, 0.042]
speed = 3.0
species = ["glass", "powder"]
seed = 5
"#;
    let text = text.replacen(
        "dimension = 3\n",
        "dimension = 3\ngravity = [0.0, 0.0, -9.81]\n",
        1,
    );
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut e = engine(&text);
            e.advance(600).unwrap();
            e
        })
    };
    let (a, b) = (run(1), run(2));
    let chunks = a.pairs.chunks.len() / a.pairs.classes();
    assert!(
        a.pairs.classes() == 3 && chunks >= 2,
        "{} pair classes in {chunks} chunks",
        a.pairs.classes()
    );
    // every class in touch, in more than one chunk
    let busy = a.pairs.chunks.iter().filter(|s| !s.is_empty()).count();
    assert!(
        busy > 3 && a.pairs.formed() + a.pairs.len() > 0,
        "{busy} sets in touch"
    );
    let bits = |e: &Engine<3>| -> Vec<u64> {
        let p = &e.p;
        let vecs = p.pos.iter().chain(&p.vel).flat_map(|v| v.iter().copied());
        vecs.chain(p.omega.iter().copied()).map(f64::to_bits).collect()
    };
    assert!(bits(&a) == bits(&b), "one thread and two part");
    assert_eq!(a.contacts(), b.contacts());
}

/// What a scene's pair tables may not say, each refused with a message naming the pair or key.
#[test]
fn bad_pair_tables_are_refused_naming_the_pair() {
    let base = tables();
    let with = |extra: &str| {
        format!(
            "{base}{extra}{}",
            particle("glass", 0.002, [0.0, 0.0, 0.01], [0.0; 3])
        )
    };
    let cases: [(String, &[&str]); 6] = [
        // no default law and no [[pair]] for powder–wall
        (
            base.replacen("[law]\nname = \"hsd\"\nparams = { eps = 0.9 }\n", "", 1)
                + &particle("powder", 0.0015, [0.0, 0.0, 0.01], [0.0; 3]),
            &["no law for the pair (powder, wall 0 ('floor'))", "[[pair]]"],
        ),
        (
            with("[[pair]]\nspecies = [\"glass\", \"glas\"]\n"),
            &["glas", "did you mean", "glass"],
        ),
        (
            with("[[pair]]\nspecies = [\"glass\", \"glass\"]\n[pair.law]\nname = \"hsd\"\n"),
            &["both give the laws of (glass, glass)"],
        ),
        (
            with("[[pair]]\nspecies = \"glass\"\nwall = 3\n"),
            &["wall = 3", "1 wall"],
        ),
        (
            base.clone()
                + &particle("glass", 0.002, [0.0, 0.0, 0.01], [0.0; 3]).replace("species = \"glass\"\n", ""),
            &["particle[0].species is missing"],
        ),
        (
            with("[material]\nyoung = 1e8\npoisson = 0.3\ndensity = 1000.0\n"),
            &["[material] and [[species]] both given"],
        ),
    ];
    for (text, needles) in cases {
        let err = match SceneFile::parse(&text).and_then(|f| f.scene::<3>()) {
            Ok(_) => panic!("accepted:\n{text}"),
            Err(e) => e.to_string(),
        };
        for n in needles {
            assert!(err.contains(n), "'{n}' not in: {err}");
        }
    }
}

/// A scene of one species written with `[[species]]` runs bit for bit as the same scene with
/// `[material]`: naming the species changes nothing.
#[test]
fn one_named_species_is_the_scene_with_material() {
    let plain = r#"
dimension = 3
gravity = [0.0, 0.0, -9.81]
duration = 0.01
[law]
name = "hsd"
params = { eps = 0.5 }
[tangential]
name = "mindlin"
params = { mu = 0.3 }
[material]
young = 1.0e7
poisson = 0.3
density = 2500.0
[[wall]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
[generate]
count = 60
diameter = [0.002, 0.003]
lo = [0.0, 0.0, 0.0]
hi = [0.012, 0.012, 0.03]
seed = 2
"#;
    let named = plain
        .replace("[material]", "[[species]]\nname = \"beads\"")
        .replace("seed = 2", "seed = 2\nspecies = \"beads\"");
    let mut a = engine(plain);
    let mut b = engine(&named);
    let k = a.steps_to(0.05, u64::MAX);
    a.advance(k).unwrap();
    b.advance(k).unwrap();
    assert!(
        a.contacts() > 5 && a.dissipated[1] > 0.0,
        "{} contacts",
        a.contacts()
    );
    for i in 0..a.p.len() {
        assert_eq!(a.p.pos[i], b.p.pos[i], "particle {i}");
        assert_eq!(a.p.vel[i], b.p.vel[i], "particle {i}");
    }
    assert_eq!(a.dissipated, b.dissipated);
}
