//! Maps of a signed quantity over a plane (the mean in- and outflow over an unrolled contour),
//! drawn like [`super::plot`]'s line plots: embedded font, written to a temporary file and
//! renamed into place. Colours diverge from white at zero: red for positive, blue for negative,
//! on a scale symmetric about zero, with a colour bar.

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

use super::plot::{register_embedded_font, render_png, tick_text};
use super::OutputError;

/// One rectangle of a [`write_heat_map_png`]: its x and y extents and its value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeatCell {
    pub x: (f64, f64),
    pub y: (f64, f64),
    pub value: f64,
}

/// Labels of a heat map: title, axes and the colour bar's quantity (with units).
pub struct HeatMapLabels<'a> {
    pub title: &'a str,
    pub x: &'a str,
    pub y: &'a str,
    pub value: &'a str,
}

/// Draws `cells` coloured by value on a scale from −m to m, m = max |value|. Refuses a map
/// without cells and non-finite values or extents, naming the cell.
pub fn write_heat_map_png(labels: &HeatMapLabels, cells: &[HeatCell], path: &Path) -> Result<(), OutputError> {
    if cells.is_empty() {
        return Err(OutputError::invalid(path, format!("heat map `{}` has no cells", labels.title)));
    }
    for (index, c) in cells.iter().enumerate() {
        for (field, value) in [("value", c.value), ("x", c.x.0), ("x", c.x.1), ("y", c.y.0), ("y", c.y.1)] {
            if !value.is_finite() {
                return Err(OutputError::NonFinite { path: path.to_path_buf(), field: format!("heat map cell {field}"), index, value });
            }
        }
    }
    register_embedded_font().map_err(|e| OutputError::invalid(path, e))?;
    let span = |pick: fn(&HeatCell) -> (f64, f64)| {
        cells.iter().map(pick).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (a, b)| (lo.min(a).min(b), hi.max(a).max(b)))
    };
    let (x, y) = (span(|c| c.x), span(|c| c.y));
    if !(x.1 > x.0 && y.1 > y.0) {
        return Err(OutputError::invalid(path, format!("heat map `{}`: its cells span x {x:?} and y {y:?}, which must not be empty", labels.title)));
    }
    // a map of zeros still gets a scale
    let scale = cells.iter().map(|c| c.value.abs()).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    render_png(path, "the heat map", |root| draw_map(root, labels, cells, x, y, scale))
}

/// White at 0, saturated red at +1 and blue at −1.
fn diverging_colour(t: f64) -> RGBColor {
    let t = t.clamp(-1.0, 1.0);
    let fade = |full: u8| (255.0 - (255.0 - full as f64) * t.abs()).round() as u8;
    if t >= 0.0 {
        RGBColor(fade(178), fade(24), fade(43))
    } else {
        RGBColor(fade(33), fade(102), fade(172))
    }
}

fn draw_map(
    root: &DrawingArea<BitMapBackend, Shift>,
    labels: &HeatMapLabels,
    cells: &[HeatCell],
    x: (f64, f64),
    y: (f64, f64),
    scale: f64,
) -> Result<(), String> {
    let error = |e: &dyn std::fmt::Display| e.to_string();
    root.fill(&WHITE).map_err(|e| error(&e))?;
    let (width, _) = root.dim_in_pixel();
    let (plot_area, bar_area) = root.split_horizontally(width - 170);
    let mut chart = ChartBuilder::on(&plot_area)
        .caption(labels.title, ("sans-serif", 24))
        .margin(20)
        .x_label_area_size(60)
        .y_label_area_size(90)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)
        .map_err(|e| error(&e))?;
    chart
        .configure_mesh()
        .x_desc(labels.x)
        .y_desc(labels.y)
        .axis_desc_style(("sans-serif", 22))
        .label_style(("sans-serif", 17))
        .x_label_formatter(&|v| tick_text(*v, 0.01 * (x.1 - x.0)))
        .y_label_formatter(&|v| tick_text(*v, 0.01 * (y.1 - y.0)))
        .disable_mesh()
        .draw()
        .map_err(|e| error(&e))?;
    chart
        .draw_series(cells.iter().map(|c| Rectangle::new([(c.x.0, c.y.0), (c.x.1, c.y.1)], diverging_colour(c.value / scale).filled())))
        .map_err(|e| error(&e))?;
    // the colour bar: 100 bands from −scale to scale
    let mut bar = ChartBuilder::on(&bar_area)
        .margin_top(60)
        .margin_bottom(80)
        .margin_right(20)
        .y_label_area_size(90)
        .build_cartesian_2d(0.0..1.0, -scale..scale)
        .map_err(|e| error(&e))?;
    bar.configure_mesh()
        .y_desc(labels.value)
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 15))
        .y_label_formatter(&|v| tick_text(*v, 0.01 * scale))
        .disable_x_axis()
        .disable_mesh()
        .draw()
        .map_err(|e| error(&e))?;
    let bands = 100;
    bar.draw_series((0..bands).map(|k| {
        let (a, b) = (-scale + 2.0 * scale * k as f64 / bands as f64, -scale + 2.0 * scale * (k + 1) as f64 / bands as f64);
        Rectangle::new([(0.0, a), (1.0, b)], diverging_colour((a + b) / (2.0 * scale)).filled())
    }))
    .map_err(|e| error(&e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scale_is_white_at_zero_and_saturated_at_the_ends() {
        assert_eq!(diverging_colour(0.0), RGBColor(255, 255, 255));
        assert_eq!(diverging_colour(1.0), RGBColor(178, 24, 43));
        assert_eq!(diverging_colour(-3.0), RGBColor(33, 102, 172));
    }

    /// A map is written; a NaN is refused naming the cell, and no file is left; cells without
    /// extent are refused.
    #[test]
    fn a_map_is_written_and_a_nan_refused() {
        let dir = crate::output::test_dir::fresh("heat_map");
        let labels = HeatMapLabels { title: "t", x: "x", y: "y", value: "v [m/s]" };
        let cells: Vec<HeatCell> = (0..20).map(|k| HeatCell { x: (k as f64, k as f64 + 1.0), y: (0.0, 1.0), value: k as f64 - 10.0 }).collect();
        let path = dir.join("map.png");
        write_heat_map_png(&labels, &cells, &path).unwrap();
        assert!(std::fs::metadata(&path).unwrap().len() > 1000);
        let mut bad = cells.clone();
        bad[7].value = f64::NAN;
        let refused = dir.join("bad.png");
        let e = write_heat_map_png(&labels, &bad, &refused).unwrap_err().to_string();
        assert!(e.contains("bad.png") && e.contains("at index 7"), "{e}");
        assert!(!refused.exists());
        let flat = [HeatCell { x: (0.0, 1.0), y: (2.0, 2.0), value: 1.0 }];
        assert!(write_heat_map_png(&labels, &flat, &dir.join("flat.png")).unwrap_err().to_string().contains("must not be empty"));
    }
}
