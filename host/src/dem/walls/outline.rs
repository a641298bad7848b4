//! A wall drawn in a picture (`dem --png`, the reports' snapshots).

use super::{Shape, Wall};
use crate::dem::state::VecD;

/// Segments of a picture: pairs of (x, y) points (m).
pub type Segments = Vec<[(f64, f64); 2]>;

impl<const D: usize> Wall<D> {
    /// The wall at time `t` (s) drawn in the plane of axes `ax`, `ay`: the points a view must
    /// hold, and the segments of its outline, a plane's line running `diag` (m) either way of
    /// its point (none where it faces out of the picture), a cylinder's circle (seen along its
    /// axis) or its two sides, a box's edges.
    pub fn outline(&self, t: f64, ax: usize, ay: usize, diag: f64) -> (Vec<(f64, f64)>, Segments) {
        let states = self.surfaces(t);
        let at = |v: &VecD<D>| (v[ax], v[ay]);
        let mut segs = Segments::new();
        let mut points = Vec::new();
        match self.shape {
            Shape::Plane { .. } => {
                let w = &states[0];
                points.push(at(&w.point));
                let (nx, ny) = (w.normal[ax], w.normal[ay]);
                let n = (nx * nx + ny * ny).sqrt();
                if n >= 0.5 {
                    let (tx, ty) = (-ny / n, nx / n);
                    let (px, py) = at(&w.point);
                    segs.push([(px - tx * diag, py - ty * diag), (px + tx * diag, py + ty * diag)]);
                }
            }
            Shape::Cylinder { radius, .. } => {
                let w = &states[0];
                let (cx, cy) = at(&w.point);
                // the axis across the picture: a circle; along it: the two sides
                let (bx, by) = if D == 2 {
                    (0.0, 0.0)
                } else {
                    (w.normal[ax], w.normal[ay])
                };
                let along = (bx * bx + by * by).sqrt();
                if along < 0.5 {
                    let k = 96;
                    let p = |m: usize| {
                        let a = 2.0 * std::f64::consts::PI * m as f64 / k as f64;
                        (cx + radius * a.cos(), cy + radius * a.sin())
                    };
                    segs.extend((0..k).map(|m| [p(m), p(m + 1)]));
                    points.extend([(cx - radius, cy - radius), (cx + radius, cy + radius)]);
                } else {
                    let (ux, uy) = (bx / along, by / along);
                    let (ox, oy) = (-uy * radius, ux * radius);
                    for s in [-1.0, 1.0] {
                        let (qx, qy) = (cx + s * ox, cy + s * oy);
                        segs.push([(qx - ux * diag, qy - uy * diag), (qx + ux * diag, qy + uy * diag)]);
                        points.push((qx, qy));
                    }
                }
            }
            Shape::Box { lo, hi, .. } => {
                // the corners now: the box's own frame turned and moved as the wall is
                let (c0, half) = ((lo + hi) * 0.5, (hi - lo) * 0.5);
                let probe = Wall {
                    shape: Shape::Box {
                        lo,
                        hi,
                        inside: false,
                    },
                    ..self.clone()
                };
                let w = probe.surfaces(t)[0];
                let corner = |m: usize| {
                    let mut y = VecD::<D>::zeros();
                    for k in 0..D {
                        y[k] = if (m >> k) & 1 == 1 { half[k] } else { -half[k] };
                    }
                    w.point + w.frame * y
                };
                let _ = c0;
                for m in 0..(1usize << D) {
                    points.push(at(&corner(m)));
                    for k in 0..D {
                        if (m >> k) & 1 == 0 {
                            segs.push([at(&corner(m)), at(&corner(m | (1 << k)))]);
                        }
                    }
                }
            }
        }
        (points, segs)
    }
}
