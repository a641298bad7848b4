//! Physics of the soft-sphere DEM engine: closed forms and invariances.
//!
//! Soft materials (E = 10⁸ Pa) and few particles keep each test to seconds in a debug build.
//! The friction law is a Cundall–Strack spring compiled into this file (the `mindlin` plugin is
//! written elsewhere); HSD is linked as an rlib and called through the checked trampoline.

#[allow(dead_code)]
#[path = "../../tests/lib.rs"]
mod ext;

use dashpot::collide::{collide, Options, PairLaw};
use dashpot::dem::{Body, DiskMass, Domain, Engine, EngineConfig, Laws, Material, Vec3, VecD, Wall};
use dashpot::laws::{compiled, compiled_tangential, NormalLaw};
use dashpot_hsd::Hsd;
use dashpot_sdk::{
    BoundTangential, EndCriterion, History, LawError, MaterialPair, Range, TangentialContact, TangentialLaw,
};

dashpot_sdk::law_params! {
    /// Cundall–Strack: a linear tangential spring of stiffness `kt` (N/m) on the displacement ξ
    /// of the contact point, rotated into the current tangent plane at its length, capped by
    /// Coulomb.
    #[derive(Clone, Copy)]
    struct CundallStrack {
        /// stiffness
        kt: f64 { unit: "N/m", default: 1e3, range: Range::positive() },
        /// friction
        mu: f64 { unit: "1", default: 0.3, range: Range::non_negative() },
    }
}

impl BoundTangential for CundallStrack {
    fn force(&self, c: &TangentialContact, h: &mut [f64]) -> [f64; 3] {
        let n = Vec3::from(c.normal);
        let v = Vec3::from(c.velocity);
        let mut xi = Vec3::new(h[0], h[1], h[2]);
        let len = xi.norm();
        xi -= n * xi.dot(&n);
        let l2 = xi.norm();
        if l2 > 0.0 {
            xi *= len / l2;
        }
        xi += (v - n * v.dot(&n)) * c.dt;
        let mut f = -xi * self.kt;
        let cap = self.mu * c.normal_force.abs();
        if f.norm() > cap {
            f *= cap / f.norm();
            xi = -f / self.kt;
        }
        h.copy_from_slice(xi.as_slice());
        [f.x, f.y, f.z]
    }
}

impl TangentialLaw for CundallStrack {
    type Bound = CundallStrack;
    const NAME: &'static str = "cundall-strack-test";
    const SUMMARY: &'static str = "linear tangential spring with Coulomb cap (test)";
    const DOC: &'static str = "test law";
    const HISTORY: &'static [History] = &[
        History::new("xi_x", "m", "spring"),
        History::new("xi_y", "m", "spring"),
        History::new("xi_z", "m", "spring"),
    ];
    fn bind(&self, _m: &MaterialPair) -> Result<CundallStrack, LawError> {
        Ok(*self)
    }
}

const D2: f64 = 0.002;

fn soft(disk_mass: DiskMass) -> Material {
    Material {
        young: 1.0e8,
        poisson: 0.3,
        density: 7800.0,
        disk_mass,
    }
}

fn laws(mat: &Material, eps: f64, friction: Option<CundallStrack>) -> Laws {
    let p = mat.particle(1.0);
    let (pp, pw) = (
        MaterialPair::spheres(&p, &p).unwrap(),
        MaterialPair::wall(&p).unwrap(),
    );
    let hsd = Hsd::with(eps);
    Laws {
        pair: Box::new(compiled(&hsd, &pp).unwrap()),
        wall: Box::new(compiled(&hsd, &pw).unwrap()),
        pair_tangential: friction.map(|f| Box::new(compiled_tangential(&f, &pp).unwrap()) as _),
        wall_tangential: friction.map(|f| Box::new(compiled_tangential(&f, &pw).unwrap()) as _),
        rotation: Default::default(),
    }
}

fn body<const D: usize>(x: [f64; D], v: [f64; D], d: f64) -> Body<D> {
    Body {
        position: VecD::<D>::from(x),
        velocity: VecD::<D>::from(v),
        angular_velocity: Vec3::zeros(),
        diameter: d,
    }
}

/// Every coordinate of the state of a 2D run (positions, velocities, spins), as bits.
fn state_bits(e: &Engine<2>) -> Vec<u64> {
    let p = &e.p;
    p.pos
        .iter()
        .chain(&p.vel)
        .flat_map(|v| v.iter().copied())
        .chain(p.omega.iter().copied())
        .map(f64::to_bits)
        .collect()
}

