//! Extended XYZ trajectories (one frame per snapshot), readable by OVITO and ASE: species,
//! position, velocity, angular velocity and radius per particle, and with energy accounting
//! on, the power its contacts dissipated at the last step (`power`, W: half of each pair
//! contact's, the whole of a wall contact's), and in a run with heat the temperature
//! (`temperature`, K); 2D runs have z = 0.

use super::state::to3;
use super::Engine;
use std::io::Write;

/// Appends the engine's current state as one frame to `w`.
pub fn write_frame<const D: usize, W: Write>(e: &Engine<D>, w: &mut W) -> std::io::Result<()> {
    let p = &e.p;
    let dom = &e.config().domain;
    // the cell: the box where it is defined, else the particles' bounding box
    let mut lo = [0.0f64; 3];
    let mut hi = [0.0f64; 3];
    for k in 0..3 {
        if k < D && (dom.periodic[k] || dom.bounded) {
            lo[k] = dom.lo[k];
            hi[k] = dom.hi[k];
        } else if k < D {
            let (a, b) = p
                .pos
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                    (a.min(x[k]), b.max(x[k]))
                });
            let r = p.radius.iter().cloned().fold(0.0, f64::max);
            (lo[k], hi[k]) = if a.is_finite() { (a - r, b + r) } else { (0.0, 1.0) };
        } else {
            let r = p.radius.iter().cloned().fold(0.0, f64::max);
            (lo[k], hi[k]) = (-r.max(1e-9), r.max(1e-9));
        }
    }
    let pbc: Vec<&str> = (0..3)
        .map(|k| if k < D && dom.periodic[k] { "T" } else { "F" })
        .collect();
    let power = e.particle_power();
    let temperature = e.temperatures();
    writeln!(w, "{}", p.len())?;
    writeln!(
        w,
        "Lattice=\"{} 0 0 0 {} 0 0 0 {}\" Origin=\"{} {} {}\" Properties=species:S:1:pos:R:3:velo:R:3:omega:R:3:radius:R:1{} Time={} pbc=\"{}\"",
        hi[0] - lo[0],
        hi[1] - lo[1],
        hi[2] - lo[2],
        lo[0],
        lo[1],
        lo[2],
        match (power.is_some(), temperature.is_some()) {
            (true, true) => ":power:R:1:temperature:R:1",
            (true, false) => ":power:R:1",
            (false, true) => ":temperature:R:1",
            (false, false) => "",
        },
        e.time(),
        pbc.join(" ")
    )?;
    for i in 0..p.len() {
        let x = to3(&p.pos[i]);
        let v = to3(&p.vel[i]);
        let o = p.angular_velocity(i);
        write!(
            w,
            "P {:.9e} {:.9e} {:.9e} {:.6e} {:.6e} {:.6e} {:.6e} {:.6e} {:.6e} {:.6e}",
            x.x, x.y, x.z, v.x, v.y, v.z, o.x, o.y, o.z, p.radius[i]
        )?;
        if let Some(pw) = &power {
            write!(w, " {:.6e}", pw[i])?;
        }
        if let Some(t) = temperature {
            write!(w, " {:.9e}", t[i])?;
        }
        writeln!(w)?;
    }
    Ok(())
}
