//! The turbulence fields a run carries from step to step (part of the fluid state, so
//! checkpoints restart bit-for-bit), and the effective viscosity the momentum equation reads.

/// Lower bounds of k [m²/s²] and ε [m²/s³] after each solve (OpenFOAM's `kMin`, `epsilonMin`
/// are `small` = 1e-15; the same here, so a bounded cell stays finite in ν_t = C_μ k²/ε).
pub const K_MIN: f64 = 1e-15;
pub const EPSILON_MIN: f64 = 1e-15;

/// k, ε and the eddy viscosities of the k–ε model at the end of a step.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TurbulenceState {
    /// Turbulent kinetic energy per cell [m²/s²].
    pub k: Vec<f64>,
    /// Dissipation rate per cell [m²/s³].
    pub epsilon: Vec<f64>,
    /// Eddy viscosity ν_t = C_μ k²/ε per cell [m²/s].
    pub nu_t: Vec<f64>,
    /// Eddy viscosity on each boundary face (index = face − n_internal_faces) [m²/s]: the wall
    /// function's ν_t,w on walls, the cell's ν_t on other boundaries.
    pub nu_t_boundary: Vec<f64>,
    /// y⁺ of each boundary face (0 on boundaries that are not walls).
    pub y_plus: Vec<f64>,
}

impl TurbulenceState {
    /// Uniform k and ε with the eddy viscosity they give at the standard C_μ,
    /// ν_t = C_μ k²/ε, in the cells and on every boundary face (the first step's momentum
    /// equation; no velocity gradient is known yet for the realizable C_μ, and starting from
    /// ν_t = 0 would run the first step laminar, far from the turbulent solution).
    pub fn uniform(n_cells: usize, n_boundary_faces: usize, k: f64, epsilon: f64, c_mu: f64) -> Self {
        let nu_t = c_mu * k * k / epsilon;
        Self {
            k: vec![k; n_cells],
            epsilon: vec![epsilon; n_cells],
            nu_t: vec![nu_t; n_cells],
            nu_t_boundary: vec![nu_t; n_boundary_faces],
            y_plus: vec![0.0; n_boundary_faces],
        }
    }

    pub fn check_matches(&self, n_cells: usize, n_boundary_faces: usize) -> Result<(), String> {
        let ok = [self.k.len(), self.epsilon.len(), self.nu_t.len()].iter().all(|&n| n == n_cells)
            && self.nu_t_boundary.len() == n_boundary_faces
            && self.y_plus.len() == n_boundary_faces;
        if ok {
            Ok(())
        } else {
            Err(format!("the turbulence state does not match the mesh ({n_cells} cells, {n_boundary_faces} boundary faces)"))
        }
    }

    /// The effective viscosity ν + ν_t this state gives the momentum equation.
    pub fn viscosity(&self, nu: f64) -> Viscosity<'_> {
        Viscosity::Turbulent { nu, nu_t: &self.nu_t, nu_t_boundary: &self.nu_t_boundary }
    }
}

/// The kinematic viscosity of the momentum equation (spec §2.4–2.5: ν_eff = ν + ν_t).
#[derive(Clone, Copy, Debug)]
pub enum Viscosity<'a> {
    /// Laminar: ν everywhere (kept a scalar so that laminar runs add no rounding).
    Uniform(f64),
    /// ν + ν_t with ν_t per cell and per boundary face.
    Turbulent { nu: f64, nu_t: &'a [f64], nu_t_boundary: &'a [f64] },
}

impl Viscosity<'_> {
    /// ν_eff on a face between cells `p` and `n` with owner weight `w` (linear interpolation of
    /// ν_t, as OpenFOAM interpolates nuEff).
    #[inline]
    pub fn face(&self, w: f64, p: usize, n: usize) -> f64 {
        match self {
            Viscosity::Uniform(nu) => *nu,
            Viscosity::Turbulent { nu, nu_t, .. } => nu + (w * nu_t[p] + (1.0 - w) * nu_t[n]),
        }
    }

    /// ν_eff on boundary face `boundary_index` (= face − n_internal_faces).
    #[inline]
    pub fn boundary(&self, boundary_index: usize) -> f64 {
        match self {
            Viscosity::Uniform(nu) => *nu,
            Viscosity::Turbulent { nu, nu_t_boundary, .. } => nu + nu_t_boundary[boundary_index],
        }
    }

    /// The molecular viscosity ν.
    pub fn molecular(&self) -> f64 {
        match self {
            Viscosity::Uniform(nu) | Viscosity::Turbulent { nu, .. } => *nu,
        }
    }
}
