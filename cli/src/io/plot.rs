//! PNG plots with plotters: line charts of time series, particle snapshots coloured by a field,
//! and stability maps. One style for every PNG the project writes (runs, benchmarks, examples):
//! the font sizes below, labelled axes with units, and for particles the plate drawn, a colour
//! bar over a robust range and a window that follows the fluid.

use plotters::prelude::*;
use std::path::Path;

/// Font sizes in pixels, chosen to stay legible when a PNG is shown at its own size.
const CAPTION: u32 = 26;
const AXIS_DESC: u32 = 21;
const TICKS: u32 = 17;
const FONT: &str = "sans-serif";

/// The one font of every PNG, DejaVu Sans 2.37 (Bitstream Vera licence, which allows
/// redistribution with the notice: `cli/assets/fonts/LICENSE-DejaVu.txt`), compiled into the
/// binary and drawn by plotters' `ab_glyph` rasteriser, so text needs no system font and the
/// binary no fontconfig or freetype: `viscosph run` draws its PNGs on a bare server.
static DEJAVU_SANS: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// A PNG of `size` pixels at `path`, the embedded font registered as [`FONT`] first.
fn png_area(
    path: &Path,
    size: (u32, u32),
) -> Result<DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>, Box<dyn std::error::Error>> {
    static REGISTERED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let registered = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, DEJAVU_SANS).is_ok()
    });
    if !registered {
        return Err("the embedded font DejaVuSans.ttf does not parse".into());
    }
    Ok(BitMapBackend::new(path, size).into_drawing_area())
}

type PlotResult = Result<(), Box<dyn std::error::Error>>;

/// A named line. A series with an empty label is a reference curve (an exact solution drawn
/// under many computed ones): a thin black line without a legend entry of its own; the legend
/// then says once what the thin black lines are. A label starting with [`REFERENCE_PREFIX`]
/// ("thin black: FEM") is a reference curve too, and the legend says that label once instead.
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
        // Reach the decades around the data, so the axis always has labelled ticks.
        let (dlo, dhi) = (
            10f64.powf(lo.log10().floor()),
            10f64.powf(hi.log10().ceil()),
        );
        if hi / lo < 10.0 {
            (dlo.min(lo / 1.2), dhi.max(hi * 1.2))
        } else {
            (lo / 1.5, hi * 1.5)
        }
    } else {
        let pad = ((hi - lo) * 0.05).max(1e-12 * hi.abs().max(1.0));
        (lo - pad, hi + pad)
    }
}

