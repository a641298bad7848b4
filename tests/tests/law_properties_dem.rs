//! Every law the workspace ships keeps the energy books of a DEM run (the companion of
//! `law_properties.rs`, whose helpers it shares): spinning contacts under every rolling and
//! twisting law lose rotational energy and close their books, and random small piles combining
//! the families (a normal law × tangential × rolling × twisting, each present or not, damped or
//! not, capped or not) close their books to 10⁻³ of the energy lost, every family's dissipation
//! ≥ 0. LAMMPS's own sub-models (`gran-*`) are left out as in `law_properties.rs`.

use dashpot::dem::scene::SceneFile;
use dashpot::dem::{Engine, Laws};
use dashpot::Registry;
use dashpot_sdk::testkit::{self, Rng};
use dashpot_sdk::{EndCriterion, LawInfo, LawKind, Pair, ParamValue, Particle};
use proptest::prelude::*;

mod properties;
use properties::*;

/// A law table of a scene as the engine's constructors take it.
fn as_ref(x: &Option<(String, Vec<ParamValue>)>) -> Option<(&str, &[ParamValue])> {
    x.as_ref().map(|(n, p)| (n.as_str(), p.as_slice()))
}

/// A scene's law table: `[kind]` with `name` and `params`.
fn table(kind: &str, name: &str, params: &[ParamValue]) -> String {
    let p: Vec<String> = params
        .iter()
        .map(|p| format!("{} = {:e}", p.name, p.value))
        .collect();
    format!("[{kind}]\nname = \"{name}\"\nparams = {{ {} }}\n", p.join(", "))
}

/// A DEM run's books: the energy at the start and at the end (J), the elastic energy left in
/// the contacts (J), what each family dissipated (J), and the run's rotational kinetic energy
/// at the start and at the end (J).
#[derive(Debug)]
struct Run {
    e0: f64,
    e: f64,
    elastic: f64,
    dissipated: [f64; 4],
    rot: (f64, f64),
}

/// Runs `text` (a scene) with the registry's laws, energy accounting on, for its duration.
fn run_scene(reg: &Registry, text: &str) -> Result<Run, String> {
    let file = SceneFile::parse(text).map_err(|e| e.to_string())?;
    let scene = file.scene::<3>().map_err(|e| e.to_string())?;
    let t =
        |t: &Option<dashpot::dem::scene::LawTable>| t.as_ref().map(|t| (t.name.clone(), t.param_values()));
    let law = file.law.as_ref().ok_or("a [law] table")?;
    let n = (law.name.clone(), law.param_values());
    let (tl, rl, wl) = (t(&file.tangential), t(&file.rolling), t(&file.twisting));
    let m = &scene.config.material;
    let laws = Laws::from_registry(reg, (&n.0, &n.1), as_ref(&tl), m)
        .and_then(|l| l.with_rotation(reg, as_ref(&rl), as_ref(&wl), m))
        .map_err(|e| e.to_string())?;
    let mut cfg = scene.config.clone();
    cfg.energy = true;
    let mut e = Engine::new(cfg, &scene.bodies, scene.walls.clone(), laws).map_err(|e| e.to_string())?;
    let e0 = e.energy().total() + e.elastic().iter().sum::<f64>();
    let rot0 = e.energy().rotational;
    while e.time() + 0.5 * e.dt() < scene.duration {
        e.step().map_err(|e| e.to_string())?;
    }
    assert_eq!(e.unreported, [false; 4], "every shipped law reports its energy");
    Ok(Run {
        e0,
        e: e.energy().total(),
        elastic: e.elastic().iter().sum(),
        dissipated: e.dissipated,
        rot: (rot0, e.energy().rotational),
    })
}

impl Run {
    /// What the particles lost (J).
    fn lost(&self) -> f64 {
        self.e0 - self.e
    }

