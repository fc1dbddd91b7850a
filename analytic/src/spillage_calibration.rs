//! Calibration of the Euler-turbine spillage model's flow factor α and pressure coefficient β
//! on simulated out-flowing fluxes, as the thesis calibrated them on its own head
//! (spillage-and-flow-verification.md §2.10, Tab. 8.1: α and β varied over [0, 1], the best fit
//! minimising the absolute error between the model's and the simulated out-flowing flux, water
//! in both segments).
//!
//! The spec leaves the error norm open (§2.10 ⚠); we take the mean absolute error over the
//! samples. α and β trade off along a long, narrow valley of that error (a larger α with a
//! larger β fits almost as well), so a coarse grid over both lands anywhere along it. The search
//! therefore takes, for every α of a grid over (0, 1) at 0.002, the best β: a grid over [0, 1]
//! at 0.02, then a golden-section search between the best grid point's neighbours to 1e-7;
//! then the same for α within ±0.002 of the best at 1e-4. No gradient method: the error is flat wherever the
//! model gives no outflow at any sample and has kinks where a sample's outflow starts.

use serde::Serialize;

use crate::error::{AnalyticError, Result};
use crate::spillage_model::{rpm_to_omega, solve, CutterProfile, SpillageInputs};

/// One simulated operating point and its out-flowing flux.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FluxSample {
    /// Rotor speed [rev/min].
    pub rpm: f64,
    /// Suction discharge Q_m [m³/s].
    pub suction_discharge: f64,
    /// Simulated out-flowing flux [m³/s].
    pub outflow: f64,
}

/// The best (α, β) and its error.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Calibration {
    /// α in (0, 1).
    pub flow_factor: f64,
    /// β in [0, 1].
    pub pressure_coefficient: f64,
    /// Mean |Q₁(model) − Q_out(simulated)| over the samples [m³/s].
    pub mean_absolute_error: f64,
}

/// α's grid: the whole range at 0.002, then ±0.002 around the best at 0.0001. α must stay inside
/// (0, 1): α = 1 makes the model singular (Eq. 4.78).
pub const FLOW_FACTOR_STEPS: [f64; 2] = [2e-3, 1e-4];
/// β's grid before its golden-section search, and that search's tolerance.
pub const PRESSURE_COEFFICIENT_STEP: f64 = 0.02;
const PRESSURE_COEFFICIENT_TOLERANCE: f64 = 1e-7;

/// The mean absolute error of the model with (α, β) on `profile` (water, ρ₁ = ρ₂ = `density`)
/// against the samples.
pub fn mean_absolute_error(profile: &CutterProfile, density: f64, flow_factor: f64, pressure_coefficient: f64, samples: &[FluxSample]) -> Result<f64> {
    validate(samples, 1)?;
    let mut inputs = water_inputs(profile, density, samples);
    error_of(&mut inputs, samples, flow_factor, pressure_coefficient)
}

/// The (α, β) of least mean absolute error (Tab. 8.1's procedure); of equal errors the smaller
/// α, then the smaller β. Needs at least two samples with finite, non-negative values.
pub fn calibrate(profile: &CutterProfile, density: f64, samples: &[FluxSample]) -> Result<Calibration> {
    validate(samples, 2)?;
    let mut inputs = water_inputs(profile, density, samples);
    let mut best_at = |alpha: f64| best_pressure_coefficient(&mut inputs, samples, alpha);
    let coarse = FLOW_FACTOR_STEPS[0];
    let mut best = best_at(coarse)?;
    for i in 2..(1.0 / coarse).round() as usize {
        best = better(best, best_at(i as f64 * coarse)?);
    }
    let (fine, centre) = (FLOW_FACTOR_STEPS[1], best.flow_factor);
    let reach = (coarse / fine).round() as i32;
    for i in -reach..=reach {
        let alpha = centre + i as f64 * fine;
        if i != 0 && alpha > 0.0 && alpha < 1.0 {
            best = better(best, best_at(alpha)?);
        }
    }
    Ok(best)
}

/// The smaller error; of equal errors the smaller α, then the smaller β.
fn better(a: Calibration, b: Calibration) -> Calibration {
    let key = |c: &Calibration| (c.mean_absolute_error, c.flow_factor, c.pressure_coefficient);
    if key(&b).partial_cmp(&key(&a)) == Some(std::cmp::Ordering::Less) {
        b
    } else {
        a
    }
}

/// At least `minimum` samples, each with a non-negative speed, discharge and flux, named by
/// its place in the list when not.
fn validate(samples: &[FluxSample], minimum: usize) -> Result<()> {
    if samples.len() < minimum {
        return Err(AnalyticError::Invalid { what: "calibration samples", reason: format!("need at least {minimum} operating points, got {}", samples.len()) });
    }
    for (i, sample) in samples.iter().enumerate() {
        for (name, value) in [("rpm", sample.rpm), ("suction_discharge", sample.suction_discharge), ("outflow", sample.outflow)] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(AnalyticError::Invalid { what: "calibration samples", reason: format!("sample {i}: {name} = {value}, must be finite and >= 0") });
            }
        }
    }
    Ok(())
}

