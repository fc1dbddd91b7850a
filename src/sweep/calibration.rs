//! The Euler-turbine model calibrated on the sweep's own runs, as the thesis calibrated it on
//! its head (spillage-and-flow-verification.md §2.10, Tab. 8.1): α and β fitted to the
//! simulated out-flowing flux of the completed points, so a user sees the thesis' pair and
//! the pair that fits their head side by side, in `sweep.md` and the comparison plots.

use spillage_analytic::spillage_calibration::{Calibration, FluxSample, FLOW_FACTOR_STEPS, PRESSURE_COEFFICIENT_STEP};

use super::analytic::HeadModel;
use super::plots::{simulated, OperatingAxis};
use super::table::{markdown_number, PointRow};

/// The simulated flux the fit uses, in order of preference: the thesis' own measure (Eqs.
/// 8.1–8.4 on the contour), else the flux through the cells' hull.
const FITTED_COLUMNS: [&str; 2] = ["contour_outflow_mean", "hull_outflow_mean"];

/// A fit and what it was fitted to.
pub struct ModelCalibration {
    /// The head's model with the fitted α and β.
    pub model: HeadModel,
    pub fit: Calibration,
    /// The model with the thesis' pair, and its mean |error| on the same points [m³/s].
    thesis: HeadModel,
    thesis_error: f64,
    /// The series column fitted.
    pub column: &'static str,
    /// (swept value, sample) per fitted point.
    samples: Vec<(f64, FluxSample)>,
}

/// The fit on the completed rows; `None` when fewer than two points have a flux column.
pub fn calibrate_on_rows(axis: OperatingAxis, xs: &[f64], rows: &[PointRow], thesis: &HeadModel) -> Option<anyhow::Result<ModelCalibration>> {
    let (column, points) = FITTED_COLUMNS.iter().map(|&c| (c, simulated(xs, rows, c))).find(|(_, points)| points.len() >= 2)?;
    let samples: Vec<(f64, FluxSample)> = points
        .iter()
        .map(|&(x, outflow)| {
            let (rpm, suction_discharge) = axis.operating_point(thesis, x);
            (x, FluxSample { rpm, suction_discharge, outflow })
        })
        .collect();
    let fluxes: Vec<FluxSample> = samples.iter().map(|(_, s)| *s).collect();
    Some(thesis.calibrated_on(&fluxes).and_then(|(model, fit)| {
        let thesis_error = thesis.mean_absolute_error(&fluxes)?;
        Ok(ModelCalibration { model, fit, thesis: thesis.clone(), thesis_error, column, samples })
    }))
}

impl ModelCalibration {
    /// One line for the terminal.
    pub fn summary(&self) -> String {
        let [fitted, fitted_error, thesis, thesis_error] = self.labels();
        format!(
            "Euler-turbine model fitted to {} of {} points (Tab. 8.1): {fitted}, mean |error| {fitted_error} m³/s (the thesis' {thesis}: {thesis_error} m³/s){}",
            self.column,
            self.samples.len(),
            self.caveat().map_or_else(String::new, |c| format!("; {c}"))
        )
    }

    /// The fitted pair, its error, the thesis' pair and its error, as printed.
    fn labels(&self) -> [String; 4] {
        [self.model.coefficients_label(), markdown_number(self.fit.mean_absolute_error), self.thesis.coefficients_label(), markdown_number(self.thesis_error)]
    }

    /// Why the pair may not mean much: it sits on the edge of the allowed range, within one of
    /// the search's coarse grid steps of an end (the best lies beyond it), or no pair fits
    /// better than another (no outflow to fit).
    fn caveat(&self) -> Option<String> {
        let (alpha, beta) = (self.fit.flow_factor, self.fit.pressure_coefficient);
        let (alpha_step, beta_step) = (FLOW_FACTOR_STEPS[0], PRESSURE_COEFFICIENT_STEP);
        if self.samples.iter().all(|(_, s)| s.outflow == 0.0) {
            Some("no point has outflow, so every pair giving none fits as well".into())
        } else if beta < beta_step || beta > 1.0 - beta_step || !(alpha_step..=1.0 - alpha_step).contains(&alpha) {
            Some("the pair sits on the edge of the allowed range (α in (0, 1), β in [0, 1]): the least error lies beyond it".into())
        } else {
            None
        }
    }

