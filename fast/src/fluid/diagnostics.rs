//! Per-step diagnostics (module doc of `spillage_reference::fluid`, "Diagnostics"; reference
//! `diagnostics`): continuity errors (spec U-31), the largest Courant number (T4.44), the
//! kinetic energy and the sliding-interface flux imbalance. Sums and maxima are fixed-order
//! reductions ([`Reducer`]), so they do not depend on the thread count.

use super::assembly::{par_for, Out};
use super::buffers::DiagnosticBuffers;
use super::layout::Links;
use super::pressure_corrector::cell_mesh_flux_share;
use super::step_inputs::{Discretisation, StepSolution, TimeStep, VolumeFractions};
use crate::linear::reduce::Reducer;

/// The diagnostics of one step.
#[derive(Clone, Copy, Debug)]
pub struct StepDiagnostics {
    /// Δt Σ_c |e_c| [m³].
    pub continuity_local: f64,
    /// Δt max_c |e_c| [m³] (the thesis' V_err,local, particle-verification.md §3).
    pub continuity_cell_max: f64,
    /// Δt Σ_c e_c [m³].
    pub continuity_global: f64,
    /// max_c ½Δt Σ_f |φ_f − φ_mesh,f| / V.
    pub courant_max: f64,
    /// ½ Σ α|u|²V [m⁵/s²].
    pub kinetic_energy: f64,
    /// |Σ_rotor-side φ + Σ_stator-side φ| / Σ_overlaps |φ| (0 without interface flow).
    pub interface_imbalance: f64,
}

/// All diagnostics of the step. Leaves the summed overlap fluxes of every sliding-interface face
/// in `work` (`interface_face_flux`, `on_interface`) for [`super::finish_step`].
pub fn step_diagnostics(
    disc: &Discretisation,
    time: TimeStep,
    alpha: VolumeFractions,
    solution: StepSolution,
    work: &mut DiagnosticBuffers,
    reducer: &mut Reducer,
) -> StepDiagnostics {
    let n = disc.n_cells();
    let dt = time.dt;
    continuity_errors_and_courant(disc, time, alpha, solution, work);
    let (errors, courant, u, vol, a) = (&work.continuity_error, &work.courant, solution.velocity, disc.cell_volumes, alpha.current);
    let [sum_abs, sum] = reducer.sum2(n, |c| [errors[c].abs(), errors[c]]);
    let courant_max = reducer.max(n, |c| courant[c]).max(0.0);
    let cell_max = reducer.max(n, |c| errors[c].abs()).max(0.0);
    let kinetic_energy = reducer.sum(n, |c| 0.5 * a[c] * (u[0][c] * u[0][c] + u[1][c] * u[1][c] + u[2][c] * u[2][c]) * vol[c]);
    let throughput = overlap_fluxes_onto_faces(disc.links, solution.link_flux, work);
    StepDiagnostics {
        continuity_local: dt * sum_abs,
        continuity_cell_max: dt * cell_max,
        continuity_global: dt * sum,
        courant_max,
        kinetic_energy,
        interface_imbalance: interface_imbalance(work, throughput),
    }
}

/// Per cell: the continuity error e_c = ∂α/∂t V + Σ_f α_f (φ_f − φ_mesh,f) (the mesh fluxes' sum,
/// zero for a rigid rotation, left out: spillage_model::fluid::moving_cells) and the Courant number
/// ½Δt Σ_f |φ_f − φ_mesh,f| / V.
fn continuity_errors_and_courant(disc: &Discretisation, time: TimeStep, alpha: VolumeFractions, solution: StepSolution, work: &mut DiagnosticBuffers) {
    let (links, adj, bnd, vol) = (disc.links, disc.adjacency, disc.boundary, disc.cell_volumes);
    let (link_flux, boundary_flux) = (solution.link_flux, solution.boundary_flux);
    let a = alpha.current;
    let dt = time.dt;
    let (out_error, out_courant) = (Out::of(&mut work.continuity_error), Out::of(&mut work.courant));
    par_for(disc.n_cells(), |c| {
        let mut error = disc.alpha_rate_volume(alpha, time, c) - cell_mesh_flux_share(disc, a, c);
        let mut relative_flux_sum = 0.0;
        for k in adj.row_start[c] as usize..adj.row_start[c + 1] as usize {
            let e = adj.entry[k] as usize;
            let l = e >> 1;
            let alpha_f = links.interpolate(l, a[links.owner[l] as usize], a[links.neighbour[l] as usize]);
            if e & 1 == 1 {
                error += alpha_f * link_flux[l];
            } else {
                error -= alpha_f * link_flux[l];
            }
            relative_flux_sum += (link_flux[l] - links.mesh_flux[l]).abs();
        }
        for &b in disc.boundary_faces_of(c) {
            let b = b as usize;
            error += a[c] * boundary_flux[b];
            relative_flux_sum += (boundary_flux[b] - bnd.mesh_flux[b]).abs();
        }
        unsafe {
            out_error.set(c, error);
            out_courant.set(c, 0.5 * dt * relative_flux_sum / vol[c]);
        }
    });
}

/// Sums every overlap link's flux onto its rotor face (+) and stator face (−) and marks those
/// faces; returns the throughput Σ_overlaps |φ|.
fn overlap_fluxes_onto_faces(links: &Links, link_flux: &[f64], work: &mut DiagnosticBuffers) -> f64 {
    let n_overlaps = links.len() - links.n_internal;
    for k in 0..n_overlaps {
        work.interface_face_flux[links.rotor_face[k] as usize] = 0.0;
        work.interface_face_flux[links.stator_face[k] as usize] = 0.0;
    }
    let mut throughput = 0.0;
    for k in 0..n_overlaps {
        let l = links.n_internal + k;
        let (rotor_face, stator_face) = (links.rotor_face[k] as usize, links.stator_face[k] as usize);
        work.interface_face_flux[rotor_face] += link_flux[l];
        work.interface_face_flux[stator_face] -= link_flux[l];
        work.on_interface[rotor_face] = true;
        work.on_interface[stator_face] = true;
        throughput += link_flux[l].abs();
    }
    throughput
}

/// |Σ of the interface faces' summed fluxes| / throughput, in face order (0 without flow).
fn interface_imbalance(work: &DiagnosticBuffers, throughput: f64) -> f64 {
    if throughput == 0.0 {
        return 0.0;
    }
    let mut net = 0.0;
    for (flux, &on_interface) in work.interface_face_flux.iter().zip(&work.on_interface) {
        if on_interface {
            net += flux;
        }
    }
    net.abs() / throughput
}