    /// Err unless the books close to 10⁻³ of the energy lost and every family's dissipation is
    /// ≥ 0 (but for LAMMPS's mirrors, `mirror[k]`).
    fn check(&self, mirror: [bool; 4]) -> Result<(), String> {
        let lost = self.lost();
        let residual = lost - self.elastic - self.dissipated.iter().sum::<f64>();
        if residual.abs() > 1e-3 * lost.abs() {
            return Err(format!(
                "the books do not close: lost {lost:e} J − elastic {:e} J − dissipated {:?} J = {residual:e} J ({:+.3e} of the loss)",
                self.elastic,
                self.dissipated,
                residual / lost
            ));
        }
        for (k, (&d, &m)) in self.dissipated.iter().zip(&mirror).enumerate() {
            if !m && d < -1e-9 * lost.abs() {
                return Err(format!("family {k} dissipated {d:e} J < 0 ({self:?})"));
            }
        }
        Ok(())
    }
}

/// A value for a parameter of a motion law in a scene of particles of mass ~`m` (kg), radius
/// ~`r` (m) and normal stiffness ~`kn` (N/m) that the scene's step resolves: by its unit, a
/// spring of stiffness up to the normal contact's (N/m; N·m/rad as k_n r²), a dashpot of damping
/// ratio up to 0.5 on it, a friction coefficient up to 1 (up to r for a twisting one, in m),
/// a dimensionless damping ratio up to 0.5; else as the law's range gives it.
fn resolved(rng: &mut Rng, unit: &str, name: &str, drawn: f64, (m, r, kn): (f64, f64, f64)) -> f64 {
    let k = kn * rng.log_between(1e-2, 1.0);
    let zeta = if rng.uniform() < 0.3 {
        0.0
    } else {
        rng.between(0.0, 0.5)
    };
    match unit {
        "N/m" => k,
        "N·m/rad" => k * r * r,
        "N·s/m" => 2.0 * zeta * (m * k).sqrt(),
        "N·m·s/rad" => 2.0 * zeta * (m * r * r * k * r * r).sqrt(),
        "m" => rng.between(0.0, r),
        "1" if name.contains("mu") => rng.between(0.0, 1.0),
        "1" => drawn.min(0.5),
        _ => drawn,
    }
}

/// Random parameters of motion law `info` for a scene ([`resolved`]).
fn motion_params(rng: &mut Rng, info: &LawInfo, scale: (f64, f64, f64)) -> Vec<ParamValue> {
    testkit::random_values(rng, info)
        .into_iter()
        .map(|p| {
            let spec = info.params.iter().find(|s| s.name == p.name).unwrap();
            let v = resolved(rng, &spec.unit, &p.name, p.value, scale);
            ParamValue::new(&p.name, if spec.range.contains(v) { v } else { p.value })
        })
        .collect()
}