/// A tick label with enough decimals to tell ticks `span / 10` apart.
fn tick_in(v: f64, span: f64) -> String {
    let a = v.abs().max(span.abs());
    if a == 0.0 || !(1e-2..1e4).contains(&a) || !span.is_finite() || span <= 0.0 {
        return tick(v);
    }
    let decimals = (-(span / 10.0).log10().floor()).clamp(0.0, 8.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
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

/// A tick label on a log axis: only at 1, 2 and 5 times a power of ten, because plotters puts a
/// tick at every integer multiple and their labels run into each other near the end of a decade.
/// One notation per axis (`range`): plain where the whole axis lies in 0.01..10^4, otherwise
/// every label in the short scientific form `2e-3`, so one axis never mixes "0.01" and
/// "1.0e-3".
fn log_tick(v: f64, range: (f64, f64)) -> String {
    if v.is_nan() || v <= 0.0 {
        return String::new();
    }
    let exp = v.log10().floor();
    let mantissa = v / 10f64.powf(exp);
    let Some(m) = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .find(|m| (mantissa - m).abs() < 1e-6 * m)
    else {
        return String::new();
    };
    let plain = range.0 >= 1e-2 && range.1 < 1e4;
    if plain {
        tick(v)
    } else {
        let (m, exp) = if m == 10.0 {
            (1.0, exp + 1.0)
        } else {
            (m, exp)
        };
        format!("{m}e{exp}")
    }
}

/// The corner of a panel with the fewest data points near it, for the legend, or None when every
/// corner has data (the legend then goes beside the chart, where it covers nothing).
fn legend_corner(panel: &Panel, xs: (f64, f64), ys: (f64, f64)) -> Option<SeriesLabelPosition> {
    let frac = |v: f64, (lo, hi): (f64, f64), log: bool| {
        if log {
            (v.max(1e-300).ln() - lo.ln()) / (hi.ln() - lo.ln())
        } else {
            (v - lo) / (hi - lo)
        }
    };
    let mut count = [0usize; 4]; // upper left, upper right, lower left, lower right
    for p in panel.series.iter().flat_map(|s| s.points.iter()) {
        let (fx, fy) = (frac(p.0, xs, panel.log.0), frac(p.1, ys, panel.log.1));
        let (left, right, low, high) = (fx < 0.4, fx > 0.6, fy < 0.45, fy > 0.55);
        count[0] += usize::from(left && high);
        count[1] += usize::from(right && high);
        count[2] += usize::from(left && low);
        count[3] += usize::from(right && low);
    }
    let best = (0..4)
        .min_by_key(|&k| (count[k], [1, 0, 3, 2][k]))
        .unwrap_or(1);
    if count[best] > 0 {
        return None;
    }
    Some(match best {
        0 => SeriesLabelPosition::UpperLeft,
        1 => SeriesLabelPosition::UpperRight,
        2 => SeriesLabelPosition::LowerLeft,
        _ => SeriesLabelPosition::LowerRight,
    })
}

/// Legend text of the reference curves with an empty label.
const REFERENCE_LABEL: &str = "thin black: exact";

/// A series whose label starts with this is a reference curve named by its label ([`Series`]).
pub const REFERENCE_PREFIX: &str = "thin black: ";

/// Whether series `s` is a reference curve (thin, black, one legend entry for all).
fn is_reference(s: &Series) -> bool {
    s.label.is_empty() || s.label.starts_with(REFERENCE_PREFIX)
}

/// Whether the panel has reference curves besides labelled ones.
fn has_references(panel: &Panel) -> bool {
    panel.series.iter().any(is_reference) && panel.series.iter().any(|s| !is_reference(s))
}

/// The legend text of the panel's reference curves: the first prefixed label, else
/// [`REFERENCE_LABEL`].
fn reference_label(panel: &Panel) -> String {
    panel
        .series
        .iter()
        .find(|s| s.label.starts_with(REFERENCE_PREFIX))
        .map_or_else(|| REFERENCE_LABEL.to_string(), |s| s.label.clone())
}

/// The legend entries of a panel: (label, colour, line width) of each labelled series, then one
/// entry for the reference curves if there are any.
fn legend_entries(panel: &Panel, keys: Option<&[String]>) -> Vec<(String, RGBAColor, u32)> {
    let mut e: Vec<(String, RGBAColor, u32)> = panel
        .series
        .iter()
        .enumerate()
        .filter(|(_, s)| !is_reference(s))
        .map(|(k, s)| (s.label.clone(), series_color(panel, k, keys), 2))
        .collect();
    if has_references(panel) {
        e.push((reference_label(panel), BLACK.to_rgba(), 1));
    }
    e
}

/// Colour of series k: black for a reference curve; otherwise the palette over the labelled
/// series of the panel, or with `keys` (the labels of the whole figure, [`line_panels_keyed`])
/// the palette entry of its label, the same in every panel.
fn series_color(panel: &Panel, k: usize, keys: Option<&[String]>) -> RGBAColor {
    let s = &panel.series[k];
    if is_reference(s) {
        return BLACK.to_rgba();
    }
    let idx = match keys.and_then(|keys| keys.iter().position(|l| *l == s.label)) {
        Some(idx) => idx,
        None => panel.series[..k]
            .iter()
            .filter(|s| !is_reference(s))
            .count(),
    };
    palette(idx)
}

/// Tableau's ten category colours (matplotlib's default cycle, "tab10"): dark enough on white
/// and apart from each other, which plotters' `Palette99` is not for nine series (its third and
/// ninth entries, yellow and lime, read as one pale line); `Palette99` from the eleventh series.
const TAB10: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Colour of the idx-th labelled series.
fn palette(idx: usize) -> RGBAColor {
    match TAB10.get(idx) {
        Some(c) => c.to_rgba(),
        None => Palette99::pick(idx).to_rgba(),
    }
}

/// Width in pixels of a legend beside the chart.
fn legend_width(entries: &[(String, RGBAColor, u32)]) -> u32 {
    let chars = entries
        .iter()
        .map(|e| e.0.chars().count())
        .max()
        .unwrap_or(0) as u32;
    48 + chars * TICKS * 11 / 20
}

/// A legend drawn in its own area (beside the chart), one entry per line from the top.
fn draw_side_legend(
    area: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    entries: &[(String, RGBAColor, u32)],
) -> PlotResult {
    let line = TICKS as i32 + 6;
    for (k, (label, color, width)) in entries.iter().enumerate() {
        let y = 40 + k as i32 * line;
        area.draw(&PathElement::new(
            vec![(6, y), (30, y)],
            color.stroke_width(*width),
        ))?;
        area.draw(&Text::new(
            label.clone(),
            (36, y - TICKS as i32 / 2),
            (FONT, TICKS).into_font(),
        ))?;
    }
    Ok(())
}

/// [`line_panels`] on a grid of `cols` columns whose cells are `cell` pixels each; nothing is
/// drawn when there are no panels (a benchmark part that ran no case).
pub fn panel_grid(path: &Path, panels: &[Panel], cols: usize, cell: (u32, u32)) -> PlotResult {
    if panels.is_empty() {
        return Ok(());
    }
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols) as u32;
    line_panels(path, panels, cols, (cell.0 * cols as u32, cell.1 * rows))
}

/// Panels side by side (in a grid of `cols` columns) in one PNG.
pub fn line_panels(path: &Path, panels: &[Panel], cols: usize, size: (u32, u32)) -> PlotResult {
    panels_with_keys(path, panels, cols, size, None)
}

/// [`line_panels`] where a label has one colour in every panel: the palette entry of its first
/// appearance in the figure (a Wi sweep drawn in several panels, some with runs others lack).
pub fn line_panels_keyed(
    path: &Path,
    panels: &[Panel],
    cols: usize,
    size: (u32, u32),
) -> PlotResult {
    let mut keys: Vec<String> = Vec::new();
    for s in panels.iter().flat_map(|p| &p.series) {
        if !is_reference(s) && !keys.contains(&s.label) {
            keys.push(s.label.clone());
        }
    }
    panels_with_keys(path, panels, cols, size, Some(&keys))
}

fn panels_with_keys(
    path: &Path,
    panels: &[Panel],
    cols: usize,
    size: (u32, u32),
    keys: Option<&[String]>,
) -> PlotResult {
    let root = png_area(path, size)?;
    root.fill(&WHITE)?;
    let rows = panels.len().div_ceil(cols);
    let areas = root.split_evenly((rows, cols));
    for (panel, area) in panels.iter().zip(areas.iter()) {
        draw_panel(panel, area, keys)?;
    }
    root.present()?;
    Ok(())
}

fn draw_panel(
    panel: &Panel,
    area: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    keys: Option<&[String]>,
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
    let entries = legend_entries(panel, keys);
    let with_legend =
        panel.series.len() > 1 || !panel.series.is_empty() && !is_reference(&panel.series[0]);
    let corner = legend_corner(panel, xs, ys);
    let (chart_area, side) = if with_legend && corner.is_none() && !entries.is_empty() {
        let w = area.dim_in_pixel().0;
        let lw = legend_width(&entries).min(w / 2);
        let (c, l) = area.split_horizontally(w - lw);
        (c, Some(l))
    } else {
        (area.clone(), None)
    };
    if let Some(l) = &side {
        draw_side_legend(l, &entries)?;
    }
    let mut b = ChartBuilder::on(&chart_area);
    b.caption(&panel.title, (FONT, CAPTION))
        .margin(14)
        .x_label_area_size(58)
        .y_label_area_size(90);
    macro_rules! draw {
        ($chart:expr) => {{
            let mut chart = $chart;
            chart
                .configure_mesh()
                .x_labels(8)
                .y_labels(8)
                .x_label_formatter(&|v| {
                    if panel.log.0 {
                        log_tick(*v, xs)
                    } else {
                        tick_in(*v, xs.1 - xs.0)
                    }
                })
                .y_label_formatter(&|v| {
                    if panel.log.1 {
                        log_tick(*v, ys)
                    } else {
                        tick_in(*v, ys.1 - ys.0)
                    }
                })
                .x_desc(panel.x_label.as_str())
                .y_desc(panel.y_label.as_str())
                .label_style((FONT, TICKS))
                .axis_desc_style((FONT, AXIS_DESC))
                .draw()?;
            for (k, s) in panel.series.iter().enumerate() {
                let color = series_color(panel, k, keys);
                let reference = is_reference(s);
                let pts: Vec<(f64, f64)> = s
                    .points
                    .iter()
                    .copied()
                    .filter(|p| p.0.is_finite() && p.1.is_finite())
                    .filter(|p| (!panel.log.0 || p.0 > 0.0) && (!panel.log.1 || p.1 > 0.0))
                    .collect();
                let line = chart.draw_series(LineSeries::new(
                    pts.clone(),
                    color.stroke_width(if reference { 1 } else { 2 }),
                ))?;
                if !reference {
                    line.label(s.label.as_str()).legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 18, y)], color.stroke_width(2))
                    });
                }
                if pts.len() < 40 && !reference {
                    chart.draw_series(pts.iter().map(|p| Circle::new(*p, 3, color.filled())))?;
                }
            }
            if let (true, Some(corner)) = (with_legend, corner) {
                if has_references(panel) {
                    chart
                        .draw_series(LineSeries::new(Vec::<(f64, f64)>::new(), BLACK))?
                        .label(reference_label(panel))
                        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK));
                }
                chart
                    .configure_series_labels()
                    .position(corner)
                    .label_font((FONT, TICKS))
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