/// Runs until the contact count of `kind` has gone up and back to zero; returns steps in contact.
fn through_one_contact<const D: usize>(e: &mut Engine<D>, wall: bool) -> u64 {
    let count = |e: &Engine<D>| {
        if wall {
            e.wall_contacts.len()
        } else {
            e.pairs.len()
        }
    };
    let mut inside = 0;
    while count(e) == 0 {
        e.step().unwrap();
        assert!(e.steps() < 1_000_000, "no contact");
    }
    while count(e) > 0 {
        e.step().unwrap();
        inside += 1;
    }
    inside
}

#[test]
fn a_disk_bounces_off_the_floor_with_the_laws_restitution() {
    // HSD realizes ε exactly (Antypov & Elliott, δ back to 0). The first touch falls anywhere
    // within a step: 16 phases of it, at 50 steps per collision (the engine's default) and more.
    // Before the first/last-step means and the second-order predictor, the error at 50 steps was
    // 1.4e-3 at one phase and 4e-3 at the worst (falling as dt^{5/4}: the δ^{1/4} kink).
    for (eps, steps_per_collision, tol) in [
        // measured worst over the phases: 1.3e-4, 1.6e-5, 8.6e-5, 1.0e-4, 6.7e-5 at 50 steps;
        // 5.6e-5 at 100, 1.3e-5 at 400 (the issue asks for 1e-3 at 50)
        (0.1, 50.0, 3e-4),
        (0.3, 50.0, 3e-4),
        (0.5, 50.0, 3e-4),
        (0.7, 50.0, 3e-4),
        (0.9, 50.0, 3e-4),
        (0.5, 100.0, 1e-4),
        (0.5, 400.0, 3e-5),
    ] {
        let mut worst: f64 = 0.0;
        for phase in 0..16 {
            let mat = soft(DiskMass::Sphere);
            let mut cfg = EngineConfig::<2>::new(mat);
            cfg.impact_speed = Some(1.0);
            cfg.steps_per_collision = steps_per_collision;
            // probe the step, then place the first touch at (phase + 0.5)/16 of a step
            let floor = || Wall::fixed(VecD::<2>::new(0.0, 0.0), VecD::<2>::new(0.0, 1.0));
            let b = body([0.0, 0.5 * D2 + 1e-6], [0.0, -1.0], D2);
            let dt = Engine::new(cfg.clone(), &[b], vec![floor()], laws(&mat, eps, None))
                .unwrap()
                .dt();
            let gap = (phase as f64 + 0.5) / 16.0 * dt * 1.0 + 2.0 * dt;
            let b = body([0.0, 0.5 * D2 + gap], [0.0, -1.0], D2);
            let mut e = Engine::new(cfg, &[b], vec![floor()], laws(&mat, eps, None)).unwrap();
            let steps = through_one_contact(&mut e, true);
            let r = e.p.vel[0].y / 1.0;
            assert!(
                steps as f64 >= steps_per_collision - 1.0,
                "{steps} steps per collision"
            );
            assert_eq!(e.p.vel[0].x, 0.0);
            worst = worst.max((r - eps).abs());
        }
        println!("eps {eps}, {steps_per_collision} steps per collision: worst |r - eps| over 16 phases {worst:.3e}");
        assert!(
            worst < tol,
            "realized restitution off by {worst} for eps {eps} at {steps_per_collision} steps"
        );
    }
}

