//! Particle state (placeholder until the DEM work defines it).

#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ParticleState {}
