//! Figures the checks draw with `--plots` / `--report` (issue 20): one PNG per figure, computed
//! values as markers, exact or published curves dashed black, guides dotted grey
//! ([`spillage_model::output::plot::Style`]).

use std::path::Path;

use anyhow::{Context, Result};
use spillage_model::output::plot::{write_png_styled, Plot, Series, Style};

/// One curve of a figure: label, points, style.
pub struct Curve {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
}

impl Curve {
    pub fn computed(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Curve { label: label.into(), points, style: Style::Computed }
    }
    pub fn exact(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Curve { label: label.into(), points, style: Style::Exact }
    }
    pub fn guide(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Curve { label: label.into(), points, style: Style::Guide }
    }
}

/// Axes of a figure: title, x label, y label (with units), log x, log y.
pub struct Axes<'a> {
    pub title: &'a str,
    pub x: &'a str,
    pub y: &'a str,
    pub log_x: bool,
    pub log_y: bool,
}

/// Writes `dir/name.png` (creating `dir`); nothing without a folder. Curves without points
/// are left out.
pub fn draw(dir: Option<&Path>, name: &str, axes: &Axes, curves: &[Curve]) -> Result<()> {
    let Some(dir) = dir else { return Ok(()) };
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let kept: Vec<&Curve> = curves.iter().filter(|c| !c.points.is_empty()).collect();
    let series: Vec<Series> = kept.iter().map(|c| Series { label: &c.label, points: &c.points }).collect();
    let styles: Vec<Style> = kept.iter().map(|c| c.style).collect();
    let plot = Plot { title: axes.title, x_label: axes.x, y_label: axes.y, log_x: axes.log_x, log_y: axes.log_y, series };
    write_png_styled(&plot, &styles, &dir.join(format!("{name}.png")))?;
    Ok(())
}

/// Observed order between the last two points of an error-against-h curve.
pub fn last_order(points: &[(f64, f64)]) -> Option<f64> {
    let [.., (h0, e0), (h1, e1)] = points else { return None };
    Some((e0 / e1).ln() / (h0 / h1).ln())
}

/// A convergence figure: each error against the mesh spacing h on log–log axes, with the
/// observed order of the last refinement in the legend and a slope-2 guide through the finest
/// point of the first curve. Errors that are zero (round-off) cannot be drawn on a log axis and
/// are left out.
pub fn convergence(dir: Option<&Path>, name: &str, title: &str, h_label: &str, error_label: &str, errors: &[(&str, Vec<(f64, f64)>)]) -> Result<()> {
    if dir.is_none() {
        return Ok(());
    }
    let mut curves = Vec::new();
    for (label, points) in errors {
        let points: Vec<(f64, f64)> = points.iter().copied().filter(|(h, e)| *h > 0.0 && *e > 0.0 && e.is_finite()).collect();
        let label = match last_order(&points) {
            Some(p) => format!("{label} (observed order {p:.2})"),
            None => label.to_string(),
        };
        curves.push(Curve::computed(label, points));
    }
    if let Some(first) = curves.first().filter(|c| c.points.len() >= 2) {
        let (h_fine, e_fine) = first.points.iter().copied().fold((f64::INFINITY, 0.0), |a, p| if p.0 < a.0 { p } else { a });
        let h_coarse = first.points.iter().map(|p| p.0).fold(0.0, f64::max);
        let guide: Vec<(f64, f64)> = (0..=10).map(|k| h_fine * (h_coarse / h_fine).powf(k as f64 / 10.0)).map(|h| (h, e_fine * (h / h_fine).powi(2))).collect();
        curves.push(Curve::guide("slope 2 (second order)", guide));
    }
    draw(dir, name, &Axes { title, x: h_label, y: error_label, log_x: true, log_y: true }, &curves)
}
