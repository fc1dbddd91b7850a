//! The fast solver's part of the particle ↔ mesh mapping (fluid-dem-model.md §6): the kernel
//! stencils, built for all particles in parallel with only the weights each use needs
//! ([`stencil`]). Each stencil depends on its own particle and the mesh alone and the cells are
//! summed afterwards in particle order ([`spillage_model::coupling::ParticleMeshMap`]), so the
//! coupled fields have the reference's bits on any number of threads (the sums into the cells
//! shared over the threads by cell ranges, [`accumulate`]); a sample takes the
//! stencils of the deposit before it when they are the same
//! ([`spillage_model::coupling::StencilCache`]), and reads the fluid through them particle by
//! particle in parallel ([`sample_in_parallel`]). And the diffusion method's smoothing on the
//! fast linear solvers ([`diffusion`]), within round-off of the reference's.

pub mod accumulate;
pub mod diffusion;
pub mod quadrature;
pub mod stencil;
pub mod walls;

pub use accumulate::accumulate_in_parallel;
pub use diffusion::smooth_in_parallel;
pub use stencil::stencils_in_parallel;

use rayon::prelude::*;

use spillage_model::coupling::kernel::Stencil;
use spillage_model::coupling::mapping::sample_one;
use spillage_model::coupling::MappingSolvers;

/// The fast solver's mapping work: stencils built in parallel and reused from the deposit by the
/// next sample, diffusion smoothed on the fast linear solvers (`Coupled::with_mapping_solvers`).
pub const MAPPING_SOLVERS: MappingSolvers = MappingSolvers {
    stencils: stencils_in_parallel,
    smoother: smooth_in_parallel,
    sampler: sample_in_parallel,
    accumulator: accumulate_in_parallel,
    reuse_stencils: true,
};

/// The fluid each particle sees, the particles in parallel (a
/// [`spillage_model::coupling::Sampler`]): each row is the reference's sum, in its order.
pub fn sample_in_parallel(stencils: &[Stencil], fields: &[&[f64]; 7], out: &mut Vec<[f64; 7]>) {
    out.clear();
    out.par_extend(stencils.par_iter().with_min_len(16).map(|s| sample_one(s, fields)));
}
