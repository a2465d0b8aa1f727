//! Plots of finished runs: side view (x-z) over the terrain, top view (x-y) and pitch/roll
//! against time, written as PNG and SVG.
//!
//! Text is drawn with DejaVu Sans embedded at compile time (crate `dejavu`), so plotting needs
//! no system fonts and no fontconfig.

use crate::error::{Error, Result};
use crate::run::RunResult;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// One run to draw, with a label for the legend.
pub struct PlotRun<'a> {
    /// Legend label.
    pub label: &'a str,
    /// The run.
    pub result: &'a RunResult,
}

/// What to draw.
pub struct PlotInput<'a> {
    /// Figure title.
    pub title: &'a str,
    /// Runs, drawn in this order (colours follow the order).
    pub runs: &'a [PlotRun<'a>],
    /// Terrain height profile under the first run's path as (x m, z m) pairs, drawn as a filled
    /// ground in the side view; may be empty.
    pub ground_profile: &'a [(f64, f64)],
    /// Optional extra outlines to draw in the side view, e.g. a step as a polygon (x, z) -- may
    /// be empty.
    pub outlines: &'a [Vec<(f64, f64)>],
    /// The first run's vehicle outline at a few instants, drawn in the side view; may be empty.
    pub snapshots: &'a [super::vehicle_outline::Snapshot],
}

/// Figure size in pixels.
const SIZE: (u32, u32) = (1200, 900);
/// Font family the embedded font is registered under.
pub(super) const FONT: &str = "sans-serif";
/// Margin around each chart, px.
const MARGIN: u32 = 8;
/// Right margin, px: room for the last x tick label.
const MARGIN_RIGHT: u32 = 24;
/// Largest vertical exaggeration the side view may use to keep climbs visible on long runs.
const MAX_EXAGGERATION: f64 = 4.0;

/// Run colours (Tableau 10).
const COLOURS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];
const GROUND_FILL: RGBColor = RGBColor(222, 205, 170);
const GROUND_LINE: RGBColor = RGBColor(120, 95, 60);
const OUTLINE: RGBColor = RGBColor(70, 70, 70);

pub(super) fn colour(i: usize) -> RGBColor {
    COLOURS[i % COLOURS.len()]
}

/// Registers the embedded font once; false if the bytes were rejected.
pub(super) fn ensure_font() -> bool {
    static DONE: OnceLock<bool> = OnceLock::new();
    *DONE.get_or_init(|| {
        register_font(FONT, FontStyle::Normal, dejavu::sans::regular()).is_ok()
            && register_font(FONT, FontStyle::Bold, dejavu::sans::bold()).is_ok()
    })
}

fn io_error(path: &Path, message: impl std::fmt::Display) -> Error {
    Error::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(message.to_string()),
    }
}

/// Writes `<stem>.png` and `<stem>.svg` into `dir` (created if needed); returns the paths
/// written.
pub fn write_plots(input: &PlotInput, dir: &Path, stem: &str) -> Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).map_err(|source| Error::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    write_png_svg(
        dir,
        stem,
        |root| draw_figure(root, input),
        |root| draw_figure(root, input),
    )
}

/// Writes `<stem>.png` and `<stem>.svg` into `dir`, drawn by `png` and `svg` (the same figure
/// on the two backends), with the embedded font.
pub(super) fn write_png_svg(
    dir: &Path,
    stem: &str,
    png_draw: impl Fn(&DrawingArea<BitMapBackend, Shift>) -> DrawResult,
    svg_draw: impl Fn(&DrawingArea<SVGBackend, Shift>) -> DrawResult,
) -> Result<Vec<PathBuf>> {
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    if !ensure_font() {
        return Err(io_error(
            &png,
            "the embedded DejaVu Sans font could not be loaded",
        ));
    }
    crate::files::write_atomic_path(&png, |tmp| {
        let root = BitMapBackend::new(tmp, SIZE).into_drawing_area();
        png_draw(&root).map_err(|e| io_error(&png, format!("drawing failed: {e}")))?;
        root.present().map_err(|e| io_error(&png, e))
    })?;
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, SIZE).into_drawing_area();
        svg_draw(&root).map_err(|e| io_error(&svg, format!("drawing failed: {e}")))?;
        root.present().map_err(|e| io_error(&svg, e))?;
    }
    crate::files::write_atomic(&svg, text.as_bytes())?;
    Ok(vec![png, svg])
}

