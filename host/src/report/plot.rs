//! Figures as PNG and SVG with plotters, using a font compiled into the binary (no system fonts).
//!
//! Drivers describe a figure as a [`Figure`] of one or more [`Panel`]s of [`Series`]; [`Figure::save`]
//! writes `NAME.png` and `NAME.svg` atomically.

use crate::output::write_atomic;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::Path;
use std::sync::Once;

/// The font family every figure uses (Ubuntu Light, registered from bytes at first use).
pub const FONT: &str = "sans-serif";

/// Registers the embedded font with plotters (idempotent).
pub fn register_fonts() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        for style in [
            FontStyle::Normal,
            FontStyle::Bold,
            FontStyle::Italic,
            FontStyle::Oblique,
        ] {
            // The font is a valid TTF shipped by a crate; failure would be a build defect.
            let _ = plotters::style::register_font(FONT, style, epaint_default_fonts::UBUNTU_LIGHT);
        }
    });
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mark {
    /// A solid line.
    Line,
    /// A dashed line.
    Dashed,
    /// Circles at the points.
    Circles,
    /// Small filled dots at the points (for scatter plots of many points).
    Dots,
}

/// One curve or point set.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend label ("" for none).
    pub label: String,
    /// (x, y) points in data units.
    pub points: Vec<(f64, f64)>,
    /// Drawing style.
    pub mark: Mark,
    /// Index into the palette.
    pub color: usize,
}

impl Series {
    /// A series.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, mark: Mark, color: usize) -> Series {
        Series {
            label: label.into(),
            points,
            mark,
            color,
        }
    }
}

/// One set of axes.
#[derive(Debug, Clone, Default)]
pub struct Panel {
    /// Title above the axes.
    pub title: String,
    /// x axis label, with unit.
    pub x_label: String,
    /// y axis label, with unit.
    pub y_label: String,
    /// Logarithmic x axis.
    pub log_x: bool,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// Explicit x range (else from the data).
    pub x_range: Option<(f64, f64)>,
    /// Explicit y range (else from the data).
    pub y_range: Option<(f64, f64)>,
    /// The curves.
    pub series: Vec<Series>,
    /// Keep x and y scales equal (for snapshots of particle positions).
    pub equal_aspect: bool,
    /// Circles to draw in data units: (x, y, radius), for particle snapshots.
    pub disks: Vec<(f64, f64, f64)>,
    /// Each disk's depth behind the picture's plane, 0 (nearest) to 1 (farthest), for the side
    /// view of a 3D scene: a farther sphere is drawn paler and outlined, so that a packing is
    /// no solid blob of one colour (empty: every disk flat, in one colour). The disks are drawn
    /// in their order: give the farthest first.
    pub disk_depth: Vec<f64>,
}

/// The fill of a disk at depth `t` (0 nearest, 1 farthest): the first colour of the palette,
/// paler with depth.
pub fn depth_color(t: f64) -> RGBColor {
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let c = PALETTE[0];
    let pale = |v: u8| (v as f64 + 0.7 * t * (255.0 - v as f64)).round() as u8;
    RGBColor(pale(c.0), pale(c.1), pale(c.2))
}

/// A figure: panels laid out in a grid.
#[derive(Debug, Clone)]
pub struct Figure {
    /// Panels, row by row.
    pub panels: Vec<Panel>,
    /// Grid columns.
    pub columns: usize,
    /// Pixel size of one panel.
    pub panel_size: (u32, u32),
}

/// Colours that stay distinct in print.
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(230, 159, 0),
    RGBColor(0, 0, 0),
    RGBColor(120, 120, 120),
];

/// A colour for the `i`-th of `n` curves of a family (from light to dark blue-green-red).
pub fn ramp(i: usize, n: usize) -> RGBColor {
    let t = if n <= 1 { 0.0 } else { i as f64 / (n - 1) as f64 };
    let (r, g, b) = (
        40.0 + 200.0 * t,
        80.0 + 80.0 * (1.0 - (2.0 * t - 1.0).abs()),
        220.0 - 190.0 * t,
    );
    RGBColor(r as u8, g as u8, b as u8)
}

/// Errors while drawing or writing a figure.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// plotters failed to draw.
    #[error("cannot draw figure {name}: {message}")]
    Draw {
        /// The figure.
        name: String,
        /// plotters' message.
        message: String,
    },
    /// The file could not be written.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
}

impl Figure {
    /// A figure of one panel.
    pub fn single(panel: Panel) -> Figure {
        Figure {
            panels: vec![panel],
            columns: 1,
            panel_size: (800, 560),
        }
    }

    /// A figure of `panels` in `columns` columns, 700 × 520 pixels each (the bed's figures).
    pub fn in_columns(panels: Vec<Panel>, columns: usize) -> Figure {
        Figure {
            panels,
            columns,
            panel_size: (700, 520),
        }
    }

