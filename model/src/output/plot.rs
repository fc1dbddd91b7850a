//! PNG line plots (plotters, bitmap backend, embedded font: no system font libraries).
//!
//! The font is DejaVu Sans, committed in `model/assets/fonts/` with its licence and compiled into
//! the binary, so a fresh machine with only the Rust toolchain draws legible text.

use super::atomic_file::{replace_with, temporary_sibling};
use super::OutputError;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

/// One named curve.
pub struct Series<'a> {
    pub label: &'a str,
    pub points: &'a [(f64, f64)],
}

/// A 2-D line plot of one or more series.
pub struct Plot<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub log_x: bool,
    pub log_y: bool,
    pub series: Vec<Series<'a>>,
}

/// How a series is drawn, so that computed values and the exact or published curves they are
/// compared with stay distinguishable (issue 20: a reviewer must tell them apart at a glance).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Style {
    /// A coloured solid line (markers at up to 60 points): the default.
    #[default]
    Line,
    /// Computed values: coloured markers at every point joined by a thin line.
    Computed,
    /// An exact or published curve: a black dashed line drawn over the computed ones.
    Exact,
    /// A guide (e.g. a slope-2 line on a convergence plot): a grey dotted line drawn first.
    Guide,
}

/// Image size in pixels: wide enough for a legend beside four-digit tick labels.
pub const WIDTH: u32 = 1000;
pub const HEIGHT: u32 = 700;

