//! The fluid state (placeholder until the reference fluid solver defines it).

/// Fluid fields on the mesh.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FluidState {}
