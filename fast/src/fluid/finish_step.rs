//! Step 5 of the algorithm (module doc of `spillage_reference::fluid`): the step's solution
//! goes into the fluid state and the time levels shift — uᵒ ← u, u ← u*, P, φᵒ ← φ, φ ← φ* (overlap
//! fluxes summed onto their rotor and stator faces), boundary pressures, α levels, the
//! cumulative continuity error — and the step report is written.

use spillage_model::fluid::state::FluidState;
use spillage_model::solver::StepReport;

use super::buffers::DiagnosticBuffers;
use super::diagnostics::StepDiagnostics;
use super::layout::{Boundary, Links};
use super::step_inputs::StepSolution;

/// Writes `solution` into `fluid` and shifts the time levels. `interface` holds the summed
/// overlap fluxes of the sliding-interface faces ([`super::diagnostics::step_diagnostics`]);
/// their marks are cleared for the next step.
pub fn shift_time_levels(
    fluid: &mut FluidState,
    links: &Links,
    boundary: &Boundary,
    n_internal_faces: usize,
    solution: StepSolution,
    interface: &mut DiagnosticBuffers,
    continuity_global: f64,
) {
    let u = solution.velocity;
    for (c, (velocity, velocity_old)) in fluid.velocity.iter_mut().zip(fluid.velocity_old.iter_mut()).enumerate() {
        *velocity_old = *velocity;
        *velocity = [u[0][c], u[1][c], u[2][c]];
    }
    fluid.pressure.copy_from_slice(solution.pressure);
    std::mem::swap(&mut fluid.flux, &mut fluid.flux_old);
    fluid.flux.fill(0.0);
    fluid.flux[..links.n_internal].copy_from_slice(&solution.link_flux[..links.n_internal]);
    for (f, on_interface) in interface.on_interface.iter_mut().enumerate() {
        if *on_interface {
            fluid.flux[f] = interface.interface_face_flux[f];
            *on_interface = false;
        }
    }
    for b in 0..boundary.len() {
        let face = boundary.face[b] as usize;
        fluid.flux[face] = solution.boundary_flux[b];
        fluid.boundary_pressure[face - n_internal_faces] = solution.boundary_pressure[b];
    }
    fluid.alpha_old_old.copy_from_slice(&fluid.alpha_old);
    fluid.alpha_old.copy_from_slice(&fluid.alpha);
    fluid.cumulative_continuity_error += continuity_global;
}

/// What the step report says besides the diagnostics.
pub struct StepTotals {
    pub continuity_cumulative: f64,
    pub outer_iterations: usize,
    /// Initial pressure residual of the last outer iteration.
    pub p_initial_residual: f64,
}

/// Appends the fluid's values to `report` (the driver clears it at the start of the step and
/// adds the clock and the rotor angle; a report reused across steps keeps its storage).
pub fn write_report(report: &mut StepReport, diagnostics: &StepDiagnostics, totals: &StepTotals) {
    report.values.extend_from_slice(&[
        ("courant_max", diagnostics.courant_max),
        ("continuity_local", diagnostics.continuity_local),
        ("continuity_cell_max", diagnostics.continuity_cell_max),
        ("continuity_global", diagnostics.continuity_global),
        ("continuity_cumulative", totals.continuity_cumulative),
        ("kinetic_energy", diagnostics.kinetic_energy),
        ("outer_iterations", totals.outer_iterations as f64),
        ("p_initial_residual", totals.p_initial_residual),
        ("interface_imbalance", diagnostics.interface_imbalance),
    ]);
}