const DEJAVU_SANS: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// Distinct colours (the "tab10" palette), cycled when there are more series.
pub(crate) const PALETTE: [RGBColor; 10] = [
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

/// Series with at most this many points also get a marker at each point, so sparse data (and a
/// single point, which draws no line) stays visible.
const MARKER_LIMIT: usize = 60;

/// How many points of line a marker weighs when the legend looks for the emptiest corner.
const MARKER_WEIGHT: usize = 100;

/// Whether a series of `points` points drawn in `style` gets a marker at each point: computed
/// values always, plain lines when sparse (dashed exact curves and guides never).
fn draws_markers(style: Style, points: usize) -> bool {
    style == Style::Computed || (style == Style::Line && points <= MARKER_LIMIT)
}

/// Draws `plot` to a PNG file at `path` (written to a temporary sibling and renamed into place).
///
/// Refuses, naming series and point: NaN/infinite coordinates, non-positive values on a log axis,
/// and a plot without any point.
pub fn write_png(plot: &Plot, path: &Path) -> Result<(), OutputError> {
    write_png_styled(plot, &[], path)
}

/// [`write_png`] with a [`Style`] per series (`styles[i]` for `plot.series[i]`; series beyond the
/// slice are [`Style::Line`]).
pub fn write_png_styled(plot: &Plot, styles: &[Style], path: &Path) -> Result<(), OutputError> {
    let x_range = axis_range(path, plot, Axis::X)?;
    let y_range = axis_range(path, plot, Axis::Y)?;
    register_embedded_font().map_err(|e| OutputError::invalid(path, e))?;

    // Label digits resolve 1/100 of a linear axis (ticks are about 1/10 apart).
    let resolution = |log: bool, (low, high): (f64, f64)| if log { 0.0 } else { 0.01 * (high - low) };
    let resolutions = (resolution(plot.log_x, x_range), resolution(plot.log_y, y_range));
    let legend = legend_corner(plot, styles, x_range, y_range);
    render_png(path, "the plot", |root| {
        let (x0, x1) = x_range;
        let (y0, y1) = y_range;
        match (plot.log_x, plot.log_y) {
            (false, false) => draw(root, plot, styles, legend, resolutions, x0..x1, y0..y1),
            (true, false) => draw(root, plot, styles, legend, resolutions, (x0..x1).log_scale(), y0..y1),
            (false, true) => draw(root, plot, styles, legend, resolutions, x0..x1, (y0..y1).log_scale()),
            (true, true) => draw(root, plot, styles, legend, resolutions, (x0..x1).log_scale(), (y0..y1).log_scale()),
        }
    })
}

/// Draws with `draw` on a WIDTH × HEIGHT bitmap written to a temporary sibling of `path`, then
/// renames it into place; on failure the temporary is removed and the error names `what`.
pub(crate) fn render_png(path: &Path, what: &str, draw: impl FnOnce(&DrawingArea<BitMapBackend, Shift>) -> Result<(), String>) -> Result<(), OutputError> {
    let temporary = temporary_sibling(path);
    let drawn = {
        let root = BitMapBackend::new(&temporary, (WIDTH, HEIGHT)).into_drawing_area();
        draw(&root).and_then(|()| root.present().map_err(|e| e.to_string()))
    };
    match drawn {
        Ok(()) => replace_with(&temporary, path),
        Err(message) => {
            let _ = std::fs::remove_file(&temporary);
            Err(OutputError::Io { path: path.to_path_buf(), source: std::io::Error::other(format!("drawing {what} failed: {message}")) })
        }
    }
}

pub(crate) fn register_embedded_font() -> Result<(), String> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| plotters::style::register_font("sans-serif", FontStyle::Normal, DEJAVU_SANS).is_ok());
    if ok {
        Ok(())
    } else {
        Err("the embedded DejaVu Sans font could not be parsed".to_string())
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Axis {
    X,
    Y,
}

/// The data range of one axis widened by a margin: 5 % of the span on each side (in decades on
/// a log axis; at least 1e-6 of the values on a linear one); a zero span (one point, constant series) gets ±10 % of the value (±half a decade
/// on a log axis, ±1 at zero) so the axis is never degenerate.
fn axis_range(path: &Path, plot: &Plot, axis: Axis) -> Result<(f64, f64), OutputError> {
    let (name, log) = match axis {
        Axis::X => ("x", plot.log_x),
        Axis::Y => ("y", plot.log_y),
    };
    let mut low = f64::INFINITY;
    let mut high = f64::NEG_INFINITY;
    for series in &plot.series {
        for (index, &(x, y)) in series.points.iter().enumerate() {
            let value = if axis == Axis::X { x } else { y };
            if !value.is_finite() {
                return Err(OutputError::NonFinite { path: path.to_path_buf(), field: format!("series `{}` {name}", series.label), index, value });
            }
            if log && value <= 0.0 {
                return Err(OutputError::invalid(
                    path,
                    format!(
                        "series `{}` point {index} has {name} = {value}, but the {name} axis is \
                         logarithmic and needs positive values",
                        series.label
                    ),
                ));
            }
            low = low.min(value);
            high = high.max(value);
        }
    }
    if low > high {
        return Err(OutputError::invalid(path, format!("plot `{}` has no data points", plot.title)));
    }
    let range = if log {
        let (a, b) = (low.log10(), high.log10());
        let pad = if b > a { 0.05 * (b - a) } else { 0.5 };
        (10f64.powf(a - pad), 10f64.powf(b + pad))
    } else {
        let span = high - low;
        // A span below a millionth of the values (round-off noise on a constant) would need
        // tick labels too long to fit; such an axis shows the values to 7 digits instead.
        let floor = 1e-6 * low.abs().max(high.abs());
        let pad = if span > 0.0 {
            (0.05 * span).max(floor)
        } else if low != 0.0 {
            0.1 * low.abs()
        } else {
            1.0
        };
        (low - pad, high + pad)
    };
    if !(range.0.is_finite() && range.1.is_finite() && range.0 < range.1) {
        return Err(OutputError::invalid(path, format!("the {name} data range {low:e}..{high:e} is too wide to draw")));
    }
    Ok(range)
}

/// Tick label text with as many significant digits as the axis resolution needs (4 on a log
/// axis, where `resolution` is 0): plain numbers for ordinary magnitudes, exponent form for very
/// small or large ones. A tick smaller than half the resolution is round-off of zero (e.g.
/// 5.6e-17 on an axis from -1 to 1) and prints as "0".
pub(crate) fn tick_text(value: f64, resolution: f64) -> String {
    let magnitude = value.abs();
    if magnitude == 0.0 || magnitude < 0.5 * resolution {
        return "0".to_string();
    }
    let exponent = magnitude.log10().floor() as i32;
    let significant = if resolution > 0.0 { (exponent - resolution.log10().floor() as i32 + 1).clamp(1, 15) } else { 4 } as usize;
    let trim = |text: &str| -> String {
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text.to_string()
        }
    };
    if (1e-3..1e5).contains(&magnitude) {
        let decimals = (significant as i32 - 1 - exponent).max(0) as usize;
        trim(&format!("{value:.decimals$}"))
    } else {
        let precision = significant - 1;
        let text = format!("{value:.precision$e}");
        let (mantissa, power) = text.split_once('e').unwrap_or((&text, "0"));
        format!("{}e{power}", trim(mantissa))
    }
}

