//! Walls beyond fixed planes, against closed forms: a sphere dropped on a moving belt ends
//! rolling at 2/7 of the belt's speed (the wall's velocity at the contact drives friction); a
//! sphere on a turntable ends spinning with it (the wall's rotation drives the twisting law);
//! a sphere bounces off the inside of a cylinder and off a post with HSD's ε along the radius;
//! a disk driven into a box's corner bounces off both faces at once, each its own contact; a
//! disk hitting a box's corner from outside bounces along the diagonal. A pile on a vibrated
//! floor and a sphere bed in a rotating drum close their energy books with the walls' work.

use dashpot::cli::dem::scene_engine;
use dashpot::dem::scene::SceneFile;
use dashpot::dem::Engine;
use dashpot_tests::registry_03;

/// The engine of the scene `text` of dimension `D`.
fn engine<const D: usize>(text: &str) -> Engine<D> {
    let reg = registry_03();
    let file = SceneFile::parse(text).unwrap();
    let scene = file.scene::<D>().unwrap();
    scene_engine(&reg, &file, &scene).unwrap().0
}

/// A scene's header: dimension, gravity, laws (HSD at `eps`, and `more` tables), material.
fn header(dim: usize, gravity: &str, eps: f64, more: &str) -> String {
    format!(
        r#"
dimension = {dim}
gravity = {gravity}
duration = 1.0
impact_speed = 1.0
[law]
name = "hsd"
params = {{ eps = {eps} }}
{more}
[material]
young = 1.0e7
poisson = 0.3
density = 2500.0
"#
    )
}

