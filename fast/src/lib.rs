//! Fast solver: the same model as `spillage-reference`, engineered for speed (struct-of-arrays
//! fields, precomputed face geometry updated in place, rayon with fixed-order reductions so the
//! results are bit-identical on any number of threads, preconditioned Krylov solvers with an
//! aggregation multigrid for the pressure).

pub mod dem;
pub mod fluid;
pub mod linear;
