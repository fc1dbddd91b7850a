//! Hindered settling of a uniform suspension: Richardson–Zaki, Di Felice, and the cloud settling
//! velocities of case P3.
//!
//! fluid-dem-model.md §5.6 (thesis Eqs. 3.47–3.62) and particle-verification.md §1.2 and §4
//! (case P3, Table 6.3 and its reconstructions (A) and (B)).
//!
//! The Di Felice exponent is called `di_felice_exponent` here to keep it apart from the
//! analytical-model β and the Legendre β (spillage-and-flow-verification.md §9 item 22).

use serde::{Deserialize, Serialize};

use crate::drag_laws::DragLaw;
use crate::error::{in_closed, in_open, non_negative, positive, Result};
use crate::roots::{brent, expand_upper};
use crate::settling::SettlingSphere;

/// Rowe (1987) fit of the Richardson–Zaki exponent,
/// n = (4.7 + 0.41 Re^0.75)/(1 + 0.175 Re^0.75) (Eq. 3.48). Limits 4.7 and 0.41/0.175.
pub fn rowe_exponent(reynolds: f64) -> Result<f64> {
    non_negative("reynolds", reynolds)?;
    let x = reynolds.powf(0.75);
    Ok((4.7 + 0.41 * x) / (1.0 + 0.175 * x))
}

/// The original Richardson & Zaki (1954) piecewise exponent with the wall term d/D, the source of
/// the "4.65 at low Re to 2.39 at high Re" quoted in fluid-dem-model.md §5.6(a). The coefficients
/// are the published 1954 table (literature, not printed in the spec):
/// 4.65 + 19.5 d/D (Re < 0.2); (4.35 + 17.5 d/D) Re^−0.03 (0.2–1); (4.45 + 18 d/D) Re^−0.1 (1–200);
/// 4.45 Re^−0.1 (200–500); 2.39 (Re > 500).
pub fn richardson_zaki_exponent(reynolds: f64, diameter_ratio: f64) -> Result<f64> {
    non_negative("reynolds", reynolds)?;
    in_closed("diameter_ratio", diameter_ratio, 0.0, 1.0, "d/D in [0, 1]")?;
    let k = diameter_ratio;
    Ok(if reynolds < 0.2 {
        4.65 + 19.5 * k
    } else if reynolds < 1.0 {
        (4.35 + 17.5 * k) * reynolds.powf(-0.03)
    } else if reynolds < 200.0 {
        (4.45 + 18.0 * k) * reynolds.powf(-0.1)
    } else if reynolds < 500.0 {
        4.45 * reynolds.powf(-0.1)
    } else {
        2.39
    })
}

/// Richardson–Zaki hindered terminal velocity u = 10^(−d/D) (1 − α_p)^n u_t0 (Eq. 3.47).
pub fn richardson_zaki_velocity(single_particle_velocity: f64, particle_fraction: f64, exponent: f64, diameter_ratio: f64) -> Result<f64> {
    non_negative("single_particle_velocity", single_particle_velocity)?;
    in_closed("particle_fraction", particle_fraction, 0.0, 1.0, "in [0, 1)")?;
    positive("exponent", exponent)?;
    in_closed("diameter_ratio", diameter_ratio, 0.0, 1.0, "d/D in [0, 1]")?;
    Ok(10f64.powf(-diameter_ratio) * (1.0 - particle_fraction).powf(exponent) * single_particle_velocity)
}

/// Di Felice (1994) exponent β = 3.7 − 0.65 exp(−(1.5 − log₁₀ Re_p)²/2) (Eq. 3.58).
pub fn di_felice_exponent(particle_reynolds: f64) -> Result<f64> {
    positive("particle_reynolds", particle_reynolds)?;
    Ok(3.7 - 0.65 * (-(1.5 - particle_reynolds.log10()).powi(2) / 2.0).exp())
}

/// Which Di Felice drag factor multiplies the single-particle drag F_d,0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum DiFeliceForm {
    /// α_c^(1−β): the form the thesis codes, because its pressure is the fluid pressure
    /// (Eq. 3.62, from 3.57 and 3.61).
    FluidPressure,
    /// α_c^(2−β): Di Felice's slip-velocity form balancing the mixture pressure (Eq. 3.57).
    MixturePressure,
}

/// Di Felice drag factor F_d/F_d,0 at fluid fraction α_c and particle Reynolds number Re_p
/// (Eqs. 3.56–3.62).
pub fn di_felice_drag_factor(fluid_fraction: f64, particle_reynolds: f64, form: DiFeliceForm) -> Result<f64> {
    in_closed("fluid_fraction", fluid_fraction, f64::MIN_POSITIVE, 1.0, "in (0, 1]")?;
    let beta = di_felice_exponent(particle_reynolds)?;
    Ok(match form {
        DiFeliceForm::FluidPressure => fluid_fraction.powf(1.0 - beta),
        DiFeliceForm::MixturePressure => fluid_fraction.powf(2.0 - beta),
    })
}