/// One snapshot of particles: positions, a scalar per particle, wall particles, and the plate.
pub struct Snapshot {
    pub title: String,
    pub points: Vec<(f64, f64)>,
    pub values: Vec<f64>,
    pub walls: Vec<(f64, f64)>,
    /// Particle spacing \[m\]: sets the size of the dots.
    pub spacing: f64,
    /// The wall surfaces, each a line through a point along a unit tangent: the drop's plate,
    /// both walls of the channel (y = 0 and y = H), none for the elliptical drop.
    pub plates: Vec<PlateLine>,
    /// A nozzle to draw: its exit from x = .0 to .1 at height .2 \[m\], walls up from there.
    pub nozzle: Option<(f64, f64, f64)>,
    /// Names of the horizontal and vertical axes ("x", "y"; a 3D side view: "x", "z").
    pub axes: (String, String),
    /// Dots as wide as the particle spacing, so that neighbours touch: a 3D top view, where
    /// the layers stacked under each other would otherwise show as lattice lines, reads as the
    /// surface it is. Otherwise dots a third of the spacing across (the lattice and any gaps
    /// stay visible).
    pub splat: bool,
    /// A closed curve drawn over the particles as a dark line (the cylinder of the cylinder
    /// array, whose field would otherwise hide its wall points); empty for none.
    pub outline: Vec<(f64, f64)>,
}

