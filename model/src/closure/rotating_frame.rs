//! A whole-domain rotating reference frame (wear-model.md §2.6 [R], §13 row 16): the fictitious
//! accelerations felt by the fluid and the particles of a case written in a frame that turns at a
//! constant angular velocity Ω about an axis through x₀ (`[physics.rotating_frame]`; the
//! Coriolis tester of §12.4 turns at 3000 rpm about +z through the origin).
//!
//! The thesis prints the rotating-frame equations as Eqs. 5.2 (fluid) and 5.3 (particle) with
//! sign and density errors: gravity's sign is flipped relative to Eq. 2.9, and the centrifugal
//! term Ω×Ω×x has no density and the sign of an acceleration *towards* the axis. We implement the
//! standard forms the spec gives instead (§2.6 [R], §13 row 16): per unit mass
//!
//!   a_fictitious = −2Ω×u − Ω×(Ω×(x − x₀))    (Coriolis + centrifugal; Ω constant, so no Euler
//!                                             term −dΩ/dt×r),
//!
//! with u the velocity relative to the rotating frame and x the position in it.
//!
//! Where the solvers add it:
//! - fluid, both solvers alike: α_c·a_fictitious·V in the kinematic, volume-averaged momentum
//!   equation, next to the body force (the inertia terms α_c(∂u/∂t + u·∇u) that the frame change
//!   transforms carry α_c; gravity and ∇p do not, spec fluid-dem-model.md §2.1). The Coriolis
//!   part takes the latest outer iterate u* (see `spillage_reference::fluid::momentum`).
//! - particles: [`fluid_force_step_in_rotating_frame`] with a fluid, [`dry_particle_update`]
//!   without one.
//!
//! Why the particle with a fluid gets more than m_p·a_fictitious: our particle equation carries
//! the fluid pressure-gradient force through the fluid's acceleration, F_pg = V ρ_c Du_c/Dt
//! (fluid-dem-model.md T3.45, gravity's hydrostatic part kept in the buoyancy V(ρ_p − ρ_c)g), and
//! added mass through the difference of the two accelerations (T3.43). Both are statements about
//! accelerations relative to an inertial frame, so in the rotating frame they take
//! Du_c/Dt − a_fictitious(u_c, x) and du_p/dt − a_fictitious(u_p, x). F_pg then supplies the
//! centrifugal buoyancy +V ρ_c Ω×(Ω×(x − x₀)) of §2.6, and with the particle's own
//! m_p·a_fictitious the net centrifugal force is the buoyancy-reduced −V(ρ_p − ρ_c)Ω×(Ω×r)
//! that §2.6 gives for the reduced-gravity form, as it must for a particle in fluid at rest in
//! the rotating frame (whose pressure gradient is ρ_c(g − Ω×(Ω×r))).

use nalgebra::Vector3;

use super::drag::{drag_factor_and_reynolds, DragLaw, FluidAtParticle, FluidForceStep};
use super::restitution::ADDED_MASS_COEFFICIENT;
use crate::case::{FieldError, Physics, RotatingFrameSection};

type Vec3 = Vector3<f64>;

/// A frame turning rigidly at the constant angular velocity Ω about the line through `origin`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotatingFrame {
    /// Ω = ω â [rad/s] (â the unit axis).
    angular_velocity: Vec3,
    /// x₀, a point on the axis [m].
    origin: Vec3,
}

impl RotatingFrame {
    /// The frame turning at `omega` [rad/s] about `axis` (normalised here) through `origin`;
    /// an error naming `physics.rotating_frame.*` for a non-finite or zero input.
    pub fn new(omega: f64, axis: [f64; 3], origin: [f64; 3]) -> Result<Self, FieldError> {
        let section = RotatingFrameSection { omega, axis, origin };
        section.validate()?;
        Ok(Self::from_valid_section(&section))
    }

    fn from_valid_section(section: &RotatingFrameSection) -> Self {
        let axis = Vec3::from(section.axis) / section.axis_length();
        Self { angular_velocity: axis * section.omega, origin: Vec3::from(section.origin) }
    }

    /// The case's frame: `None` for an inertial case (no `[physics.rotating_frame]`).
    pub fn of_physics(physics: &Physics) -> Result<Option<Self>, FieldError> {
        match &physics.rotating_frame {
            None => Ok(None),
            Some(section) => {
                section.validate()?;
                Ok(Some(Self::from_valid_section(section)))
            }
        }
    }

    /// Ω [rad/s].
    pub fn angular_velocity(&self) -> Vec3 {
        self.angular_velocity
    }

    /// x₀ [m].
    pub fn origin(&self) -> Vec3 {
        self.origin
    }

    /// Coriolis acceleration −2Ω×u of a body moving at `velocity` relative to the frame [m/s²].
    pub fn coriolis_acceleration(&self, velocity: Vec3) -> Vec3 {
        -2.0 * self.angular_velocity.cross(&velocity)
    }