/// The legend goes to the corner whose data crowd it least, the upper right on a tie (a rising
/// curve such as a settling velocity ends under an upper-right legend; two curves that rise from
/// zero, one of them to the top, as a head's production and spillage, leave only the upper left).
/// A legend of long labels reaches past the middle of the plot, and a marker it covers hides a
/// datum where a covered stretch of line only hides a stretch (a lone computed point at the
/// middle of the x range went under a legend this way), so the box grows with the labels and a
/// marker weighs [`MARKER_WEIGHT`] points of line.
fn legend_corner(plot: &Plot, styles: &[Style], (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> SeriesLabelPosition {
    let unit = |v: f64, (a, b): (f64, f64), log: bool| if log { (v.log10() - a.log10()) / (b.log10() - a.log10()) } else { (v - a) / (b - a) };
    // points under each corner's box, in order of preference: a tie keeps the legend on the
    // right, where readers look for it
    const CORNERS: [(SeriesLabelPosition, bool, bool); 4] = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    // the box: at least half the width and a third of the height; ≈ 10 px per character of
    // the longest label at 18 px plus the line sample, over the ≈ 850 × 560 px plot area
    let longest = plot.series.iter().map(|s| s.label.chars().count()).max().unwrap_or(0) as f64;
    let width = ((10.0 * longest + 70.0) / 850.0).clamp(0.5, 0.95);
    let height = ((26.0 * plot.series.len() as f64 + 20.0) / 560.0).clamp(0.35, 0.95);
    let mut covered = [0usize; 4];
    for (index, series) in plot.series.iter().enumerate() {
        let style = styles.get(index).copied().unwrap_or_default();
        let weight = if draws_markers(style, series.points.len()) { MARKER_WEIGHT } else { 1 };
        for &(x, y) in series.points {
            let (u, v) = (unit(x, (x0, x1), plot.log_x), unit(y, (y0, y1), plot.log_y));
            for (count, &(_, right, upper)) in covered.iter_mut().zip(&CORNERS) {
                let in_x = if right { u > 1.0 - width } else { u < width };
                let in_y = if upper { v > 1.0 - height } else { v < height };
                *count += weight * usize::from(in_x && in_y);
            }
        }
    }
    let best = (0..CORNERS.len()).min_by_key(|&k| covered[k]).unwrap_or(0);
    CORNERS[best].0.clone()
}

fn draw<XR, YR>(
    root: &DrawingArea<BitMapBackend, Shift>,
    plot: &Plot,
    styles: &[Style],
    legend: SeriesLabelPosition,
    (x_resolution, y_resolution): (f64, f64),
    x_spec: XR,
    y_spec: YR,
) -> Result<(), String>
where
    XR: AsRangedCoord<Value = f64>,
    YR: AsRangedCoord<Value = f64>,
    XR::CoordDescType: ValueFormatter<f64>,
    YR::CoordDescType: ValueFormatter<f64>,
{
    let error = |e: &dyn std::fmt::Display| e.to_string();
    root.fill(&WHITE).map_err(|e| error(&e))?;
    let mut chart = ChartBuilder::on(root)
        .caption(plot.title, ("sans-serif", 30))
        .margin(20)
        .x_label_area_size(60)
        .y_label_area_size(110)
        .build_cartesian_2d(x_spec, y_spec)
        .map_err(|e| error(&e))?;
    chart
        .configure_mesh()
        .x_desc(plot.x_label)
        .y_desc(plot.y_label)
        .axis_desc_style(("sans-serif", 22))
        .label_style(("sans-serif", 17))
        .x_label_formatter(&|v| tick_text(*v, x_resolution))
        .y_label_formatter(&|v| tick_text(*v, y_resolution))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(205, 205, 205))
        .draw()
        .map_err(|e| error(&e))?;

    // guides first (behind everything), then lines, computed markers, and exact curves last
    // (dashed, over the computed values they are compared with, so both stay visible where
    // they coincide)
    let style_of = |index: usize| styles.get(index).copied().unwrap_or_default();
    let rank = |style: Style| match style {
        Style::Guide => 0,
        Style::Line => 1,
        Style::Computed => 2,
        Style::Exact => 3,
    };
    let mut order: Vec<usize> = (0..plot.series.len()).collect();
    order.sort_by_key(|&i| rank(style_of(i)));
    for index in order {
        let series = &plot.series[index];
        let style = style_of(index);
        let colour = match style {
            Style::Exact => BLACK,
            Style::Guide => RGBColor(110, 110, 110),
            Style::Line | Style::Computed => PALETTE[index % PALETTE.len()],
        };
        match style {
            Style::Exact | Style::Guide => {
                let (width, dash, gap) = if style == Style::Exact { (2, 12, 7) } else { (2, 4, 5) };
                let line = colour.stroke_width(width);
                chart
                    .draw_series(DashedLineSeries::new(series.points.iter().copied(), dash, gap, line))
                    .map_err(|e| error(&e))?
                    .label(series.label)
                    .legend(move |(x, y)| DashedPathElement::new(vec![(x, y), (x + 24, y)], dash / 2, gap / 2, line));
            }
            Style::Line | Style::Computed => {
                let line_style = colour.stroke_width(if style == Style::Computed { 1 } else { 2 });
                // one path per segment: plotters joins a thick polyline with miters, which shoot far out
                // of the frame where a spiky series turns back sharply (issue 15)
                let segments: Vec<PathElement<(f64, f64)>> = match series.points {
                    [single] => vec![PathElement::new(vec![*single, *single], line_style)],
                    points => points.windows(2).map(|w| PathElement::new(vec![w[0], w[1]], line_style)).collect(),
                };
                let computed = style == Style::Computed;
                chart.draw_series(segments).map_err(|e| error(&e))?.label(series.label).legend(move |(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(0, 0), (24, 0)], colour.stroke_width(if computed { 1 } else { 3 }))
                        + Circle::new((12, 0), if computed { 5 } else { 0 }, colour.filled())
                });
                if draws_markers(style, series.points.len()) {
                    let radius = if computed { 5 } else { 4 };
                    chart.draw_series(series.points.iter().map(|&point| Circle::new(point, radius, colour.filled()))).map_err(|e| error(&e))?;
                }
            }
        }
    }
    chart
        .configure_series_labels()
        .position(legend)
        .label_font(("sans-serif", 18))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| error(&e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::bar_chart::{write_bar_chart_png, Bar};
    use crate::output::test_dir;

    /// Width and height from a PNG's IHDR chunk, after checking the signature.
    fn png_size(path: &Path) -> (u32, u32) {
        let bytes = std::fs::read(path).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
        assert_eq!(&bytes[12..16], b"IHDR", "first chunk is IHDR");
        let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
        (be(16), be(20))
    }

    fn series_points(n: usize, f: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
        (1..=n).map(|i| (i as f64, f(i as f64))).collect()
    }

    #[test]
    fn writes_a_png_of_the_declared_size_for_every_axis_kind() {
        let dir = test_dir::fresh("plot_png");
        let error = series_points(8, |h| 0.3 * h.powi(-2));
        let first_order = series_points(8, |h| 0.5 * h.powi(-1));
        let constant = series_points(8, |_| 0.2);
        let single = [(3.0, 0.05)];
        for (log_x, log_y) in [(false, false), (true, false), (false, true), (true, true)] {
            let path = dir.join(format!("convergence_{log_x}_{log_y}.png"));
            let plot = Plot {
                title: "Convergence of the drag-law test (α, ρ, µ)",
                x_label: "refinement level N",
                y_label: "relative error",
                log_x,
                log_y,
                series: vec![
                    Series { label: "measured error", points: &error },
                    Series { label: "first order slope", points: &first_order },
                    Series { label: "constant", points: &constant },
                    Series { label: "single point", points: &single },
                ],
            };
            write_png(&plot, &path).unwrap();
            assert_eq!(png_size(&path), (WIDTH, HEIGHT));
        }
        // Only the finished images remain: temporaries were renamed away.
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 4);
    }

    #[test]
    fn styled_plots_and_bar_charts_write_pngs_and_refuse_bad_input() {
        let dir = test_dir::fresh("plot_styled");
        let computed = series_points(4, |h| 0.3 * h.powi(-2));
        let exact = series_points(40, |h| 0.3 * h.powi(-2));
        let plot = Plot {
            title: "styled",
            x_label: "h [m]",
            y_label: "error [-]",
            log_x: true,
            log_y: true,
            series: vec![Series { label: "computed", points: &computed }, Series { label: "exact", points: &exact }, Series { label: "guide", points: &exact }],
        };
        let path = dir.join("styled.png");
        write_png_styled(&plot, &[Style::Computed, Style::Exact, Style::Guide], &path).unwrap();
        assert_eq!(png_size(&path), (WIDTH, HEIGHT));
        let bars = [Bar { label: "exactly equal", value: 0.0 }, Bar { label: "a case", value: 3e-12 }, Bar { label: "another case", value: 2e-9 }];
        let path = dir.join("bars.png");
        write_bar_chart_png("bars", "difference [-]", &bars, 1e-14, Some(("bound", 1e-8)), &path).unwrap();
        assert_eq!(png_size(&path), (WIDTH, HEIGHT));
        write_bar_chart_png("one bar", "difference [-]", &bars[1..2], 1e-14, None, &dir.join("one.png")).unwrap();
        assert!(write_bar_chart_png("none", "d", &[], 1e-14, None, &dir.join("none.png")).unwrap_err().to_string().contains("no bars"));
        let nan = [Bar { label: "broken", value: f64::NAN }];
        assert!(matches!(write_bar_chart_png("nan", "d", &nan, 1e-14, None, &dir.join("nan.png")), Err(OutputError::NonFinite { .. })));
        assert!(write_bar_chart_png("floor", "d", &bars, 0.0, None, &dir.join("floor.png")).is_err());
    }

    #[test]
    fn degenerate_data_draws_without_panicking() {
        let dir = test_dir::fresh("plot_degenerate");
        let cases: [&[(f64, f64)]; 5] = [
            &[(0.0, 0.0)],
            &[(1.0, 5.0), (1.0, 5.0)],
            &[(-2.0, 1e-300), (-2.0, 2e-300)],
            &[(0.0, 1.0), (1e-12, 1.0 + 1e-15)],
            &[(0.0, 1e-9), (1.0, 3e-9), (2.0, 2e-9)],
        ];
        for (i, points) in cases.iter().enumerate() {
            let path = dir.join(format!("degenerate_{i}.png"));
            let plot = Plot { title: "degenerate", x_label: "x", y_label: "y", log_x: false, log_y: false, series: vec![Series { label: "s", points }] };
            write_png(&plot, &path).unwrap();
            assert_eq!(png_size(&path), (WIDTH, HEIGHT));
        }
    }

    #[test]
    fn refuses_nan_nonpositive_log_data_and_empty_plots() {
        let dir = test_dir::fresh("plot_refuse");
        let path = dir.join("bad.png");
        let with = |points: &[(f64, f64)], log_y: bool| {
            let plot = Plot { title: "t", x_label: "x", y_label: "y", log_x: false, log_y, series: vec![Series { label: "torque", points }] };
            write_png(&plot, &path)
        };
        let e = with(&[(0.0, 1.0), (1.0, f64::NAN)], false).unwrap_err();
        assert!(matches!(&e, OutputError::NonFinite { field, index: 1, .. } if field == "series `torque` y"), "{e}");
        let e = with(&[(0.0, 1.0), (1.0, 0.0)], true).unwrap_err();
        assert!(e.to_string().contains("logarithmic"), "{e}");
        let e = with(&[], false).unwrap_err();
        assert!(e.to_string().contains("no data points"), "{e}");
        assert!(!path.exists());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
    }

    #[test]
    fn tick_text_has_the_digits_the_axis_needs() {
        // Linear axis 0..0.5: resolution 0.005.
        assert_eq!(tick_text(0.30000000000000004, 0.005), "0.3");
        assert_eq!(tick_text(0.45, 0.005), "0.45");
        assert_eq!(tick_text(5.551115123125783e-17, 0.005), "0");
        // Linear axis 0..3000: resolution 30.
        assert_eq!(tick_text(1500.0, 30.0), "1500");
        // An axis 1 ± 1e-9 needs ten decimals to tell its ticks apart.
        assert_eq!(tick_text(1.0000000004, 2e-11), "1.0000000004");
        assert_eq!(tick_text(2.5e7, 1e6), "2.5e7");
        assert_eq!(tick_text(-1.25e-9, 1e-11), "-1.25e-9");
        // Log axis: four significant digits, tiny values kept.
        assert_eq!(tick_text(-0.0125, 0.0), "-0.0125");
        assert_eq!(tick_text(1e-6, 0.0), "1e-6");
        assert_eq!(tick_text(1e-17, 0.0), "1e-17");
    }
}

