//! `[[walls]]` entries.

use serde::Deserialize;

use crate::case::error::FieldError;

/// One `[[walls]]` entry (placeholder until the DEM work defines it).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallSection {
    pub name: String,
}

impl WallSection {
    pub fn validate(&self, index: usize) -> Result<(), FieldError> {
        let _ = index;
        Ok(())
    }
}