/// One model input per sample, built once (the search then sets α and β in place).
fn water_inputs(profile: &CutterProfile, density: f64, samples: &[FluxSample]) -> Vec<SpillageInputs> {
    samples
        .iter()
        .map(|sample| SpillageInputs {
            profile: profile.clone(),
            omega: rpm_to_omega(sample.rpm),
            suction_discharge: sample.suction_discharge,
            flow_factor: 0.5,
            pressure_coefficient: 0.5,
            density_top: density,
            density_bottom: density,
        })
        .collect()
}

fn error_of(inputs: &mut [SpillageInputs], samples: &[FluxSample], flow_factor: f64, pressure_coefficient: f64) -> Result<f64> {
    let mut sum = 0.0;
    for (input, sample) in inputs.iter_mut().zip(samples) {
        (input.flow_factor, input.pressure_coefficient) = (flow_factor, pressure_coefficient);
        sum += (solve(input)?.outflow_discharge - sample.outflow).abs();
    }
    Ok(sum / samples.len() as f64)
}

/// The best β at a given α: the grid's best point, then golden-section search between its
/// neighbours.
fn best_pressure_coefficient(inputs: &mut [SpillageInputs], samples: &[FluxSample], alpha: f64) -> Result<Calibration> {
    let mut error = |beta: f64| error_of(inputs, samples, alpha, beta);
    let at = |beta: f64, e: f64| Calibration { flow_factor: alpha, pressure_coefficient: beta, mean_absolute_error: e };
    let n = (1.0 / PRESSURE_COEFFICIENT_STEP).round() as usize;
    let mut best = at(0.0, error(0.0)?);
    for j in 1..=n {
        let beta = j as f64 * PRESSURE_COEFFICIENT_STEP;
        best = better(best, at(beta, error(beta)?));
    }
    let (mut low, mut high) =
        ((best.pressure_coefficient - PRESSURE_COEFFICIENT_STEP).max(0.0), (best.pressure_coefficient + PRESSURE_COEFFICIENT_STEP).min(1.0));
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (high - ratio * (high - low), low + ratio * (high - low));
    let (mut ea, mut eb) = (error(a)?, error(b)?);
    while high - low > PRESSURE_COEFFICIENT_TOLERANCE {
        if ea <= eb {
            (high, b, eb) = (b, a, ea);
            a = high - ratio * (high - low);
            ea = error(a)?;
        } else {
            (low, a, ea) = (a, b, eb);
            b = low + ratio * (high - low);
            eb = error(b)?;
        }
    }
    Ok(better(better(best, at(a, ea)), at(b, eb)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spillage_model::{CALIBRATED_FLOW_FACTOR, CALIBRATED_PRESSURE_COEFFICIENT, WATER_DENSITY};

    fn model_samples(alpha: f64, beta: f64, rpms: &[f64], qm: f64) -> Vec<FluxSample> {
        let profile = CutterProfile::illustrative_lab_head();
        rpms.iter()
            .map(|&rpm| {
                let inputs = SpillageInputs {
                    profile: profile.clone(),
                    omega: rpm_to_omega(rpm),
                    suction_discharge: qm,
                    flow_factor: alpha,
                    pressure_coefficient: beta,
                    density_top: WATER_DENSITY,
                    density_bottom: WATER_DENSITY,
                };
                FluxSample { rpm, suction_discharge: qm, outflow: solve(&inputs).unwrap().outflow_discharge }
            })
            .collect()
    }

    #[test]
    fn fluxes_made_by_the_model_give_back_its_coefficients() {
        // the thesis' own pair and one far from it, each on the thesis' calibration set (Tab. 8.2:
        // 20–90 rpm at 0.12 m³/s)
        let rpms = [20.0, 30.0, 45.0, 60.0, 75.0, 90.0];
        for (alpha, beta) in [(CALIBRATED_FLOW_FACTOR, CALIBRATED_PRESSURE_COEFFICIENT), (0.61, 0.42)] {
            let samples = model_samples(alpha, beta, &rpms, 0.12);
            assert!(samples.iter().filter(|s| s.outflow > 0.0).count() >= 3, "the set must carry outflow: {samples:?}");
            let fit = calibrate(&CutterProfile::illustrative_lab_head(), WATER_DENSITY, &samples).unwrap();
            // α lies on the fine 1e-4 grid and β is searched to 1e-7: the pair comes back to those
            // resolutions, and its fluxes to within the error a 1e-7 shift of β makes
            assert!((fit.flow_factor - alpha).abs() < 1e-9 && (fit.pressure_coefficient - beta).abs() < 1e-6, "({alpha}, {beta}): {fit:?}");
            assert!(fit.mean_absolute_error < 1e-7, "{fit:?}");
        }
    }

    #[test]
    fn the_answer_is_no_worse_than_a_dense_grid_around_it() {
        // fluxes no (α, β) reproduces: falling and rising again with rpm, where the model's
        // outflow only rises (a scaled and offset model curve is fitted to 2e-7 m³/s by some
        // pair), so the least error is at least the fall's 0.02 m³/s over 5 points
        let samples: Vec<FluxSample> = [(30.0, 0.05), (45.0, 0.03), (60.0, 0.07), (75.0, 0.12), (90.0, 0.11)]
            .map(|(rpm, outflow)| FluxSample { rpm, suction_discharge: 0.12, outflow })
            .to_vec();
        let profile = CutterProfile::illustrative_lab_head();
        let fit = calibrate(&profile, WATER_DENSITY, &samples).unwrap();
        assert!(fit.mean_absolute_error >= 0.02 / 5.0 - 1e-12, "not an exact fit: {fit:?}");
        // a brute-force grid of 41 × 41 points at a quarter of the search's α step, ±0.0005
        // around the answer, finds nothing better than what the search's resolution leaves: α
        // is resolved to 1e-4, so between its grid points the error may dip by up to its change
        // over one step
        let one_step = [-1e-4, 1e-4]
            .map(|d| {
                (mean_absolute_error(&profile, WATER_DENSITY, fit.flow_factor + d, fit.pressure_coefficient, &samples).unwrap() - fit.mean_absolute_error).abs()
            })
            .into_iter()
            .fold(0.0, f64::max);
        for i in -20..=20 {
            for j in -20..=20 {
                let (alpha, beta) = (fit.flow_factor + i as f64 * 2.5e-5, fit.pressure_coefficient + j as f64 * 2.5e-5);
                if alpha > 0.0 && alpha < 1.0 && (0.0..=1.0).contains(&beta) {
                    let e = mean_absolute_error(&profile, WATER_DENSITY, alpha, beta, &samples).unwrap();
                    assert!(e >= fit.mean_absolute_error - one_step, "({alpha}, {beta}): {e} beats {fit:?} by more than {one_step}");
                }
            }
        }
        // and it beats the thesis' pair on these fluxes
        let thesis = mean_absolute_error(&profile, WATER_DENSITY, CALIBRATED_FLOW_FACTOR, CALIBRATED_PRESSURE_COEFFICIENT, &samples).unwrap();
        assert!(fit.mean_absolute_error < thesis, "{fit:?} vs {thesis}");
    }

    #[test]
    fn too_few_or_bad_samples_are_refused_by_name() {
        let profile = CutterProfile::illustrative_lab_head();
        let one = [FluxSample { rpm: 60.0, suction_discharge: 0.12, outflow: 0.06 }];
        let message = calibrate(&profile, WATER_DENSITY, &one).unwrap_err().to_string();
        assert!(message.contains("at least 2") && message.contains("got 1"), "{message}");
        let bad = [one[0], FluxSample { outflow: f64::NAN, ..one[0] }];
        let message = calibrate(&profile, WATER_DENSITY, &bad).unwrap_err().to_string();
        assert!(message.contains("sample 1: outflow = NaN"), "{message}");
        let negative = [one[0], FluxSample { rpm: -20.0, ..one[0] }];
        assert!(calibrate(&profile, WATER_DENSITY, &negative).unwrap_err().to_string().contains("sample 1: rpm = -20"));
        // the error alone needs one sample, and refuses bad ones the same way
        assert!(mean_absolute_error(&profile, WATER_DENSITY, 0.375, 0.774, &[]).unwrap_err().to_string().contains("at least 1"));
        assert!(mean_absolute_error(&profile, WATER_DENSITY, 0.375, 0.774, &bad).unwrap_err().to_string().contains("sample 1: outflow = NaN"));
    }

    #[test]
    fn of_equal_errors_the_smallest_pair_is_taken() {
        // no outflow anywhere: every pair whose model gives none at these points fits exactly,
        // the smallest α of the search's grids and β = 0 is the answer
        let samples = [20.0, 30.0].map(|rpm| FluxSample { rpm, suction_discharge: 0.12, outflow: 0.0 });
        let fit = calibrate(&CutterProfile::illustrative_lab_head(), WATER_DENSITY, &samples).unwrap();
        assert_eq!(fit.mean_absolute_error, 0.0);
        assert!((fit.flow_factor - 1e-4).abs() < 1e-12 && fit.pressure_coefficient == 0.0, "{fit:?}");
    }
}