    /// Centrifugal acceleration −Ω×(Ω×(x − x₀)) at `position` [m/s²]: Ω²·(distance from the
    /// axis), pointing away from it.
    pub fn centrifugal_acceleration(&self, position: Vec3) -> Vec3 {
        let w = self.angular_velocity;
        -w.cross(&w.cross(&(position - self.origin)))
    }

    /// The fictitious acceleration −2Ω×u − Ω×(Ω×(x − x₀)) of a body at `position` moving at
    /// `velocity` relative to the frame (wear-model.md §2.6 [R]) [m/s²].
    pub fn fictitious_acceleration(&self, velocity: Vec3, position: Vec3) -> Vec3 {
        self.coriolis_acceleration(velocity) + self.centrifugal_acceleration(position)
    }

    /// The velocity v with v + h Ω×v = `rhs` (h [s]): the implicit half of a trapezoidal
    /// (Crank–Nicolson) Coriolis update. With w = hΩ,
    /// v = (rhs − w×rhs + (w·rhs) w) / (1 + |w|²) (checked by substitution; always solvable).
    pub fn solve_coriolis_implicit(&self, rhs: Vec3, h: f64) -> Vec3 {
        let w = self.angular_velocity * h;
        (rhs - w.cross(&rhs) + w * w.dot(&rhs)) / (1.0 + w.norm_squared())
    }
}

/// Velocity after `dt` of a particle without any fluid (no `[fluid]`, no `[particles.ambient]`):
/// nothing exerts a pressure gradient on it, so it feels gravity and the full fictitious
/// acceleration per unit particle mass (wear-model.md §2.6 [R]; neither buoyancy form applies):
///
///   u' = u + Δt [g − Ω×(Ω×(r − x₀)) − Ω×(u + u')],
///
/// centrifugal at the particle's position and Coriolis by the trapezoidal rule −2Ω×(u + u')/2,
/// solved exactly ([`RotatingFrame::solve_coriolis_implicit`]). The trapezoidal Coriolis turns
/// the velocity without changing its length, as Coriolis does (it does no work), where an
/// explicit −2Ω×u would make it grow by √(1 + (2ΩΔt)²) every update; and it keeps the DEM's
/// velocity-Verlet step (half update, move, half update) time-symmetric, hence second order.
pub fn dry_particle_update(frame: &RotatingFrame, velocity: Vec3, position: Vec3, gravity: Vec3, dt: f64) -> Vec3 {
    let rhs = velocity + dt * (gravity + frame.centrifugal_acceleration(position) + 0.5 * frame.coriolis_acceleration(velocity));
    frame.solve_coriolis_implicit(rhs, dt)
}

