//! A step whose fluid diverges is taken again, from the state of its start, with half the step
//! (issue 15, "time stepping that does not fall over").
//!
//! - With `[time] max_courant` (adaptive stepping) the first halved step that converges is
//!   kept and the run goes on; the adaptive rule then grows Δt again by at most 20 % per step.
//!   Each step's halvings go to `series.csv` as `dt_halvings`.
//! - With a fixed `[time] dt` the run stops, but first finds by the same halvings a Δt with
//!   which the step converges, so that the error names it, the Courant number it reaches and
//!   the one the case's Δt implies.
//!
//! What counts as a diverged fluid: a failed linear solve, a non-finite field or Courant number,
//! or an outer loop that made no progress ([`crate::step::FluidStepOutcome::outer_loop_failure`]). A failing
//! particle phase (a DEM fault) or a case the solver cannot run is not retried: the DEM's
//! sub-steps follow the collision time, not Δt.
//!
//! The state of the step's start is kept by cloning it before every step of a run with a fluid
//! (one copy of the state: 2.4 MB for the shipped cutter head, whose steps take 0.17 s, so well
//! under 1 % of a step).

use super::*;
use crate::step::time_step::DT_LIMIT_GROWTH;

/// Halvings tried on a diverging step: down to 1/32 of it. A step that diverges even then has
/// a cause a smaller step does not cure (a boundary condition, the mesh).
pub const MAX_HALVINGS: u32 = 5;

impl<F: FluidPhase, P: ParticlePhase> Coupled<F, P> {
    /// One step of the size the case asks for, retried with a smaller Δt if its fluid diverges
    /// (module doc). Every step of a run with a fluid reports `dt_halvings`.
    pub fn advance(&mut self, report: &mut StepReport) -> Result<(), SolverError> {
        let dt = self.next_dt()?;
        if self.fluid.is_none() {
            return self.advance_by(dt, report);
        }
        let start = self.state.clone();
        let adaptive = matches!(self.time_step, TimeStepControl::Courant { .. });
        let diverged = match self.advance_by(dt, report) {
            Ok(()) => {
                if let Some(limit) = self.state.dt_limit.as_mut().filter(|_| adaptive) {
                    *limit *= DT_LIMIT_GROWTH;
                }
                report.values.push(("dt_halvings", 0.0));
                return Ok(());
            }
            Err(e) if self.failed_in_fluid => e,
            Err(e) => return Err(e),
        };
        for halving in 1..=MAX_HALVINGS {
            self.rewind(&start);
            let smaller = dt / f64::from(1u32 << halving);
            match self.advance_by(smaller, report) {
                Ok(()) if adaptive => {
                    // between the Δt that converged and the one that did not
                    self.state.dt_limit = Some(smaller * std::f64::consts::SQRT_2);
                    report.values.push(("dt_halvings", f64::from(halving)));
                    return Ok(());
                }
                Ok(()) => {
                    let numbers = StepNumbers { courant: self.state.courant, diffusion: self.diffusion_number(smaller) };
                    self.rewind(&start);
                    return Err(fixed_step_diverged(&start, dt, &diverged, smaller, numbers));
                }
                Err(_) if self.failed_in_fluid => {}
                Err(e) => return Err(e),
            }
        }
        self.rewind(&start);
        let step = start.step + 1;
        Err(SolverError::Diverged {
            step,
            time: start.time + dt,
            what: format!(
                "{}; the step diverges with every Δt down to {:e} s (1/{} of {dt:e} s), so a smaller time step will not cure it: check the boundary conditions and the mesh (`spillage check`)",
                cause(&diverged),
                dt / f64::from(1u32 << MAX_HALVINGS),
                1u32 << MAX_HALVINGS
            ),
        })
    }

