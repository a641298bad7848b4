//! Walls beyond fixed planes, against closed forms: a sphere dropped on a moving belt ends
//! rolling at 2/7 of the belt's speed (the wall's velocity at the contact drives friction); a
//! sphere on a turntable ends spinning with it (the wall's rotation drives the twisting law);
//! a sphere bounces off the inside of a cylinder and off a post with HSD's ε along the radius;
//! a disk driven into a box's corner bounces off both faces at once, each its own contact; a
//! disk hitting a box's corner from outside bounces along the diagonal. A pile on a vibrated
//! floor and a sphere bed in a rotating drum close their energy books with the walls' work; the
//! drum comparison script (examples/dem/drum_compare.py) measures a synthetic tilted bed to 0.1°.

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
        .replace("count = 2100", "count = 200")
        .replace("[0.0038, 0.0042]", "[0.0028, 0.0032]")
        .replace("young = 1.0e6", "young = 5.0e6")
        .replace("lo = [-0.045, 0.0, -0.045]", "lo = [-0.025, 0.0, -0.025]")
        .replace("hi = [0.045, 0.0486, 0.045]", "hi = [0.025, 0.01344, 0.025]")
        .replace("lo = [-0.04, 0.0, -0.04]", "lo = [-0.02, 0.0, -0.02]")
        .replace("hi = [0.04, 0.0486, 0.04]", "hi = [0.02, 0.01344, 0.02]");
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
    let m: f64 = e.p.radius.iter().map(|r| r.powi(3)).sum();
    let centre = |k: usize| {
        e.p.pos
            .iter()
            .zip(&e.p.radius)
            .map(|(x, r)| x[k] * r.powi(3))
            .sum::<f64>()
            / m
    };
    let angle = (-centre(0)).atan2(-centre(2)).to_degrees();
    eprintln!(
        "drum: angle {angle:.2}°, books residual {r:.2e} of the dissipated, wall work {} J",
        e.wall_work
    );
    assert!((15.0..45.0).contains(&angle), "the surface's angle {angle}°");
    assert!(e.wall_work > 0.0, "the drum lifts the bed: {}", e.wall_work);
    // the comparison script (examples/dem/drum_compare.py) reads dashpot's own frames: its
    // centroid angle of this state is the one computed here (to the file's 7-10 digits)
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("drum.xyz");
    let mut w = std::io::BufWriter::new(std::fs::File::create(&file).unwrap());
    dashpot::dem::xyz::write_frame(&e, &mut w).unwrap();
    drop(w);
    let got = drum_script(&file, 0.0, None, 0.02);
    assert_eq!(got.frames, 1);
    assert!(
        (got.centroid[0] - angle).abs() < 1e-4,
        "the script's centroid angle {}° against {angle}°",
        got.centroid[0]
    );
}

/// The angles the drum comparison script measures in a trajectory file (degrees).
struct DrumAngles {
    frames: usize,
    centroid: [f64; 2],
    surface: [f64; 2],
}

/// Runs `examples/dem/drum_compare.py --measure FILE` (the frames at t >= `since` s, a LAMMPS
/// dump's step `dt` s, the drum's radius `radius` m) with `python3`.
fn drum_script(file: &std::path::Path, since: f64, dt: Option<f64>, radius: f64) -> DrumAngles {
    let script = dashpot_tests::workspace_root().join("examples/dem/drum_compare.py");
    let mut cmd = std::process::Command::new("python3");
    cmd.arg(&script).arg("--measure").arg(file);
    cmd.args(["--since", &since.to_string(), "--radius", &radius.to_string()]);
    if let Some(dt) = dt {
        cmd.args(["--dt", &dt.to_string()]);
    }
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("python3 (for {}): {e}", script.display()));
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let pair = |k: &str| [v[k][0].as_f64().unwrap(), v[k][1].as_f64().unwrap()];
    DrumAngles {
        frames: v["frames"].as_u64().unwrap() as usize,
        centroid: pair("centroid"),
        surface: pair("surface"),
    }
}