/// [`super::drag::fluid_force_step`] in a rotating frame, for a particle at `position`: the same
/// linearised implicit update (fluid-dem-model.md §5.10, K at the start of the update) with the
/// pressure-gradient and added-mass forces taken on the fluid's inertial acceleration
/// a_c = Du_c/Dt − a_fictitious(u_c, r) (module doc), and the particle's fictitious acceleration
/// a_fictitious(u_p, r) per unit effective mass m_eff = V(ρ_p + C_AM ρ_c) (the added-mass part of
/// it is C_AM V ρ_c times the particle's frame acceleration, T3.43):
///
///   m_eff (u' − u)/Δt = K (u_c − u') + (1 + C_AM) V ρ_c a_c + V(ρ_p − ρ_c) g
///                       + m_eff [−Ω×(Ω×(r − x₀)) − Ω×(u + u')],
///
/// Coriolis trapezoidal as in [`dry_particle_update`], solved exactly. Per unit particle mass
/// this is the −2Ω×u_p − Ω×(Ω×r) of §2.6 [R] for a particle whose equation carries the fluid
/// pressure-gradient force; with u_c = 0 and Du_c/Dt = 0 (fluid at rest in the frame, the
/// still `[particles.ambient]` fluid) the net centrifugal force is −V(ρ_p − ρ_c)Ω×(Ω×r).
///
/// The returned forces keep the meaning of [`FluidForceStep`]: `fluid_acceleration_force` is
/// F_AM + F_pg = (1 + C_AM) V ρ_c a_c − C_AM V ρ_c a_p with a_p = (u' − u)/Δt −
/// a_fictitious(ū, r) the particle's inertial acceleration (ū the trapezoidal Coriolis velocity),
/// so m_p (u' − u)/Δt = F_d + F_AM + F_pg + V(ρ_p − ρ_c) g + m_p a_fictitious(ū, r), and the
/// fluid receives −(F_d + F_AM + F_pg) (fluid-dem-model.md §2.6), centrifugal buoyancy
/// included: that matches the α_c-weighted fictitious force of the fluid, so a suspension at
/// rest in the frame still carries its mixture weight ∇p = ρ_m(g − Ω×(Ω×r)).
#[allow(clippy::too_many_arguments)]
pub fn fluid_force_step_in_rotating_frame(
    frame: &RotatingFrame,
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
    let effective_mass = volume * (particle_density + ADDED_MASS_COEFFICIENT * fluid.density);
    let fluid_mass = volume * fluid.density;
    let slip = (fluid.velocity - velocity).norm();
    let (k, slip_reynolds) = drag_factor_and_reynolds(law, diameter, fluid.density, fluid.kinematic_viscosity, slip, fluid.fluid_fraction);
    let fluid_inertial_acceleration = fluid.material_acceleration - frame.fictitious_acceleration(fluid.velocity, position);
    let centrifugal = frame.centrifugal_acceleration(position);
    let explicit =
        k * fluid.velocity + (1.0 + ADDED_MASS_COEFFICIENT) * fluid_mass * fluid_inertial_acceleration + volume * (particle_density - fluid.density) * gravity;
    let rhs = effective_mass * velocity + dt * (explicit + effective_mass * (centrifugal + 0.5 * frame.coriolis_acceleration(velocity)));
    let denominator = effective_mass + k * dt;
    // (m_eff + KΔt) u' + m_eff Δt Ω×u' = rhs  ⇔  u' + h Ω×u' = rhs/(m_eff + KΔt), h = m_eff Δt/(m_eff + KΔt)
    let new = frame.solve_coriolis_implicit(rhs / denominator, effective_mass * dt / denominator);
    let particle_fictitious = centrifugal + frame.coriolis_acceleration(0.5 * (velocity + new));
    let particle_inertial_acceleration = (new - velocity) / dt - particle_fictitious;
    FluidForceStep {
        velocity: new,
        drag_factor: k,
        drag: k * (fluid.velocity - new),
        fluid_acceleration_force: (1.0 + ADDED_MASS_COEFFICIENT) * fluid_mass * fluid_inertial_acceleration
            - ADDED_MASS_COEFFICIENT * fluid_mass * particle_inertial_acceleration,
        slip_reynolds,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::closure::drag::fluid_force_step;

    fn frame() -> RotatingFrame {
        RotatingFrame::new(3.0, [0.0, 0.0, 2.0], [0.5, -0.25, 7.0]).unwrap()
    }

    /// Ω = 3 ẑ about (0.5, −0.25, ·): Coriolis of u = x̂ is −6 ŷ; centrifugal at 2 m from the
    /// axis is 9·2 = 18 m/s² outwards, whatever the height along the axis.
    #[test]
    fn fictitious_acceleration_components() {
        let f = frame();
        assert_eq!(f.angular_velocity(), Vec3::new(0.0, 0.0, 3.0));
        assert!((f.coriolis_acceleration(Vec3::x()) - Vec3::new(0.0, -6.0, 0.0)).norm() < 1e-15);
        let r = Vec3::new(0.5 + 2.0, -0.25, -4.0);
        assert!((f.centrifugal_acceleration(r) - Vec3::new(18.0, 0.0, 0.0)).norm() < 1e-13);
        let u = Vec3::new(0.3, -1.0, 5.0);
        assert_eq!(f.fictitious_acceleration(u, r), f.coriolis_acceleration(u) + f.centrifugal_acceleration(r));
        // Coriolis does no work
        assert!(f.coriolis_acceleration(u).dot(&u).abs() < 1e-14);
    }

    #[test]
    fn bad_frames_name_their_key() {
        let zero = RotatingFrame::new(1.0, [0.0, 0.0, 0.0], [0.0; 3]).unwrap_err();
        assert_eq!(zero.key, "physics.rotating_frame.axis");
        let nan = RotatingFrame::new(f64::NAN, [0.0, 0.0, 1.0], [0.0; 3]).unwrap_err();
        assert_eq!(nan.key, "physics.rotating_frame.omega");
        let origin = RotatingFrame::new(1.0, [0.0, 0.0, 1.0], [0.0, f64::INFINITY, 0.0]).unwrap_err();
        assert_eq!(origin.key, "physics.rotating_frame.origin");
        assert_eq!(RotatingFrame::of_physics(&Physics::default()), Ok(None));
    }

    /// v + hΩ×v = rhs is solved to round-off, and the trapezoidal Coriolis update keeps |u|.
    #[test]
    fn implicit_coriolis_solve_and_norm_preservation() {
        let f = RotatingFrame::new(-40.0, [1.0, 2.0, -0.5], [0.0; 3]).unwrap();
        let rhs = Vec3::new(0.7, -1.1, 2.3);
        let v = f.solve_coriolis_implicit(rhs, 0.013);
        assert!((v + 0.013 * f.angular_velocity().cross(&v) - rhs).norm() < 1e-14);
        let u = Vec3::new(1.0, -2.0, 0.5);
        let after = dry_particle_update(&f, u, f.origin(), Vec3::zeros(), 0.05);
        assert!((after.norm() - u.norm()).abs() < 1e-14, "{} vs {}", after.norm(), u.norm());
    }

    /// Water with some velocity and acceleration, partly displaced by particles.
    fn moving_fluid() -> FluidAtParticle {
        FluidAtParticle {
            density: 998.2,
            kinematic_viscosity: 1.0034e-6,
            velocity: Vec3::new(0.2, -0.1, 0.05),
            material_acceleration: Vec3::new(-1.0, 0.3, 2.0),
            fluid_fraction: 0.8,
        }
    }

    /// At Ω = 0 the rotating-frame update is the inertial one.
    #[test]
    fn zero_rotation_reproduces_the_inertial_update() {
        let still = RotatingFrame::new(0.0, [0.0, 0.0, 1.0], [0.0; 3]).unwrap();
        let fluid = moving_fluid();
        let (u, r, g) = (Vec3::new(-0.3, 0.4, -0.6), Vec3::new(1.0, 2.0, 3.0), Vec3::new(0.0, 0.0, -9.81));
        let a = fluid_force_step(DragLaw::BrownLawler, u, 0.01, 2650.0, &fluid, g, 1e-3);
        let b = fluid_force_step_in_rotating_frame(&still, DragLaw::BrownLawler, u, r, 0.01, 2650.0, &fluid, g, 1e-3);
        assert!((a.velocity - b.velocity).norm() < 1e-15 * a.velocity.norm());
        assert!((a.fluid_acceleration_force - b.fluid_acceleration_force).norm() < 1e-12 * a.fluid_acceleration_force.norm());
        assert_eq!(a.drag_factor, b.drag_factor);
        assert!((dry_particle_update(&still, u, r, g, 1e-3) - (u + 1e-3 * g)).norm() < 1e-16);
    }

    /// The update's forces balance the particle's momentum change in the rotating frame:
    /// m_p (u' − u)/Δt = F_d + F_AM + F_pg + V(ρ_p − ρ_c) g + m_p a_fictitious(ū, r).
    #[test]
    fn forces_of_the_update_balance_the_momentum_change() {
        let f = frame();
        let fluid = moving_fluid();
        let (d, rho, g, dt) = (0.01, 2650.0, Vec3::new(0.0, 0.0, -9.81), 1e-3);
        let (u, r) = (Vec3::new(-0.3, 0.4, -0.6), Vec3::new(1.5, 0.2, -0.3));
        let step = fluid_force_step_in_rotating_frame(&f, DragLaw::BrownLawler, u, r, d, rho, &fluid, g, dt);
        let volume = std::f64::consts::PI * d.powi(3) / 6.0;
        let mass = rho * volume;
        let lhs = mass * (step.velocity - u) / dt;
        let rhs =
            step.drag + step.fluid_acceleration_force + volume * (rho - fluid.density) * g + mass * f.fictitious_acceleration(0.5 * (u + step.velocity), r);
        assert!((lhs - rhs).norm() < 1e-11 * lhs.norm(), "{lhs} vs {rhs}");
    }

    /// A particle at rest in fluid at rest in the frame starts off along the buoyancy-reduced
    /// centrifugal acceleration (ρ_p − ρ_c)/(ρ_p + C_AM ρ_c) Ω²r (§2.6 [R], reduced form).
    #[test]
    fn centrifugal_buoyancy_in_fluid_at_rest() {
        let f = RotatingFrame::new(10.0, [0.0, 0.0, 1.0], [0.0; 3]).unwrap();
        let fluid = FluidAtParticle::still(998.2, 1.0034e-6);
        let dt = 1e-9;
        let step = fluid_force_step_in_rotating_frame(&f, DragLaw::Stokes, Vec3::zeros(), Vec3::new(0.1, 0.0, 0.0), 0.001, 2650.0, &fluid, Vec3::zeros(), dt);
        let expected = (2650.0 - 998.2) / (2650.0 + ADDED_MASS_COEFFICIENT * 998.2) * 100.0 * 0.1;
        assert!((step.velocity.x / dt - expected).abs() < 1e-6 * expected, "{} vs {expected}", step.velocity.x / dt);
        // a neutrally buoyant particle stays where it is
        let neutral =
            fluid_force_step_in_rotating_frame(&f, DragLaw::Stokes, Vec3::zeros(), Vec3::new(0.1, 0.0, 0.0), 0.001, 998.2, &fluid, Vec3::zeros(), 1e-3);
        assert!(neutral.velocity.norm() < 1e-15, "{}", neutral.velocity);
    }
}
