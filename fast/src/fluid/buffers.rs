//! Work arrays of one time step, sized once ([`StepBuffers::resize`]) and reused, so the time
//! loop does not allocate (except a resize when the overlap links grow). Cell vectors are
//! stored by component (struct of arrays); per-link arrays follow the [`super::layout::Links`]
//! order, per-boundary-face arrays the [`super::layout::Boundary`] order.

use spillage_model::mesh::Vec3;

use super::layout::Adjacency;
use crate::linear::Csr;

/// Everything the stages of a step read and write besides the state.
#[derive(Default)]
pub struct StepBuffers {
    /// Cell velocity u of the current iterate, by component.
    pub velocity: [Vec<f64>; 3],
    /// uᵒ: the velocity at the end of the previous step.
    pub velocity_old: [Vec<f64>; 3],
    /// uᵒᵒ: the velocity two steps back.
    pub velocity_old_old: [Vec<f64>; 3],
    /// Cell kinematic pressure P of the current iterate (under-relaxed).
    pub pressure: Vec<f64>,
    /// Kinematic pressure on each boundary face.
    pub boundary_pressure: Vec<f64>,
    /// Gauss gradient ∇P per cell.
    pub pressure_gradient: Vec<Vec3>,
    /// Absolute volumetric flux φ per link.
    pub link_flux: Vec<f64>,
    /// Absolute volumetric flux φ_b per boundary face.
    pub boundary_flux: Vec<f64>,
    /// Time-derivative flux correction per link divided by rAU_f (reference
    /// `solver::ddt_flux_correction`).
    pub ddt_flux_correction: Vec<f64>,
    /// Prescribed flux per boundary face (NaN where the pressure is fixed).
    pub prescribed_boundary_flux: Vec<f64>,
    /// Fixed velocity per boundary face (NaN where none).
    pub fixed_boundary_velocity: Vec<Vec3>,
    /// Velocity per boundary face from the conditions and the latest cell velocity.
    pub boundary_velocity: Vec<Vec3>,
    /// Velocity gradient per cell, g[i][j] = ∂u_j/∂x_i.
    pub velocity_gradient: Vec<[Vec3; 3]>,
    /// The velocity and its gradient the `limited_linear` limiter reads when it is evaluated
    /// once per step (`[numerics] limiter_update = "time_step"`): the step's first iterate's.
    pub limiter_velocity: [Vec<f64>; 3],
    pub limiter_gradient: Vec<[Vec3; 3]>,
    pub momentum_links: MomentumLinkCoefficients,
    pub momentum: MomentumSystem,
    /// Right-hand side b − V∇P of the momentum predictor, by component.
    pub momentum_rhs: [Vec<f64>; 3],
    pub corrector: CorrectorBuffers,
    pub diagnostics: DiagnosticBuffers,
}

/// Per-link parts of the momentum matrix, computed once per link and gathered per cell.
#[derive(Default)]
pub struct MomentumLinkCoefficients {
    /// Coefficient of the neighbour in the owner's row (convection + diffusion).
    pub owner_row: Vec<f64>,
    /// Coefficient of the owner in the neighbour's row.
    pub neighbour_row: Vec<f64>,
    /// Explicit viscous flux (non-orthogonal correction + transpose/dilatation stress): a
    /// source of the owner, a sink of the neighbour.
    pub explicit_viscous_flux: Vec<Vec3>,
}

/// The relaxed momentum matrix (the same for every component) and its source b without −V∇P.
#[derive(Default)]
pub struct MomentumSystem {
    pub matrix: Csr,
    pub source: Vec<Vec3>,
}