#[test]
fn a_head_on_collision_reproduces_the_two_body_driver() {
    let mat = soft(DiskMass::Sphere);
    let eps = 0.7;
    let v = 1.0;
    let mut cfg = EngineConfig::<3>::new(mat);
    cfg.impact_speed = Some(v);
    cfg.steps_per_collision = 200.0;
    let a = body([-0.5 * D2 - 1e-7, 0.0, 0.0], [0.5 * v, 0.0, 0.0], D2);
    let b = body([0.5 * D2 + 1e-7, 0.0, 0.0], [-0.5 * v, 0.0, 0.0], D2);
    let l = laws(&mat, eps, None);
    let (m, _) = mat.mass_inertia(3, D2);
    let (meff, reff) = (0.5 * m, 0.25 * D2);
    let reference = collide(
        &PairLaw::new(&*l.pair as &dyn NormalLaw, meff, reff),
        meff,
        v,
        EndCriterion::Overlap,
        &Options::default(),
    )
    .unwrap();
    let mut e = Engine::new(cfg, &[a, b], vec![], l).unwrap();
    let steps = through_one_contact(&mut e, false);
    let dt = e.dt();
    let r = (e.p.vel[1].x - e.p.vel[0].x) / v;
    let tau = steps as f64 * dt;
    println!(
        "engine: r = {r:.6}, tau = {tau:.4e} s ({steps} steps of {dt:.3e}); driver: r = {:.6}, tau = {:.4e} s",
        reference.restitution, reference.contact_time
    );
    assert!((r - reference.restitution).abs() < 1e-3);
    // contact found at the first step end after touching, lost at the first after separating
    assert!(
        (tau - reference.contact_time).abs() <= 1.0 * dt,
        "tau {tau} vs {}",
        reference.contact_time
    );
    // momentum is conserved exactly (equal and opposite forces)
    assert!((e.p.vel[0].x + e.p.vel[1].x).abs() < 1e-12);
}

#[test]
fn elastic_energy_is_conserved_over_1e5_steps() {
    let mat = soft(DiskMass::Sphere);
    let mut cfg = EngineConfig::<2>::new(mat);
    cfg.impact_speed = Some(1.0);
    cfg.steps_per_collision = 200.0;
    let side = 6.0 * D2;
    let mut bodies = Vec::new();
    let mut uniform = ext::lcg_uniform(12345);
    let mut rnd = || uniform() - 0.5;
    for a in 0..3 {
        for b in 0..3 {
            let x = [(a as f64 + 1.0) * 1.5 * D2, (b as f64 + 1.0) * 1.5 * D2];
            bodies.push(body(
                x,
                [0.5 * rnd(), 0.5 * rnd()],
                D2 * (0.9 + 0.2 * (rnd() + 0.5)),
            ));
        }
    }
    let walls = vec![
        Wall::fixed(VecD::<2>::new(0.0, 0.0), VecD::<2>::new(0.0, 1.0)),
        Wall::fixed(VecD::<2>::new(0.0, side), VecD::<2>::new(0.0, -1.0)),
        Wall::fixed(VecD::<2>::new(0.0, 0.0), VecD::<2>::new(1.0, 0.0)),
        Wall::fixed(VecD::<2>::new(side, 0.0), VecD::<2>::new(-1.0, 0.0)),
    ];
    let mut e = Engine::new(cfg, &bodies, walls, laws(&mat, 1.0, None)).unwrap();
    // Hertz potential (2/5) K δ^{5/2}, K = (4/3) E_eff √r_eff
    let p = mat.particle(1.0);
    let (epp, epw) = (
        MaterialPair::spheres(&p, &p).unwrap().young,
        MaterialPair::wall(&p).unwrap().young,
    );
    let total = |e: &Engine<2>| {
        let elastic = |cs: &dashpot::dem::contacts::Contacts, ey: f64| -> f64 {
            cs.chunks
                .iter()
                .flat_map(|c| c.radius.iter().zip(&c.delta))
                .map(|(r, d)| 0.4 * 4.0 / 3.0 * ey * r.sqrt() * d.powf(2.5))
                .sum::<f64>()
        };
        e.energy().total() + elastic(&e.pairs, epp) + elastic(&e.wall_contacts, epw)
    };
    let e0 = total(&e);
    // Velocity Verlet conserves a shadow energy: inside a contact the true energy differs from it
    // by O((dt/τ)²) of the colliding pair's energy, and returns when the contact is over; the drift
    // is what is left between contacts.
    let (mut worst, mut worst_in_contact): (f64, f64) = (0.0, 0.0);
    let mut collisions = 0;
    let mut free = 0;
    for _ in 0..100_000 {
        e.step().unwrap();
        let err = (total(&e) - e0).abs() / e0;
        worst_in_contact = worst_in_contact.max(err);
        if e.contacts() == 0 {
            worst = worst.max(err);
            free += 1;
        }
        collisions = e.pair_episodes + e.wall_episodes.iter().sum::<u64>();
    }
    println!(
        "1e5 steps, {collisions} contact episodes, max relative energy error {worst:.3e} between contacts \
         ({free} steps), {worst_in_contact:.3e} within"
    );
    assert!(free > 10_000);
    assert!(collisions > 20, "{collisions} collisions only");
    assert!(worst < 1e-6, "energy drift {worst}");
}