/// A straight wall surface: a point on it and its unit tangent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlateLine {
    pub point: (f64, f64),
    pub tangent: (f64, f64),
}

/// Perceptually ordered colour map (anchors of matplotlib's viridis), `t` in \[0, 1\].
fn viridis(t: f64) -> RGBColor {
    const A: [(f64, f64, f64); 6] = [
        (68.0, 1.0, 84.0),
        (65.0, 68.0, 135.0),
        (42.0, 120.0, 142.0),
        (34.0, 168.0, 132.0),
        (122.0, 209.0, 81.0),
        (253.0, 231.0, 37.0),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (A.len() - 1) as f64;
    let k = (x.floor() as usize).min(A.len() - 2);
    let f = x - k as f64;
    let mix = |a: f64, b: f64| (a + f * (b - a)).round() as u8;
    RGBColor(
        mix(A[k].0, A[k + 1].0),
        mix(A[k].1, A[k + 1].1),
        mix(A[k].2, A[k + 1].2),
    )
}

/// Colour of `v` on the scale [lo, hi], saturated beyond it.
fn colour(v: f64, lo: f64, hi: f64) -> RGBColor {
    viridis(if hi > lo { (v - lo) / (hi - lo) } else { 0.5 })
}

/// The 1st and 99th percentiles of the finite values: a colour range a few outliers cannot
/// stretch until every particle has one colour. Widened a little if all values are equal.
pub fn robust_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let mut v: Vec<f64> = values.filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return (0.0, 1.0);
    }
    v.sort_by(|a, b| a.total_cmp(b));
    let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    let (lo, hi) = (at(0.01), at(0.99));
    if hi > lo {
        (lo, hi)
    } else {
        let pad = 0.05 * lo.abs().max(1e-12);
        (lo - pad, hi + pad)
    }
}

