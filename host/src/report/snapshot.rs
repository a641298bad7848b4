//! The one picture of particles both engines draw: the disks to scale, the walls as lines and
//! periodic boundaries dashed (`dashpot bed --snapshot`, `dashpot dem --png`, the bed figures).

use crate::bed::{Bed, Restitution};
use crate::dem::Engine;
use crate::plot::{Figure, Mark, Panel, Series};
use anyhow::{Context, Result};
use std::path::Path;

/// What a snapshot shows, in the plane of the picture (m).
#[derive(Debug, Clone, Default)]
pub struct Scene {
    /// Disks: centre (x, y) and radius.
    pub disks: Vec<(f64, f64, f64)>,
    /// Each disk's depth behind the picture's plane, 0 (nearest) to 1 (farthest), the disks
    /// ordered farthest first (a 3D side view; empty in 2D).
    pub depth: Vec<f64>,
    /// Walls, as segments across the view.
    pub walls: Vec<[(f64, f64); 2]>,
    /// Periodic boundaries, as segments.
    pub boundaries: Vec<[(f64, f64); 2]>,
    /// The view: x range and y range.
    pub view: ((f64, f64), (f64, f64)),
    /// The axes' labels.
    pub labels: (&'static str, &'static str),
}

impl Scene {
    /// The event-driven bed: its disks, the lid and the piston (at its height now), the periodic
    /// sides.
    pub fn bed<R: Restitution>(bed: &Bed<R>) -> Scene {
        let c = bed.config();
        let r = 0.5 * c.diameter;
        let z = bed.piston().state(bed.now()).z;
        let (l, lid) = (c.width, bed.lid());
        Scene {
            disks: bed.positions().into_iter().map(|(x, y)| (x, y, r)).collect(),
            depth: Vec::new(),
            walls: vec![[(0.0, lid), (l, lid)], [(0.0, z), (l, z)]],
            boundaries: vec![[(0.0, z), (0.0, lid)], [(l, z), (l, lid)]],
            view: ((-0.005, l + 0.005), (-0.5 * c.amplitude - 0.003, lid + 0.003)),
            labels: ("x (m)", "y (m)"),
        }
    }