/// Launched sliding without spin, a particle ends rolling at m/(m + I/R²) of its launch speed.
fn rolls_at<const D: usize>(disk_mass: DiskMass, expected: f64) {
    rolls_with::<D>(disk_mass, expected, false)
}

fn rolls_with<const D: usize>(disk_mass: DiskMass, expected: f64, mindlin: bool) {
    let mat = soft(disk_mass);
    let r = 0.5 * D2;
    let (m, _) = mat.mass_inertia(D, D2);
    let g = 9.81;
    let ew = MaterialPair::wall(&mat.particle(1.0)).unwrap().young;
    let k = 4.0 / 3.0 * ew * r.sqrt();
    let delta_eq = (m * g / k).powf(2.0 / 3.0);
    let mut cfg = EngineConfig::<D>::new(mat);
    let mut grav = VecD::<D>::zeros();
    grav[1] = -g;
    cfg.gravity = grav;
    let mut x = VecD::<D>::zeros();
    x[1] = r - delta_eq;
    let v0 = 0.2;
    let mut v = VecD::<D>::zeros();
    v[0] = v0;
    let b = Body {
        position: x,
        velocity: v,
        angular_velocity: Vec3::zeros(),
        diameter: D2,
    };
    let mut up = VecD::<D>::zeros();
    up[1] = 1.0;
    let floor = Wall::fixed(VecD::<D>::zeros(), up);
    let kn = 1.5 * k * delta_eq.sqrt();
    let mu = 0.3;
    let friction = CundallStrack { kt: kn, mu };
    let mut l = laws(&mat, 0.5, Some(friction));
    if mindlin {
        // the workspace's Mindlin–Deresiewicz law (linked as an rlib, called through the trampoline)
        let m = dashpot_mindlin::Mindlin::with(mu, 0.0);
        let pw = MaterialPair::wall(&mat.particle(1.0)).unwrap();
        l.wall_tangential = Some(Box::new(compiled_tangential(&m, &pw).unwrap()));
    }
    let mut e = Engine::new(cfg, &[b], vec![floor], l).unwrap();
    // sliding lasts v0 (1 − expected)/(μ g); run three times that, then average over a window
    let t_slide = v0 * (1.0 - expected) / (mu * g);
    e.run_until(3.0 * t_slide, 0, &mut |_| {}).unwrap();
    let (mut vs, mut slip, mut n) = (0.0, 0.0, 0.0);
    while e.time() < 4.0 * t_slide {
        e.step().unwrap();
        vs += e.p.vel[0][0];
        slip += e.p.vel[0][0] + e.p.angular_velocity(0).z * r;
        n += 1.0;
    }
    let ratio = vs / n / v0;
    println!(
        "D = {D}, {}: v/v0 = {ratio:.5} (expected {expected:.5}), mean slip {:.2e} m/s",
        disk_mass.as_str(),
        slip / n
    );
    assert!(
        (ratio - expected).abs() < 2e-3,
        "rolling at {ratio} of launch speed, expected {expected}"
    );
    assert!((slip / n).abs() < 1e-3 * v0);
    assert_eq!(e.wall_contacts.len(), 1, "stays on the floor");
}

#[test]
fn a_disk_launched_sliding_ends_rolling_at_two_thirds() {
    rolls_at::<2>(DiskMass::Disk, 2.0 / 3.0);
}

#[test]
fn a_sphere_launched_sliding_ends_rolling_at_five_sevenths() {
    rolls_at::<3>(DiskMass::Sphere, 5.0 / 7.0);
    // a 2D disk carrying a sphere's mass and inertia (the paper's convention) rolls as a sphere
    rolls_at::<2>(DiskMass::Sphere, 5.0 / 7.0);
    // and with the Mindlin law (stiffness 8 G a) instead of the test's linear spring
    rolls_with::<3>(DiskMass::Sphere, 5.0 / 7.0, true);
}