    /// Writes `dir/name.png` and `dir/name.svg`.
    pub fn save(&self, dir: &Path, name: &str) -> Result<(), PlotError> {
        register_fonts();
        let cols = self.columns.max(1) as u32;
        let rows = self.panels.len().div_ceil(self.columns.max(1)) as u32;
        let size = (self.panel_size.0 * cols, self.panel_size.1 * rows);
        let err = |e: String| PlotError::Draw {
            name: name.to_string(),
            message: e,
        };
        // PNG: plotters writes the file itself; draw to a temporary name and rename it, so a
        // failed run never leaves a half-written figure.
        std::fs::create_dir_all(dir).map_err(|source| PlotError::Write {
            path: dir.display().to_string(),
            source,
        })?;
        let p = dir.join(format!("{name}.png"));
        let tmp = dir.join(format!(".{name}.png.tmp-{}.png", std::process::id()));
        let drawn = (|| {
            let root = BitMapBackend::new(&tmp, size).into_drawing_area();
            self.draw(&root)?;
            root.present().map_err(|e| e.to_string())
        })();
        if let Err(e) = drawn {
            let _ = std::fs::remove_file(&tmp);
            return Err(err(e));
        }
        std::fs::rename(&tmp, &p).map_err(|source| PlotError::Write {
            path: p.display().to_string(),
            source,
        })?;
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
            self.draw(&root).map_err(err)?;
            root.present().map_err(|e| err(e.to_string()))?;
        }
        let p = dir.join(format!("{name}.svg"));
        write_atomic(&p, svg.as_bytes()).map_err(|source| PlotError::Write {
            path: p.display().to_string(),
            source,
        })
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let cols = self.columns.max(1);
        let rows = self.panels.len().div_ceil(cols);
        let areas = root.split_evenly((rows, cols));
        for (panel, area) in self.panels.iter().zip(areas.iter()) {
            draw_panel(panel, area).map_err(|e| e.to_string())?;
        }
        Ok(())
    }
}

