//! Turbulence closure (spec fluid-dem-model.md §3): the case-file selection, the realizable
//! k–ε closure per cell, standard wall functions and the turbulence state.
//!
//! The equations live here once; each fluid solver discretises and solves the k and ε transport
//! equations with its own linear algebra (`spillage_reference::fluid::turbulence`,
//! `spillage_fast::fluid::turbulence`), once per time step after the outer loop (spec §3.2,
//! Algorithm 1 line 25), and reads the effective viscosity of the next step from
//! [`TurbulenceState`] through [`Viscosity`].

pub mod realizable;
pub mod settings;
pub mod state;
pub mod wall_function;

pub use settings::{TurbulenceModelName, TurbulenceSection};
pub use state::{TurbulenceState, Viscosity};