/// An oblique collision with friction: in the middle of a periodic box with a neighbour list
/// built once, or straddling the periodic boundary (one disk is wrapped during the contact) with
/// the list rebuilt every step. The history (the tangential spring) must come through both.
#[test]
fn history_survives_the_periodic_boundary_and_rebuilds() {
    let mat = soft(DiskMass::Disk);
    let run = |x0: f64, rebuild_every_step: bool| -> (Engine<2>, f64) {
        let mut cfg = EngineConfig::<2>::new(mat);
        let l = 10.0 * D2;
        cfg.domain = Domain {
            lo: VecD::<2>::new(0.0, -l),
            hi: VecD::<2>::new(l, l),
            periodic: [true, false],
            bounded: false,
        };
        cfg.impact_speed = Some(1.0);
        cfg.steps_per_collision = 100.0;
        cfg.skin = Some(0.5 * D2);
        // i above j, touching at x0; i slides +x, j −x, approaching along y
        let a = body([x0, 0.5 * D2 + 1e-7], [0.3, -0.2], D2);
        let b = body([x0, -0.5 * D2 - 1e-7], [-0.3, 0.2], D2);
        let f = CundallStrack { kt: 2.0e3, mu: 0.5 };
        let mut e = Engine::new(cfg, &[a, b], vec![], laws(&mat, 0.8, Some(f))).unwrap();
        let mut max_spring: f64 = 0.0;
        while e.pairs.is_empty() {
            e.step().unwrap();
        }
        while !e.pairs.is_empty() {
            if rebuild_every_step {
                e.invalidate_neighbours();
            }
            e.step().unwrap();
            if !e.pairs.is_empty() {
                max_spring = max_spring.max(e.pairs.chunks[0].hist_t[0].abs());
            }
        }
        (e, max_spring)
    };
    let l = 10.0 * D2;
    let (a, spring_a) = run(0.5 * l, false);
    let (b, spring_b) = run(l - 1e-5, true);
    println!(
        "rebuilds: {} vs {}; spring max {spring_a:.3e} vs {spring_b:.3e} m; omega {:.6} vs {:.6} rad/s",
        a.rebuilds(),
        b.rebuilds(),
        a.p.angular_velocity(0).z,
        b.p.angular_velocity(0).z
    );
    assert!(b.rebuilds() >= 50 && a.rebuilds() <= 2);
    assert!(
        b.p.pos[0].x < 0.5 * l,
        "disk 0 crossed the periodic boundary and was wrapped"
    );
    assert!(spring_a > 0.0 && (spring_a - spring_b).abs() <= 1e-9 * spring_a);
    for k in 0..2 {
        assert!((a.p.vel[k] - b.p.vel[k]).norm() < 1e-9, "velocity of {k}");
        assert!((a.p.omega[k] - b.p.omega[k]).abs() < 1e-9 * a.p.omega[k].abs());
    }
    // the spring mattered: both disks spin, and the tangential impulse slowed the sliding
    assert!(a.p.omega[0].abs() > 1.0 && a.p.vel[0].x < 0.3 - 1e-3);
}

/// A dense 2D lattice of `cols` × `rows` disks, spacing 0.99 of the largest diameter (so that
/// most neighbours overlap from the start), random directions at 0.2 m/s, diameters in
/// [0.97, 1] × D2; periodic sideways, and periodic vertically too when `closed` is false.
fn dense_lattice(cols: usize, rows: usize, closed: bool) -> (EngineConfig<2>, Vec<Body<2>>) {
    let mat = soft(DiskMass::Disk);
    let a = 0.99 * D2;
    let mut rnd = ext::lcg_uniform(99);
    let bodies = (0..cols * rows)
        .map(|k| {
            let (q, r) = ((k % cols) as f64, (k / cols) as f64);
            let t = 2.0 * std::f64::consts::PI * rnd();
            let d = D2 * (0.97 + 0.03 * rnd());
            body([(q + 0.5) * a, (r + 0.5) * a], [0.2 * t.cos(), 0.2 * t.sin()], d)
        })
        .collect();
    let mut cfg = EngineConfig::<2>::new(mat);
    cfg.impact_speed = Some(1.0);
    cfg.domain = Domain {
        lo: VecD::<2>::new(0.0, if closed { -1.0 } else { 0.0 }),
        hi: VecD::<2>::new(cols as f64 * a, rows as f64 * a + if closed { 1.0 } else { 0.0 }),
        periodic: [true, !closed],
        bounded: false,
    };
    (cfg, bodies)
}

