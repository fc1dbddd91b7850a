//! The Euler-turbine spillage model (`spillage_analytic::spillage_model`) evaluated on a
//! `[cutter_head]` case's own contour, so a sweep of the head compares the simulation with the
//! model on the same geometry.

use anyhow::Context;
use spillage_analytic::spillage_calibration::{calibrate, mean_absolute_error, Calibration, FluxSample};
use spillage_analytic::spillage_model::{
    solve, CutterProfile, ProfilePoint, SpillageInputs, CALIBRATED_FLOW_FACTOR, CALIBRATED_PRESSURE_COEFFICIENT, MIXTURE_DENSITY_TOP, WATER_DENSITY,
};
use spillage_model::case::Case;

/// The model's inputs that come from a head case: its contour, rotor speed and suction.
#[derive(Clone, Debug)]
pub struct HeadModel {
    profile: CutterProfile,
    /// Rotor speed of the case [rev/min] (|ω|: the model needs no direction).
    pub rpm: f64,
    /// Q_m of the case [m³/s].
    pub suction_discharge: f64,
    /// α and β: the thesis' (Tab. 8.1) unless calibrated on simulated fluxes.
    pub flow_factor: f64,
    pub pressure_coefficient: f64,
}

/// The model's answers at one operating point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelAnswer {
    /// Out-flowing flux Q₁ in water (ρ₁ = ρ₂ = 998.2 kg/m³, as the thesis calibrated it,
    /// Tab. 8.1) [m³/s]: the simulation's fluid is water.
    pub outflow_water: f64,
    /// Production fraction P = Q_m/(Q_m + Q₁) with a cutting-side mixture ρ₁ = 1254 kg/m³ and
    /// water ρ₂ = 998.2 kg/m³ (Tab. 8.5), as the model compares with the measured production.
    pub production_mixture: f64,
    /// Spillage fraction S = 1 − P with the same densities.
    pub spillage_mixture: f64,
}

impl HeadModel {
    /// The model of a case with a `[cutter_head]` and a `[rotor]`; `None` for other cases.
    pub fn of_case(case: &Case) -> Option<anyhow::Result<Self>> {
        let head = case.cutter_head.as_ref()?;
        let rotor = case.rotor.as_ref()?;
        Some(profile_of_contour(&head.contour).map(|profile| HeadModel {
            profile,
            rpm: rotor.rpm.unwrap_or_else(|| rotor.angular_velocity() * 60.0 / std::f64::consts::TAU).abs(),
            suction_discharge: head.suction_discharge,
            flow_factor: CALIBRATED_FLOW_FACTOR,
            pressure_coefficient: CALIBRATED_PRESSURE_COEFFICIENT,
        }))
    }

    /// The same head with α and β fitted to simulated out-flowing fluxes by the thesis'
    /// procedure (`spillage_analytic::spillage_calibration`, Tab. 8.1), and the fit.
    pub fn calibrated_on(&self, samples: &[FluxSample]) -> anyhow::Result<(HeadModel, Calibration)> {
        let fit =
            calibrate(&self.profile, WATER_DENSITY, samples).context("calibrating the Euler-turbine model's α and β on the simulated out-flowing flux")?;
        Ok((self.with_coefficients(fit.flow_factor, fit.pressure_coefficient), fit))
    }

    /// The same head with α and β given.
    pub fn with_coefficients(&self, flow_factor: f64, pressure_coefficient: f64) -> HeadModel {
        HeadModel { flow_factor, pressure_coefficient, ..self.clone() }
    }

    /// This model's mean |Q₁ − simulated| over the samples (water) [m³/s].
    pub fn mean_absolute_error(&self, samples: &[FluxSample]) -> anyhow::Result<f64> {
        mean_absolute_error(&self.profile, WATER_DENSITY, self.flow_factor, self.pressure_coefficient, samples)
            .context("the Euler-turbine model on the simulated operating points")
    }

    /// "α 0.375, β 0.774", for legends and tables.
    pub fn coefficients_label(&self) -> String {
        format!("α {}, β {}", trimmed(self.flow_factor), trimmed(self.pressure_coefficient))
    }

    /// The model at `rpm` and `suction_discharge` on this head's contour.
    pub fn answer(&self, rpm: f64, suction_discharge: f64) -> anyhow::Result<ModelAnswer> {
        let mut water = SpillageInputs::calibrated_water(self.profile.clone(), rpm, suction_discharge);
        (water.flow_factor, water.pressure_coefficient) = (self.flow_factor, self.pressure_coefficient);
        let mut mixture = water.clone();
        mixture.density_top = MIXTURE_DENSITY_TOP;
        let context = || format!("the analytic spillage model at {rpm} rpm, Q_m = {suction_discharge} m³/s");
        let in_water = solve(&water).with_context(context)?;
        let in_mixture = solve(&mixture).with_context(context)?;
        Ok(ModelAnswer {
            outflow_water: in_water.outflow_discharge,
            production_mixture: in_mixture.production_fraction,
            spillage_mixture: in_mixture.spillage_fraction,
        })
    }

    /// The model at the case's own operating point.
    pub fn answer_at_case(&self) -> anyhow::Result<ModelAnswer> {
        self.answer(self.rpm, self.suction_discharge)
    }
}

/// Four decimals without trailing zeros (the calibration's grid is 1e-4 in α).
fn trimmed(value: f64) -> String {
    let text = format!("{value:.4}");
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// `cutter_head.contour` rows `[s (m), R (m), φ (deg)]` as the model's profile (φ in radians).
fn profile_of_contour(contour: &[[f64; 3]]) -> anyhow::Result<CutterProfile> {
    let points = contour.iter().map(|&[s, radius, degrees]| ProfilePoint { axial_distance: s, radius, blade_angle: degrees.to_radians() }).collect();
    CutterProfile::new(points).context("cutter_head.contour as the analytic model's profile")
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn the_shipped_head_gives_the_illustrative_lab_head_answers() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/cutter_head.toml");
        let case = Case::from_toml(&std::fs::read_to_string(&path).unwrap(), &path).unwrap();
        let model = HeadModel::of_case(&case).unwrap().unwrap();
        assert_eq!((model.rpm, model.suction_discharge), (60.0, 0.12));
        // The case's contour is the analytic crate's illustrative head, built the same way (30°
        // converted to radians); a relative 1e-12 allows for a different order of operations.
        let direct = solve(&SpillageInputs::calibrated_water(CutterProfile::illustrative_lab_head(), 60.0, 0.12)).unwrap();
        let answer = model.answer_at_case().unwrap();
        assert!((answer.outflow_water - direct.outflow_discharge).abs() < 1e-12 * direct.outflow_discharge);
        // The model's documented number for this head: Q₁ = 0.079 m³/s at 60 rpm (to the 2 digits quoted).
        assert!((answer.outflow_water - 0.079).abs() < 0.0005, "{answer:?}");
        // P + S = 1 by definition; only the subtraction rounds.
        assert!((answer.production_mixture + answer.spillage_mixture - 1.0).abs() < 1e-15);
    }
}
