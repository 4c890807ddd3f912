//! PNG plots with plotters: line charts of time series and particle snapshots coloured by a field.

use plotters::prelude::*;
use std::path::Path;

type PlotResult = Result<(), Box<dyn std::error::Error>>;

/// A named line.
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
}

/// One panel of lines sharing axes.
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    /// Log axes (x, y).
    pub log: (bool, bool),
}

fn bounds(points: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in points.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return if log { (0.1, 10.0) } else { (0.0, 1.0) };
    }
    if log {
        (lo / 1.5, hi * 1.5)
    } else {
        let pad = ((hi - lo) * 0.05).max(1e-12 * hi.abs().max(1.0));
        (lo - pad, hi + pad)
    }
}

/// A short tick label: plain for moderate magnitudes, scientific otherwise.
fn tick(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-2..1e4).contains(&a) {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.1e}")
    }
}

/// Panels side by side (in a grid of `cols` columns) in one PNG.
pub fn line_panels(path: &Path, panels: &[Panel], cols: usize, size: (u32, u32)) -> PlotResult {
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE)?;
    let rows = panels.len().div_ceil(cols);
    let areas = root.split_evenly((rows, cols));
    for (panel, area) in panels.iter().zip(areas.iter()) {
        draw_panel(panel, area)?;
    }
    root.present()?;
    Ok(())
}

fn draw_panel(
    panel: &Panel,
    area: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
) -> PlotResult {
    let xs = bounds(
        panel
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.0)),
        panel.log.0,
    );
    let ys = bounds(
        panel
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.1)),
        panel.log.1,
    );
    let mut b = ChartBuilder::on(area);
    b.caption(&panel.title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60);
    macro_rules! draw {
        ($chart:expr) => {{
            let mut chart = $chart;
            chart
                .configure_mesh()
                .x_label_formatter(&|v| tick(*v))
                .y_label_formatter(&|v| tick(*v))
                .x_desc(panel.x_label.as_str())
                .y_desc(panel.y_label.as_str())
                .draw()?;
            for (k, s) in panel.series.iter().enumerate() {
                let color = Palette99::pick(k).to_rgba();
                let pts: Vec<(f64, f64)> = s
                    .points
                    .iter()
                    .copied()
                    .filter(|p| p.0.is_finite() && p.1.is_finite())
                    .filter(|p| (!panel.log.0 || p.0 > 0.0) && (!panel.log.1 || p.1 > 0.0))
                    .collect();
                chart
                    .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))?
                    .label(s.label.as_str())
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
                    });
                if pts.len() < 40 {
                    chart.draw_series(pts.iter().map(|p| Circle::new(*p, 3, color.filled())))?;
                }
            }
            if panel.series.len() > 1
                || !panel.series.is_empty() && !panel.series[0].label.is_empty()
            {
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.8))
                    .border_style(BLACK)
                    .draw()?;
            }
        }};
    }
    match panel.log {
        (false, false) => draw!(b.build_cartesian_2d(xs.0..xs.1, ys.0..ys.1)?),
        (true, false) => draw!(b.build_cartesian_2d((xs.0..xs.1).log_scale(), ys.0..ys.1)?),
        (false, true) => draw!(b.build_cartesian_2d(xs.0..xs.1, (ys.0..ys.1).log_scale())?),
        (true, true) => {
            draw!(b.build_cartesian_2d((xs.0..xs.1).log_scale(), (ys.0..ys.1).log_scale())?)
        }
    }
    Ok(())
}

/// One snapshot of particles: positions, a scalar per particle, and wall particles in grey.
pub struct Snapshot {
    pub title: String,
    pub points: Vec<(f64, f64)>,
    pub values: Vec<f64>,
    pub walls: Vec<(f64, f64)>,
}

/// Colour of `v` in [lo, hi] on a blue-to-red map.
fn colour(v: f64, lo: f64, hi: f64) -> RGBColor {
    let t = if hi > lo {
        ((v - lo) / (hi - lo)).clamp(0.0, 1.0)
    } else {
        0.5
    };
    let c = HSLColor(0.66 * (1.0 - t), 0.9, 0.45).to_rgba();
    RGBColor(c.0, c.1, c.2)
}

