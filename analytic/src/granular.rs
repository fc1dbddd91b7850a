//! The kinetic theory of granular flow as the thesis' wear model uses it (wear-model.md §4):
//! the granular temperature of a control volume's particle velocities (Eq. 2.19, A34) and the
//! solids pressure (Eqs. 2.25–2.26, A33).

use crate::error::{finite, in_closed, non_negative, positive, AnalyticError};

/// Θ = ⟨|c − u_p|²⟩/3 over `velocities` (Eq. 2.19), c their mean; 0 for fewer than two
/// (wear-model.md §4.1 [R]). Computed from the deviations themselves, two passes.
pub fn granular_temperature(velocities: &[[f64; 3]]) -> f64 {
    if velocities.len() < 2 {
        return 0.0;
    }
    let n = velocities.len() as f64;
    let mut mean = [0.0; 3];
    for v in velocities {
        for k in 0..3 {
            mean[k] += v[k] / n;
        }
    }
    velocities.iter().map(|v| (0..3).map(|k| (v[k] - mean[k]).powi(2)).sum::<f64>()).sum::<f64>() / (3.0 * n)
}

/// p_p = α_p ρ_p Θ [1 + 2 (1 + e) α_p g₀], g₀ = [1 − (α_p/α_max)^{1/3}]⁻¹ (Eqs. 2.25, 2.26) [Pa],
/// for 0 ≤ α_p < α_max. A33: α_p = 0.1, Θ = 0.01, e = 0.99, ρ_p = 2500, α_max = 0.6 give
/// 4.7126905 Pa.
pub fn solids_pressure(alpha_p: f64, density: f64, temperature: f64, restitution: f64, packing_limit: f64) -> Result<f64, AnalyticError> {
    positive("density", density)?;
    non_negative("temperature", temperature)?;
    in_closed("restitution", restitution, 0.0, 1.0, "0 ≤ e ≤ 1")?;
    in_closed("packing_limit", packing_limit, 0.0, 1.0, "0 ≤ α_max ≤ 1")?;
    finite("alpha_p", alpha_p)?;
    if !(alpha_p >= 0.0 && alpha_p < packing_limit) {
        return Err(AnalyticError::OutOfRange { name: "alpha_p", value: alpha_p, allowed: "0 ≤ α_p < α_max" });
    }
    let g0 = 1.0 / (1.0 - (alpha_p / packing_limit).powf(1.0 / 3.0));
    Ok(alpha_p * density * temperature * (1.0 + 2.0 * (1.0 + restitution) * alpha_p * g0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a33_solids_pressure() {
        // wear-model.md §15 A33, to its printed eight digits (rel 1e-7)
        let p = solids_pressure(0.1, 2500.0, 0.01, 0.99, 0.6).unwrap();
        assert!((p / 4.7126905 - 1.0).abs() < 1e-7, "{p}");
        assert!(solids_pressure(0.6, 2500.0, 0.01, 0.99, 0.6).is_err());
    }

    #[test]
    fn a34_granular_temperature() {
        assert!((granular_temperature(&[[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]) - 1.0 / 3.0).abs() <= 1e-14);
        assert_eq!(granular_temperature(&[[0.3, 1.0, -2.0], [0.3, 1.0, -2.0]]), 0.0);
        assert_eq!(granular_temperature(&[[1.0, 0.0, 0.0]]), 0.0);
    }
}