    /// Largest cell diffusion number ½ Δt ν_eff Σ_f |A_f| / (|d_f| V) of the current fluid state
    /// (internal faces; on a uniform grid ν Δt (1/Δx² + 1/Δy² + …)).
    fn diffusion_number(&self, dt: f64) -> f64 {
        let (Some(phase), Some(fluid)) = (self.fluid.as_ref(), self.state.fluid.as_ref()) else {
            return 0.0;
        };
        let mesh = phase.mesh();
        let nu = phase.sample_source(fluid).kinematic_viscosity;
        let mut conductance = vec![0.0; mesh.n_cells()];
        for f in 0..mesh.n_internal_faces {
            let w = mesh.face_areas[f].norm() / mesh.face_delta[f].norm();
            conductance[mesh.face_owner[f]] += w;
            conductance[mesh.face_neighbour[f]] += w;
        }
        let eddy = fluid.turbulence.as_ref().map(|t| t.nu_t.as_slice());
        (0..mesh.n_cells()).map(|c| 0.5 * dt * (nu + eddy.map_or(0.0, |e| e[c])) * conductance[c] / mesh.cell_volumes[c]).fold(0.0, f64::max)
    }

    /// Back to the state of the step's start, with the phases told to forget the rejected step.
    fn rewind(&mut self, start: &State) {
        self.state.clone_from(start);
        if let Some(fluid) = self.fluid.as_mut() {
            fluid.rewind(start.dt);
        }
        if let (Some(phase), Some(particles)) = (self.particles.as_mut(), start.particles.as_ref()) {
            phase.rewind(particles);
        }
    }
}

/// The Courant and diffusion numbers of a converged step.
struct StepNumbers {
    courant: f64,
    diffusion: f64,
}

/// What diverged, without the "diverged at step …" its error message starts with.
fn cause(error: &SolverError) -> String {
    match error {
        SolverError::Diverged { what, .. } => what.clone(),
        other => other.to_string(),
    }
}

/// The error of a fixed-Δt step that diverged, naming the Δt with which it converges.
fn fixed_step_diverged(start: &State, dt: f64, diverged: &SolverError, smaller: f64, at_smaller: StepNumbers) -> SolverError {
    // the same flow at a larger step: both numbers scale with Δt
    let scale = dt / smaller;
    let StepNumbers { courant, diffusion } = at_smaller;
    SolverError::Diverged {
        step: start.step + 1,
        time: start.time + dt,
        what: format!(
            "with Δt = {dt:e} s: {}. The same step converges with Δt = {smaller:e} s, where its Courant number is {courant:.3} and its diffusion number ν Δt/Δx² {diffusion:.3} \
             (so Δt = {dt:e} s means a Courant number of about {:.3} and a diffusion number of {:.3}). \
             Set [time] dt = {smaller:e} or smaller, or let Δt adapt with [time] max_courant in place of dt (a diverging step is then taken again with half the step); \
             more PISO correctors ([numerics] piso_correctors = 2 or 3) or under-relaxation (relax_velocity = 0.7, relax_pressure = 0.3) can also let the outer loop converge at a larger Δt",
            cause(diverged),
            courant * scale,
            diffusion * scale
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fixed_step_error_names_both_steps_and_the_courant_numbers() {
        let start = State { step: 0, time: 0.0, ..State::default() };
        let cause = SolverError::LinearSolve("momentum predictor: did not converge".into());
        let e = fixed_step_diverged(&start, 0.05, &cause, 0.0125, StepNumbers { courant: 0.21, diffusion: 0.26 }).to_string();
        for part in [
            "step 1",
            "Δt = 5e-2 s",
            "momentum predictor",
            "converges with Δt = 1.25e-2 s",
            "Courant number is 0.210",
            "diffusion number ν Δt/Δx² 0.260",
            "Courant number of about 0.840",
            "diffusion number of 1.040",
            "dt = 1.25e-2",
            "max_courant",
        ] {
            assert!(e.contains(part), "{part:?} missing from: {e}");
        }
    }
}