#[cfg(test)]
mod frame_tests {
    use super::*;

    /// Draws `plot` into an RGB buffer (what `write_png` encodes).
    fn render(plot: &Plot) -> Vec<u8> {
        let x = axis_range(Path::new("t.png"), plot, Axis::X).unwrap();
        let y = axis_range(Path::new("t.png"), plot, Axis::Y).unwrap();
        register_embedded_font().unwrap();
        let mut buffer = vec![0u8; (WIDTH * HEIGHT * 3) as usize];
        {
            let root = BitMapBackend::with_buffer(&mut buffer, (WIDTH, HEIGHT)).into_drawing_area();
            draw(&root, plot, &[], SeriesLabelPosition::UpperRight, (0.01 * (x.1 - x.0), 0.01 * (y.1 - y.0)), x.0..x.1, y.0..y.1).unwrap();
            root.present().unwrap();
        }
        buffer
    }

    /// A spiky series (a DEM overlap ratio: mostly 0, single-step peaks) stays inside its frame:
    /// no pixel of the series' colour in the caption band at the top or below the x axis labels.
    #[test]
    fn legend_takes_the_emptiest_corner() {
        let rising: Vec<(f64, f64)> = (0..=100).map(|k| (k as f64, 0.005 * k as f64)).collect();
        let low: Vec<(f64, f64)> = (0..=100).map(|k| (k as f64, 0.0015 * k as f64)).collect();
        let falling: Vec<(f64, f64)> = (0..=100).map(|k| (k as f64, 1.0 - 0.01 * k as f64)).collect();
        let corner = |series: Vec<Series>| {
            let plot = Plot { title: "t", x_label: "x", y_label: "y", log_x: false, log_y: false, series };
            let (x, y) = (axis_range(Path::new("t.png"), &plot, Axis::X).unwrap(), axis_range(Path::new("t.png"), &plot, Axis::Y).unwrap());
            legend_corner(&plot, &[], x, y)
        };
        // a head's production (to 0.15) and spillage (to 0.5): the upper right holds spillage's end
        let two = corner(vec![Series { label: "s", points: &rising }, Series { label: "p", points: &low }]);
        assert!(matches!(two, SeriesLabelPosition::UpperLeft), "production and spillage");
        assert!(matches!(corner(vec![Series { label: "f", points: &falling }]), SeriesLabelPosition::UpperRight), "a falling curve");
        assert!(matches!(corner(vec![Series { label: "r", points: &rising }]), SeriesLabelPosition::LowerRight), "a rising curve");
        // a verification figure: one computed point at the middle of the x range near the top,
        // a long label, and a model curve along the bottom: the legend may not hide the point
        let model: Vec<(f64, f64)> = (0..=40).map(|k| (20.0 + 2.0 * k as f64, if k < 23 { 0.0 } else { 0.0025 * (k - 23) as f64 })).collect();
        let point = [(60.0, 0.093)];
        let series = vec![
            Series { label: "computed (fast fluid, mean over the last revolution)", points: &point },
            Series { label: "analytic spillage model Q₁ (water, same contour)", points: &model },
        ];
        let plot = Plot { title: "t", x_label: "x", y_label: "y", log_x: false, log_y: false, series };
        let (x, y) = (axis_range(Path::new("t.png"), &plot, Axis::X).unwrap(), axis_range(Path::new("t.png"), &plot, Axis::Y).unwrap());
        let place = legend_corner(&plot, &[Style::Computed, Style::Exact], x, y);
        assert!(!matches!(place, SeriesLabelPosition::UpperRight | SeriesLabelPosition::UpperLeft), "the point at the top middle: {place:?}");
    }

    #[test]
    fn spiky_series_stay_inside_the_frame() {
        let points: Vec<(f64, f64)> = (0..3000).map(|i| (i as f64 * 1e-3, if i % 7 == 3 { 0.161 } else { 0.0 })).collect();
        let plot = Plot {
            title: "spikes",
            x_label: "time [s]",
            y_label: "ratio",
            log_x: false,
            log_y: false,
            series: vec![Series { label: "spikes", points: &points }],
        };
        let buffer = render(&plot);
        let colour = PALETTE[0];
        let is_series = |row: u32| {
            (0..WIDTH).any(|col| {
                let i = ((row * WIDTH + col) * 3) as usize;
                (buffer[i], buffer[i + 1], buffer[i + 2]) == (colour.0, colour.1, colour.2)
            })
        };
        // the caption and margin take the top ~60 rows, the x labels the bottom ~80
        let outside: Vec<u32> = (0..50).chain(HEIGHT - 50..HEIGHT).filter(|&r| is_series(r)).collect();
        assert!(outside.is_empty(), "series pixels outside the frame in rows {:?}…", &outside[..outside.len().min(10)]);
    }
}
