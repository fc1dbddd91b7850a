//! Particle definitions shared by both solvers: the `[particles]` section, the particle state
//! and the initial-state builder.

pub mod batch;
pub mod bookkeeping;
pub mod dem_setup;
pub mod first_touch;
pub mod guards;
pub mod initial;
pub mod materials;
pub mod non_contact;
pub mod placement;
pub mod random;
pub mod settings;
pub mod solids_pressure;
pub mod state;
pub mod substeps;

pub use initial::{initial_state, place_without_overlap};
pub use state::{ContactRecord, ImpactRecord, Particle, ParticleCounts, ParticleState, Partner};