/// A tick label: plain decimals on linear axes, compact powers of ten on log axes.
fn tick(v: f64, log: bool) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if log || !(1e-3..1e5).contains(&a) {
        let e = a.log10().floor();
        let m = v / 10f64.powf(e);
        if (m.abs() - 1.0).abs() < 1e-9 {
            format!("1e{e}")
        } else {
            format!("{m:.0}e{e}")
        }
    } else {
        let s = format!("{v:.6}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

fn bounds(panel: &Panel) -> ((f64, f64), (f64, f64)) {
    let pts = panel.series.iter().flat_map(|s| s.points.iter()).copied();
    let disk_pts = panel
        .disks
        .iter()
        .flat_map(|&(x, y, r)| [(x - r, y - r), (x + r, y + r)]);
    let (mut x0, mut x1, mut y0, mut y1) =
        (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for (x, y) in pts.chain(disk_pts) {
        if !x.is_finite() || !y.is_finite() || (panel.log_x && x <= 0.0) || (panel.log_y && y <= 0.0) {
            continue;
        }
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if !x0.is_finite() {
        (x0, x1, y0, y1) = (0.1, 1.0, 0.1, 1.0);
    }
    let pad = |a: f64, b: f64, log: bool| {
        if log {
            let (la, lb) = (a.ln(), b.ln());
            let d = ((lb - la) * 0.05).max(1e-3);
            ((la - d).exp(), (lb + d).exp())
        } else {
            let d = ((b - a) * 0.05).max(a.abs().max(b.abs()) * 1e-3).max(1e-300);
            (a - d, b + d)
        }
    };
    (
        panel.x_range.unwrap_or_else(|| pad(x0, x1, panel.log_x)),
        panel.y_range.unwrap_or_else(|| pad(y0, y1, panel.log_y)),
    )
}

fn draw_panel<DB: DrawingBackend>(
    panel: &Panel,
    area: &DrawingArea<DB, Shift>,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let ((x0, x1), (y0, y1)) = bounds(panel);
    let mut b = ChartBuilder::on(area);
    b.caption(&panel.title, (FONT, 20))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(70);
    macro_rules! finish {
        ($chart:expr) => {{
            let mut chart = $chart;
            let xf = |v: &f64| tick(*v, panel.log_x);
            let yf = |v: &f64| tick(*v, panel.log_y);
            chart
                .configure_mesh()
                .x_desc(&panel.x_label)
                .y_desc(&panel.y_label)
                .x_label_formatter(&xf)
                .y_label_formatter(&yf)
                .label_style((FONT, 14))
                .axis_desc_style((FONT, 16))
                .light_line_style(RGBColor(235, 235, 235))
                .draw()?;
            for (k, &(x, y, r)) in panel.disks.iter().enumerate() {
                // radius in pixels from data units along x
                let (px0, _) = chart.backend_coord(&(x - r, y));
                let (px1, _) = chart.backend_coord(&(x + r, y));
                let rp = ((px1 - px0).abs() / 2).max(1);
                match panel.disk_depth.get(k) {
                    None => {
                        chart
                            .plotting_area()
                            .draw(&Circle::new((x, y), rp as u32, PALETTE[0].filled()))?
                    }
                    Some(&t) => {
                        let area = chart.plotting_area();
                        area.draw(&Circle::new((x, y), rp as u32, depth_color(t).filled()))?;
                        area.draw(&Circle::new(
                            (x, y),
                            rp as u32,
                            RGBColor(0, 60, 100).stroke_width(1),
                        ))?;
                    }
                }
            }
            let mut any_label = false;
            for s in &panel.series {
                let c = if s.color < PALETTE.len() {
                    PALETTE[s.color]
                } else {
                    ramp(s.color - PALETTE.len(), 16)
                };
                let pts = s.points.iter().copied().filter(|(x, y)| {
                    x.is_finite() && y.is_finite() && (!panel.log_x || *x > 0.0) && (!panel.log_y || *y > 0.0)
                });
                let anno = match s.mark {
                    Mark::Line => chart.draw_series(LineSeries::new(pts, c.stroke_width(2)))?,
                    Mark::Dashed => chart.draw_series(DashedLineSeries::new(pts, 8, 5, c.stroke_width(2)))?,
                    Mark::Circles => chart.draw_series(pts.map(|p| Circle::new(p, 4, c.stroke_width(2))))?,
                    Mark::Dots => chart.draw_series(pts.map(|p| Circle::new(p, 2, c.filled())))?,
                };
                if !s.label.is_empty() {
                    any_label = true;
                    let mark = s.mark;
                    anno.label(s.label.clone())
                        .legend(move |(x, y)| -> DynElement<'static, _, _> {
                            match mark {
                                Mark::Line => {
                                    PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2)).into_dyn()
                                }
                                Mark::Dashed => {
                                    PathElement::new(vec![(x, y), (x + 7, y)], c.stroke_width(2)).into_dyn()
                                }
                                Mark::Circles => Circle::new((x + 9, y), 4, c.stroke_width(2)).into_dyn(),
                                Mark::Dots => Circle::new((x + 9, y), 3, c.filled()).into_dyn(),
                            }
                        });
                }
            }
            if any_label {
                chart
                    .configure_series_labels()
                    .label_font((FONT, 13))
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK.mix(0.4))
                    .position(SeriesLabelPosition::UpperRight)
                    .draw()?;
            }
        }};
    }
    match (panel.log_x, panel.log_y) {
        (false, false) => finish!(b.build_cartesian_2d(x0..x1, y0..y1)?),
        (true, false) => finish!(b.build_cartesian_2d((x0..x1).log_scale(), y0..y1)?),
        (false, true) => finish!(b.build_cartesian_2d(x0..x1, (y0..y1).log_scale())?),
        (true, true) => finish!(b.build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?),
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_figure_renders_to_png_and_svg_with_the_embedded_font() {
        let dir = std::env::temp_dir().join(format!("dashpot-plot-{}", std::process::id()));
        let p = Panel {
            title: "test".into(),
            x_label: "v (m/s)".into(),
            y_label: "r".into(),
            log_x: true,
            series: vec![Series::new(
                "a",
                vec![(0.01, 1.0), (1.0, 0.7), (10.0, 0.4)],
                Mark::Line,
                0,
            )],
            ..Default::default()
        };
        Figure::single(p).save(&dir, "t").unwrap();
        let png = std::fs::read(dir.join("t.png")).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        let svg = std::fs::read_to_string(dir.join("t.svg")).unwrap();
        assert!(svg.contains("v (m/s)"));
        std::fs::remove_dir_all(&dir).ok();
    }

    /// A side view's spheres at three depths are drawn in three colours, paler with depth, each
    /// outlined: not one solid blob.
    #[test]
    fn disks_at_depth_are_shaded_and_outlined() {
        let dir = std::env::temp_dir().join(format!("dashpot-depth-{}", std::process::id()));
        let p = Panel {
            equal_aspect: true,
            disks: vec![(0.0, 0.0, 1.0), (1.0, 0.0, 1.0), (2.0, 0.0, 1.0)],
            disk_depth: vec![1.0, 0.5, 0.0],
            ..Default::default()
        };
        Figure::single(p).save(&dir, "d").unwrap();
        let svg = std::fs::read_to_string(dir.join("d.svg")).unwrap();
        let fills: std::collections::BTreeSet<String> = [0.0, 0.5, 1.0]
            .iter()
            .map(|&t| {
                let c = depth_color(t);
                format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2)
            })
            .collect();
        assert_eq!(fills.len(), 3);
        for f in &fills {
            assert!(svg.to_uppercase().contains(f.as_str()), "{f} missing");
        }
        // paler with depth: every channel rises towards white
        let (a, b) = (depth_color(0.0), depth_color(1.0));
        assert!(a.0 < b.0 && a.1 < b.1 && a.2 < b.2);
        std::fs::remove_dir_all(&dir).ok();
    }
}
