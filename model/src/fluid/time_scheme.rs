//! Time discretisation coefficients shared by both fluid solvers (spec fluid-dem-model.md §8.7;
//! module doc of `spillage_reference::fluid`, step 1).

use super::settings::TimeScheme;

/// Coefficients (c₀, c₁, c₂) of d/dt q ≈ (c₀ qⁿ + c₁ qᵒ + c₂ qᵒᵒ)/Δt for a step of `dt` after
/// one of `dt_old`.
///
/// Variable-step BDF2 with r = Δt/Δtᵒ: c₀ = (1+2r)/(1+r), c₁ = −(1+r), c₂ = r²/(1+r) (exact for
/// quadratics in t). Implicit Euler (1, −1, 0) on the first step (`first_step`, no qᵒᵒ yet),
/// with `time_scheme = "euler"`, or when `dt_old ≤ 0` (no previous step size).
pub fn time_coefficients(scheme: TimeScheme, first_step: bool, dt: f64, dt_old: f64) -> [f64; 3] {
    if first_step || scheme == TimeScheme::Euler || dt_old <= 0.0 {
        [1.0, -1.0, 0.0]
    } else {
        let r = dt / dt_old;
        [(1.0 + 2.0 * r) / (1.0 + r), -(1.0 + r), r * r / (1.0 + r)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// BDF2 with unequal steps differentiates q(t) = a + b t + c t² exactly at tⁿ.
    #[test]
    fn bdf2_differentiates_a_quadratic_exactly_for_unequal_steps() {
        let q = |t: f64| 0.7 - 1.3 * t + 2.9 * t * t;
        let dq = |t: f64| -1.3 + 2.0 * 2.9 * t;
        for (dt, dt_old) in [(0.1, 0.05), (0.02, 0.1), (0.3, 0.3)] {
            let t = 1.25;
            let [c0, c1, c2] = time_coefficients(TimeScheme::Backward, false, dt, dt_old);
            let estimate = (c0 * q(t) + c1 * q(t - dt) + c2 * q(t - dt - dt_old)) / dt;
            assert!((estimate - dq(t)).abs() < 1e-12 * (1.0 + dq(t).abs()), "dt {dt}, dt_old {dt_old}: {estimate} vs {}", dq(t));
            // consistency: the coefficients sum to zero (a constant has no derivative)
            assert!((c0 + c1 + c2).abs() < 1e-15);
        }
    }

    #[test]
    fn euler_on_the_first_step_when_asked_and_without_a_previous_step() {
        assert_eq!(time_coefficients(TimeScheme::Backward, true, 0.1, 0.1), [1.0, -1.0, 0.0]);
        assert_eq!(time_coefficients(TimeScheme::Euler, false, 0.1, 0.1), [1.0, -1.0, 0.0]);
        assert_eq!(time_coefficients(TimeScheme::Backward, false, 0.1, 0.0), [1.0, -1.0, 0.0]);
        assert_eq!(time_coefficients(TimeScheme::Backward, false, 0.1, 0.1), [1.5, -2.0, 0.5]);
    }
}
