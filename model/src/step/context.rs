//! What every phase of one step is told: the time level, the step size, the time-derivative
//! coefficients and the rotor pose (spec fluid-dem-model.md §8.7, Algorithm 1).

use super::rotor_pose::RotorPose;
use crate::fluid::settings::TimeScheme;

/// The clock of one step from tⁿ to tⁿ⁺¹ = tⁿ + Δt. Built by the driver only.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepContext {
    /// Number of the step being taken (1 for the first).
    pub step: u64,
    /// tⁿ [s].
    pub time: f64,
    /// Δt = tⁿ⁺¹ − tⁿ [s].
    pub dt: f64,
    /// Δtᵒ of the previous step [s] (0 before the first).
    pub dt_old: f64,
    /// d/dt q ≈ (c₀qⁿ⁺¹ + c₁qⁿ + c₂qⁿ⁻¹)/Δt ([`time_coefficients`]).
    pub time_coefficients: [f64; 3],
    /// The rotor at tⁿ, `None` without a rotor.
    pub rotor_start: Option<RotorPose>,
    /// The rotor at tⁿ⁺¹: the pose the fluid is solved at.
    pub rotor: Option<RotorPose>,
}

impl StepContext {
    /// The context of the step after a state at `time` that took `dt_old` (0 before the first
    /// step), with the rotor at `rotor_start`.
    pub fn new(step: u64, time: f64, dt: f64, dt_old: f64, scheme: TimeScheme, rotor_start: Option<RotorPose>) -> StepContext {
        StepContext {
            step,
            time,
            dt,
            dt_old,
            time_coefficients: time_coefficients(scheme, step <= 1, dt, dt_old),
            rotor_start,
            rotor: rotor_start.map(|r| r.advanced(dt)),
        }
    }

    /// tⁿ⁺¹ [s].
    pub fn time_end(&self) -> f64 {
        self.time + self.dt
    }

    /// The rotor `elapsed` seconds after tⁿ (DEM sub-steps), from the start pose: the same
    /// arithmetic as [`RotorPose::advanced`], so the pose at `elapsed = dt` is the end pose bit
    /// for bit.
    pub fn rotor_after(&self, elapsed: f64) -> Option<RotorPose> {
        self.rotor_start.map(|r| r.advanced(elapsed))
    }
}

/// Coefficients of the time derivative d/dt q ≈ (c₀qⁿ⁺¹ + c₁qⁿ + c₂qⁿ⁻¹)/Δt (spec
/// fluid-dem-model.md §8.7; reference fluid module doc, step 1).
///
/// Implicit Euler (1, −1, 0) on the first step, with `time_scheme = "euler"`, or when there is
/// no previous step (`dt_old ≤ 0`); otherwise BDF2 for variable steps with r = Δt/Δtᵒ:
/// c₀ = (1+2r)/(1+r), c₁ = −(1+r), c₂ = r²/(1+r), exact for quadratics in t on any step
/// sequence, so an adaptive Δt keeps second order.
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

    /// Variable-step BDF2 differentiates q(t) = a + bt + ct² exactly at tⁿ⁺¹ for any step
    /// ratio (round-off: the coefficients are O(1) and q is O(10), so 1e-12 relative).
    #[test]
    fn variable_step_bdf2_is_exact_for_quadratics() {
        let q = |t: f64| 3.0 - 2.0 * t + 5.0 * t * t;
        let dq = |t: f64| -2.0 + 10.0 * t;
        for (dt, dt_old) in [(0.1, 0.1), (0.13, 0.07), (0.07, 0.13), (0.3, 0.01)] {
            let t0 = 0.4;
            let (t_old, t_new) = (t0 - dt_old, t0 + dt);
            let [c0, c1, c2] = time_coefficients(TimeScheme::Backward, false, dt, dt_old);
            let estimate = (c0 * q(t_new) + c1 * q(t0) + c2 * q(t_old)) / dt;
            assert!((estimate - dq(t_new)).abs() <= 1e-12 * dq(t_new).abs().max(1.0), "Δt {dt}, Δtᵒ {dt_old}: {estimate} vs {}", dq(t_new));
        }
    }

    #[test]
    fn euler_on_the_first_step_and_when_chosen() {
        assert_eq!(time_coefficients(TimeScheme::Backward, true, 0.1, 0.1), [1.0, -1.0, 0.0]);
        assert_eq!(time_coefficients(TimeScheme::Euler, false, 0.1, 0.1), [1.0, -1.0, 0.0]);
        assert_eq!(time_coefficients(TimeScheme::Backward, false, 0.1, 0.0), [1.0, -1.0, 0.0]);
    }

    #[test]
    fn rotor_after_the_whole_step_is_the_end_pose() {
        let pose = RotorPose { axis: crate::mesh::Vec3::z(), origin: Default::default(), omega: 0.7, angle: 0.1 };
        let ctx = StepContext::new(3, 1.0, 0.3, 0.3, TimeScheme::Backward, Some(pose));
        assert_eq!(ctx.rotor_after(ctx.dt), ctx.rotor);
    }
}
