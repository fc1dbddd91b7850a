//! The wear model's representative particle (wear-model.md §2.5, Eq. 2.11, and §2.6, Eq. 5.3
//! with the [R] correction): drag, buoyancy-reduced gravity and, in a rotating frame, the full
//! Coriolis force with the buoyancy-reduced centrifugal force, per particle:
//!
//!   m_p du/dt = K (u_c − u) + V (ρ_p − ρ_c) g − V (ρ_p − ρ_c) Ω×(Ω×(r − x₀)) − 2 m_p Ω×u.
//!
//! No added mass and no pressure-gradient force: this is the equation the thesis ran its
//! Coriolis tester and jet with (`[particles] fluid_forces = "drag_and_buoyancy"`). The full
//! set of fluid-dem-model.md §5 ([`super::drag::fluid_force_step`],
//! [`super::rotating_frame::fluid_force_step_in_rotating_frame`]) differs from it most in a
//! turning frame: there the pressure-gradient force on the particle carries the fluid's own
//! Coriolis balance, so a grain moving with the water is pressed across the flow by
//! (ρ_p − ρ_c)/(ρ_p + C_AM ρ_c) of 2Ω×u (0.5 for garnet in water) instead of all of it.
//!
//! The update is the same linearised implicit one (K at the start of the update, §5.10), with
//! the Coriolis part trapezoidal in u (as in [`super::rotating_frame::dry_particle_update`]),
//! solved exactly.

use super::drag::{drag_factor_and_reynolds, DragLaw, FluidAtParticle, FluidForceStep};
use super::rotating_frame::RotatingFrame;
use nalgebra::Vector3;

type Vec3 = Vector3<f64>;

/// One update of length `dt` of a particle (`diameter`, `particle_density`, at `position`,
/// moving at `velocity`) in `fluid`, in `frame` if the case turns. The returned
/// `fluid_acceleration_force` is zero: the fluid receives the drag alone (§2.4, Eq. 2.10).
#[allow(clippy::too_many_arguments)]
pub fn drag_and_buoyancy_step(
    frame: Option<&RotatingFrame>,
    law: DragLaw,
    velocity: Vec3,
    position: Vec3,
    diameter: f64,
    particle_density: f64,
    fluid: &FluidAtParticle,
    gravity: Vec3,
    dt: f64,
) -> FluidForceStep {
    let volume = std::f64::consts::PI * diameter.powi(3) / 6.0;
    let mass = volume * particle_density;
    let submerged = volume * (particle_density - fluid.density);
    let slip = (fluid.velocity - velocity).norm();
    let (k, slip_reynolds) = drag_factor_and_reynolds(law, diameter, fluid.density, fluid.kinematic_viscosity, slip, fluid.fluid_fraction);
    let mut explicit = k * fluid.velocity + submerged * gravity;
    if let Some(frame) = frame {
        explicit += submerged * frame.centrifugal_acceleration(position) + mass * 0.5 * frame.coriolis_acceleration(velocity);
    }
    let denominator = mass + k * dt;
    let rhs = (mass * velocity + dt * explicit) / denominator;
    // (m + KΔt) u' + m Δt Ω×u' = … ⇔ u' + h Ω×u' = rhs, h = m Δt/(m + KΔt)
    let new = match frame {
        Some(frame) => frame.solve_coriolis_implicit(rhs, mass * dt / denominator),
        None => rhs,
    };
    FluidForceStep { velocity: new, drag_factor: k, drag: k * (fluid.velocity - new), fluid_acceleration_force: Vec3::zeros(), slip_reynolds }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn water_at_rest() -> FluidAtParticle {
        FluidAtParticle { velocity: Vec3::zeros(), material_acceleration: Vec3::zeros(), density: 1000.0, kinematic_viscosity: 1e-6, fluid_fraction: 1.0 }
    }

    /// Without a frame and with Stokes drag the update is implicit Euler of
    /// m du/dt = −3πμd u + V(ρ_p − ρ_c) g: it settles at the Stokes velocity
    /// (ρ_p − ρ_c) g d²/(18 μ) exactly, and approaches it at the rate of implicit Euler.
    #[test]
    fn settles_at_the_stokes_velocity_without_added_mass() {
        let (d, rho_p, g) = (1e-4, 2500.0, Vec3::new(0.0, 0.0, -9.81));
        let fluid = water_at_rest();
        let stokes = 1500.0 * 9.81 * d * d / (18.0 * 1e-3);
        let tau = rho_p * d * d / (18.0 * 1e-3);
        let dt = 0.1 * tau;
        let mut u = Vec3::zeros();
        for n in 1..=400 {
            u = drag_and_buoyancy_step(None, DragLaw::Stokes, u, Vec3::zeros(), d, rho_p, &fluid, g, dt).velocity;
            if n == 10 {
                // implicit Euler: u_n = u_t (1 − (1 + Δt/τ)^−n), no added mass in τ
                let expected = stokes * (1.0 - (1.0f64 + dt / tau).powi(-10));
                assert!((-u.z - expected).abs() < 1e-12 * stokes, "{} vs {expected}", -u.z);
            }
        }
        assert!((-u.z - stokes).abs() < 1e-12 * stokes, "{} vs {stokes}", -u.z);
    }

    /// In a turning frame a grain at rest in the frame, in water at rest in the frame, is
    /// pushed outward by the buoyancy-reduced centrifugal force, (1 − ρ_c/ρ_p) Ω²r, and a grain
    /// moving with the water across it feels the whole Coriolis force −2Ω×u (no pressure
    /// gradient to take part of it away).
    #[test]
    fn a_turning_frame_adds_the_full_coriolis_and_the_buoyant_centrifugal_force() {
        let frame = RotatingFrame::new(314.159, [0.0, 0.0, 1.0], [0.0; 3]).unwrap();
        let (d, rho_p, dt) = (1e-3, 2500.0, 1e-7);
        let position = Vec3::new(0.1, 0.0, 0.0);
        let at_rest = drag_and_buoyancy_step(Some(&frame), DragLaw::Stokes, Vec3::zeros(), position, d, rho_p, &water_at_rest(), Vec3::zeros(), dt);
        let centrifugal = 0.6 * 314.159f64.powi(2) * 0.1;
        // the drag of the velocity gained within the step changes it by K Δt/m ~ 1e-4
        assert!((at_rest.velocity.x / dt - centrifugal).abs() < 2e-4 * centrifugal, "{} vs {centrifugal}", at_rest.velocity.x / dt);
        let u = Vec3::new(20.0, 0.0, 0.0);
        let moving = FluidAtParticle { velocity: u, ..water_at_rest() };
        let step = drag_and_buoyancy_step(Some(&frame), DragLaw::Stokes, u, Vec3::zeros(), d, rho_p, &moving, Vec3::zeros(), dt);
        let coriolis = -2.0 * 314.159 * 20.0;
        assert!((step.velocity.y / dt - coriolis).abs() < 2e-4 * coriolis.abs(), "{} vs {coriolis}", step.velocity.y / dt);
        assert_eq!(step.fluid_acceleration_force, Vec3::zeros());
    }
}