/// Length unit for a scene of size `extent` \[m\]: millimetres below half a metre.
fn length_unit(extent: f64) -> (f64, &'static str) {
    if extent < 0.5 {
        (1e3, "mm")
    } else {
        (1.0, "m")
    }
}

/// The part of the line p(s) = point + s tangent inside the window, if any (Liang-Barsky).
fn clip_plate(line: &PlateLine, x: (f64, f64), y: (f64, f64)) -> Option<[(f64, f64); 2]> {
    let (p, d) = (line.point, line.tangent);
    let (mut s0, mut s1) = (-1e30, 1e30);
    for (dir, o, lo, hi) in [(d.0, p.0, x.0, x.1), (d.1, p.1, y.0, y.1)] {
        if dir.abs() < 1e-15 {
            if o < lo || o > hi {
                return None;
            }
        } else {
            let (a, b) = ((lo - o) / dir, (hi - o) / dir);
            s0 = f64::max(s0, a.min(b));
            s1 = f64::min(s1, a.max(b));
        }
    }
    (s1 > s0).then_some([
        (p.0 + s0 * d.0, p.1 + s0 * d.1),
        (p.0 + s1 * d.0, p.1 + s1 * d.1),
    ])
}

/// The window of one snapshot: its fluid with a margin, stretched to include the nearest point
/// of the plate (so the plate is in every panel), and to the panel's aspect ratio (equal scales).
fn window(shot: &Snapshot, aspect: f64, min_size: f64) -> ((f64, f64), (f64, f64)) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in &shot.points {
        x0 = x0.min(p.0);
        x1 = x1.max(p.0);
        y0 = y0.min(p.1);
        y1 = y1.max(p.1);
    }
    if x0 > x1 {
        return ((-1.0, 1.0), (-1.0, 1.0));
    }
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    for line in &shot.plates {
        // Nearest point of the plate to the fluid's centre.
        let (o, d) = (line.point, line.tangent);
        let s = (cx - o.0) * d.0 + (cy - o.1) * d.1;
        let (px, py) = (o.0 + s * d.0, o.1 + s * d.1);
        x0 = x0.min(px);
        x1 = x1.max(px);
        y0 = y0.min(py);
        y1 = y1.max(py);
    }
    let m = 0.12 * (x1 - x0).max(y1 - y0).max(min_size);
    let (mut x0, mut x1, mut y0, mut y1) = (x0 - m, x1 + m, y0 - m, y1 + m);
    let (wx, wy) = (x1 - x0, y1 - y0);
    if wx / wy < aspect {
        let grow = 0.5 * (wy * aspect - wx);
        x0 -= grow;
        x1 += grow;
    } else {
        let grow = 0.5 * (wx / aspect - wy);
        y0 -= grow;
        y1 += grow;
    }
    ((x0, x1), (y0, y1))
}

