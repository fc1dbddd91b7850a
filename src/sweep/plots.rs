//! The sweep's figures, drawn when one numeric key is swept: every series column's window mean
//! against the swept value, and for a cutter head swept in rotor speed or suction discharge the
//! simulation against the Euler-turbine model on the same contour.

use std::path::{Path, PathBuf};

use anyhow::Context;
use spillage_model::output::plot::{write_png, Plot, Series};

use super::analytic::{HeadModel, ModelAnswer};
use super::table::PointRow;

/// Points of the analytic curve across the swept range: dense enough to look smooth between
/// the simulated points.
const ANALYTIC_SAMPLES: usize = 201;

/// Draws the figures into `dir`; `xs[i]` is row i's swept value. Only completed points are
/// drawn (a failed run's means describe a different, shorter run). `models`: the head's
/// Euler-turbine model with the thesis' α and β, then any calibrated on these runs (none for
/// a case without a head). Returns the files written.
pub fn draw_sweep_plots(dir: &Path, key: &str, xs: &[f64], rows: &[PointRow], models: &[HeadModel]) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create the plot folder {}", dir.display()))?;
    let mut written = Vec::new();
    for column in series_columns(rows) {
        let mean = format!("{column}_mean");
        let points = simulated(xs, rows, &mean);
        if points.is_empty() {
            continue;
        }
        let path = dir.join(format!("{mean}.png"));
        let title = format!("{column}: mean over the averaging window");
        let plot = Plot { title: &title, x_label: key, y_label: &column, log_x: false, log_y: false, series: vec![Series { label: &mean, points: &points }] };
        write_png(&plot, &path)?;
        written.push(path);
    }
    if let (false, Some(axis)) = (models.is_empty(), OperatingAxis::of_key(key)) {
        written.extend(draw_model_comparison(dir, axis, xs, rows, models)?);
    }
    Ok(written)
}

/// Series column names of the completed rows, in order of first appearance.
fn series_columns(rows: &[PointRow]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for row in rows.iter().filter(|r| r.completed()) {
        for column in &row.series.columns {
            if !names.contains(&column.name) {
                names.push(column.name.clone());
            }
        }
    }
    names
}

/// (swept value, value of `column`) of the completed rows that have it, sorted by the value.
pub(super) fn simulated(xs: &[f64], rows: &[PointRow], column: &str) -> Vec<(f64, f64)> {
    let mut points: Vec<(f64, f64)> = xs.iter().zip(rows).filter(|(_, row)| row.completed()).filter_map(|(&x, row)| Some((x, row.number(column)?))).collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    points
}

/// The swept operating parameter of a head, when the key is one the model takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OperatingAxis {
    RotorSpeed,
    SuctionDischarge,
}

impl OperatingAxis {
    pub fn of_key(key: &str) -> Option<Self> {
        match key {
            "rotor.rpm" => Some(OperatingAxis::RotorSpeed),
            "cutter_head.suction_discharge" => Some(OperatingAxis::SuctionDischarge),
            _ => None,
        }
    }

    fn label(self) -> &'static str {
        match self {
            OperatingAxis::RotorSpeed => "rotor.rpm [rev/min]",
            OperatingAxis::SuctionDischarge => "cutter_head.suction_discharge (Q_m) [m³/s]",
        }
    }

    fn file_suffix(self) -> &'static str {
        match self {
            OperatingAxis::RotorSpeed => "rpm",
            OperatingAxis::SuctionDischarge => "suction_discharge",
        }
    }

    /// (rpm, Q_m) at swept value `x`, the other parameter at the case's value.
    pub(super) fn operating_point(self, model: &HeadModel, x: f64) -> (f64, f64) {
        match self {
            OperatingAxis::RotorSpeed => (x, model.suction_discharge),
            OperatingAxis::SuctionDischarge => (model.rpm, x),
        }
    }

    /// The model at swept value `x`.
    fn answer(self, model: &HeadModel, x: f64) -> anyhow::Result<ModelAnswer> {
        let (rpm, suction_discharge) = self.operating_point(model, x);
        model.answer(rpm, suction_discharge)
    }
}

