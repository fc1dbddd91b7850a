//! Fluid-phase definitions shared by both solvers: properties, numerics settings, boundary
//! conditions and the fluid state. (Owned by the reference-fluid work; placeholders for now.)

pub mod sampling;
pub mod settings;
pub mod state;
