//! What the bed's commands show: progress bars and snapshots of the disks. Shared by
//! [`super::cli`] and [`super::figures`], which do not import each other.

use super::engine::Bed;
use crate::plot::{Figure, Mark, Panel, Series};
use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::Path;

/// A progress bar on stderr, hidden when stderr is not a terminal.
pub fn progress_bar(len: u64, what: &str) -> ProgressBar {
    let target = if std::io::stderr().is_terminal() {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    };
    let pb = ProgressBar::with_draw_target(Some(len), target);
    if let Ok(style) = ProgressStyle::with_template(&format!(
        "{what} [{{elapsed_precise}}] {{wide_bar}} {{pos}}/{{len}} {{msg}} (eta {{eta}})"
    )) {
        pb.set_style(style);
    }
    pb
}

/// A snapshot of the disks (m), the lid, the piston and the periodic boundaries.
pub fn snapshot_panel<R: super::Restitution>(bed: &Bed<R>, title: &str) -> Panel {
    let c = bed.config();
    let r = 0.5 * c.diameter;
    let z = bed.piston().state(bed.now()).z;
    let (l, lid) = (c.width, bed.lid());
    Panel {
        title: title.to_string(),
        x_label: "x (m)".into(),
        y_label: "y (m)".into(),
        equal_aspect: true,
        x_range: Some((-0.005, l + 0.005)),
        y_range: Some((-0.5 * c.amplitude - 0.003, lid + 0.003)),
        disks: bed.positions().into_iter().map(|(x, y)| (x, y, r)).collect(),
        series: vec![
            Series::new("", vec![(0.0, lid), (l, lid)], Mark::Line, 6),
            Series::new("", vec![(0.0, z), (l, z)], Mark::Line, 6),
            Series::new("", vec![(0.0, z), (0.0, lid)], Mark::Dashed, 7),
            Series::new("", vec![(l, z), (l, lid)], Mark::Dashed, 7),
        ],
        ..Default::default()
    }
}

/// The snapshot as a figure sized to the box.
pub fn snapshot_figure<R: super::Restitution>(bed: &Bed<R>, title: &str) -> Figure {
    let c = bed.config();
    let mut f = Figure::single(snapshot_panel(bed, title));
    let h = (bed.lid() + 0.5 * c.amplitude + 0.006) / (c.width + 0.01);
    f.panel_size = (1400, ((1400.0 * h) as u32 + 120).clamp(200, 1400));
    f
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
            .with_context(|| format!("--snapshot {}: not a file name", path.display()))?;
        self.save(dir, &stem)?;
        Ok(())
    }
}
