//! What every phase of one step is told: the time level, the step size, the time-derivative
//! coefficients and the rotor pose (spec fluid-dem-model.md §8.7, Algorithm 1).

use super::rotor_pose::RotorPose;
use crate::fluid::settings::TimeScheme;
pub use crate::fluid::time_scheme::time_coefficients;

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
    /// d/dt q ≈ (c₀qⁿ⁺¹ + c₁qⁿ + c₂qⁿ⁻¹)/Δt ([`crate::fluid::time_scheme::time_coefficients`]).
    pub time_coefficients: [f64; 3],
    /// The rotor at tⁿ, `None` without a rotor.
    pub rotor_start: Option<RotorPose>,
    /// The rotor at tⁿ⁺¹: the pose the fluid is solved at.
    pub rotor: Option<RotorPose>,
    /// A frozen-rotor start-up step: the rotor keeps its pose while ω acts, and the fluid adds
    /// the frame term ([`crate::fluid::frozen_rotor`]). Set by the start-up only.
    pub frozen_rotor: bool,
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
            frozen_rotor: false,
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
        if self.frozen_rotor {
            return self.rotor_start;
        }
        self.rotor_start.map(|r| r.advanced(elapsed))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The context turns the rotor by ω Δt, takes Euler on the first step and BDF2 with the
    /// step ratio afterwards.
    #[test]
    fn the_context_turns_the_rotor_and_picks_the_time_scheme() {
        let pose = RotorPose { axis: crate::mesh::Vec3::z(), origin: Default::default(), omega: 0.7, angle: 0.1 };
        let first = StepContext::new(1, 0.0, 0.3, 0.0, TimeScheme::Backward, Some(pose));
        assert_eq!(first.time_coefficients, [1.0, -1.0, 0.0]);
        assert_eq!(first.rotor.unwrap().angle, 0.1 + 0.7 * 0.3);
        assert_eq!(first.rotor_start.unwrap().angle, 0.1);
        let later = StepContext::new(3, 1.0, 0.2, 0.1, TimeScheme::Backward, Some(pose));
        // r = 2: c₀ = 5/3, c₁ = −3, c₂ = 4/3
        let [c0, c1, c2] = later.time_coefficients;
        assert!((c0 - 5.0 / 3.0).abs() < 1e-15 && (c1 + 3.0).abs() < 1e-15 && (c2 - 4.0 / 3.0).abs() < 1e-15);
        assert_eq!(later.time_end(), 1.2);
        assert!(StepContext::new(2, 0.0, 0.1, 0.1, TimeScheme::Backward, None).rotor.is_none());
    }
}
