//! Per-step diagnostics of the fluid solution (spec U-31, T4.44).

use spillage_model::mesh::Vec3;

use super::geometry::{Geometry, LinkOrigin};
use super::momentum::StepInputs;

/// Continuity errors e_c = ∂α/∂t V + Σ_f α_f (φ_f − φ_mesh,f) per cell [m³/s] (the mesh
/// fluxes' sum over a cell, zero for a rigid rotation, left out: `moving_cells`).
pub fn continuity_errors(inputs: &StepInputs, link_flux: &[f64], boundary_flux: &[f64]) -> Vec<f64> {
    let geo = inputs.geo;
    let shares = inputs.mesh_flux_shares_per_cell();
    let mut e: Vec<f64> = (0..geo.n_cells()).map(|c| inputs.alpha_rate_volume(c) - shares[c]).collect();
    for (l, link) in geo.links.iter().enumerate() {
        let alpha_f = link.interpolate(inputs.alpha[link.owner], inputs.alpha[link.neighbour]);
        e[link.owner] += alpha_f * link_flux[l];
        e[link.neighbour] -= alpha_f * link_flux[l];
    }
    for (b, face) in geo.boundary.iter().enumerate() {
        e[face.cell] += inputs.alpha[face.cell] * boundary_flux[b];
    }
    e
}

/// Largest cell Courant number ½Δt Σ|φ − φ_mesh|/V.
pub fn max_courant(geo: &Geometry, volumes: &[f64], dt: f64, link_flux: &[f64], boundary_flux: &[f64]) -> f64 {
    let mut sum = vec![0.0; geo.n_cells()];
    for (l, link) in geo.links.iter().enumerate() {
        let f = (link_flux[l] - link.mesh_flux).abs();
        sum[link.owner] += f;
        sum[link.neighbour] += f;
    }
    for (b, face) in geo.boundary.iter().enumerate() {
        sum[face.cell] += (boundary_flux[b] - face.mesh_flux).abs();
    }
    sum.iter().zip(volumes).map(|(s, v)| 0.5 * dt * s / v).fold(0.0, f64::max)
}

/// ½ Σ α|u|²V.
pub fn kinetic_energy(u: &[Vec3], alpha: &[f64], volumes: &[f64]) -> f64 {
    u.iter().zip(alpha).zip(volumes).map(|((u, a), v)| 0.5 * a * u.norm_squared() * v).sum()
}

/// Interface flux imbalance |Σ_rotor faces φ_out + Σ_stator faces φ_out| / Σ_overlaps |φ|, with
/// every face flux summed from its overlaps (0 when there is no interface or no flow).
pub fn interface_imbalance(geo: &Geometry, link_flux: &[f64], n_faces: usize) -> f64 {
    let mut face_flux = vec![0.0; n_faces];
    let mut used = vec![false; n_faces];
    let mut throughput = 0.0;
    for (l, link) in geo.links.iter().enumerate() {
        if let LinkOrigin::Interface { rotor_face, stator_face } = link.origin {
            face_flux[rotor_face] += link_flux[l];
            face_flux[stator_face] -= link_flux[l];
            used[rotor_face] = true;
            used[stator_face] = true;
            throughput += link_flux[l].abs();
        }
    }
    if throughput == 0.0 {
        return 0.0;
    }
    let net: f64 = face_flux.iter().zip(&used).filter(|(_, u)| **u).map(|(f, _)| f).sum();
    net.abs() / throughput
}
