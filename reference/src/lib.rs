//! Reference solver.