/// Snapshots in a grid, like Fang 2006 Fig. 3: each panel's window follows the fluid (equal
/// scales on both axes, lengths in mm or m), the plate is a dark line with the wall particles
/// in grey, and one colour scale for all panels: `field` (name and unit) between the 1st and
/// 99th percentiles of all values, saturated beyond, shown by a colour bar on the right.
pub fn particle_snapshots(
    path: &Path,
    title: &str,
    shots: &[Snapshot],
    field: &str,
    cols: usize,
    size: (u32, u32),
) -> PlotResult {
    let root = png_area(path, size)?;
    root.fill(&WHITE)?;
    let (title_area, rest) = root.split_vertically(50);
    let (body, bar_area) = rest.split_horizontally(size.0.saturating_sub(190));
    title_area.titled(title, (FONT, CAPTION))?;
    let (lo, hi) = robust_range(shots.iter().flat_map(|s| s.values.iter().copied()));
    let extent = shots
        .iter()
        .flat_map(|s| s.points.iter())
        .fold(0.0f64, |e, p| e.max(p.0.abs()).max(p.1.abs()));
    let (scale, unit) = length_unit(extent);
    let min_size = shots.first().map_or(0.0, |s| {
        let (a, b) = s
            .points
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
        0.5 * (b - a).max(0.0)
    });
    let rows = shots.len().div_ceil(cols).max(1);
    let areas = body.split_evenly((rows, cols));
    let (xl, yl) = (52u32, 78u32);
    for (shot, area) in shots.iter().zip(areas.iter()) {
        let (aw, ah) = area.dim_in_pixel();
        let pw = aw as f64 - yl as f64 - 16.0;
        let ph = ah as f64 - xl as f64 - 16.0 - 30.0;
        let ((x0, x1), (y0, y1)) = window(shot, pw / ph.max(1.0), min_size);
        let mut chart = ChartBuilder::on(area)
            .caption(&shot.title, (FONT, AXIS_DESC))
            .margin(8)
            .x_label_area_size(xl)
            .y_label_area_size(yl)
            .build_cartesian_2d(x0 * scale..x1 * scale, y0 * scale..y1 * scale)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_labels(5)
            .y_labels(5)
            .x_desc(format!("{} [{unit}]", shot.axes.0))
            .y_desc(format!("{} [{unit}]", shot.axes.1))
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&|v| tick(*v))
            .label_style((FONT, TICKS))
            .axis_desc_style((FONT, TICKS + 1))
            .draw()?;
        // Small squares in pixel offsets: far cheaper to rasterise than circles at 10^5 particles.
        let dot = |p: (f64, f64), r: i32, c: RGBColor| {
            EmptyElement::at((p.0 * scale, p.1 * scale))
                + Rectangle::new([(-r, -r), (r, r)], c.filled())
        };
        // Dots a third of the particle spacing across, or the spacing ([`Snapshot::splat`]).
        let px_per_m = pw / (x1 - x0);
        let r = if shot.splat {
            (0.5 * shot.spacing * px_per_m).ceil().clamp(1.0, 12.0) as i32
        } else {
            (0.22 * shot.spacing * px_per_m).round().clamp(1.0, 6.0) as i32
        };
        // plotters does not clip elements placed by pixel offsets: keep only what is inside.
        let inside = |p: &&(f64, f64)| p.0 >= x0 && p.0 <= x1 && p.1 >= y0 && p.1 <= y1;
        chart.draw_series(
            shot.walls
                .iter()
                .filter(inside)
                .map(|p| dot(*p, 1, RGBColor(170, 170, 170))),
        )?;
        for line in &shot.plates {
            if let Some([p, q]) = clip_plate(line, (x0, x1), (y0, y1)) {
                chart.draw_series(std::iter::once(PathElement::new(
                    vec![(p.0 * scale, p.1 * scale), (q.0 * scale, q.1 * scale)],
                    RGBColor(40, 40, 40).stroke_width(3),
                )))?;
            }
        }
        if let Some((a, b, y)) = shot.nozzle {
            // The nozzle's two walls, from the exit up one and a half jet widths.
            let top = y + 1.5 * (b - a);
            for x in [a, b] {
                chart.draw_series(std::iter::once(PathElement::new(
                    vec![(x * scale, y * scale), (x * scale, top * scale)],
                    RGBColor(40, 40, 40).stroke_width(3),
                )))?;
            }
        }
        chart.draw_series(
            shot.points
                .iter()
                .zip(&shot.values)
                .filter(|(p, _)| inside(p))
                .map(|(p, v)| dot(*p, r, colour(*v, lo, hi))),
        )?;
        if let Some(first) = shot.outline.first() {
            let closed: Vec<(f64, f64)> = shot
                .outline
                .iter()
                .chain(std::iter::once(first))
                .map(|p| (p.0 * scale, p.1 * scale))
                .collect();
            chart.draw_series(std::iter::once(PathElement::new(
                closed,
                RGBColor(40, 40, 40).stroke_width(3),
            )))?;
        }
    }
    colour_bar(&bar_area, field, lo, hi)?;
    root.present()?;
    Ok(())
}