/// `outflow_vs_<axis>.png` (simulated `hull_outflow_mean` and `contour_outflow_mean`, and each
/// model's Q₁) and `production_vs_<axis>.png` (simulated `production`, `spillage` and each
/// model's P, S), each only when the runs report the simulated columns.
fn draw_model_comparison(dir: &Path, axis: OperatingAxis, xs: &[f64], rows: &[PointRow], models: &[HeadModel]) -> anyhow::Result<Vec<PathBuf>> {
    // the first model has the thesis' pair, the others were fitted to these runs
    let curves = models
        .iter()
        .enumerate()
        .map(|(i, model)| Ok((format!("{}{}", if i == 0 { "thesis' " } else { "fitted " }, model.coefficients_label()), model_curve(axis, xs, model)?)))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let mut written = Vec::new();

    let outflow = simulated(xs, rows, "hull_outflow_mean");
    let contour = simulated(xs, rows, "contour_outflow_mean");
    if !outflow.is_empty() || !contour.is_empty() {
        let analytic: Vec<(String, Vec<(f64, f64)>)> =
            curves.iter().map(|(label, curve)| (format!("model Q₁ (water, {label})"), curve.iter().map(|(x, a)| (*x, a.outflow_water)).collect())).collect();
        let mut series = simulated_series([("simulation (hull_outflow_mean)", &outflow), ("simulation (contour_outflow_mean)", &contour)]);
        series.extend(analytic.iter().map(|(label, points)| Series { label, points }));
        let path = dir.join(format!("outflow_vs_{}.png", axis.file_suffix()));
        let plot = Plot {
            title: "Out-flowing flux: simulation and Euler-turbine model",
            x_label: axis.label(),
            y_label: "out-flowing flux [m³/s]",
            log_x: false,
            log_y: false,
            series,
        };
        write_png(&plot, &path)?;
        written.push(path);
    }

    let (production, spillage) = (simulated(xs, rows, "production"), simulated(xs, rows, "spillage"));
    if !production.is_empty() || !spillage.is_empty() {
        let analytic: Vec<(String, Vec<(f64, f64)>)> = curves
            .iter()
            .flat_map(|(label, curve)| {
                [
                    (format!("model P ({label}; ρ₁ 1254 kg/m³)"), curve.iter().map(|(x, a)| (*x, a.production_mixture)).collect()),
                    (format!("model S ({label}; ρ₁ 1254 kg/m³)"), curve.iter().map(|(x, a)| (*x, a.spillage_mixture)).collect()),
                ]
            })
            .collect();
        let mut series = simulated_series([("simulation: production", &production), ("simulation: spillage", &spillage)]);
        series.extend(analytic.iter().map(|(label, points)| Series { label, points }));
        let path = dir.join(format!("production_vs_{}.png", axis.file_suffix()));
        let plot = Plot {
            title: "Production and spillage: simulation and Euler-turbine model",
            x_label: axis.label(),
            y_label: "fraction",
            log_x: false,
            log_y: false,
            series,
        };
        write_png(&plot, &path)?;
        written.push(path);
    }
    Ok(written)
}

/// The model at [`ANALYTIC_SAMPLES`] evenly spaced values from the smallest to the largest swept
/// value.
fn model_curve(axis: OperatingAxis, xs: &[f64], model: &HeadModel) -> anyhow::Result<Vec<(f64, ModelAnswer)>> {
    let low = xs.iter().copied().fold(f64::INFINITY, f64::min);
    let high = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !(low.is_finite() && high.is_finite()) {
        return Ok(Vec::new()); // no points (or values no case would accept)
    }
    let samples = if high > low { ANALYTIC_SAMPLES } else { 1 };
    (0..samples)
        .map(|i| {
            let x = if samples == 1 { low } else { low + (high - low) * i as f64 / (samples - 1) as f64 };
            axis.answer(model, x).map(|answer| (x, answer))
        })
        .collect()
}

