//! Fluid-phase definitions shared by both solvers: properties, numerics settings, boundary
//! conditions, time coefficients, the initial state and the fluid state.

pub mod conditions;
pub mod frozen_rotor;
pub mod initial;
pub mod limiter;
pub mod moving_cells;
pub mod sampling;
pub mod settings;
pub mod state;
pub mod time_scheme;
pub mod velocity_gradient;