/// Contacts are gathered, evaluated and summed in chunks of particles, in parallel: a pair
/// whose partners lie in different chunks must still give equal and opposite forces (Newton's
/// third law, so the total force vanishes in a periodic box), and every overlapping pair must
/// be found (against a brute-force count over all pairs, minimum image).
#[test]
fn chunked_contacts_keep_newtons_third_law_and_miss_no_pair() {
    // 70 columns: the chunk boundaries (every 2,048 disks) fall inside rows, and the rows
    // above and below a boundary hold partners of both chunks
    let (cols, rows) = (70, 72);
    let (cfg, bodies) = dense_lattice(cols, rows, false);
    let f = CundallStrack { kt: 2.0e3, mu: 0.5 };
    let mat = cfg.material;
    let mut e = Engine::new(cfg.clone(), &bodies, vec![], laws(&mat, 0.8, Some(f))).unwrap();
    for _ in 0..5 {
        e.step().unwrap();
    }
    let (lx, ly) = (cfg.domain.length(0), cfg.domain.length(1));
    let p = &e.p;
    let mut brute = 0;
    for i in 0..p.len() {
        for j in i + 1..p.len() {
            let mut d = p.pos[i] - p.pos[j];
            d.x -= lx * (d.x / lx).round();
            d.y -= ly * (d.y / ly).round();
            if d.norm() < p.radius[i] + p.radius[j] {
                brute += 1;
            }
        }
    }
    assert!(e.pairs.chunks.len() >= 3, "{} chunks", e.pairs.chunks.len());
    assert_eq!(e.pairs.len(), brute, "pair contacts found against brute force");
    let total: VecD<2> = p.force.iter().sum();
    let scale: f64 = p.force.iter().map(|f| f.norm()).sum();
    println!(
        "{brute} contacts; |sum F| = {:.3e} N of sum |F| = {scale:.3e} N",
        total.norm()
    );
    assert!(scale > 0.0 && total.norm() <= 1e-12 * scale);
    // the tangential forces are there too, so the torques are not all zero
    assert!(p.torque.iter().any(|t| t.abs() > 0.0));
}

/// The forces of a step are summed in a fixed order whatever the number of threads (chunk by
/// chunk, partners beyond a chunk afterwards), so a run is bit for bit the same on one thread
/// and on two.
#[test]
fn a_run_is_the_same_bit_for_bit_on_one_thread_and_two() {
    let run = |threads: usize| -> Engine<2> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let (mut cfg, bodies) = dense_lattice(70, 72, true);
            cfg.gravity = VecD::<2>::new(0.0, -9.81);
            let mat = cfg.material;
            let f = CundallStrack { kt: 2.0e3, mu: 0.5 };
            let floor = Wall::fixed(VecD::<2>::new(0.0, 0.0), VecD::<2>::new(0.0, 1.0));
            let mut e = Engine::new(cfg, &bodies, vec![floor], laws(&mat, 0.8, Some(f))).unwrap();
            for _ in 0..40 {
                e.step().unwrap();
            }
            e
        })
    };
    let (a, b) = (run(1), run(2));
    println!(
        "{} pair and {} wall contacts after 40 steps",
        a.pairs.len(),
        a.wall_contacts.len()
    );
    assert!(a.pairs.len() > 1000 && !a.wall_contacts.is_empty());
    assert!(state_bits(&a) == state_bits(&b), "one thread and two part");
}

/// A step with a valid neighbour list is one pass over the particles (each chunk drifted, then
/// its forces evaluated, chunks in reverse order, the chunks cut into one range per thread
/// whose first chunks drift as soon as an earlier range needs them); on a step where the list
/// goes stale mid-pass, the forces are evaluated again after a rebuild. Its result must be the
/// same bit for bit as the plain two passes (every drift, a fresh list, every force: forced
/// here by invalidating the list before each step) on one, two and three threads, step by step
/// or in blocks of steps. An open box, so that no wrapping at the rebuilds tells the runs apart.
#[test]
fn the_one_pass_step_is_the_same_bit_for_bit_as_two_passes() {
    // 70 × 72 disks: 3 chunks, one range each on 2 and 3 threads (each a whole head or none);
    // 140 × 130 disks: 9 chunks, ranges of 3 to 5 chunks, some with a head and more (3D piles
    // of small chunks: `dem_order.rs`)
    for (cols, rows, steps) in [(70, 72, 600), (140, 130, 480)] {
        one_pass_against_two(cols, rows, steps);
    }
}

