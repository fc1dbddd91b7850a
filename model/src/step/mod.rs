//! One step, one pipeline (DESIGN.md; spec fluid-dem-model.md §8.7, Algorithm 1).
//!
//! - [`rotor_pose`]: the rotor's pose, stored once (as `State::rotor_angle`) and handed to every
//!   consumer; the one rigid-body velocity function.
//! - [`context`]: the clock of one step (Δt, time coefficients, rotor pose at both ends).
//! - [`time_step`]: fixed Δt or Δt from the Courant number.
//! - [`phases`]: the `FluidPhase`, `ParticlePhase` and `WearPhase` traits the solvers implement.
//! - [`coupled`]: the driver, the only thing that advances time.

pub mod context;
pub mod coupled;
pub mod phases;
pub mod rotor_pose;
pub mod time_step;

pub use context::{time_coefficients, StepContext};
pub use coupled::{check_state_matches_case, Coupled, FluidOnly, ParticlesOnly};
pub use phases::{Absent, FluidPhase, FluidStepOutcome, ParticleLoad, ParticlePhase, WearPhase};
pub use rotor_pose::{rigid_rotation_velocity, RotorPose, RotorZone};
pub use time_step::{reached_end_time, TimeStepControl};