/// The scene's common part: gravity, material, the box's walls (floor and four sides of width
/// `w`, m), a duration (s) and the steps a collision.
fn scene_head(young: f64, w: f64, duration: f64, gravity: f64, steps: u32) -> String {
    let mut s = format!(
        "dimension = 3\ngravity = [0.0, 0.0, {}]\nduration = {duration:e}\nsteps_per_collision = {steps}\n\
         [material]\nyoung = {young:e}\npoisson = 0.3\ndensity = 2500.0\n",
        -gravity
    );
    for (p, n) in [
        ([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
        ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
        ([w, 0.0, 0.0], [-1.0, 0.0, 0.0]),
        ([0.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, w, 0.0], [0.0, -1.0, 0.0]),
    ] {
        s += &format!("[[wall]]\npoint = {p:?}\nnormal = {n:?}\n");
    }
    s
}

/// Parameters of normal law `info` for a DEM scene of spheres of diameter `d` (m) and Young's
/// modulus `young` (Pa) meeting at up to `v` (m/s): drawn across their ranges until the
/// two-body driver says a head-on impact at `v` stays below a tenth of the radius and rebounds
/// with ε ≥ 0.5 (a run's step resolves that damping: the books of a normal dashpot, booked at
/// the step's end, are first order in the step, some 10⁻³ at ε = 0.5 and 10⁻² at ε = 0.2 with
/// 100 steps a collision); none after 20 draws (the case is then rejected).
fn scene_normal(
    reg: &Registry,
    info: &LawInfo,
    rng: &mut Rng,
    d: f64,
    young: f64,
    v: f64,
) -> Option<Vec<ParamValue>> {
    use dashpot::collide::{collide, Options, PairLaw};
    let p = Particle {
        diameter: d,
        density: 2500.0,
        young,
        poisson: 0.3,
    };
    let pair = Pair::spheres(&p, &p).ok()?;
    (0..20).find_map(|_| {
        let params = testkit::random_values(rng, info);
        let law = reg.contact(&info.name, &params).ok()?;
        let bound = PairLaw::bind(&law, &pair, 0.3).ok()?;
        let c = collide(&bound, pair.mass, v, EndCriterion::Overlap, &Options::default()).ok()?;
        (c.restitution >= 0.5 && !c.stuck && c.max_overlap < 0.05 * d).then_some(params)
    })
}

/// A pair of spheres meeting head-on (or a sphere dropped on the floor) spinning about random
/// axes, under rolling law `info` or twisting law `info` (random parameters) and a random
/// normal law, without friction (so only the law acts on the spins): the rotational energy
/// falls and the books close.
fn spinning_pair(
    reg: &Registry,
    info: &LawInfo,
    normals: &[LawInfo],
    seed: u64,
) -> Result<(), TestCaseError> {
    let mut rng = Rng::new(seed);
    let normal = pick(&mut rng, normals);
    let (d, young) = (rng.log_between(1e-3, 1e-2), rng.log_between(1e6, 1e8));
    let m = 2500.0 * std::f64::consts::PI / 6.0 * d * d * d;
    let v = rng.log_between(0.05, 1.0);
    let Some(nparams) = scene_normal(reg, normal, &mut rng, d, young, v) else {
        return Err(TestCaseError::reject("no normal parameters the step resolves"));
    };
    let kn = young / (2.0 * (1.0 - 0.09)) * (0.25 * d * d * 1e-3).sqrt();
    let params = motion_params(&mut rng, info, (0.5 * m, 0.25 * d, kn));
    let kind = if info.kind == LawKind::Rolling {
        "rolling"
    } else {
        "twisting"
    };
    let spin = |rng: &mut Rng| {
        let a = rng.direction();
        let w = rng.between(1.0, 30.0) * v / d;
        format!("[{:e}, {:e}, {:e}]", w * a[0], w * a[1], w * a[2])
    };
    let wall = rng.uniform() < 0.5;
    let w = 20.0 * d;
    // (1000 steps a collision: an impact's books are first order in dt where a contact starts
    // and ends: its normal dashpot's, and the last force of a motion law, which acts over half
    // a step after the contact is gone)
    let mut text = scene_head(young, w, 6.0 * d / v, if wall { 9.81 } else { 0.0 }, 1000);
    text += &table("law", &normal.name, &nparams);
    text += &table(kind, &info.name, &params);
    if wall {
        text += &format!(
            "[[particle]]\nposition = [{c:e}, {c:e}, {z:e}]\nvelocity = [0.0, 0.0, {:e}]\nangular_velocity = {}\ndiameter = {d:e}\n",
            -v,
            spin(&mut rng),
            c = 0.5 * w,
            z = 0.6 * d
        );
    } else {
        for (x, u) in [(0.5 * w - 0.6 * d, v), (0.5 * w + 0.6 * d, -v)] {
            text += &format!(
                "[[particle]]\nposition = [{x:e}, {c:e}, {c:e}]\nvelocity = [{u:e}, 0.0, 0.0]\nangular_velocity = {}\ndiameter = {d:e}\n",
                spin(&mut rng),
                c = 0.5 * w
            );
        }
    }
    let what = || {
        format!(
            "law '{}' {params:?} on '{}' {nparams:?}, seed {seed}:\n{text}",
            info.name, normal.name
        )
    };
    let r = match run_scene(reg, &text) {
        Ok(r) => r,
        Err(e) => return Err(TestCaseError::fail(format!("{}: {e}", what()))),
    };
    let mirror = lammps_mirror(&info.name);
    prop_assert!(
        r.rot.1 <= r.rot.0 * (1.0 + 1e-9) || mirror,
        "{}: the rotational energy rose from {:e} J to {:e} J",
        what(),
        r.rot.0,
        r.rot.1
    );
    let checked = r.check([lammps_mirror(&normal.name), false, mirror, mirror]);
    prop_assert!(checked.is_ok(), "{}: {}", what(), checked.unwrap_err());
    Ok(())
}

#[test]
fn every_rolling_and_twisting_law_takes_energy_out_of_spinning_contacts() {
    let reg = shipped();
    let normals: Vec<LawInfo> = of_kind(&reg, LawKind::Contact)
        .into_iter()
        .filter(|i| !["jkr", "dmt"].contains(&i.name.as_str()))
        .collect();
    let mut laws = of_kind(&reg, LawKind::Rolling);
    laws.extend(of_kind(&reg, LawKind::Twisting));
    for_each_law(&laws, 8, |info, seed| spinning_pair(&reg, info, &normals, seed));
}

/// A small random pile: 20–60 spheres poured into a box under a random normal law and, each
/// present or not, a tangential, a rolling and a twisting law of the registry with random
/// parameters the step resolves ([`resolved`]): the books close and every family's
/// dissipation is ≥ 0.
fn pile(reg: &Registry, seed: u64) -> Result<(), TestCaseError> {
    let mut rng = Rng::new(seed);
    let normal = pick(&mut rng, &of_kind(reg, LawKind::Contact)).clone();
    let (d, young) = (rng.log_between(2e-3, 5e-3), rng.log_between(1e6, 1e7));
    let m = 2500.0 * std::f64::consts::PI / 6.0 * d * d * d;
    let kn = young / (2.0 * (1.0 - 0.09)) * (0.25 * d * d * 1e-3).sqrt();
    let scale = (0.5 * m, 0.25 * d, kn);
    let count = 20 + (rng.uniform() * 10.0) as usize;
    let w = 5.0 * d;
    // the fall from the top of the box (at most 3 w), and a third as long again
    let fall = (6.0 * w / 9.81).sqrt();
    let Some(nparams) = scene_normal(reg, &normal, &mut rng, d, young, 9.81 * fall) else {
        return Err(TestCaseError::reject("no normal parameters the step resolves"));
    };
    let mut text = scene_head(young, w, 1.3 * fall, 9.81, 100);
    text += &table("law", &normal.name, &nparams);
    let mut mirror = [lammps_mirror(&normal.name), false, false, false];
    for (k, (kind, table_name)) in [
        (LawKind::Tangential, "tangential"),
        (LawKind::Rolling, "rolling"),
        (LawKind::Twisting, "twisting"),
    ]
    .into_iter()
    .enumerate()
    {
        let laws = of_kind(reg, kind);
        if laws.is_empty() || rng.uniform() < 0.3 {
            continue;
        }
        let law = pick(&mut rng, &laws);
        mirror[k + 1] = lammps_mirror(&law.name);
        text += &table(table_name, &law.name, &motion_params(&mut rng, law, scale));
    }
    text += &format!(
        "[generate]\ncount = {count}\ndiameter = [{:e}, {:e}]\nlo = [0.0, 0.0, 0.0]\nhi = [{w:e}, {w:e}, {:e}]\nseed = {}\n",
        0.8 * d,
        d,
        3.0 * w,
        seed % 1000
    );
    let r = match run_scene(reg, &text) {
        Ok(r) => r,
        Err(e) => return Err(TestCaseError::fail(format!("seed {seed}: {e}\n{text}"))),
    };
    let checked = r.check(mirror);
    prop_assert!(checked.is_ok(), "seed {seed}: {}\n{text}", checked.unwrap_err());
    Ok(())
}

#[test]
fn random_small_piles_close_their_books_and_every_family_dissipates() {
    let reg = shipped();
    runner(10).run(&any::<u64>(), |seed| pile(&reg, seed)).unwrap();
}
