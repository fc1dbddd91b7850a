//! Erosive wear of the walls (spec wear-model.md): the `[wear]` section, the erosion laws, the
//! wear surface of a wall (welded nodes, smoothing operators, swept volume), the wear state and
//! the wear profile. The stepping (deposit, smooth, recede) is a [`crate::step::WearPhase`] of
//! each solver.

pub mod fluid_mesh;
pub mod law_from_case;
pub mod laws;
pub mod profile;
pub mod recession;
pub mod settings;
pub mod setup;
pub mod sliding;
pub mod state;
pub mod surface;
#[cfg(test)]
mod test_support;