/// A vertical colour bar from `lo` (bottom) to `hi` (top) with five ticks and the field's name.
fn colour_bar(
    area: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    field: &str,
    lo: f64,
    hi: f64,
) -> PlotResult {
    let (_, h) = area.dim_in_pixel();
    let (top, bottom) = (90i32, h as i32 - 90);
    let (left, right) = (20i32, 50i32);
    let n = (bottom - top).max(1);
    for k in 0..n {
        let t = 1.0 - k as f64 / n as f64;
        area.draw(&Rectangle::new(
            [(left, top + k), (right, top + k + 1)],
            viridis(t).filled(),
        ))?;
    }
    area.draw(&Rectangle::new([(left, top), (right, bottom)], BLACK))?;
    for k in 0..5 {
        let f = k as f64 / 4.0;
        let y = bottom - (f * (bottom - top) as f64).round() as i32;
        area.draw(&PathElement::new(vec![(right, y), (right + 6, y)], BLACK))?;
        area.draw(&Text::new(
            tick(lo + f * (hi - lo)),
            (right + 10, y - TICKS as i32 / 2),
            (FONT, TICKS),
        ))?;
    }
    area.draw(&Text::new(
        field.to_string(),
        (left - 10, top - 60),
        (FONT, TICKS + 1),
    ))?;
    area.draw(&Text::new(
        "1st-99th percentile,".to_string(),
        (left - 10, bottom + 20),
        (FONT, TICKS - 3),
    ))?;
    area.draw(&Text::new(
        "saturated beyond".to_string(),
        (left - 10, bottom + 40),
        (FONT, TICKS - 3),
    ))?;
    Ok(())
}