pub(super) type DrawResult = std::result::Result<(), Box<dyn std::error::Error>>;

/// Most points a plotted series keeps: a run with more samples is drawn from the smallest and
/// largest value of each of `PLOT_POINTS / 2` equal stretches of samples, in time order (the
/// min-max envelope: every peak and dip stays; a plot is at most 1400 pixels wide). 20,000 is
/// 200 s at PackBot's 100 Hz output: shorter runs are drawn from every sample.
pub const PLOT_POINTS: usize = 20_000;

/// Finite points of one run, mapped by `f` (one pass; at most [`PLOT_POINTS`], see there).
pub(super) fn points(
    result: &RunResult,
    f: impl Fn(&crate::world::Sample) -> (f64, f64),
) -> Vec<(f64, f64)> {
    let finite = result
        .samples
        .iter()
        .map(|s| f(&s))
        .filter(|(a, b)| a.is_finite() && b.is_finite());
    let n = result.samples.len();
    if n <= PLOT_POINTS {
        return finite.collect();
    }
    let stretch = n.div_ceil(PLOT_POINTS / 2);
    let mut out = Vec::with_capacity(PLOT_POINTS + 2);
    let mut bucket: Vec<(f64, f64)> = Vec::with_capacity(stretch);
    let mut flush = |bucket: &mut Vec<(f64, f64)>| {
        let by_value = |a: &&(f64, f64), b: &&(f64, f64)| a.1.total_cmp(&b.1);
        let lo = bucket
            .iter()
            .enumerate()
            .min_by(|a, b| by_value(&a.1, &b.1));
        let hi = bucket
            .iter()
            .enumerate()
            .max_by(|a, b| by_value(&a.1, &b.1));
        if let (Some((i, &p)), Some((j, &q))) = (lo, hi) {
            match i.cmp(&j) {
                std::cmp::Ordering::Less => out.extend([p, q]),
                std::cmp::Ordering::Greater => out.extend([q, p]),
                std::cmp::Ordering::Equal => out.push(p),
            }
        }
        bucket.clear();
    };
    for p in finite {
        bucket.push(p);
        if bucket.len() == stretch {
            flush(&mut bucket);
        }
    }
    flush(&mut bucket);
    out
}

/// Smallest interval holding every finite value, or None.
fn bounds(values: impl IntoIterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .into_iter()
        .filter(|v| v.is_finite())
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        })
}

/// `b` padded by `frac` of its span (at least `min_pad`), widened about its centre to at least
/// `min_span`; `default` when there is no data.
fn padded(
    b: Option<(f64, f64)>,
    frac: f64,
    min_pad: f64,
    min_span: f64,
    default: (f64, f64),
) -> (f64, f64) {
    let Some((lo, hi)) = b else { return default };
    let pad = ((hi - lo) * frac).max(min_pad);
    let (mut lo, mut hi) = (lo - pad, hi + pad);
    if hi - lo < min_span {
        let c = 0.5 * (lo + hi);
        lo = c - 0.5 * min_span;
        hi = c + 0.5 * min_span;
    }
    if !(lo.is_finite() && hi.is_finite() && hi > lo) {
        return default;
    }
    (lo, hi)
}

/// Widens `(lo, hi)` about its centre to `span` if it is narrower.
fn widen(r: (f64, f64), span: f64) -> (f64, f64) {
    if r.1 - r.0 >= span {
        return r;
    }
    let c = 0.5 * (r.0 + r.1);
    (c - 0.5 * span, c + 0.5 * span)
}

/// Plotting-area size in pixels of a chart on `area` with the given label areas.
fn plot_px<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    y_label: u32,
    x_label: u32,
) -> (f64, f64) {
    let (w, h) = area.dim_in_pixel();
    let w = w.saturating_sub(MARGIN + MARGIN_RIGHT + y_label).max(10);
    let h = h.saturating_sub(2 * MARGIN + x_label).max(10);
    (w as f64, h as f64)
}

