//! Geometry of a cylindrical sliding interface between a rotor and a stator zone.

/// A cylindrical sliding interface (placeholder: the mesh helper defines it fully).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SlidingInterface {}
