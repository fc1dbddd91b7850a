//! Frozen-rotor (multiple reference frame, MRF) start-up of a case with a turning rotor:
//! `[fluid] initial = { type = "frozen_rotor", time = T }` (issue 16 "Start-up"; the thesis
//! "initialise[s] with a Multiple Reference Frame (MRF) steady solution, then run[s] … with the
//! sliding mesh", spillage-and-flow-verification.md §4.2, and starts its spillage runs from
//! "Steady frozen-rotor (MRF) flow", §5.4).
//!
//! # The equations
//! Both solvers solve the absolute velocity u on a mesh whose rotor zone turns rigidly with
//! Ω = ω â about the axis through x₀ (sliding mesh, ALE, fluid-dem-model.md §4.1; module doc of
//! `spillage_reference::fluid`): per cell, moving with the rotor,
//!
//!   d/dt ∫_V(t) α u dV + Σ_f α_f u_f (φ_f − φ_mesh,f) = (stresses, g, −∇P),
//!   φ_mesh,f = (Ω × (x_f − x₀))·S_f on the rotor's faces, rotating walls at Ω × (x − x₀).
//!
//! If the flow is steady as seen from the rotor, a rotor cell carries the same velocity vector
//! relative to the blades at every instant, so its Cartesian components turn with it:
//! d/dt ∫_V(t) α u dV = Ω × ∫_V α u dV. A frozen rotor keeps the rotor zone (and so the sliding
//! interface) at its start pose and writes the rate of the cell as this turning plus the rate
//! seen from the rotor, ∂/∂τ, which is zero in the steady state:
//!
//!   ∂/∂τ ∫_V α u dV + α Ω × u V + Σ_f α_f u_f (φ_f − φ_mesh,f) = (stresses, g, −∇P)
//!
//! in the rotor zone's cells, unchanged outside it. This is OpenFOAM's MRF in the
//! absolute-velocity form (`src/finiteVolume/cfdTools/general/MRF/MRFZone.C`: `makeRelative`
//! subtracts (Ω × (C_f − origin))·S_f from φ on the faces of the zone's cells — our φ_mesh;
//! `addCoriolis` adds Ω × U V to the zone's cells on the left-hand side — [`FrozenRotor`];
//! `correctBoundaryVelocity` sets the zone's walls to Ω × (C_f − origin) — our rotating walls).
//! It is the same identity from the other side: in the rotating frame the relative velocity
//! w = u − Ω×r has Coriolis 2Ω×w and centrifugal Ω×(Ω×r), and with (w·∇)(Ω×r) = Ω×w,
//! (w·∇)w + 2Ω×w + Ω×(Ω×r) = (w·∇)u + Ω×u.
//! So a frozen-rotor step is a sliding-mesh step whose pose keeps its angle while ω stays
//! (mesh fluxes, wall velocities, interface overlaps all follow the pose as before) plus the
//! source −α Ω × u V in the rotor zone's cells: the one term this file holds.
//!
//! Like the Coriolis force of `[physics.rotating_frame]` (crate::closure::rotating_frame), the
//! source is explicit in the latest outer iterate u* (the momentum matrix is one for all three
//! components, so it cannot couple them), hence implicit at tⁿ⁺¹ once the outer loop has
//! converged; as a fixed-point iteration it contracts by about |Ω|Δt/c₀ per outer iteration.
//!
//! # The clock ([`StartUp`])
//! A fresh run starts at t = −T; every step from tⁿ < 0 is a frozen-rotor step (the rotor's
//! angle stays at its start value, which [`crate::step::time_step`] makes land exactly on
//! t = 0, so the start-up's steps are the rows of `series.csv` with t ≤ 0). The sliding-mesh run
//! then starts at t = 0 from the frozen-rotor solution with one implicit-Euler step, as a fresh
//! start does: BDF2's older level in a rotor cell would be the frozen, unturned velocity. A
//! checkpoint written during the start-up has t < 0 and continues it. Particles are refused
//! (the case check, [`check_case`]): their walls would have to stand while ω moves them.

use crate::case::{Case, FieldError};
use crate::fluid::settings::{InitialVelocity, TimeScheme};
use crate::mesh::Vec3;
use crate::step::{time_coefficients, StepContext};

/// The frame term of a frozen-rotor step (module doc): Ω = ω â of the rotor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrozenRotor {
    angular_velocity: Vec3,
}

impl FrozenRotor {
    /// The frame of a frozen-rotor step: `Some` when `ctx` is one and has a rotor.
    pub fn of_step(ctx: &StepContext) -> Option<FrozenRotor> {
        ctx.rotor.filter(|_| ctx.frozen_rotor).map(|pose| FrozenRotor { angular_velocity: pose.axis * pose.omega })
    }

    /// The source per unit mass of a rotor-zone cell with velocity `u`, −Ω × u [m/s²] (it moves
    /// to the right-hand side with its sign flipped; multiply by α V for the cell).
    #[inline]
    pub fn acceleration(&self, u: Vec3) -> Vec3 {
        -self.angular_velocity.cross(&u)
    }
}

/// The frozen-rotor start-up of a case: its length T in pseudo-time (module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StartUp {
    /// T [s].
    pub duration: f64,
}