#[test]
fn a_sphere_dropped_on_a_moving_belt_ends_rolling_at_two_sevenths_of_its_speed() {
    let u = 0.1;
    let text = header(
        3,
        "[0.0, 0.0, -9.81]",
        0.5,
        "[tangential]\nname = \"mindlin\"\nparams = { mu = 0.5 }\n",
    ) + &format!(
        r#"
[[wall]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
motion = {{ kind = "translate", velocity = [{u}, 0.0, 0.0] }}
[[particle]]
position = [0.0, 0.0, 0.001]
diameter = 0.002
"#
    );
    let mut e = engine::<3>(&text);
    // sliding lasts 2u / (7 μ g) = 5.8 ms; then the (undamped) tangential spring rings about
    // the rolling state: the velocity and the slip averaged over 20 ms
    let k = e.steps_to(0.02, u64::MAX);
    e.advance(k).unwrap();
    let (mut v, mut slip, mut n) = (0.0, 0.0, 0.0);
    while e.time() < 0.04 {
        e.step().unwrap();
        let w = e.p.angular_velocity(0);
        v += e.p.vel[0][0];
        // (the contact point, r below the centre, moves at v + ω × (0, 0, -r))
        slip += e.p.vel[0][0] - w.y * 0.001 - u;
        n += 1.0;
    }
    let (v, slip) = (v / n, slip / n);
    assert!(
        (v / u - 2.0 / 7.0).abs() < 2e-3,
        "mean v = {v}: 2/7 of {u} m/s expected"
    );
    // rolling without slipping on the belt: the contact point moves with it
    assert!(slip.abs() < 2e-3 * u, "mean slip {slip} m/s");
    assert!(e.p.vel[0][1].abs() < 1e-12 && e.wall_contacts.len() == 1);
}

#[test]
fn a_sphere_on_a_turntable_ends_spinning_with_it() {
    let omega = 5.0;
    let text = header(
        3,
        "[0.0, 0.0, -9.81]",
        0.5,
        "[tangential]\nname = \"mindlin\"\nparams = { mu = 0.5 }\n[twisting]\nname = \"twisting-sds\"\nparams = { k = 1e-4, gamma = 1e-7, mu = 1e-3 }\n",
    ) + &format!(
        r#"
[[wall]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
motion = {{ kind = "rotate", angular_velocity = {omega}, axis = [0.0, 0.0, 1.0], point = [0.0, 0.0, 0.0] }}
[[particle]]
position = [0.0, 0.0, 0.001]
diameter = 0.002
"#
    );
    let mut e = engine::<3>(&text);
    let k = e.steps_to(0.2, u64::MAX);
    e.advance(k).unwrap();
    let w = e.p.angular_velocity(0);
    assert!(
        (w.z / omega - 1.0).abs() < 1e-2,
        "spin {w:?}: {omega} rad/s about z expected"
    );
    // on the axis, the table's surface does not move under it: it stays put
    assert!(
        e.p.pos[0][0].abs() < 1e-9 && e.p.pos[0][1].abs() < 1e-9,
        "{:?}",
        e.p.pos[0]
    );
}

/// The restitution of a sphere launched at `v` from `x0` along +x into the wall `wall` (3D, no
/// gravity): its velocity after the bounce over before.
fn bounce(wall: &str, x0: [f64; 3], v: [f64; 3], eps: f64) -> (f64, [f64; 3]) {
    let text = header(3, "[0.0, 0.0, 0.0]", eps, "")
        + wall
        + &format!("[[particle]]\nposition = {x0:?}\nvelocity = {v:?}\ndiameter = 0.002\n");
    let mut e = engine::<3>(&text);
    let mut touched = false;
    while e.time() < 0.05 {
        e.step().unwrap();
        touched |= !e.wall_contacts.is_empty();
        if touched && e.wall_contacts.is_empty() {
            break;
        }
    }
    assert!(touched && e.wall_contacts.is_empty(), "the sphere bounced");
    let after = e.p.vel[0];
    let speed = |a: &[f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    (
        speed(&[after[0], after[1], after[2]]) / speed(&v),
        [after[0], after[1], after[2]],
    )
}

#[test]
fn a_sphere_bounces_off_a_drums_inside_and_a_posts_outside_along_the_radius() {
    let eps = 0.6;
    // inside a drum about y of radius 10 mm, launched along a radius: back along it
    let drum =
        "[[wall]]\nkind = \"cylinder\"\npoint = [0.0, 0.0, 0.0]\naxis = [0.0, 1.0, 0.0]\nradius = 0.01\n";
    let (e, after) = bounce(drum, [0.0, 0.0, 0.0], [0.3, 0.0, 0.4], eps);
    assert!(
        (e - eps).abs() < 2e-3 && after[0] < 0.0 && (after[2] / after[0] - 4.0 / 3.0).abs() < 1e-6,
        "{e}: {after:?}"
    );
    // launched off the axis (at z = 3 mm, along x): the normal at impact is from the contact
    // towards the axis, through the centre at x = sqrt((R - r)² - z²); frictionless, the
    // tangential velocity is kept, the normal one reversed times ε (up to the turn of the
    // normal while the sphere slides along the curved wall, |v_t| τ / R ~ 0.5 %)
    let z = 0.003;
    let (_, after) = bounce(drum, [0.0, 0.0, z], [0.5, 0.0, 0.0], eps);
    let xc = ((0.009f64).powi(2) - z * z).sqrt();
    let n = [-xc / 0.009, -z / 0.009];
    let (vn, vt) = (0.5 * n[0], 0.5 * n[1]);
    let (an, at) = (
        after[0] * n[0] + after[2] * n[1],
        after[0] * n[1] - after[2] * n[0],
    );
    assert!(
        (an / -vn - eps).abs() < 1e-2,
        "normal restitution {} (ε {eps})",
        an / -vn
    );
    assert!((at / vt - 1.0).abs() < 1e-2, "tangential {at} kept ({vt})");
    // a post of radius 5 mm about y at x = 10 mm: head on from the left
    let post = "[[wall]]\nkind = \"cylinder\"\npoint = [0.01, 0.0, 0.0]\naxis = [0.0, 1.0, 0.0]\nradius = 0.005\ninside = false\n";
    let (e, after) = bounce(post, [0.0, 0.0, 0.0], [0.5, 0.0, 0.0], eps);
    assert!(
        (e - eps).abs() < 2e-3 && after[0] < 0.0,
        "off the post: {e}, {after:?}"
    );
}

#[test]
fn a_disk_driven_into_a_boxs_corner_bounces_off_both_faces_each_its_own_contact() {
    let eps = 0.7;
    let text = header(2, "[0.0, 0.0]", eps, "")
        + r#"
[[wall]]
kind = "box"
lo = [0.0, 0.0]
hi = [0.02, 0.01]
[[particle]]
position = [0.002, 0.002]
velocity = [-0.3, -0.3]
diameter = 0.002
"#;
    let mut e = engine::<2>(&text);
    let mut most = 0;
    while e.time() < 0.02 {
        e.step().unwrap();
        most = most.max(e.wall_contacts.len());
    }
    assert_eq!(most, 2, "two faces touched at once");
    let v = e.p.vel[0];
    assert!(
        (v[0] / 0.3 - eps).abs() < 2e-3 && (v[1] / 0.3 - eps).abs() < 2e-3,
        "{v:?}: ε {eps} on both faces"
    );
    // the box's impulse: both faces' belong to wall 0
    assert!(e.wall_episodes[0] == 2, "{:?}", e.wall_episodes);
}

#[test]
fn a_disk_hitting_a_boxs_corner_from_outside_bounces_along_the_diagonal() {
    let eps = 0.5;
    let text = header(2, "[0.0, 0.0]", eps, "")
        + r#"
[[wall]]
kind = "box"
lo = [0.0, 0.0]
hi = [0.01, 0.01]
inside = false
[[particle]]
position = [0.013, 0.013]
velocity = [-0.2, -0.2]
diameter = 0.002
"#;
    let mut e = engine::<2>(&text);
    while e.time() < 0.05 {
        e.step().unwrap();
    }
    let v = e.p.vel[0];
    assert!((v[0] - v[1]).abs() < 1e-9 * 0.2, "along the diagonal: {v:?}");
    assert!((v[0] / 0.2 - eps).abs() < 2e-3, "{v:?}: ε {eps}");
}

/// The books with moving walls: initial + the walls' work = kinetic + gravity + elastic +
/// dissipated, within 1e-3 of the dissipated energy.
fn books_close<const D: usize>(e: &Engine<D>, e0: f64) -> f64 {
    let lost: f64 = e.dissipated.iter().sum();
    let now = e.energy().total() + e.elastic().iter().sum::<f64>();
    let residual = e0 + e.wall_work - now - lost;
    assert!(e.unreported.iter().all(|u| !u) && lost > 0.0);
    assert!(
        residual.abs() < 1e-3 * lost,
        "E0 {e0} + wall work {} - E {now} - dissipated {lost} = {residual} J",
        e.wall_work
    );
    residual / lost
}

#[test]
fn a_pile_on_a_vibrated_floor_closes_its_books_with_the_floors_work() {
    let text = header(
        3,
        "[0.0, 0.0, -9.81]",
        0.5,
        "[tangential]\nname = \"mindlin\"\nparams = { mu = 0.3 }\n",
    ) + r#"
[box]
lo = [0.0, 0.0, -0.01]
hi = [0.012, 0.012, 0.05]
periodic = [true, true, false]
[[wall]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
motion = { kind = "sine", amplitude = 5e-4, frequency = 40.0 }
[generate]
count = 100
diameter = [0.0018, 0.0022]
lo = [0.0, 0.0, 0.0006]
hi = [0.012, 0.012, 0.03]
seed = 9
"#;
    let reg = registry_03();
    let file = SceneFile::parse(&text).unwrap();
    let scene = file.scene::<3>().unwrap();
    let (mut e, e0) = scene_engine(&reg, &file, &scene).unwrap();
    let k = e.steps_to(0.15, u64::MAX);
    e.advance(k).unwrap();
    assert!(e.wall_work > 0.0, "the floor feeds energy in: {}", e.wall_work);
    books_close(&e, e0);
}

#[test]
fn a_bed_in_a_rotating_drum_rises_and_closes_its_books_with_the_drums_work() {
    // the example drum made small and quick: 20 mm radius, 10 rpm, 200 spheres (a third full)
    let text =
        std::fs::read_to_string(dashpot_tests::workspace_root().join("examples/dem/drum.toml")).unwrap();
    let text = text
        .replace("duration = 8.0", "duration = 1.0")
        .replace("rpm = 3.0", "rpm = 10.0")
        .replace("radius = 0.04", "radius = 0.02")
        .replace("count = 2800", "count = 200")
        .replace("lo = [-0.045, 0.0, -0.045]", "lo = [-0.025, 0.0, -0.025]")
        .replace("hi = [0.045, 0.02688, 0.045]", "hi = [0.025, 0.01344, 0.025]")
        .replace("lo = [-0.04, 0.0, -0.04]", "lo = [-0.02, 0.0, -0.02]")
        .replace("hi = [0.04, 0.02688, 0.04]", "hi = [0.02, 0.01344, 0.02]");
    let reg = registry_03();
    let file = SceneFile::parse(&text).unwrap();
    let scene = file.scene::<3>().unwrap();
    assert_eq!(scene.bodies.len(), 200);
    let (mut e, e0) = scene_engine(&reg, &file, &scene).unwrap();
    let k = e.steps_to(1.0, u64::MAX);
    e.advance(k).unwrap();
    let r = books_close(&e, e0);
    // the bed has been carried up the rising side (the drum's bottom moves towards -x) and
    // flows down its surface: the centroid's angle from the vertical is the surface's (for a
    // flat surface, at any fill)
    let n = e.p.len() as f64;
    let (cx, cz) = (
        e.p.pos.iter().map(|x| x[0]).sum::<f64>() / n,
        e.p.pos.iter().map(|x| x[2]).sum::<f64>() / n,
    );
    let angle = (-cx).atan2(-cz).to_degrees();
    eprintln!(
        "drum: angle {angle:.2}°, books residual {r:.2e} of the dissipated, wall work {} J",
        e.wall_work
    );
    assert!((15.0..45.0).contains(&angle), "the surface's angle {angle}°");
    assert!(e.wall_work > 0.0, "the drum lifts the bed: {}", e.wall_work);
}
