//! The fluid state: everything the fluid solvers need to continue a run bit-for-bit.

/// Fluid fields on the mesh (cell-centred, SI units; pressure is kinematic, P = p/ρ, spec §8.1).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FluidState {
    /// Cell velocity u^n [m/s] (absolute frame, spec §4.1).
    pub velocity: Vec<[f64; 3]>,
    /// Cell velocity one step back, u^{n−1} (BDF2).
    pub velocity_old: Vec<[f64; 3]>,
    /// Kinematic pressure P^n [m²/s²].
    pub pressure: Vec<f64>,
    /// Kinematic pressure on each boundary face (index = face − n_internal_faces); needed by
    /// the pressure gradient at the start of the next step (fixed-flux condition, spec §8.8).
    pub boundary_pressure: Vec<f64>,
    /// Absolute volumetric flux u·S through every mesh face [m³/s], in the direction of the
    /// face's area vector. On a sliding-interface face it is the sum of its overlap fluxes,
    /// out of that face's cell.
    pub flux: Vec<f64>,
    /// Fluid fraction α_c at the new, old and old-old time levels (1 without particles).
    pub alpha: Vec<f64>,
    pub alpha_old: Vec<f64>,
    pub alpha_old_old: Vec<f64>,
    /// Σ over steps of the global continuity error [m³] (spec U-31).
    pub cumulative_continuity_error: f64,
}

impl FluidState {
    /// A fluid at rest, zero pressure, α_c = 1.
    pub fn at_rest(n_cells: usize, n_faces: usize, n_internal_faces: usize) -> Self {
        Self {
            velocity: vec![[0.0; 3]; n_cells],
            velocity_old: vec![[0.0; 3]; n_cells],
            pressure: vec![0.0; n_cells],
            boundary_pressure: vec![0.0; n_faces - n_internal_faces],
            flux: vec![0.0; n_faces],
            alpha: vec![1.0; n_cells],
            alpha_old: vec![1.0; n_cells],
            alpha_old_old: vec![1.0; n_cells],
            cumulative_continuity_error: 0.0,
        }
    }
}
