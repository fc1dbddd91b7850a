//! The fast solver's part of the particle ↔ mesh mapping (fluid-dem-model.md §6): the kernel
//! stencils, built for all particles in parallel. Each stencil depends on its own particle and
//! the mesh alone and the cells are summed afterwards in particle order
//! ([`spillage_model::coupling::ParticleMeshMap`]), so the coupled fields have the reference's
//! bits on any number of threads. And the diffusion method's smoothing on the fast linear
//! solvers ([`diffusion`]), within round-off of the reference's.

pub mod diffusion;

pub use diffusion::smooth_in_parallel;

use rayon::prelude::*;

use spillage_model::coupling::kernel::{stencil, KernelGeometry, Stencil};
use spillage_model::coupling::mapping::host_cell;
use spillage_model::coupling::MappingSolvers;
use spillage_model::particles::Particle;

/// The fast solver's mapping work: stencils built in parallel, diffusion smoothed on the fast
/// linear solvers (`Coupled::with_mapping_solvers`).
pub const MAPPING_SOLVERS: MappingSolvers = MappingSolvers { stencils: stencils_in_parallel, smoother: smooth_in_parallel };

/// The kernel stencils of `particles` (σ = γ d), in particle order, built in parallel (a
/// [`spillage_model::coupling::StencilBuilder`]).
pub fn stencils_in_parallel(geo: &KernelGeometry, particles: &[Particle], gamma: f64) -> Vec<Stencil> {
    particles
        .par_iter()
        .with_min_len(32)
        .map_init(Vec::new, |scratch, p| stencil(geo, &p.position, p.diameter, gamma, host_cell(geo.mesh, &p.position), scratch))
        .collect()
}