/// Snapshots in a grid sharing one colour scale (`field` names it) and one window `view`
/// ((x0, x1), (y0, y1)), like Fang 2006 Fig. 3.
pub fn particle_snapshots(
    path: &Path,
    shots: &[Snapshot],
    field: &str,
    cols: usize,
    view: ((f64, f64), (f64, f64)),
    size: (u32, u32),
) -> PlotResult {
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE)?;
    let (title_area, body) = root.split_vertically(40);
    // The colour scale spans the values exactly (no axis padding), so the legend is true.
    let (lo, hi) = shots
        .iter()
        .flat_map(|s| s.values.iter().copied())
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    let (lo, hi) = if lo.is_finite() { (lo, hi) } else { (0.0, 1.0) };
    title_area.titled(
        &format!("particles coloured by {field}: {lo:.3} (blue) to {hi:.3} (red)"),
        ("sans-serif", 22),
    )?;
    let rows = shots.len().div_ceil(cols);
    let areas = body.split_evenly((rows, cols));
    // Equal aspect: widen the shorter side of the window to the panel's plotting area.
    let (pw, ph) = (
        size.0 as f64 / cols as f64 - 60.0,
        (size.1 as f64 - 40.0) / rows as f64 - 50.0,
    );
    let ((mut x0, mut x1), (mut y0, mut y1)) = view;
    let (wx, wy) = (x1 - x0, y1 - y0);
    if wx / wy < pw / ph {
        let grow = 0.5 * (wy * pw / ph - wx);
        x0 -= grow;
        x1 += grow;
    } else {
        let grow = wx * ph / pw - wy;
        y1 += grow;
        let _ = &mut y0;
    }
    for (shot, area) in shots.iter().zip(areas.iter()) {
        let mut chart = ChartBuilder::on(area)
            .caption(&shot.title, ("sans-serif", 16))
            .margin(6)
            .x_label_area_size(25)
            .y_label_area_size(45)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        chart.configure_mesh().disable_mesh().draw()?;
        // Small squares in pixel offsets: far cheaper to rasterise than circles at 10^5 particles.
        let dot = |p: (f64, f64), r: i32, c: RGBColor| {
            EmptyElement::at(p) + Rectangle::new([(-r, -r), (r, r)], c.filled())
        };
        let r = if shot.points.len() > 20_000 { 0 } else { 1 };
        chart.draw_series(
            shot.walls
                .iter()
                .map(|p| dot(*p, 0, RGBColor(150, 150, 150))),
        )?;
        chart.draw_series(
            shot.points
                .iter()
                .zip(&shot.values)
                .map(|(p, v)| dot(*p, r, colour(*v, lo, hi))),
        )?;
    }
    root.present()?;
    Ok(())
}

/// A grid of cells coloured green (true), red (false) or grey (None), with row and column labels:
/// a stability map.
pub fn status_grid(
    path: &Path,
    title: &str,
    x_title: &str,
    x_labels: &[String],
    y_labels: &[String],
    cells: &[Vec<Option<bool>>],
) -> PlotResult {
    let (w, h) = (
        (220 + 90 * x_labels.len()) as u32,
        (120 + 40 * y_labels.len()) as u32,
    );
    let root = BitMapBackend::new(path, (w, h)).into_drawing_area();
    root.fill(&WHITE)?;
    let nx = x_labels.len() as f64;
    let ny = y_labels.len() as f64;
    let xl = x_labels.to_vec();
    let yl = y_labels.to_vec();
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(10)
        .x_label_area_size(45)
        .y_label_area_size(150)
        .build_cartesian_2d(0.0..nx, 0.0..ny)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(x_labels.len() * 2 + 1)
        .y_labels(y_labels.len() * 2 + 1)
        .x_label_formatter(&|v| {
            let k = v.floor() as usize;
            if (v - k as f64 - 0.5).abs() < 0.01 && k < xl.len() {
                xl[k].clone()
            } else {
                String::new()
            }
        })
        .y_label_formatter(&|v| {
            let k = v.floor() as usize;
            if (v - k as f64 - 0.5).abs() < 0.01 && k < yl.len() {
                yl[k].clone()
            } else {
                String::new()
            }
        })
        .x_desc(x_title)
        .draw()?;
    for (j, row) in cells.iter().enumerate() {
        for (i, c) in row.iter().enumerate() {
            let colour = match c {
                Some(true) => RGBColor(60, 170, 80),
                Some(false) => RGBColor(210, 60, 50),
                None => RGBColor(200, 200, 200),
            };
            let (x, y) = (i as f64, j as f64);
            chart.draw_series(std::iter::once(Rectangle::new(
                [(x + 0.04, y + 0.06), (x + 0.96, y + 0.94)],
                colour.filled(),
            )))?;
        }
    }
    root.present()?;
    Ok(())
}