fn draw_figure<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, input: &PlotInput) -> DrawResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let body = root.titled(input.title, (FONT, 26).into_font().style(FontStyle::Bold))?;
    let (_, h) = body.dim_in_pixel();
    let (side, bottom) = body.split_vertically((h as f64 * 0.44) as u32);
    let (top, right) = bottom.split_horizontally(560);
    let right = right.titled(
        "Attitude (REP 103: pitch > 0 is nose down)",
        caption_style(),
    )?;
    let (pitch, roll) = right.split_vertically(right.dim_in_pixel().1 / 2);
    draw_side(&side, input)?;
    draw_top(&top, input)?;
    draw_angle(&pitch, input, "pitch", |s| s.pose.pitch)?;
    draw_angle(&roll, input, "roll", |s| s.pose.roll)?;
    Ok(())
}

/// Tick label formatter for an axis spanning `span`: as many decimals as the ticks need, and
/// no "-0".
fn ticks(span: f64) -> impl Fn(&f64) -> String {
    let decimals = (-(span / 8.0).log10()).ceil().clamp(0.0, 6.0) as usize;
    move |v: &f64| {
        let s = format!("{v:.decimals$}");
        match s.strip_prefix('-') {
            Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
            _ => s,
        }
    }
}

fn caption_style() -> TextStyle<'static> {
    (FONT, 18).into_font().into()
}

fn draw_side<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, input: &PlotInput) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let area = area.titled("Side view (body centre over the terrain)", caption_style())?;
    let (y_label, x_label) = (70, 45);
    let (pw, ph) = plot_px(&area, y_label, x_label);
    let runs: Vec<Vec<(f64, f64)>> = input
        .runs
        .iter()
        .map(|r| points(r.result, |s| (s.pose.x, s.pose.z)))
        .collect();
    let all = || {
        runs.iter()
            .flatten()
            .chain(input.ground_profile.iter())
            .chain(input.outlines.iter().flatten())
            .chain(
                input
                    .snapshots
                    .iter()
                    .flat_map(|s| s.lines.iter().flatten()),
            )
            .copied()
            .filter(|(a, b)| a.is_finite() && b.is_finite())
    };
    let mut xr = padded(bounds(all().map(|p| p.0)), 0.03, 0.02, 0.5, (0.0, 1.0));
    let zb = bounds(all().map(|p| p.1));
    let (zlo, zhi) = padded(zb, 0.15, 0.03, 0.1, (0.0, 0.5));
    // Equal aspect: the z span that makes a metre as tall as it is wide.
    let equal = (xr.1 - xr.0) * ph / pw;
    let dz = zhi - zlo;
    let mut exaggeration = 1.0;
    let zr = if dz <= equal {
        // Too flat at equal aspect: exaggerate (up to a limit) so the data fill a quarter of the
        // height, and put the spare room mostly above the data (room for the legend).
        let e = (0.25 * equal / dz).min(MAX_EXAGGERATION);
        if e >= 1.5 {
            exaggeration = (e * 2.0).round() / 2.0;
        }
        let span = equal / exaggeration;
        let extra = span - dz;
        (zlo - 0.3 * extra, zhi + 0.7 * extra)
    } else {
        // Too tall (short runs): widen x instead.
        xr = widen(xr, dz * pw / ph);
        (zlo, zhi)
    };
    let z_desc = if exaggeration > 1.0 {
        format!("z (m), vertical ×{exaggeration:.1}")
    } else {
        "z (m)".to_string()
    };
    let mut chart = ChartBuilder::on(&area)
        .margin(MARGIN)
        .margin_right(MARGIN_RIGHT)
        .x_label_area_size(x_label)
        .y_label_area_size(y_label)
        .build_cartesian_2d(xr.0..xr.1, zr.0..zr.1)?;
    chart
        .configure_mesh()
        .x_desc("x (m)")
        .y_desc(z_desc)
        .x_label_formatter(&ticks(xr.1 - xr.0))
        .y_label_formatter(&ticks(zr.1 - zr.0))
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .light_line_style(RGBColor(235, 235, 235))
        .x_labels(12)
        .y_labels(6)
        .draw()?;
    draw_terrain(&mut chart, input, zr.0)?;
    draw_snapshots(&mut chart, input.snapshots)?;
    for (i, (run, pts)) in input.runs.iter().zip(&runs).enumerate() {
        let c = colour(i);
        let series = chart.draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))?;
        if input.runs.len() > 1 {
            series.label(run.label).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], c.stroke_width(3))
            });
        }
        if let Some(&p) = pts.first() {
            chart.draw_series(std::iter::once(Circle::new(p, 4, c.filled())))?;
        }
        if let Some(&p) = pts.last() {
            chart.draw_series(std::iter::once(Cross::new(p, 5, c.stroke_width(2))))?;
        }
    }
    if input.runs.len() > 1 {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .label_font((FONT, 15))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .draw()?;
    }
    Ok(())
}

