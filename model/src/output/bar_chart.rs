//! Horizontal bar charts on a logarithmic value axis (the verification report's comparison of
//! solver differences against their bound), drawn like [`super::plot`]'s line plots: embedded
//! font, written to a temporary file and renamed into place.

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use std::path::Path;

use super::plot::{register_embedded_font, render_png, tick_text, PALETTE, WIDTH};
use super::OutputError;

/// One bar of a [`write_bar_chart_png`]: its label and its value.
pub struct Bar<'a> {
    pub label: &'a str,
    pub value: f64,
}

/// A horizontal bar chart on a logarithmic value axis: one labelled bar per entry, from `floor`
/// to its value (values below `floor`, such as exact zeros, are drawn at `floor`, as a stub),
/// and a dashed vertical `bound` line (a limit the bars must stay under). For comparisons of
/// magnitudes that span decades, such as solver differences against their bound.
pub fn write_bar_chart_png(title: &str, value_label: &str, bars: &[Bar], floor: f64, bound: Option<(&str, f64)>, path: &Path) -> Result<(), OutputError> {
    if bars.is_empty() {
        return Err(OutputError::invalid(path, format!("bar chart `{title}` has no bars")));
    }
    if !(floor > 0.0 && floor.is_finite()) {
        return Err(OutputError::invalid(path, format!("bar chart `{title}`: the floor {floor} must be positive")));
    }
    for (index, bar) in bars.iter().enumerate() {
        if bar.value.is_nan() || bar.value.is_infinite() {
            return Err(OutputError::NonFinite { path: path.to_path_buf(), field: format!("bar `{}`", bar.label), index, value: bar.value });
        }
    }
    register_embedded_font().map_err(|e| OutputError::invalid(path, e))?;
    let high = bars.iter().map(|b| b.value).chain(bound.map(|b| b.1)).fold(floor, f64::max) * 10.0;
    render_png(path, "the bar chart", |root| draw_bars(root, title, value_label, bars, floor, high, bound))
}

fn draw_bars(
    root: &DrawingArea<BitMapBackend, Shift>,
    title: &str,
    value_label: &str,
    bars: &[Bar],
    floor: f64,
    high: f64,
    bound: Option<(&str, f64)>,
) -> Result<(), String> {
    use plotters::coord::ranged1d::SegmentValue;
    let error = |e: &dyn std::fmt::Display| e.to_string();
    root.fill(&WHITE).map_err(|e| error(&e))?;
    let n = bars.len();
    // the longest label decides the label area (≈ 9 px per character at 17 px)
    let label_width = bars.iter().map(|b| b.label.chars().count()).max().unwrap_or(0) as u32 * 9 + 20;
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 30))
        .margin(20)
        .x_label_area_size(60)
        .y_label_area_size(label_width.clamp(80, WIDTH / 2))
        // an integer range includes its end: n bars take 0..n−1 (one bar needs a second slot)
        .build_cartesian_2d((floor..high).log_scale(), (0..(n - 1).max(1)).into_segmented())
        .map_err(|e| error(&e))?;
    chart
        .configure_mesh()
        .x_desc(value_label)
        .axis_desc_style(("sans-serif", 22))
        .label_style(("sans-serif", 17))
        .x_label_formatter(&|v| tick_text(*v, 0.0))
        .y_labels(n)
        .y_label_formatter(&|v| match v {
            // the first bar at the top
            SegmentValue::CenterOf(i) | SegmentValue::Exact(i) => n.checked_sub(i + 1).and_then(|k| bars.get(k)).map_or(String::new(), |b| b.label.to_string()),
            SegmentValue::Last => String::new(),
        })
        .disable_y_mesh()
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(205, 205, 205))
        .draw()
        .map_err(|e| error(&e))?;
    let colour = PALETTE[0];
    chart
        .draw_series(bars.iter().enumerate().map(|(k, bar)| {
            let i = n - 1 - k;
            let mut rectangle = Rectangle::new([(floor, SegmentValue::Exact(i)), (bar.value.max(floor), SegmentValue::Exact(i + 1))], colour.filled());
            rectangle.set_margin(4, 4, 0, 0);
            rectangle
        }))
        .map_err(|e| error(&e))?
        .label("largest difference")
        .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 24, y + 6)], colour.filled()));
    if let Some((label, value)) = bound {
        let line = BLACK.stroke_width(2);
        chart
            .draw_series(DashedLineSeries::new(vec![(value, SegmentValue::Exact(0)), (value, SegmentValue::Last)], 12, 7, line))
            .map_err(|e| error(&e))?
            .label(label)
            .legend(move |(x, y)| DashedPathElement::new(vec![(x, y), (x + 24, y)], 6, 3, line));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .label_font(("sans-serif", 18))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| error(&e))?;
    Ok(())
}
