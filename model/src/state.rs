//! The state one step of either solver maps to the next.

use crate::fluid::state::FluidState;
use crate::particles::state::ParticleState;
use crate::walls::state::WallState;
use crate::wear::state::WearState;

/// Everything needed to continue a run bit-for-bit: written to and read from checkpoints.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct State {
    /// Simulated time [s].
    pub time: f64,
    /// Steps taken.
    pub step: u64,
    /// Time step used for the last step [s] (needed by BDF2 after a restart).
    pub dt: f64,
    /// Rotor angle [rad]: the one stored copy of the rotor pose's angle (the mesh zone and the
    /// rotor walls are placed from it, [`crate::step::RotorPose`]).
    pub rotor_angle: f64,
    /// Largest Courant number of the last step (the adaptive Δt of the next step follows from
    /// it, so a restart continues with the same steps).
    pub courant: f64,
    /// Largest Δt the adaptive rule may take: set below a Δt at which a step diverged, and
    /// raised by 1 % per step after ([`crate::step::time_step`], issue 15).
    pub dt_limit: Option<f64>,
    pub fluid: Option<FluidState>,
    pub particles: Option<ParticleState>,
    pub walls: Option<WallState>,
    /// What the eroding walls have lost (`[wear]`).
    pub wear: Option<WearState>,
}
