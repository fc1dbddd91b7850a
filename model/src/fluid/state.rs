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
    /// The face flux one step back, φ^{n−1} (BDF2 part of the time-derivative flux correction,
    /// reference fluid module doc step 4d). Empty in checkpoints written before it existed:
    /// [`FluidState::fill_missing_old_flux`] then rebuilds it.
    #[serde(default)]
    pub flux_old: Vec<f64>,
    /// Fluid fraction α_c at the new, old and old-old time levels (1 without particles).
    pub alpha: Vec<f64>,
    pub alpha_old: Vec<f64>,
    pub alpha_old_old: Vec<f64>,
    /// Σ over steps of the global continuity error [m³] (spec U-31).
    pub cumulative_continuity_error: f64,
    /// k, ε and ν_t of the turbulence model (`[turbulence] model = "realizable-k-epsilon"`).
    pub turbulence: Option<crate::turbulence::TurbulenceState>,
    /// Per mesh point, its displacement along the followed wall's normal at tⁿ [m]
    /// (`[wear.fluid_mesh]`, crate::wear::fluid_mesh); empty on a mesh that does not deform.
    #[serde(default)]
    pub mesh_displacement: Vec<f64>,
    /// The same at tⁿ⁻¹: the last step's mesh motion, which the particles' Du/Dt at tⁿ takes
    /// (crate::fluid::sampling); empty on a mesh that does not deform.
    #[serde(default)]
    pub mesh_displacement_old: Vec<f64>,
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
            flux_old: vec![0.0; n_faces],
            alpha: vec![1.0; n_cells],
            alpha_old: vec![1.0; n_cells],
            alpha_old_old: vec![1.0; n_cells],
            cumulative_continuity_error: 0.0,
            turbulence: None,
            mesh_displacement: Vec::new(),
            mesh_displacement_old: Vec::new(),
        }
    }

    /// Whether every field has the length `mesh` asks for (cells, faces, boundary faces); the
    /// error names the mesh's sizes.
    pub fn check_matches(&self, mesh: &crate::mesh::Mesh) -> Result<(), String> {
        let (n, nf) = (mesh.n_cells(), mesh.n_faces());
        let ok = self.velocity.len() == n
            && self.velocity_old.len() == n
            && self.pressure.len() == n
            && self.alpha.len() == n
            && self.alpha_old.len() == n
            && self.alpha_old_old.len() == n
            && self.flux.len() == nf
            && self.flux_old.len() == nf
            && self.boundary_pressure.len() == nf - mesh.n_internal_faces;
        if !ok {
            return Err(format!("the fluid state does not match the mesh ({n} cells, {nf} faces)"));
        }
        match &self.turbulence {
            Some(t) => t.check_matches(n, nf - mesh.n_internal_faces),
            None => Ok(()),
        }
    }

    /// A checkpoint without φ^{n−1} (written before it was stored) gets the flux of the
    /// interpolated u^{n−1} on internal faces and φⁿ on boundary faces: the old-old part of
    /// the time-derivative flux correction then vanishes on the first step instead of using
    /// a flux that does not belong to u^{n−1}.
    pub fn fill_missing_old_flux(&mut self, mesh: &crate::mesh::Mesh) {
        if !self.flux_old.is_empty() || self.velocity_old.len() != mesh.cell_volumes.len() {
            return;
        }
        let mut flux_old = self.flux.clone();
        for (face, value) in flux_old.iter_mut().enumerate().take(mesh.n_internal_faces) {
            let (p, nb) = (mesh.face_owner[face], mesh.face_neighbour[face]);
            let w = mesh.face_weight[face];
            let u = crate::mesh::Vec3::from(self.velocity_old[p]) * w + crate::mesh::Vec3::from(self.velocity_old[nb]) * (1.0 - w);
            *value = u.dot(&mesh.face_areas[face]);
        }
        self.flux_old = flux_old;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn check_matches_names_the_mesh_sizes() {
        let mesh = crate::mesh::Mesh::rotor_stator(&crate::mesh::cylindrical::tests::rotor_stator()).unwrap();
        let mut state = FluidState::at_rest(mesh.n_cells(), mesh.n_faces(), mesh.n_internal_faces);
        assert_eq!(state.check_matches(&mesh), Ok(()));
        state.flux_old.pop();
        let message = state.check_matches(&mesh).unwrap_err();
        assert!(message.contains(&format!("{} cells, {} faces", mesh.n_cells(), mesh.n_faces())), "{message}");
    }

    /// A state serialised before `flux_old` existed still reads (empty `flux_old`).
    #[test]
    fn flux_old_defaults_to_empty_when_missing() {
        let mut value = serde_json::to_value(FluidState::at_rest(2, 7, 1)).unwrap();
        value.as_object_mut().unwrap().remove("flux_old");
        let state: FluidState = serde_json::from_value(value).unwrap();
        assert!(state.flux_old.is_empty());
        assert_eq!(state.flux.len(), 7);
    }
}