/// How the steady cloud velocity of Table 6.3 is reconstructed (particle-verification.md §4 [R]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum CloudReconstruction {
    /// (A) thesis-consistent: ½C_d(Re_s)A ρ u_s² α_c^(1−β(Re_p)) = V(ρ_p−ρ_f)g with
    /// Re_s = u_s d/ν, Re_p = α_c Re_s (Eq. 3.55), then u_p = α_c u_s (Eq. 3.53). Within 0.3 %.
    SlipVelocity,
    /// (B) empirical best fit: ½C_d(Re)A ρ u² α_c^(−1−β(Re)) = V(ρ_p−ρ_f)g with u = u_p.
    ParticleVelocity,
}

/// Steady hindered settling state of a uniform batch-settling suspension.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct HinderedSettling {
    pub particle_fraction: f64,
    /// Particle settling velocity u_p [m/s].
    pub particle_velocity: f64,
    /// Slip velocity u_s = u_c − u_p magnitude [m/s].
    pub slip_velocity: f64,
    /// Di Felice exponent at the solution.
    pub di_felice_exponent: f64,
}

/// Steady settling velocity of a uniform suspension with particle fraction `particle_fraction`
/// (particle-verification.md §4, §8 check 8). Uses Brown–Lawler drag as the thesis does.
pub fn cloud_settling_velocity(sphere: &SettlingSphere, particle_fraction: f64, reconstruction: CloudReconstruction) -> Result<HinderedSettling> {
    in_open("particle_fraction", particle_fraction, -f64::MIN_POSITIVE, 1.0, "in [0, 1)")?;
    let alpha_c = 1.0 - particle_fraction;
    let weight = sphere.submerged_weight();
    let drag0 = |u: f64| sphere.drag_force(DragLaw::BrownLawler, u);
    let d_over_nu = sphere.diameter / sphere.kinematic_viscosity;
    // Residual in the unknown u (slip speed for (A), particle speed for (B)).
    let residual = |u: f64| -> f64 {
        let value = match reconstruction {
            CloudReconstruction::SlipVelocity => {
                let re_p = alpha_c * u * d_over_nu;
                di_felice_exponent(re_p).and_then(|beta| Ok(drag0(u)? * alpha_c.powf(1.0 - beta)))
            }
            CloudReconstruction::ParticleVelocity => {
                let re = u * d_over_nu;
                di_felice_exponent(re).and_then(|beta| Ok(drag0(u)? * alpha_c.powf(-1.0 - beta)))
            }
        };
        value.map_or(f64::NAN, |drag| weight - drag)
    };
    let guess = sphere.terminal_velocity(DragLaw::BrownLawler)?.velocity;
    let lower = guess * 1e-9;
    let (lo, hi) = expand_upper("hindered settling force balance", residual, lower, guess, 1.5, 100)?;
    let u = brent("hindered settling force balance", residual, lo, hi, 1e-15 * hi)?;
    let (particle_velocity, slip_velocity, re_p) = match reconstruction {
        CloudReconstruction::SlipVelocity => (alpha_c * u, u, alpha_c * u * d_over_nu),
        CloudReconstruction::ParticleVelocity => (u, u / alpha_c, u * d_over_nu),
    };
    Ok(HinderedSettling { particle_fraction, particle_velocity, slip_velocity, di_felice_exponent: di_felice_exponent(re_p)? })
}