fn one_pass_against_two(cols: usize, rows: usize, steps: usize) {
    // `threads` 0: off any pool (the global one, as the CLI runs); `blocks`: the steps as
    // blocks of `advance` (the pool's other threads kept awake through each block) instead of
    // single steps
    let run = |threads: usize, two_passes: bool, blocks: bool| -> Engine<2> {
        let go = || {
            let (mut cfg, mut bodies) = dense_lattice(cols, rows, false);
            cfg.domain.periodic = [false, false];
            cfg.gravity = VecD::<2>::new(0.0, -9.81);
            // 1 m/s: the list goes stale every few dozen steps
            bodies.iter_mut().for_each(|b| b.velocity *= 5.0);
            cfg.impact_speed = Some(2.0);
            let mat = cfg.material;
            let f = CundallStrack { kt: 2.0e3, mu: 0.5 };
            let floor = Wall::fixed(VecD::<2>::new(0.0, 0.0), VecD::<2>::new(0.0, 1.0));
            let mut e = Engine::new(cfg, &bodies, vec![floor], laws(&mat, 0.8, Some(f))).unwrap();
            if blocks {
                for _ in 0..4 {
                    e.advance(steps as u64 / 4).unwrap();
                }
                return e;
            }
            for _ in 0..steps {
                if two_passes {
                    e.invalidate_neighbours();
                }
                e.step().unwrap();
            }
            e
        };
        if threads == 0 {
            return go();
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(go)
    };
    let reference = run(1, true, false);
    assert_eq!(reference.rebuilds(), steps as u64 + 1);
    for (threads, blocks) in [
        (1, false),
        (2, false),
        (3, false),
        (2, true),
        (3, true),
        (0, true),
    ] {
        let e = run(threads, false, blocks);
        println!(
            "{cols} x {rows} disks, {threads} thread(s), blocks {blocks}: {} list builds in {steps} steps, {} pair and {} wall contacts",
            e.rebuilds(),
            e.pairs.len(),
            e.wall_contacts.len()
        );
        assert!(e.rebuilds() >= 3, "the run must cross stale lists");
        assert!(e.pairs.len() > 1000 && !e.wall_contacts.is_empty());
        assert!(
            state_bits(&e) == state_bits(&reference),
            "{threads} thread(s), blocks {blocks}: one pass and two part"
        );
    }
}

/// A non-finite coordinate, however it got there, stops the run at the next step with an error
/// naming the particle, not a result: in a velocity, a spin, or a position (here an isolated
/// disk, so that no contact test meets it first).
#[test]
fn a_non_finite_state_stops_the_run_naming_the_particle() {
    let (cfg, bodies) = dense_lattice(70, 72, false);
    let mat = cfg.material;
    for what in 0..3 {
        let mut e = Engine::new(cfg.clone(), &bodies, vec![], laws(&mat, 0.8, None)).unwrap();
        e.step().unwrap();
        match what {
            0 => e.p.vel[4321].x = f64::NAN,
            1 => e.p.omega[4321] = f64::INFINITY,
            _ => {
                // far from every other disk: no pair test sees it
                e.p.pos[4321].x = f64::NAN;
                e.invalidate_neighbours();
            }
        }
        let err = e.step().expect_err("a non-finite state must stop the run");
        let msg = err.to_string();
        println!("{msg}");
        assert!(msg.contains("particle 4321"), "{msg}");
    }
}

/// `advance(k)` does the second half-kick of each step in the same pass as the next step's
/// first half-kick and drift: the end state must be the same bit for bit as after `k` steps.
#[test]
fn advance_is_the_same_bit_for_bit_as_single_steps() {
    let (mut cfg, bodies) = dense_lattice(30, 20, true);
    cfg.gravity = VecD::<2>::new(0.0, -9.81);
    let mat = cfg.material;
    let f = CundallStrack { kt: 2.0e3, mu: 0.5 };
    let floor = Wall::fixed(VecD::<2>::new(0.0, 0.0), VecD::<2>::new(0.0, 1.0));
    let new = || {
        Engine::new(
            cfg.clone(),
            &bodies,
            vec![floor.clone()],
            laws(&mat, 0.8, Some(f)),
        )
        .unwrap()
    };
    let (mut a, mut b) = (new(), new());
    for _ in 0..60 {
        a.step().unwrap();
    }
    b.advance(25).unwrap();
    b.advance(35).unwrap();
    assert!(a.pairs.len() > 100 && a.steps() == b.steps());
    assert!(state_bits(&a) == state_bits(&b), "advance and single steps part");
}
