//! The non-contact part of a DEM sub-step, the same in both particle phases: the implicit
//! fluid-force update of one particle (fluid-dem-model.md §5.10), gravity, the rotating frame's
//! fictitious forces (wear-model.md §2.6 [R]), and what the fluid receives in return (§8.4).

use super::settings::{FluidForces, Motion};
use super::state::Vec3;
use crate::closure::drag::{fluid_force_step, held_fluid_force, DragLaw, FluidAtParticle, FluidForceStep};
use crate::closure::drag_and_buoyancy::drag_and_buoyancy_step;
use crate::closure::rotating_frame::{dry_particle_update, fluid_force_step_in_rotating_frame, RotatingFrame};
use crate::coupling::Feedback;
use crate::step::ParticleLoad;

/// The forces on a particle other than contacts, as the case sets them up.
#[derive(Clone, Debug)]
pub struct NonContactForces {
    pub drag_law: DragLaw,
    pub gravity: Vec3,
    /// The case's rotating frame, if any.
    pub rotating_frame: Option<RotatingFrame>,
    /// With `[coupling]`: which forces the fluid receives.
    pub feedback: Option<Feedback>,
    /// `[particles] motion`: held particles keep their velocity ([`Motion::Held`]).
    pub motion: Motion,
    /// `[particles] fluid_forces`: the full set or the wear model's drag and buoyancy.
    pub fluid_forces: FluidForces,
}

/// A particle's share of the step's load from one update of length `dt`, as time integrals
/// (∫K dt, ∫(K u_p − F_AM − F_pg) dt, ∫F_d dt) and the update's slip Reynolds number.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LoadShare {
    pub implicit_drag: f64,
    pub explicit_force: Vec3,
    pub drag: Vec3,
    pub slip_reynolds: f64,
}

impl NonContactForces {
    /// The velocity after the implicit fluid-force update over `dt` (§5.10) of a particle
    /// (`diameter`, `density`, at `position`), and, two-way coupled, its load share:
    /// ∫K dt and ∫(K u_p − F_AM − F_pg) dt (§8.4), with −∫V_p(ρ_p − ρ_c) g dt more for the
    /// literal feedback (§2.6).
    ///
    /// In a rotating frame (wear-model.md §2.6 [R]) the update adds −2Ω×u_p − Ω×(Ω×r) per unit
    /// particle mass. With a fluid (coupled, or the still `[particles.ambient]` fluid, at rest
    /// in the frame) the particle equation carries the pressure-gradient force, taken on the
    /// fluid's acceleration relative to an inertial frame, which supplies the centrifugal
    /// buoyancy ([`fluid_force_step_in_rotating_frame`]). Without any fluid (particle-only, no
    /// ambient) nothing supplies buoyancy and the full per-unit-mass form applies
    /// ([`dry_particle_update`]). Either way the Coriolis part is trapezoidal in u_p, which
    /// keeps the sub-step symmetric (and second order without drag).
    ///
    /// A held particle ([`Motion::Held`]) keeps `velocity`; its load share is that of the fluid
    /// forces at the held velocity ([`held_fluid_force`]), fed back as for a free particle.
    pub fn update(
        &self,
        velocity: Vec3,
        position: Vec3,
        diameter: f64,
        density: f64,
        volume: f64,
        fluid: Option<&FluidAtParticle>,
        dt: f64,
    ) -> (Vec3, Option<LoadShare>) {
        let Some(fluid) = fluid else {
            let velocity = match (&self.rotating_frame, self.motion) {
                (_, Motion::Held) => velocity,
                (None, Motion::Free) => velocity + dt * self.gravity,
                (Some(frame), Motion::Free) => dry_particle_update(frame, velocity, position, self.gravity, dt),
            };
            return (velocity, None);
        };
        let step = match &self.rotating_frame {
            _ if self.motion == Motion::Held => {
                let mut held = held_fluid_force(self.drag_law, velocity, diameter, fluid);
                if self.fluid_forces == FluidForces::DragAndBuoyancy {
                    held.fluid_acceleration_force = Vec3::zeros();
                }
                held
            }
            frame if self.fluid_forces == FluidForces::DragAndBuoyancy => {
                drag_and_buoyancy_step(frame.as_ref(), self.drag_law, velocity, position, diameter, density, fluid, self.gravity, dt)
            }
            None => fluid_force_step(self.drag_law, velocity, diameter, density, fluid, self.gravity, dt),
            Some(frame) => fluid_force_step_in_rotating_frame(frame, self.drag_law, velocity, position, diameter, density, fluid, self.gravity, dt),
        };
        let share = self.feedback.map(|feedback| LoadShare::of_update(feedback, &step, volume, density, fluid.density, self.gravity, dt));
        (step.velocity, share)
    }
}

impl LoadShare {
    /// Adds the share of a later update of the step: the integrals add up, the slip Reynolds
    /// number is the latest update's.
    #[inline]
    pub fn add(&mut self, later: &LoadShare) {
        self.implicit_drag += later.implicit_drag;
        self.explicit_force += later.explicit_force;
        self.drag += later.drag;
        self.slip_reynolds = later.slip_reynolds;
    }

    /// The share of one fluid-force update `step` of length `dt` (particle `volume` and
    /// `density` in a fluid of `fluid_density`): ∫K dt and ∫(K u_p − F_AM − F_pg) dt (§8.4),
    /// with −∫V_p(ρ_p − ρ_c) g dt more for the literal feedback (§2.6).
    #[inline(always)]
    pub fn of_update(feedback: Feedback, step: &FluidForceStep, volume: f64, density: f64, fluid_density: f64, gravity: Vec3, dt: f64) -> Self {
        let mut explicit = step.explicit_feedback();
        if feedback == Feedback::Literal {
            explicit -= volume * (density - fluid_density) * gravity;
        }
        LoadShare { implicit_drag: step.drag_factor * dt, explicit_force: explicit * dt, drag: step.drag * dt, slip_reynolds: step.slip_reynolds }
    }
}

impl ParticleLoad {
    /// Adds particle `i`'s share of one update (ignored beyond the load's particles).
    pub fn accumulate(&mut self, i: usize, share: &LoadShare) {
        if i >= self.volume.len() {
            return;
        }
        self.implicit_drag[i] += share.implicit_drag;
        for k in 0..3 {
            self.explicit_force[i][k] += share.explicit_force[k];
            self.drag[i][k] += share.drag[k];
        }
        self.slip_reynolds[i] = share.slip_reynolds;
    }
}

impl ParticleLoad {
    /// Turns the time integrals summed over a step of length `dt` into the step's averages
    /// (§5.10: "accumulate the time average over the sub-steps") and sets the volumes of
    /// `particles` (in the load's order).
    pub fn time_average(&mut self, particles: &[super::state::Particle], dt: f64) {
        for (i, p) in particles.iter().enumerate() {
            self.volume[i] = p.volume();
            self.implicit_drag[i] /= dt;
            for k in 0..3 {
                self.explicit_force[i][k] /= dt;
                self.drag[i][k] /= dt;
            }
        }
    }
}