/// Work arrays of the PISO corrector.
#[derive(Default)]
pub struct CorrectorBuffers {
    /// HbyA = (b − Σ_N a_N u_N)/a_P per cell: the velocity of the momentum equation without the
    /// pressure gradient.
    pub h_by_a: Vec<Vec3>,
    /// rAU = V/a_P per cell: how the velocity answers the pressure gradient.
    pub r_au: Vec<f64>,
    /// Σ_N a_N u_N of one velocity component per cell (off-diagonal product of the momentum
    /// matrix).
    pub neighbour_sum: Vec<f64>,
    /// Pressure P* when the corrector started, the base of the under-relaxation.
    pub pressure_start: Vec<f64>,
    /// The unrelaxed pressure the pressure equation solves for.
    pub pressure_solution: Vec<f64>,
    /// Per link: HbyA_f·S − rAU_f (∇P)_f·T + rAU_f·(ddt correction), the flux without its
    /// implicit pressure part.
    pub predicted_link_flux: Vec<f64>,
    /// Per link: α_f × the predicted flux (its divergence is the pressure equation's source).
    pub alpha_predicted_link_flux: Vec<f64>,
    /// Per link: α_f rAU_f |S|²/(d·S), the coefficient of the pressure Laplacian.
    pub pressure_laplacian_coefficient: Vec<f64>,
    pub pressure_matrix: Csr,
    pub pressure_rhs: Vec<f64>,
}

/// Work arrays of the end-of-step diagnostics.
#[derive(Default)]
pub struct DiagnosticBuffers {
    /// Continuity error e_c = ∂α/∂t V + Σ_f α_f φ_f per cell [m³/s].
    pub continuity_error: Vec<f64>,
    /// Courant number ½Δt Σ_f |φ_f − φ_mesh,f| / V per cell.
    pub courant: Vec<f64>,
    /// Per mesh face: the sum of its overlap fluxes, out of its cell (sliding-interface faces).
    pub interface_face_flux: Vec<f64>,
    /// Per mesh face: whether `interface_face_flux` holds this step's sum.
    pub on_interface: Vec<bool>,
}

impl StepBuffers {
    /// Sizes every array for `n_cells` cells, `n_boundary` boundary faces with a condition,
    /// `n_links` links and `n_faces` mesh faces; the matrices get the pattern of `adjacency`.
    pub fn resize(&mut self, n_cells: usize, n_boundary: usize, n_links: usize, n_faces: usize, adjacency: &Adjacency) {
        let n = n_cells;
        for j in 0..3 {
            self.velocity[j].resize(n, 0.0);
            self.velocity_old[j].resize(n, 0.0);
            self.velocity_old_old[j].resize(n, 0.0);
            self.momentum_rhs[j].resize(n, 0.0);
        }
        let c = &mut self.corrector;
        let d = &mut self.diagnostics;
        for v in [
            &mut self.pressure,
            &mut c.pressure_start,
            &mut c.pressure_solution,
            &mut c.neighbour_sum,
            &mut c.r_au,
            &mut c.pressure_rhs,
            &mut d.courant,
            &mut d.continuity_error,
        ] {
            v.resize(n, 0.0);
        }
        for v in [&mut self.boundary_pressure, &mut self.boundary_flux, &mut self.prescribed_boundary_flux] {
            v.resize(n_boundary, 0.0);
        }
        for v in [&mut self.fixed_boundary_velocity, &mut self.boundary_velocity] {
            v.resize(n_boundary, Vec3::zeros());
        }
        let m = &mut self.momentum_links;
        for v in [
            &mut self.link_flux,
            &mut c.predicted_link_flux,
            &mut self.ddt_flux_correction,
            &mut m.owner_row,
            &mut m.neighbour_row,
            &mut c.pressure_laplacian_coefficient,
            &mut c.alpha_predicted_link_flux,
        ] {
            v.resize(n_links, 0.0);
        }
        m.explicit_viscous_flux.resize(n_links, Vec3::zeros());
        self.velocity_gradient.resize(n, [Vec3::zeros(); 3]);
        self.pressure_gradient.resize(n, Vec3::zeros());
        self.momentum.source.resize(n, Vec3::zeros());
        c.h_by_a.resize(n, Vec3::zeros());
        d.interface_face_flux.resize(n_faces, 0.0);
        d.on_interface.resize(n_faces, false);
        // matrix structure = adjacency
        for matrix in [&mut self.momentum.matrix, &mut c.pressure_matrix] {
            matrix.n = n;
            matrix.row_start.clone_from(&adjacency.row_start);
            matrix.col.clone_from(&adjacency.col);
            matrix.val.resize(adjacency.col.len(), 0.0);
            matrix.diag.resize(n, 0.0);
        }
    }
}
