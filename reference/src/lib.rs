//! Reference solver: readable, direct sparse solves, no cleverness (DESIGN.md "The two solvers").

pub mod fluid;
