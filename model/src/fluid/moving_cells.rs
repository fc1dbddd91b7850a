//! The water's continuity in cells that move with a rotor (fluid-dem-model.md §2.3 T3.89 in the
//! ALE form of §4.1): d/dt ∫_V(t) α_c dV + ∮ α_c (u − u_mesh)·dS = 0.
//!
//! Both solvers hold α_c per cell and shift its time levels cell by cell, so their ∂α_c/∂t
//! follows the moving cells, and their face fluxes φ_f are absolute. Each face therefore owes
//! the continuity −α_f φ_mesh,f beside α_f φ_f. A rigid rotation's mesh fluxes sum to zero over
//! every closed cell (the space-conservation law of §4.1), so only the particles' share
//! (α_f − 1) φ_mesh,f is left. It is exactly zero without particles or on a mesh that stands
//! still, so water-only runs keep their bits. Without it, a rock at rest next to turning cells
//! pushed the water aside as if it swept against them, and a rock riding with the rotor
//! displaced no water at all (cases/verification/coupling/rock_at_rest_in_turning_cells.toml:
//! the rock at rest sees the water move at 4.7e-2 of the sweeping speed without the share,
//! 3.4e-3 with it).

/// The particles' share (α_f − 1) φ_mesh,f [m³/s] of a face's mesh flux that the face's
/// outflow α_f φ_f leaves out of the continuity of the cell it leaves: cell P's equation reads
/// ∂(α_c V)/∂t + Σ_f [α_f φ_f − particle_share_of_mesh_flux(α_f, φ_mesh,f)] = 0, the faces
/// oriented out of P.
#[inline]
pub fn particle_share_of_mesh_flux(alpha_face: f64, mesh_flux: f64) -> f64 {
    (alpha_face - 1.0) * mesh_flux
}
