//! Particle definitions shared by both solvers (owned by the DEM work; placeholders for now).

pub mod settings;
pub mod state;
