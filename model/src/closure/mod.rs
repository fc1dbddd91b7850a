//! Closure laws shared by both solvers: contact forces, restitution, drag, and the fictitious
//! forces of a rotating frame.
//!
//! Each function is a plain formula with its spec equation cited; solvers call these and never
//! re-derive them.

pub mod collision_time;
pub mod contact;
pub mod drag;
pub mod drag_and_buoyancy;
pub mod elementary;
pub mod restitution;
pub mod rotating_frame;
pub mod solids_pressure;