    /// The section appended to `sweep.md`: the fit, and per point the simulated flux beside
    /// both models'.
    pub fn markdown_section(&self, key: &str) -> anyhow::Result<String> {
        let [fitted, fitted_error, thesis, thesis_error] = self.labels();
        let mut text = String::from("\n## The Euler-turbine model fitted to these runs\n\n");
        text.push_str(&format!(
            "α and β fitted as the thesis fitted them to its head (spillage-and-flow-verification.md §2.10, Tab. 8.1: α over (0, 1), β over [0, 1], \
             the least mean absolute error; water in both segments) to `{}` of the {} points that have it: **{fitted}**, mean |error| {fitted_error} m³/s. \
             The thesis' {thesis} gives {thesis_error} m³/s on the same points. α and β trade off along a narrow valley of the error, so nearby pairs fit \
             almost as well; the fit describes this head's flux, not its physics.{}\n\n",
            self.column,
            self.samples.len(),
            self.caveat().map_or_else(String::new, |c| format!(" Note: {c}."))
        ));
        text.push_str(&format!("| {key} | simulated [m³/s] | thesis' model, {thesis} [m³/s] | fitted model, {fitted} [m³/s] |\n|---|---|---|---|\n"));
        for (x, sample) in &self.samples {
            let by_thesis = self.thesis.answer(sample.rpm, sample.suction_discharge)?.outflow_water;
            let by_fit = self.model.answer(sample.rpm, sample.suction_discharge)?.outflow_water;
            text.push_str(&format!(
                "| {} | {} | {} | {} |\n",
                markdown_number(*x),
                markdown_number(sample.outflow),
                markdown_number(by_thesis),
                markdown_number(by_fit)
            ));
        }
        Ok(text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::shipped_head_model as thesis_model;
    use crate::sweep::table::{ColumnStats, SeriesSummary};

    fn row(columns: &[(&str, f64)], status: &str) -> PointRow {
        let columns = columns.iter().map(|&(name, value)| ColumnStats { name: name.to_string(), final_value: value, mean: value }).collect();
        PointRow {
            values: vec![],
            status: status.into(),
            wall_seconds: Some(1.0),
            rule: None,
            series: SeriesSummary { final_time: Some(1.0), window: Some((0.0, 1.0)), columns },
            extras: vec![],
        }
    }

    #[test]
    fn runs_that_pump_like_the_model_give_back_its_pair_and_the_table_shows_both() {
        let thesis = thesis_model();
        let rpms = [30.0, 45.0, 60.0, 90.0];
        // the contour's flux as a model with (0.5, 0.9) would give it; the cells' hull differs
        let pumping = thesis.with_coefficients(0.5, 0.9);
        let mut rows: Vec<PointRow> =
            rpms.iter().map(|&rpm| row(&[("contour_outflow", pumping.answer(rpm, 0.12).unwrap().outflow_water), ("hull_outflow", 1.0)], "completed")).collect();
        rows.push(row(&[("contour_outflow", 5.0)], "failed: diverged"));
        let xs = [30.0, 45.0, 60.0, 90.0, 75.0];
        let calibration = calibrate_on_rows(OperatingAxis::RotorSpeed, &xs, &rows, &thesis).unwrap().unwrap();
        assert_eq!(calibration.column, "contour_outflow_mean");
        assert_eq!(calibration.samples.len(), 4, "the failed point is not fitted");
        // α on the fit's 1e-4 grid, β searched to 1e-7
        assert!((calibration.model.flow_factor - 0.5).abs() < 1e-9 && (calibration.model.pressure_coefficient - 0.9).abs() < 1e-6, "{:?}", calibration.fit);
        assert!(calibration.thesis_error > 1e-3 && calibration.fit.mean_absolute_error < 1e-7);
        let section = calibration.markdown_section("rotor.rpm").unwrap();
        assert!(
            section.contains("**α 0.5, β 0.9**")
                && section.contains("| rotor.rpm | simulated [m³/s] | thesis' model, α 0.375, β 0.774 [m³/s] | fitted model, α 0.5, β 0.9 [m³/s] |"),
            "{section}"
        );
        assert_eq!(section.lines().filter(|l| l.starts_with("| ") && !l.starts_with("| rotor")).count(), 4);
        assert!(calibration.summary().contains("contour_outflow_mean of 4 points") && !section.contains("Note:"));
    }

    #[test]
    fn a_pair_on_the_range_edge_or_a_flat_error_is_flagged() {
        let thesis = thesis_model();
        let edge = thesis.with_coefficients(0.3, 0.0);
        let rows: Vec<PointRow> =
            [60.0, 90.0].iter().map(|&rpm| row(&[("contour_outflow", edge.answer(rpm, 0.12).unwrap().outflow_water)], "completed")).collect();
        let calibration = calibrate_on_rows(OperatingAxis::RotorSpeed, &[60.0, 90.0], &rows, &thesis).unwrap().unwrap();
        assert!(calibration.summary().contains("edge of the allowed range"), "{}", calibration.summary());
        assert!(calibration.markdown_section("rotor.rpm").unwrap().contains("Note: the pair sits on the edge"));
        let still: Vec<PointRow> = [20.0, 30.0].iter().map(|_| row(&[("contour_outflow", 0.0)], "completed")).collect();
        let calibration = calibrate_on_rows(OperatingAxis::RotorSpeed, &[20.0, 30.0], &still, &thesis).unwrap().unwrap();
        assert!(calibration.summary().contains("no point has outflow"), "{}", calibration.summary());
    }

    #[test]
    fn without_two_fluxes_there_is_no_fit() {
        let thesis = thesis_model();
        let rows = vec![row(&[("hull_outflow", 0.05)], "completed"), row(&[("kinetic_energy", 1.0)], "completed")];
        assert!(calibrate_on_rows(OperatingAxis::RotorSpeed, &[30.0, 60.0], &rows, &thesis).is_none());
    }
}