    /// The DEM engine's particles and walls at its time: x and y in 2D, the side view x–z in 3D
    /// (y into the page); the view spans the particles, the bounded or periodic domain and the
    /// walls' points.
    pub fn dem<const D: usize>(e: &Engine<D>) -> Scene {
        let (ax, ay) = (0, D - 1);
        let (disks, depth) = side_view(
            (0..e.p.len()).map(|i| (e.p.pos[i][ax], e.p.pos[i][ay], e.p.radius[i])),
            (D == 3).then(|| e.p.pos.iter().map(|p| p[1]).collect()),
        );
        let rmax = e.p.radius.iter().cloned().fold(0.0, f64::max);
        let (mut x0, mut x1, mut y0, mut y1) = disks.iter().fold(
            (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY),
            |(a, b, c, d), &(x, y, _)| (a.min(x), b.max(x), c.min(y), d.max(y)),
        );
        let dom = &e.config().domain;
        if dom.bounded || dom.periodic.iter().any(|&p| p) {
            (x0, x1) = (x0.min(dom.lo[ax]), x1.max(dom.hi[ax]));
            if dom.bounded {
                (y0, y1) = (y0.min(dom.lo[ay]), y1.max(dom.hi[ay]));
            }
        }
        // (each wall's outline: the points the view must hold, then its segments)
        let t = e.time();
        for w in &e.walls {
            for (x, y) in w.outline(t, ax, ay, 0.0).0 {
                (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
            }
        }
        if !(x0.is_finite() && y0.is_finite()) {
            (x0, x1, y0, y1) = (-1.0, 1.0, -1.0, 1.0);
        }
        let pad = 2.0 * rmax.max(1e-12);
        let (x0, x1, y0, y1) = (x0 - pad, x1 + pad, y0 - pad, y1 + pad);
        let diag = ((x1 - x0).powi(2) + (y1 - y0).powi(2)).sqrt();
        let walls = e
            .walls
            .iter()
            .flat_map(|w| w.outline(t, ax, ay, diag).1)
            .collect();
        Scene {
            disks,
            depth,
            walls,
            boundaries: Vec::new(),
            view: ((x0, x1), (y0, y1)),
            labels: if D == 2 {
                ("x (m)", "y (m)")
            } else {
                ("x (m), side view", "z (m)")
            },
        }
    }

    /// The snapshot as a panel titled `title`.
    pub fn panel(self, title: &str) -> Panel {
        let line = |s: [(f64, f64); 2], mark, color| Series::new("", s.to_vec(), mark, color);
        let series = (self.walls.into_iter().map(|s| line(s, Mark::Line, 6)))
            .chain(self.boundaries.into_iter().map(|s| line(s, Mark::Dashed, 7)))
            .collect();
        Panel {
            title: title.to_string(),
            x_label: self.labels.0.into(),
            y_label: self.labels.1.into(),
            equal_aspect: true,
            x_range: Some(self.view.0),
            y_range: Some(self.view.1),
            disks: self.disks,
            disk_depth: self.depth,
            series,
            ..Default::default()
        }
    }

    /// The snapshot as a figure titled `title`, sized to its view (1400 pixels wide).
    pub fn figure(self, title: &str) -> Figure {
        let ((x0, x1), (y0, y1)) = self.view;
        let mut f = Figure::single(self.panel(title));
        let width = 1400u32;
        f.panel_size = (
            width,
            ((width as f64 * (y1 - y0) / (x1 - x0).max(1e-300)) as u32 + 120).clamp(200, 2400),
        );
        f
    }
}

/// The disks of a picture and, given each one's coordinate into the page (`into`: a 3D side
/// view, y into the page), their depths from 0 (nearest) to 1 (farthest), the disks reordered
/// farthest first so that nearer spheres are drawn over farther ones.
fn side_view(
    disks: impl Iterator<Item = (f64, f64, f64)>,
    into: Option<Vec<f64>>,
) -> (Vec<(f64, f64, f64)>, Vec<f64>) {
    let disks: Vec<(f64, f64, f64)> = disks.collect();
    let Some(y) = into else {
        return (disks, Vec::new());
    };
    let (lo, hi) = y.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
        (a.min(v), b.max(v))
    });
    let span = hi - lo;
    let t = |v: f64| if span > 0.0 { (v - lo) / span } else { 0.0 };
    let mut order: Vec<usize> = (0..disks.len()).collect();
    order.sort_by(|&a, &b| y[b].total_cmp(&y[a]));
    (
        order.iter().map(|&i| disks[i]).collect(),
        order.iter().map(|&i| t(y[i])).collect(),
    )
}

/// Saving a figure by its PNG path.
pub trait SaveAs {
    /// Writes `path` (.png) and the same name with .svg.
    fn save_as(&self, path: &Path) -> Result<()>;
}

impl SaveAs for Figure {
    fn save_as(&self, path: &Path) -> Result<()> {
        let dir = path
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().to_string())
            .with_context(|| format!("{}: not a file name", path.display()))?;
        self.save(dir, &stem)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_side_view_draws_the_farthest_first_with_depths_from_0_to_1() {
        let disks = [(0.0, 0.0, 1.0), (1.0, 0.0, 1.0), (2.0, 0.0, 1.0)];
        let (d, t) = side_view(disks.into_iter(), Some(vec![0.5, 2.0, -1.0]));
        assert_eq!(d, vec![(1.0, 0.0, 1.0), (0.0, 0.0, 1.0), (2.0, 0.0, 1.0)]);
        assert_eq!(t, vec![1.0, 0.5, 0.0]);
        // a 2D picture: the disks as they are, no depth
        let (d, t) = side_view(disks.into_iter(), None);
        assert_eq!(d, disks.to_vec());
        assert!(t.is_empty());
    }
}