/// The simulated series that have points, in the order given (a column the runs do not
/// write, such as production without rock, is left off the plot).
fn simulated_series<'a>(series: [(&'a str, &'a Vec<(f64, f64)>); 2]) -> Vec<Series<'a>> {
    series.into_iter().filter(|(_, points)| !points.is_empty()).map(|(label, points)| Series { label, points }).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::shipped_head_model as head_model;
    use crate::sweep::table::{ColumnStats, SeriesSummary};

    /// A completed row whose series had the given columns (final = mean = the value).
    fn row(columns: &[(&str, f64)]) -> PointRow {
        let columns = columns.iter().map(|&(name, value)| ColumnStats { name: name.to_string(), final_value: value, mean: value }).collect();
        PointRow {
            values: vec![],
            status: "completed".into(),
            wall_seconds: Some(1.0),
            rule: None,
            series: SeriesSummary { final_time: Some(1.0), window: Some((0.0, 1.0)), columns },
            extras: vec![],
        }
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("spillage-sweep-plots-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    #[test]
    fn a_head_swept_in_rpm_gets_the_model_comparison() {
        let dir = scratch("head");
        let rows: Vec<PointRow> = [30.0, 60.0, 90.0].iter().map(|&rpm| row(&[("hull_outflow", 0.001 * rpm), ("production", 0.6), ("spillage", 0.4)])).collect();
        let written = draw_sweep_plots(&dir, "rotor.rpm", &[30.0, 60.0, 90.0], &rows, &[head_model()]).unwrap();
        let names: Vec<String> = written.iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
        assert_eq!(names, ["hull_outflow_mean.png", "production_mean.png", "spillage_mean.png", "outflow_vs_rpm.png", "production_vs_rpm.png"]);
        assert!(written.iter().all(|p| p.is_file()));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_fitted_model_and_the_contour_flux_join_the_comparison() {
        let dir = scratch("fitted");
        let rows: Vec<PointRow> = [30.0, 60.0].iter().map(|&rpm| row(&[("contour_outflow", 0.001 * rpm)])).collect();
        let models = [head_model(), head_model().with_coefficients(0.5, 0.9)];
        let written = draw_sweep_plots(&dir, "rotor.rpm", &[30.0, 60.0], &rows, &models).unwrap();
        let names: Vec<String> = written.iter().map(|p| p.file_name().unwrap().to_string_lossy().into_owned()).collect();
        assert_eq!(names, ["contour_outflow_mean.png", "outflow_vs_rpm.png"], "the contour's flux alone makes the comparison");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn runs_without_the_head_columns_get_no_comparison() {
        let dir = scratch("no_head_columns");
        let rows = vec![row(&[("kinetic_energy", 1.0)]), row(&[("kinetic_energy", 2.0)])];
        let written = draw_sweep_plots(&dir, "cutter_head.suction_discharge", &[0.1, 0.2], &rows, &[head_model()]).unwrap();
        assert_eq!(written, [dir.join("kinetic_energy_mean.png")]);
        let mut failed = rows.clone();
        failed[0].status = "failed: diverged".into();
        failed[1].status = "failed: diverged".into();
        assert!(draw_sweep_plots(&dir, "rotor.rpm", &[1.0, 2.0], &failed, &[]).unwrap().is_empty(), "failed points are not drawn");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_model_curve_spans_the_swept_range_densely() {
        let curve = model_curve(OperatingAxis::RotorSpeed, &[90.0, 20.0, 45.0], &head_model()).unwrap();
        assert_eq!(curve.len(), ANALYTIC_SAMPLES);
        assert_eq!((curve[0].0, curve[ANALYTIC_SAMPLES - 1].0), (20.0, 90.0));
        // The model pumps more with speed: Q₁ grows from the lowest to the highest rpm.
        assert!(curve[ANALYTIC_SAMPLES - 1].1.outflow_water > curve[0].1.outflow_water);
        assert_eq!(model_curve(OperatingAxis::SuctionDischarge, &[0.12], &head_model()).unwrap().len(), 1);
    }
}
