//! Reference solver: readable, direct sparse solves, no cleverness (DESIGN.md "The two solvers").
//! Speed is not a goal here; clarity and determinism are.

pub mod dem;
pub mod fluid;
pub mod wear;
