//! Reference solver.

pub mod dem;