/// A grid of cells coloured green (true), red (false) or grey (None), with row and column labels:
/// a stability map.
pub fn status_grid(
    path: &Path,
    title: &str,
    x_title: &str,
    y_title: &str,
    x_labels: &[String],
    y_labels: &[String],
    cells: &[Vec<Option<bool>>],
) -> PlotResult {
    let (w, h) = (
        (260 + 110 * x_labels.len()).max(60 + 13 * title.len()) as u32,
        (150 + 50 * y_labels.len()) as u32,
    );
    let root = png_area(path, (w, h))?;
    root.fill(&WHITE)?;
    let nx = x_labels.len() as f64;
    let ny = y_labels.len() as f64;
    let xl = x_labels.to_vec();
    let yl = y_labels.to_vec();
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, CAPTION - 4))
        .margin(12)
        .x_label_area_size(62)
        .y_label_area_size(190)
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
        .y_desc(y_title)
        .label_style((FONT, TICKS))
        .axis_desc_style((FONT, AXIS_DESC))
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_ticks_are_labelled_at_one_two_five_only() {
        let labels: Vec<String> = [7.0, 10.0, 20.0, 30.0, 50.0, 70.0, 90.0, 100.0]
            .iter()
            .map(|v| log_tick(*v, (1.0, 1000.0)))
            .collect();
        assert_eq!(labels, ["", "10", "20", "", "50", "", "", "100"]);
        assert_eq!(log_tick(0.0, (1.0, 1000.0)), "");
        // An axis reaching below 0.01 labels every tick the same way.
        let labels: Vec<String> = [0.002, 0.01, 0.05, 0.1, 1.0]
            .iter()
            .map(|v| log_tick(*v, (1e-3, 1.0)))
            .collect();
        assert_eq!(labels, ["2e-3", "1e-2", "5e-2", "1e-1", "1e0"]);
    }

    /// Draws a cost-against-error panel like the benchmark's to `VISCOSPH_PLOT_DIR` (for a
    /// person to look at) or a temporary directory, and checks it is a PNG of the asked size.
    #[test]
    fn a_log_log_panel_draws() {
        let dir = std::env::var_os("VISCOSPH_PLOT_DIR")
            .map(std::path::PathBuf::from)
            .unwrap_or_else(std::env::temp_dir);
        let path = dir.join("viscosph_log_panel.png");
        let panel = Panel {
            title: "cost against difference".into(),
            x_label: "wall time [s]".into(),
            y_label: "error [-]".into(),
            series: vec![Series {
                label: "a".into(),
                points: vec![(6.0, 0.25), (70.0, 0.007), (104.0, 0.0004)],
            }],
            log: (true, true),
        };
        line_panels(&path, &[panel], 1, (640, 480)).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
    }

    #[test]
    fn plates_off_the_origin_are_clipped_to_the_window() {
        // The channel's upper wall y = 1 (tangent -x) across the window [-0.5, 1.5] x [-0.2, 1.2].
        let top = PlateLine {
            point: (0.0, 1.0),
            tangent: (-1.0, 0.0),
        };
        let [p, q] = clip_plate(&top, (-0.5, 1.5), (-0.2, 1.2)).unwrap();
        let (mut xs, ys) = ([p.0, q.0], [p.1, q.1]);
        xs.sort_by(f64::total_cmp);
        assert_eq!(xs, [-0.5, 1.5]);
        assert_eq!(ys, [1.0, 1.0]);
        // Above the window: not drawn.
        assert!(clip_plate(&top, (-0.5, 1.5), (-0.2, 0.9)).is_none());
        // Fang's plate inclined by 30 degrees through the origin, downhill towards +x.
        let a = 30f64.to_radians();
        let plate = PlateLine {
            point: (0.0, 0.0),
            tangent: (a.cos(), -a.sin()),
        };
        let [p, q] = clip_plate(&plate, (-1.0, 1.0), (-1.0, 1.0)).unwrap();
        for e in [p, q] {
            assert!((e.1 + e.0 * a.tan()).abs() < 1e-12, "{e:?} off the plate");
            assert!(
                (e.0.abs() - 1.0).abs() < 1e-12,
                "{e:?} not at the window edge"
            );
        }
    }
}
