//! Fast solver: the same model as `spillage-reference`, engineered for speed (struct-of-arrays
//! fields, precomputed face geometry updated in place, rayon with fixed-order reductions so the
//! results are bit-identical on any number of threads, preconditioned Krylov solvers with an
//! aggregation multigrid for the pressure), the DEM ([`dem`]: struct-of-arrays particles, a
//! neighbour list with contact histories beside its pairs, walls through their BVHs) and the wear
//! phase ([`wear`]) on the same linear solvers.

#[cfg(test)]
mod counting_allocator;
pub mod coupling;
pub mod dem;
pub mod fluid;
pub mod linear;
pub mod team;
pub mod wear;
