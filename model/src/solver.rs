//! The interface both solvers implement.

use crate::closure::drag::FluidAtParticle;
use crate::coupling::CellLoad;
use crate::state::State;
use crate::step::ParticleLoad;

/// What one step did, for the progress bar and the time series.
#[derive(Clone, Debug, Default)]
pub struct StepReport {
    /// Named scalar diagnostics of this step (continuity error, Courant number, kinetic
    /// energy, outer iterations, particle counts…), in a fixed order.
    pub values: Vec<(&'static str, f64)>,
}

/// What the phases of a two-way coupled run exchanged in the last step, for output.
#[derive(Clone, Copy, Debug)]
pub struct CouplingOutput<'a> {
    /// The particle load mapped to the cells, in cell order.
    pub cells: &'a CellLoad,
    /// The particle load (drag, slip Reynolds number…), in particle order.
    pub particles: &'a ParticleLoad,
    /// The fluid each particle saw in the step, in particle order.
    pub fluid_at_particles: &'a [Option<FluidAtParticle>],
}

/// Why a step failed.
#[derive(Debug, thiserror::Error)]
pub enum SolverError {
    #[error("the case cannot be run by this solver: {0}")]
    Unsupported(String),
    #[error("the solution diverged at step {step} (t = {time} s): {what}")]
    Diverged { step: u64, time: f64, what: String },
    #[error("a linear solve failed: {0}")]
    LinearSolve(String),
}

/// One time-stepping solver of the spillage model.
pub trait Solver {
    /// `"reference"` or `"fast"`.
    fn name(&self) -> &'static str;
    /// Advances the state by one time step and writes what it did into `report`, replacing
    /// its previous values. A time loop that passes the same report every step lets a solver
    /// reuse the report's storage (the fast solver clears and refills it, no allocation);
    /// on error the report's contents are unspecified.
    fn step_into(&mut self, report: &mut StepReport) -> Result<(), SolverError>;
    /// Advances the state by one time step and returns a new report (allocates; for callers
    /// outside a time loop).
    fn step(&mut self) -> Result<StepReport, SolverError> {
        let mut report = StepReport::default();
        self.step_into(&mut report)?;
        Ok(report)
    }
    /// The current state.
    fn state(&self) -> &State;
    /// The mesh at the current time (rotor turned), for output; `None` for particle-only runs.
    fn mesh(&self) -> Option<&crate::mesh::Mesh> {
        None
    }
    /// The coupling exchange of the last step, for output; `None` unless the run is two-way
    /// coupled and has taken a step.
    fn coupling_output(&self) -> Option<CouplingOutput<'_>> {
        None
    }
}