/// Batch-settling volume balance (Eqs. 3.49–3.53): fluid velocity u_c = −(1−α_c)/α_c u_p and
/// slip u_s = u_c − u_p = −u_p/α_c, for particle velocity `particle_velocity`.
pub fn batch_settling_fluid_and_slip(particle_velocity: f64, fluid_fraction: f64) -> Result<(f64, f64)> {
    in_closed("fluid_fraction", fluid_fraction, f64::MIN_POSITIVE, 1.0, "in (0, 1]")?;
    let u_c = -(1.0 - fluid_fraction) / fluid_fraction * particle_velocity;
    Ok((u_c, u_c - particle_velocity))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rowe_exponent_matches_spec() {
        // particle-verification.md §8 check 5 and fluid-dem-model.md U-05.
        assert_eq!(rowe_exponent(0.0).unwrap(), 4.7);
        let cases = [(1.0, 4.348936), (10.0, 3.53087), (100.0, 2.703608), (1000.0, 2.41624), (7332.78, 2.359733)];
        for (re, n) in cases {
            assert!((rowe_exponent(re).unwrap() - n).abs() < 6e-6, "Re={re}");
        }
        assert!((rowe_exponent(1e30).unwrap() - 0.41 / 0.175).abs() < 1e-6);
    }

    #[test]
    fn richardson_zaki_table_limits() {
        // fluid-dem-model.md §5.6(a): "n ≈ 4.65 at low Re and 2.39 at high Re".
        assert_eq!(richardson_zaki_exponent(0.1, 0.0).unwrap(), 4.65);
        assert_eq!(richardson_zaki_exponent(7000.0, 0.0).unwrap(), 2.39);
        // Wall term of the 1954 table.
        assert!((richardson_zaki_exponent(0.1, 0.01).unwrap() - 4.845).abs() < 1e-12);
        // U-36: α_c = 0.9, n = 2.4 → factor 0.7766; wall factor 10^(−d/D).
        let f = richardson_zaki_velocity(1.0, 0.1, 2.4, 0.0).unwrap();
        assert!((f - 0.7766).abs() < 5e-5);
        assert!((richardson_zaki_velocity(1.0, 0.0, 2.4, 0.01).unwrap() - 0.977237).abs() < 1e-6);
    }

    #[test]
    fn richardson_zaki_velocities_match_spec() {
        // particle-verification.md §8 check 7: u_t0 = 0.73577, n = 2.359733.
        let expected = [(0.027, 0.6898), (0.05, 0.6519), (0.1, 0.5738), (0.208, 0.4244), (0.308, 0.3086)];
        for (phi, u) in expected {
            let got = richardson_zaki_velocity(0.73577, phi, 2.359733, 0.0).unwrap();
            assert!((got - u).abs() < 1e-4, "phi={phi}: {got}");
        }
    }

    #[test]
    fn di_felice_exponent_matches_spec() {
        // particle-verification.md §8 check 6 and fluid-dem-model.md U-04.
        assert!((di_felice_exponent(10f64.powf(1.5)).unwrap() - 3.05).abs() < 1e-12);
        for (re, beta) in [(1.0, 3.488976), (1000.0, 3.488976), (10.0, 3.126377), (100.0, 3.126377), (7332.78, 3.660365), (7000.0, 3.65844)] {
            assert!((di_felice_exponent(re).unwrap() - beta).abs() < 6e-6, "Re={re}");
        }
        // U-06: the factor is 1 without particles; the two forms differ by α_c (Eq. 3.61).
        assert_eq!(di_felice_drag_factor(1.0, 50.0, DiFeliceForm::FluidPressure).unwrap(), 1.0);
        let fluid = di_felice_drag_factor(0.8, 50.0, DiFeliceForm::FluidPressure).unwrap();
        let mixture = di_felice_drag_factor(0.8, 50.0, DiFeliceForm::MixturePressure).unwrap();
        assert!((mixture / fluid - 0.8).abs() < 1e-14);
    }

    #[test]
    #[allow(clippy::approx_constant)] // 0.4342 is a table value, not log10(e)
    fn cloud_velocities_reproduce_table_6_3() {
        // particle-verification.md §4 Table 6.3 and fluid-dem-model.md U-09: reconstruction (A)
        // within 0.3 % of the thesis values and within 5e-5 of the spec's 4-decimal (A) column.
        let sphere = SettlingSphere::case_p1();
        let table = [
            (0.027, 0.692, 0.6912, 0.6919),
            (0.05, 0.656, 0.6546, 0.6557),
            (0.1, 0.580, 0.5787, 0.5804),
            (0.208, 0.434, 0.4327, 0.4342),
            (0.308, 0.319, 0.3187, 0.3182),
        ];
        for (phi, thesis, a, b) in table {
            let got_a = cloud_settling_velocity(&sphere, phi, CloudReconstruction::SlipVelocity).unwrap();
            let got_b = cloud_settling_velocity(&sphere, phi, CloudReconstruction::ParticleVelocity).unwrap();
            // The spec's bound: "(A) is within 0.0015 m/s (≤ 0.3 %) of Table 6.3".
            let deviation = (got_a.particle_velocity - thesis).abs();
            assert!(deviation <= 0.0015, "phi={phi}: {} vs {thesis}", got_a.particle_velocity);
            assert!(deviation / thesis < 3.5e-3, "phi={phi}: the spec rounds 0.306 % to 0.3 %");
            assert!((got_a.particle_velocity - a).abs() < 5e-5, "(A) phi={phi}: {}", got_a.particle_velocity);
            assert!((got_b.particle_velocity - b).abs() < 5e-5, "(B) phi={phi}: {}", got_b.particle_velocity);
        }
        // (A) slip speeds of the spec table: 0.7104 at 0.027, 0.4605 at 0.308.
        let s = cloud_settling_velocity(&sphere, 0.027, CloudReconstruction::SlipVelocity).unwrap();
        assert!((s.slip_velocity - 0.7104).abs() < 5e-5);
        // α_p = 0 returns the single-particle terminal velocity 0.736 (Table 6.3 first column).
        let zero = cloud_settling_velocity(&sphere, 0.0, CloudReconstruction::SlipVelocity).unwrap();
        assert!((zero.particle_velocity - 0.73577).abs() < 5e-6);
    }

    #[test]
    fn volume_balance_identities() {
        // U-07: u_p = −α_c u_s.
        let (u_c, u_s) = batch_settling_fluid_and_slip(-0.5, 0.8).unwrap();
        assert!((u_c - 0.125).abs() < 1e-15 && (-0.5 - (-0.8 * u_s)).abs() < 1e-15);
        assert!(cloud_settling_velocity(&SettlingSphere::case_p1(), 1.0, CloudReconstruction::SlipVelocity).is_err());
    }
}
