//! The read-only inputs the kernels of one step share: the discretised mesh with its boundary
//! conditions, the time step with its BDF coefficients, the fluid fraction at the three time
//! levels, and the step's solution as the last stages read it.

use spillage_model::fluid::conditions::{Condition, Conditions};
use spillage_model::fluid::settings::NumericsSection;
use spillage_model::fluid::state::FluidState;
use spillage_model::mesh::Vec3;
use spillage_model::wear::fluid_mesh::deforming_alpha_rate_volume;

use super::assembly::{scalar_gradient, vector_gradient};
use super::layout::{Adjacency, Boundary, Links};

/// The mesh in its current position as the kernels see it: links, boundary faces, the cell →
/// link adjacency, cell volumes, and the condition of every boundary face.
#[derive(Clone, Copy)]
pub struct Discretisation<'a> {
    pub links: &'a Links,
    pub adjacency: &'a Adjacency,
    pub boundary: &'a Boundary,
    pub cell_volumes: &'a [f64],
    /// Cell volumes at tⁿ: `cell_volumes` itself unless the mesh deforms this step.
    pub cell_volumes_old: &'a [f64],
    /// Whether the mesh deforms this step (`[wear.fluid_mesh]`, spillage_model::wear::fluid_mesh;
    /// implicit Euler only).
    pub deforming: bool,
    /// Cell centres (error messages name the worst cell's position).
    pub cell_centres: &'a [Vec3],
    pub conditions: &'a Conditions,
    /// Velocity components solved (false along the normal of empty patches: 2-D meshes).
    pub solved: [bool; 3],
    /// Whether particles meet moving cells this step (a rotor or a deforming mesh, and a
    /// particle load): only then
    /// does a cell's ∂α/∂t V owe the particles' share of its mesh fluxes
    /// (spillage_model::fluid::moving_cells), which is zero otherwise.
    pub particles_in_turning_cells: bool,
}

impl<'a> Discretisation<'a> {
    pub fn n_cells(&self) -> usize {
        self.cell_volumes.len()
    }

    /// The condition of boundary face `b`.
    #[inline]
    pub fn condition(&self, b: usize) -> &'a Condition {
        &self.conditions.conditions[self.boundary.condition[b] as usize]
    }

    /// Boundary faces of cell `c` (indices into the [`Boundary`] arrays).
    #[inline]
    pub fn boundary_faces_of(&self, c: usize) -> &'a [u32] {
        let bnd = self.boundary;
        &bnd.faces_of_cell[bnd.cell_start[c] as usize..bnd.cell_start[c + 1] as usize]
    }

    /// ∂α/∂t V of cell `c` (zero without particles); on a deforming mesh d(αV)/dt less the
    /// mesh's own dV/dt ([`deforming_alpha_rate_volume`]).
    #[inline]
    pub fn alpha_rate_volume(&self, alpha: VolumeFractions, time: TimeStep, c: usize) -> f64 {
        if self.deforming {
            return deforming_alpha_rate_volume(time.coefficients, time.dt, alpha.current[c], alpha.old[c], self.cell_volumes[c], self.cell_volumes_old[c]);
        }
        alpha.rate_times_volume(time, c, self.cell_volumes[c])
    }

    /// Gauss gradient of cell scalar `phi` with boundary values `phi_b` ([`scalar_gradient`]).
    pub fn scalar_gradient(&self, phi: &[f64], phi_b: &[f64], gradient: &mut [Vec3]) {
        scalar_gradient(self.links, self.adjacency, self.boundary, self.cell_volumes, phi, phi_b, gradient);
    }

    /// Gauss gradient of cell vector `u` with boundary values `u_b` ([`vector_gradient`]).
    pub fn vector_gradient(&self, u: &[Vec<f64>; 3], u_b: &[Vec3], gradient: &mut [[Vec3; 3]]) {
        vector_gradient(self.links, self.adjacency, self.boundary, self.cell_volumes, u, u_b, gradient);
    }
}

/// The time step Δt and the coefficients (c₀, c₁, c₂) of d/dt q ≈ (c₀qⁿ + c₁qᵒ + c₂qᵒᵒ)/Δt
/// ([`spillage_model::fluid::time_scheme::time_coefficients`]).
#[derive(Clone, Copy, Debug)]
pub struct TimeStep {
    pub dt: f64,
    pub coefficients: [f64; 3],
}

/// Fluid fraction α_c per cell at the new, old and old-old time levels.
#[derive(Clone, Copy)]
pub struct VolumeFractions<'a> {
    pub current: &'a [f64],
    pub old: &'a [f64],
    pub old_old: &'a [f64],
}

impl<'a> VolumeFractions<'a> {
    pub fn of(fluid: &'a FluidState) -> Self {
        VolumeFractions { current: &fluid.alpha, old: &fluid.alpha_old, old_old: &fluid.alpha_old_old }
    }

    /// ∂α/∂t V of cell `c` with volume `volume` (zero without particles).
    #[inline]
    pub fn rate_times_volume(&self, time: TimeStep, c: usize, volume: f64) -> f64 {
        let [c0, c1, c2] = time.coefficients;
        (c0 * self.current[c] + c1 * self.old[c] + c2 * self.old_old[c]) * volume / time.dt
    }
}

/// The particle load of a two-way coupled step in kinematic form (spec §8.4): per cell the
/// implicit drag C_j/ρ [m³/s] for the momentum diagonal, the explicit force F_j/ρ [m⁴/s²] for
/// its source, and whether the interface mask covers a cell (T4.54; spillage_model::coupling::mask).
#[derive(Clone, Debug, Default)]
pub struct ParticleSources {
    pub implicit_drag: Vec<f64>,
    pub explicit_force: Vec<Vec3>,
    pub masked: Vec<bool>,
}

impl ParticleSources {
    /// Copies `load` divided by `density` into the buffers (allocation-free once sized).
    pub fn set(&mut self, load: &spillage_model::coupling::CellLoad, density: f64) {
        self.implicit_drag.clear();
        self.implicit_drag.extend(load.implicit_drag.iter().map(|c| c / density));
        self.explicit_force.clear();
        self.explicit_force.extend(load.explicit_force.iter().map(|f| f / density));
        self.masked.clear();
        self.masked.extend_from_slice(&load.masked);
    }
}

/// What the momentum and pressure kernels of the outer loop all read, fixed during the step.
#[derive(Clone, Copy)]
pub struct StepConstants<'a> {
    pub disc: Discretisation<'a>,
    pub time: TimeStep,
    pub alpha: VolumeFractions<'a>,
    pub numerics: &'a NumericsSection,
    /// The particle load (two-way coupling), if any.
    pub particles: Option<&'a ParticleSources>,
}

/// The solution of a step: cell velocity and pressure, boundary pressures, link and boundary
/// fluxes.
#[derive(Clone, Copy)]
pub struct StepSolution<'a> {
    pub velocity: &'a [Vec<f64>; 3],
    pub pressure: &'a [f64],
    pub boundary_pressure: &'a [f64],
    pub link_flux: &'a [f64],
    pub boundary_flux: &'a [f64],
}