/// The terrain under the runs: the ground profile filled down to `z_floor` m, and the boxes'
/// outlines.
fn draw_terrain<DB: DrawingBackend>(
    chart: &mut ChartContext<
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    input: &PlotInput,
    z_floor: f64,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let profile: Vec<(f64, f64)> = input
        .ground_profile
        .iter()
        .copied()
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .collect();
    if let (Some(first), Some(last)) = (profile.first(), profile.last()) {
        let mut poly = vec![(first.0, z_floor)];
        poly.extend(profile.iter().copied());
        poly.push((last.0, z_floor));
        chart.draw_series(std::iter::once(Polygon::new(poly, GROUND_FILL.filled())))?;
        chart.draw_series(std::iter::once(PathElement::new(
            profile.clone(),
            GROUND_LINE.stroke_width(2),
        )))?;
    }
    for outline in input.outlines {
        let mut pts: Vec<(f64, f64)> = outline
            .iter()
            .copied()
            .filter(|(a, b)| a.is_finite() && b.is_finite())
            .collect();
        if pts.len() >= 3 {
            chart.draw_series(std::iter::once(Polygon::new(
                pts.clone(),
                OUTLINE.mix(0.12).filled(),
            )))?;
        }
        if let Some(&p0) = pts.first() {
            pts.push(p0);
            chart.draw_series(std::iter::once(PathElement::new(
                pts,
                OUTLINE.stroke_width(2),
            )))?;
        }
    }
    Ok(())
}

/// The vehicle's outlines at their instants, each labelled with its time above it.
fn draw_snapshots<DB: DrawingBackend>(
    chart: &mut ChartContext<
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    snapshots: &[super::vehicle_outline::Snapshot],
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let ink = RGBColor(60, 60, 60);
    for snap in snapshots {
        for line in &snap.lines {
            chart.draw_series(std::iter::once(PathElement::new(
                line.clone(),
                ink.mix(0.55).stroke_width(1),
            )))?;
        }
        let pts = snap.lines.iter().flatten();
        let top = pts.clone().map(|p| p.1).fold(f64::MIN, f64::max);
        let mid = pts.clone().map(|p| p.0).sum::<f64>() / pts.count().max(1) as f64;
        if top.is_finite() && mid.is_finite() {
            chart.draw_series(std::iter::once(Text::new(
                format!("{:.1} s", snap.t),
                (mid, top),
                (FONT, 13).into_font().color(&ink),
            )))?;
        }
    }
    Ok(())
}

