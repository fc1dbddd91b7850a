//! Fast solver.
