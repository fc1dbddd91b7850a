//! Volume-averaged two-way coupling between the particles and the fluid (spec
//! fluid-dem-model.md §2, §6, §8.4): the mapping of particle volume and forces to the cells and
//! of the fluid back to the particles.
//!
//! - [`settings`]: `[coupling]` (method, distance factor γ, feedback, interface mask);
//! - [`kernel`]: the Gaussian φ and quadratic ψ kernels, ghosts and renormalisation (§6.3, §6.5, §6.7);
//! - [`diffusion`]: the diffusion method's smoothing step (§6.4);
//! - [`accumulate`]: the particles' loads summed into the cells through the deposit weights;
//! - [`mapping`]: [`ParticleMeshMap`], the selected method both ways, and the [`CellLoad`] it makes;
//! - [`cell_quadrature`]: a kernel integrated over a cell wider than the kernel;
//! - [`cell_search`]: cells within a radius of a point;
//! - [`stencil_cache`]: the stencils of a deposit kept for the next sample;
//! - [`mask`]: the ∂α_c/∂t the pressure equation takes in the interface mask (T4.54).

pub mod accumulate;
pub mod bucket_grid;
pub mod cell_quadrature;
pub mod cell_search;
pub mod diffusion;
pub mod kernel;
pub mod mapping;
pub mod mask;
pub mod settings;
pub mod stencil_cache;

pub use mapping::{CellLoad, MappingSolvers, ParticleMeshMap, Sampler, Smoother, StencilBuilder};
pub use settings::{CouplingSection, Feedback, InterfaceTreatment, MappingMethod};
pub use stencil_cache::{BuilderMemory, StencilCache, Weights};