fn draw_top<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, input: &PlotInput) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let area = area.titled("Top view (● start, × end)", caption_style())?;
    let (y_label, x_label) = (70, 45);
    let (pw, ph) = plot_px(&area, y_label, x_label);
    let runs: Vec<Vec<(f64, f64)>> = input
        .runs
        .iter()
        .map(|r| points(r.result, |s| (s.pose.x, s.pose.y)))
        .collect();
    let xr = padded(
        bounds(runs.iter().flatten().map(|p| p.0)),
        0.05,
        0.05,
        0.5,
        (0.0, 1.0),
    );
    let yr = padded(
        bounds(runs.iter().flatten().map(|p| p.1)),
        0.05,
        0.05,
        0.5,
        (-0.5, 0.5),
    );
    // Equal aspect: the same metres per pixel on both axes.
    let m_per_px = ((xr.1 - xr.0) / pw).max((yr.1 - yr.0) / ph);
    let xr = widen(xr, m_per_px * pw);
    let yr = widen(yr, m_per_px * ph);
    let mut chart = ChartBuilder::on(&area)
        .margin(MARGIN)
        .margin_right(MARGIN_RIGHT)
        .x_label_area_size(x_label)
        .y_label_area_size(y_label)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)?;
    chart
        .configure_mesh()
        .x_desc("x (m)")
        .y_desc("y (m)")
        .x_label_formatter(&ticks(xr.1 - xr.0))
        .y_label_formatter(&ticks(yr.1 - yr.0))
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    for (i, pts) in runs.iter().enumerate() {
        let c = colour(i);
        chart.draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))?;
        if let Some(&p) = pts.first() {
            chart.draw_series(std::iter::once(Circle::new(p, 4, c.filled())))?;
        }
        if let Some(&p) = pts.last() {
            chart.draw_series(std::iter::once(Cross::new(p, 5, c.stroke_width(2))))?;
        }
    }
    Ok(())
}

fn draw_angle<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    input: &PlotInput,
    name: &str,
    angle: impl Fn(&crate::world::Sample) -> f64,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let runs: Vec<Vec<(f64, f64)>> = input
        .runs
        .iter()
        .map(|r| points(r.result, |s| (s.t, angle(s).to_degrees())))
        .collect();
    let series: Vec<(String, Vec<(f64, f64)>)> =
        runs.into_iter().map(|p| (String::new(), p)).collect();
    draw_time_panel(area, &format!("{name} (°)"), &series)
}