/// A synthetic bed in a drum of radius `big_r` (m) about y: a free surface at `theta_deg` to the
/// horizontal, lifted on the -x side, `depth` m below the axis (0: half full), sphere tops on
/// it; below a gap, a square lattice. Symmetric about the surface's perpendicular through the
/// axis, so the bed's centre of mass lies on it. Spheres as (x, y, z, radius) (m).
fn tilted_bed(theta_deg: f64, depth: f64, big_r: f64) -> Vec<[f64; 4]> {
    let (s, r0) = (0.003, 0.0015);
    let (sin, cos) = theta_deg.to_radians().sin_cos();
    // u along the surface (cos, -sin), v up its normal (sin, cos)
    let at = |u: f64, v: f64, y: f64, r: f64| [u * cos + v * sin, y, -u * sin + v * cos, r];
    let mut out = Vec::new();
    let n = (big_r / s).ceil() as i32 + 1;
    for layer in 0..3 {
        let y = layer as f64 * s;
        for j in -n..n {
            let u = (j as f64 + 0.5) * s;
            // the surface layer: radii varying along it (symmetric in u), tops on the surface
            let r = r0 + 0.0002 * (u / (2.3 * s)).cos();
            let v = -depth - r;
            if u.hypot(v) <= big_r - r {
                out.push(at(u, v, y, r));
            }
            for k in 3..2 * n {
                let v = -depth - r0 - k as f64 * s;
                if u.hypot(v) <= big_r - r0 {
                    out.push(at(u, v, y, r0));
                }
            }
        }
    }
    out
}

#[test]
fn the_drum_script_measures_a_tilted_bed_to_a_tenth_of_a_degree_from_both_codes_outputs() {
    let big_r = 0.04;
    let dir = tempfile::tempdir().unwrap();
    for (theta, depth) in [(14.0f64, 0.0f64), (27.3, 0.0), (38.6, 0.0), (31.0, 0.008)] {
        // two frames: the bed flat at t = 0, tilted at t = 1 s; the script measures from 0.5 s
        let frames = [
            (0.0f64, tilted_bed(0.0, depth, big_r)),
            (1.0, tilted_bed(theta, depth, big_r)),
        ];
        let (xyz, dump) = (dir.path().join("bed.xyz"), dir.path().join("bed.dump"));
        let (mut a, mut b) = (String::new(), String::new());
        for (t, bed) in &frames {
            // dashpot's extended XYZ (as dashpot::dem::xyz writes it)
            a += &format!(
                "{}\nLattice=\"0.09 0 0 0 0.009 0 0 0 0.09\" Origin=\"-0.045 0 -0.045\" \
                 Properties=species:S:1:pos:R:3:velo:R:3:omega:R:3:radius:R:1:power:R:1 \
                 Time={t} pbc=\"F T F\"\n",
                bed.len()
            );
            for p in bed {
                a += &format!("P {} {} {} 0 0 0 0 0 0 {} 0\n", p[0], p[1], p[2], p[3]);
            }
            // a LAMMPS custom dump (id x y z radius) at a step of 1e-5 s, ids in reverse
            b += &format!(
                "ITEM: TIMESTEP\n{}\nITEM: NUMBER OF ATOMS\n{}\nITEM: BOX BOUNDS ff pp ff\n\
                 -0.045 0.045\n0 0.009\n-0.045 0.045\nITEM: ATOMS id x y z radius\n",
                (t / 1e-5).round(),
                bed.len()
            );
            for (i, p) in bed.iter().enumerate().rev() {
                b += &format!("{} {} {} {} {}\n", i + 1, p[0], p[1], p[2], p[3]);
            }
        }
        std::fs::write(&xyz, a).unwrap();
        std::fs::write(&dump, b).unwrap();
        for got in [
            drum_script(&xyz, 0.5, None, big_r),
            drum_script(&dump, 0.5, Some(1e-5), big_r),
        ] {
            assert_eq!(got.frames, 1, "the frames from t = 0.5 s on");
            for (what, a) in [("centroid", got.centroid), ("surface fit", got.surface)] {
                assert!(
                    (a[0] - theta).abs() < 0.1 && a[1] == 0.0,
                    "{what}: {:.3} ± {:.3}° for a surface at {theta}° ({depth} m below the axis)",
                    a[0],
                    a[1]
                );
            }
        }
    }
}