impl StartUp {
    /// The start-up of `case`, `None` unless `[fluid] initial` is a frozen-rotor start.
    pub fn of_case(case: &Case) -> Option<StartUp> {
        match case.fluid.as_ref().map(|f| &f.initial) {
            Some(InitialVelocity::FrozenRotor { time, .. }) => Some(StartUp { duration: *time }),
            _ => None,
        }
    }

    /// The time a fresh run starts at, −T [s].
    pub fn start_time(&self) -> f64 {
        -self.duration
    }

    /// The step `ctx` as this start-up takes it: a frozen-rotor step (the pose at tⁿ⁺¹ is the
    /// pose at tⁿ) from tⁿ < 0; the first sliding-mesh step, from tⁿ = 0 after the start-up, an
    /// implicit-Euler step.
    pub fn step(&self, ctx: StepContext, scheme: TimeScheme) -> StepContext {
        if ctx.time < 0.0 {
            StepContext { frozen_rotor: true, rotor: ctx.rotor_start, ..ctx }
        } else if ctx.time == 0.0 {
            StepContext { time_coefficients: time_coefficients(scheme, true, ctx.dt, ctx.dt_old), ..ctx }
        } else {
            ctx
        }
    }
}

/// What a frozen-rotor start needs of the rest of the case: a turning `[rotor]` on a mesh with a
/// rotor zone, no `[particles]`, and a run length in time (`steps` would count the start-up's).
pub fn check_case(case: &Case) -> Result<(), FieldError> {
    if StartUp::of_case(case).is_none() {
        return Ok(());
    }
    let key = "fluid.initial.type";
    let value = "\"frozen_rotor\"";
    if case.rotor.as_ref().is_none_or(|r| r.angular_velocity() == 0.0) {
        return Err(FieldError::new(key, value, "a frozen-rotor start only with a turning [rotor] (rpm or omega ≠ 0)"));
    }
    let rotor_mesh = matches!(case.mesh, Some(crate::case::MeshSection::RotorStator { .. })) || case.cutter_head.is_some();
    if !rotor_mesh {
        return Err(FieldError::new(
            key,
            value,
            "a frozen-rotor start only on a mesh with a rotor zone (mesh.generator = \"rotor_stator\" or a [cutter_head])",
        ));
    }
    if case.particles.is_some() {
        return Err(FieldError::new(
            key,
            value,
            "a frozen-rotor start only without [particles] (the blades would stand while ω moves them); start a particle case with \"solid_body\" or \"rest\"",
        ));
    }
    if let Some(n) = case.time.steps {
        return Err(FieldError::new(
            "time.steps",
            n,
            "time.end_time or time.revolutions with a frozen-rotor start (they count from t = 0, after the start-up)",
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::step::RotorPose;

    #[test]
    fn the_source_is_minus_omega_cross_u() {
        let pose = RotorPose { axis: Vec3::z(), origin: Vec3::zeros(), omega: 2.0, angle: 0.3 };
        let ctx = StepContext::new(1, -1.0, 0.1, 0.0, TimeScheme::Backward, Some(pose));
        assert!(FrozenRotor::of_step(&ctx).is_none(), "a step is frozen only when the start-up says so");
        let frozen = StartUp { duration: 1.0 }.step(ctx, TimeScheme::Backward);
        let f = FrozenRotor::of_step(&frozen).unwrap();
        // −2ẑ × (1, 0, 0) = (0, −2, 0): a fluid particle moving along x in a frame turning
        // counter-clockwise is turned clockwise relative to the frame
        assert_eq!(f.acceleration(Vec3::new(1.0, 0.0, 0.0)), Vec3::new(0.0, -2.0, 0.0));
        // solid-body rotation u = Ω × r: −Ω × (Ω × r) = Ω² r, the centripetal balance ∇P = Ω² r
        let r = Vec3::new(0.5, 0.0, 0.0);
        assert_eq!(f.acceleration(Vec3::z().cross(&r) * 2.0), r * 4.0);
    }

    #[test]
    fn the_start_up_holds_the_pose_and_restarts_the_time_scheme_at_zero() {
        let pose = RotorPose { axis: Vec3::z(), origin: Vec3::zeros(), omega: 2.0, angle: 0.0 };
        let s = StartUp { duration: 0.5 };
        let frozen = s.step(StepContext::new(3, -0.2, 0.1, 0.1, TimeScheme::Backward, Some(pose)), TimeScheme::Backward);
        assert!(frozen.frozen_rotor);
        assert_eq!(frozen.rotor.unwrap().angle, 0.0);
        assert_eq!(frozen.time_coefficients, [1.5, -2.0, 0.5]);
        let first = s.step(StepContext::new(6, 0.0, 0.1, 0.1, TimeScheme::Backward, Some(pose)), TimeScheme::Backward);
        assert!(!first.frozen_rotor);
        assert_eq!(first.rotor.unwrap().angle, 0.2);
        assert_eq!(first.time_coefficients, [1.0, -1.0, 0.0]);
        let later = s.step(StepContext::new(7, 0.1, 0.1, 0.1, TimeScheme::Backward, Some(pose)), TimeScheme::Backward);
        assert_eq!(later.time_coefficients, [1.5, -2.0, 0.5]);
    }
}
