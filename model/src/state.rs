//! The state one step of either solver maps to the next.

use crate::fluid::state::FluidState;
use crate::particles::state::ParticleState;
use crate::walls::state::WallState;

/// Everything needed to continue a run bit-for-bit: written to and read from checkpoints.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct State {
    /// Simulated time [s].
    pub time: f64,
    /// Steps taken.
    pub step: u64,
    /// Time step used for the last step [s] (needed by BDF2 after a restart).
    pub dt: f64,
    /// Rotor angle [rad].
    pub rotor_angle: f64,
    pub fluid: Option<FluidState>,
    pub particles: Option<ParticleState>,
    pub walls: Option<WallState>,
}
