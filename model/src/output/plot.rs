//! PNG line plots (plotters, bitmap backend, embedded font: no system font libraries).

use std::path::Path;

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

/// Draws `plot` to a PNG file at `path`.
pub fn write_png(plot: &Plot, path: &Path) -> Result<(), std::io::Error> {
    let _ = (plot, path);
    Err(std::io::Error::other("plotting not implemented yet"))
}
