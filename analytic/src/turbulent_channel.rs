//! Fully developed turbulent channel flow: the log law of the wall and Dean's skin-friction
//! correlation, the references of the realizable k–ε verification (issue 18; spec
//! fluid-dem-model.md §3 names the model, not these classical correlations).
//!
//! Channel of half-height h, friction velocity u_τ = √(τ_w/ρ), bulk velocity U_b, wall units
//! y⁺ = u_τ y/ν, U⁺ = u/u_τ, Re_τ = u_τ h/ν.

use serde::Serialize;

use crate::error::{positive, Result};

/// The log law U⁺ = ln(y⁺)/κ + B (von Kármán constant κ, intercept B; κ = 0.41, B = 5.2 are the
/// values the issue names).
pub fn log_law_u_plus(y_plus: f64, kappa: f64, b: f64) -> Result<f64> {
    positive("y_plus", y_plus)?;
    positive("kappa", kappa)?;
    Ok(y_plus.ln() / kappa + b)
}

/// Dean (1978): C_f = τ_w/(½ρU_b²) = 0.073 Re_m^(−1/4), with Re_m = 2hU_b/ν the bulk Reynolds
/// number on the full channel height.
pub fn dean_skin_friction(re_m: f64) -> Result<f64> {
    positive("re_m", re_m)?;
    Ok(0.073 * re_m.powf(-0.25))
}

/// Dean's correlation solved for the bulk velocity at a given Re_τ: with C_f = 2/U_b⁺² and
/// Re_m = 2 Re_τ U_b⁺, U_b⁺^(7/4) = (2/0.073)(2 Re_τ)^(1/4).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DeanChannel {
    pub re_tau: f64,
    /// U_b/u_τ.
    pub bulk_velocity_plus: f64,
    /// 2hU_b/ν.
    pub re_m: f64,
    pub skin_friction: f64,
}

impl DeanChannel {
    pub fn at_re_tau(re_tau: f64) -> Result<Self> {
        positive("re_tau", re_tau)?;
        let bulk_velocity_plus = (2.0 / 0.073 * (2.0 * re_tau).powf(0.25)).powf(4.0 / 7.0);
        let re_m = 2.0 * re_tau * bulk_velocity_plus;
        Ok(Self { re_tau, bulk_velocity_plus, re_m, skin_friction: 2.0 / (bulk_velocity_plus * bulk_velocity_plus) })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dean_bulk_velocity_is_consistent_with_the_correlation() {
        for re_tau in [180.0, 395.0, 2000.0] {
            let d = DeanChannel::at_re_tau(re_tau).unwrap();
            let cf = dean_skin_friction(d.re_m).unwrap();
            assert!((cf - d.skin_friction).abs() < 1e-14, "{re_tau}: {cf} vs {}", d.skin_friction);
        }
        // Re_τ = 395: DNS (Moser, Kim & Mansour 1999) has U_b⁺ ≈ 17.5; Dean gives 17.2 (the
        // correlation's own scatter is a few per cent, hence 3 %)
        let d = DeanChannel::at_re_tau(395.0).unwrap();
        assert!((d.bulk_velocity_plus - 17.5).abs() < 0.03 * 17.5, "{}", d.bulk_velocity_plus);
    }

    #[test]
    fn log_law_values() {
        assert!((log_law_u_plus(100.0, 0.41, 5.2).unwrap() - (100f64.ln() / 0.41 + 5.2)).abs() < 1e-15);
        assert!(log_law_u_plus(0.0, 0.41, 5.2).is_err());
    }
}