/// A panel of `series` (legend label, (t s, value) points) against time, `y_desc` naming the
/// value and its unit; a legend when any label is non-empty.
pub(super) fn draw_time_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    y_desc: &str,
    series: &[(String, Vec<(f64, f64)>)],
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let (y_label, x_label) = (70, 40);
    let all: Vec<(f64, f64)> = series.iter().flat_map(|(_, p)| p.iter().copied()).collect();
    let tb = bounds(all.iter().map(|p| p.0));
    let tr = match tb {
        Some((lo, hi)) if hi > lo => (lo, hi),
        Some((lo, _)) => (lo, lo + 1.0),
        None => (0.0, 1.0),
    };
    let ar = padded(bounds(all.iter().map(|p| p.1)), 0.1, 0.5, 2.0, (-1.0, 1.0));
    let mut chart = ChartBuilder::on(area)
        .margin(MARGIN)
        .margin_right(MARGIN_RIGHT)
        .x_label_area_size(x_label)
        .y_label_area_size(y_label)
        .build_cartesian_2d(tr.0..tr.1, ar.0..ar.1)?;
    chart
        .configure_mesh()
        .x_desc("t (s)")
        .y_desc(y_desc)
        .x_label_formatter(&ticks(tr.1 - tr.0))
        .y_label_formatter(&ticks(ar.1 - ar.0))
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()?;
    if ar.0 < 0.0 && ar.1 > 0.0 {
        chart.draw_series(std::iter::once(PathElement::new(
            vec![(tr.0, 0.0), (tr.1, 0.0)],
            BLACK.mix(0.35).stroke_width(1),
        )))?;
    }
    for (i, (label, pts)) in series.iter().enumerate() {
        let s = chart.draw_series(LineSeries::new(
            pts.iter().copied(),
            colour(i).stroke_width(2),
        ))?;
        if !label.is_empty() {
            s.label(label.as_str()).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 16, y)], colour(i).stroke_width(2))
            });
        }
    }
    if series.iter().any(|(l, _)| !l.is_empty()) {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK.mix(0.3))
            .label_font((FONT, 13))
            .position(SeriesLabelPosition::UpperLeft)
            .draw()?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::{Outcome, SolverSummary, Summary};
    use crate::world::{PoseRpy, Sample};

    fn sample(t: f64, x: f64, y: f64, z: f64, roll: f64, pitch: f64) -> Sample {
        Sample {
            t,
            pose: PoseRpy {
                x,
                y,
                z,
                roll,
                pitch,
                yaw: 0.0,
            },
            linvel: [0.3, 0.0, 0.0],
            angvel: [0.0; 3],
            belt_speed: vec![0.3, 0.3],
            belt_phase: vec![0.3 * t, 0.3 * t],
            belt_position: vec![0.3 * t, 0.3 * t],
            flipper_angle: vec![],
            contacts: 12,
            ..Default::default()
        }
    }

    /// A run longer than [`PLOT_POINTS`] is drawn from at most that many points, in time order,
    /// with its one-sample spike and dip kept (the min-max envelope); a shorter one from every
    /// sample.
    #[test]
    fn a_long_run_is_plotted_from_its_envelope() {
        let n = 3 * PLOT_POINTS + 7;
        let z = |i: usize| match i {
            40_001 => 5.0,
            50_003 => -4.0,
            _ => (i as f64 * 0.01).sin(),
        };
        let r = result(
            (0..n)
                .map(|i| sample(i as f64 * 0.01, 0.0, 0.0, z(i), 0.0, 0.0))
                .collect(),
        );
        let pts = points(&r, |s| (s.t, s.pose.z));
        assert!(pts.len() <= PLOT_POINTS + 2, "{}", pts.len());
        assert!(pts.len() >= PLOT_POINTS / 2);
        assert!(pts.windows(2).all(|w| w[0].0 < w[1].0), "in time order");
        assert!(pts.contains(&(40_001.0 * 0.01, 5.0)) && pts.contains(&(50_003.0 * 0.01, -4.0)));
        assert_eq!(pts.first().unwrap().0, 0.0);
        let short = result(
            (0..100)
                .map(|i| sample(i as f64, 0.0, 0.0, z(i), 0.0, 0.0))
                .collect(),
        );
        assert_eq!(points(&short, |s| (s.t, s.pose.z)).len(), 100);
    }

    fn result(samples: Vec<Sample>) -> RunResult {
        let first = samples.first().map(|s| s.pose).unwrap_or_default();
        let last = samples.last().map(|s| s.pose).unwrap_or(first);
        let sim_time = samples.last().map(|s| s.t).unwrap_or(0.0);
        RunResult {
            summary: Summary {
                scenario: Some("scenarios/packbot_step.toml".into()),
                vehicle: "PackBot 510".into(),
                method: "okada2020".into(),
                dt_s: 0.001,
                steps: (sim_time / 0.001).round() as u64,
                sim_time_s: sim_time,
                wall_time_s: sim_time / 5.0,
                real_time_factor: 5.0,
                elapsed_time_s: sim_time / 5.0,
                paced_real_time_factor: 5.0,
                paced: false,
                mass: crate::world::MassReport {
                    parts: Vec::new(),
                    total_file_kg: 13.0,
                    total_simulated_kg: 13.0,
                    centre_of_mass_body_m: [0.0; 3],
                },
                randomized: Default::default(),
                events: Vec::new(),
                mean_speed_mps: if sim_time > 0.0 {
                    (last.x - first.x) / sim_time
                } else {
                    0.0
                },
                distance_m: (last.x - first.x).abs(),
                net_displacement_m: (last.x - first.x).abs(),
                progress_m: last.x - first.x,
                initial_pose: first,
                final_pose: last,
                outcome: "completed".into(),
                outcome_reason: "ran to the end".into(),
                outcome_time_s: sim_time,
                solver: SolverSummary {
                    dt_s: 0.001,
                    iterations: 4,
                    stabilization_iterations: 1,
                    contact_clustering: false,
                    min_link_mass_kg: 0.02,
                    prediction_distance_m: 0.02,
                    contact_slop_m: 0.0,
                    held_friction_in_bias_pass: true,
                    contact_recycling: true,
                    floating_origin: true,
                    order_salt: 0,
                },
                seed: 0,
                max_link_error_m: 1e-4,
                max_link_error_rad: 1e-3,
                max_penetration_m: 0.0,
                tracks: vec![],
                odometry: Default::default(),
                drawbar: None,
                soil: None,
                turns: Vec::new(),
                sensors: Vec::new(),
                trainee: None,
                started_utc: "2026-01-01T00:00:00Z".into(),
                course: None,
                attempts: Vec::new(),
                margins: Default::default(),
                stopped: None,
            },
            samples: samples.into(),
            track_names: vec!["left".into(), "right".into()],
            flipper_names: vec![],
            outcome: Outcome::Completed,
            sensors: Vec::new(),
            ruts: Vec::new(),
            patches: Vec::new(),
        }
    }

    fn smoothstep(u: f64) -> f64 {
        let u = u.clamp(0.0, 1.0);
        u * u * (3.0 - 2.0 * u)
    }

    /// A robot driving at 0.3 m/s onto a 0.1 m step at x = 1 m (front of the track reaches
    /// it at x = 0.66 m); `stall` stops it at the step edge with the nose up.
    fn climb(stall: bool) -> RunResult {
        let h0 = 0.09;
        let samples = (0..=1000)
            .map(|i| {
                let t = i as f64 * 0.01;
                let mut x = 0.3 * t;
                if stall {
                    x = x.min(0.8 + 0.02 * (t - 2.67).max(0.0).sin());
                }
                let u = (x - 0.66) / 0.7;
                let z = h0 + 0.1 * smoothstep(u);
                // Nose up (negative pitch, REP 103) while climbing, a little nose down after.
                let pitch = -0.35 * (std::f64::consts::PI * u.clamp(0.0, 1.0)).sin()
                    + 0.05 * (std::f64::consts::PI * ((u - 1.0) / 0.3).clamp(0.0, 1.0)).sin();
                let roll = if stall {
                    0.03 * (1.3 * t).cos()
                } else {
                    0.02 * (2.0 * t).sin()
                };
                let y = if stall {
                    -0.01 * x
                } else {
                    0.03 * (x / 1.5).sin()
                };
                sample(t, x, y, z, roll, pitch)
            })
            .collect();
        result(samples)
    }

    fn temp_dir(name: &str) -> PathBuf {
        std::env::temp_dir().join(format!("tracksim-plot-{}-{name}", std::process::id()))
    }

    fn png_size(bytes: &[u8]) -> (u32, u32) {
        assert!(bytes.len() > 24, "PNG too short");
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
        assert_eq!(&bytes[12..16], b"IHDR", "first chunk is IHDR");
        let w = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
        let h = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
        (w, h)
    }

    fn step_profile() -> Vec<(f64, f64)> {
        vec![(-0.3, 0.0), (1.0, 0.0), (1.0, 0.1), (3.3, 0.1)]
    }

    #[test]
    fn plot_step_climb_writes_png_and_svg() {
        let climbed = climb(false);
        let stalled = climb(true);
        let runs = [
            PlotRun {
                label: "friction 0.6 (climbs)",
                result: &climbed,
            },
            PlotRun {
                label: "friction 0.3 (stalls)",
                result: &stalled,
            },
        ];
        let profile = step_profile();
        let outlines = vec![vec![(1.0, 0.0), (1.0, 0.1), (3.3, 0.1), (3.3, 0.0)]];
        let input = PlotInput {
            title: "PackBot 510 on a 0.1 m step",
            runs: &runs,
            ground_profile: &profile,
            outlines: &outlines,
            snapshots: &[],
        };
        // Set TRACKSIM_PLOT_DIR to keep the figure for a look.
        let keep = std::env::var_os("TRACKSIM_PLOT_DIR").map(PathBuf::from);
        let dir = keep.clone().unwrap_or_else(|| temp_dir("step"));
        let written = write_plots(&input, &dir, "step").expect("plots written");
        assert_eq!(written, vec![dir.join("step.png"), dir.join("step.svg")]);
        let png = std::fs::read(&written[0]).expect("png exists");
        assert_eq!(png_size(&png), SIZE);
        let svg = std::fs::read_to_string(&written[1]).expect("svg exists");
        assert!(svg.starts_with("<svg"), "{}", &svg[..svg.len().min(80)]);
        for label in [
            "x (m)",
            "z (m)",
            "y (m)",
            "t (s)",
            "pitch (°)",
            "roll (°)",
            "friction 0.6 (climbs)",
            "friction 0.3 (stalls)",
            "PackBot 510 on a 0.1 m step",
        ] {
            assert!(svg.contains(label), "SVG lacks {label:?}");
        }
        if keep.is_none() {
            std::fs::remove_dir_all(&dir).ok();
        }
    }

    #[test]
    fn plot_degenerate_inputs_do_not_panic() {
        let empty = result(vec![]);
        let single = result(vec![sample(0.0, 0.5, 0.0, 0.1, 0.0, 0.0)]);
        // All x (and everything else) equal over time.
        let still = result(
            (0..50)
                .map(|i| sample(i as f64 * 0.1, 0.0, 0.0, 0.1, 0.0, 0.0))
                .collect(),
        );
        let keep = std::env::var_os("TRACKSIM_PLOT_DIR").map(PathBuf::from);
        let dir = keep.clone().unwrap_or_else(|| temp_dir("degenerate"));
        let cases: Vec<Vec<PlotRun>> = vec![
            vec![],
            vec![PlotRun {
                label: "empty",
                result: &empty,
            }],
            vec![PlotRun {
                label: "single",
                result: &single,
            }],
            vec![
                PlotRun {
                    label: "still",
                    result: &still,
                },
                PlotRun {
                    label: "single",
                    result: &single,
                },
                PlotRun {
                    label: "empty",
                    result: &empty,
                },
            ],
        ];
        for (i, runs) in cases.iter().enumerate() {
            let input = PlotInput {
                title: "degenerate",
                runs,
                ground_profile: &[],
                outlines: &[],
                snapshots: &[],
            };
            let written = write_plots(&input, &dir, &format!("case{i}")).expect("plots written");
            let png = std::fs::read(&written[0]).expect("png exists");
            assert_eq!(png_size(&png), SIZE);
        }
        if keep.is_none() {
            std::fs::remove_dir_all(&dir).ok();
        }
    }

    #[test]
    fn plot_into_a_file_is_an_io_error() {
        let dir = temp_dir("not-a-dir");
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("file");
        std::fs::write(&file, b"x").unwrap();
        let input = PlotInput {
            title: "x",
            runs: &[],
            ground_profile: &[],
            outlines: &[],
            snapshots: &[],
        };
        let err = write_plots(&input, &file, "p").expect_err("a file is not a directory");
        assert!(matches!(err, Error::Io { .. }), "{err}");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn plot_long_run_exaggerates_height_and_says_so() {
        // 12 m at 0.3 m/s over a 0.1 m step at x = 6 m.
        let samples = (0..=400)
            .map(|i| {
                let t = i as f64 * 0.1;
                let x = 0.3 * t;
                let z = 0.09 + 0.1 * smoothstep((x - 5.66) / 0.7);
                sample(t, x, 0.0, z, 0.0, 0.0)
            })
            .collect();
        let run = result(samples);
        let runs = [PlotRun {
            label: "long",
            result: &run,
        }];
        let profile = vec![(0.0, 0.0), (6.0, 0.0), (6.0, 0.1), (12.0, 0.1)];
        let input = PlotInput {
            title: "12 m run over a 0.1 m step",
            runs: &runs,
            ground_profile: &profile,
            outlines: &[],
            snapshots: &[],
        };
        let keep = std::env::var_os("TRACKSIM_PLOT_DIR").map(PathBuf::from);
        let dir = keep.clone().unwrap_or_else(|| temp_dir("long"));
        let written = write_plots(&input, &dir, "long").expect("plots written");
        let svg = std::fs::read_to_string(&written[1]).expect("svg exists");
        assert!(
            svg.contains("z (m), vertical ×"),
            "the exaggeration is labelled"
        );
        // A single run needs no legend.
        assert!(!svg.contains(">long<"));
        if keep.is_none() {
            std::fs::remove_dir_all(&dir).ok();
        }
    }
}
