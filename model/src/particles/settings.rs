//! `[particles]` section.

use serde::Deserialize;

use crate::case::error::FieldError;

/// `[particles]` (placeholder until the DEM work defines it).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParticlesSection {}

impl ParticlesSection {
    pub fn validate(&self) -> Result<(), FieldError> {
        Ok(())
    }
}
