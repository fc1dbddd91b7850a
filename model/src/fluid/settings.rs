//! `[fluid]`, `[numerics]` and `[boundary.<patch>]` sections.

use serde::Deserialize;

use crate::case::error::{positive, FieldError};

/// `[fluid]`: fluid properties.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidSection {
    /// Density ρ [kg/m³].
    pub density: f64,
    /// Kinematic viscosity ν [m²/s].
    pub kinematic_viscosity: f64,
}

impl FluidSection {
    pub fn validate(&self) -> Result<(), FieldError> {
        positive("fluid.density", self.density, "kg/m³")?;
        positive("fluid.kinematic_viscosity", self.kinematic_viscosity, "m²/s")
    }
}

/// `[boundary.<patch>]`: the condition on one mesh patch, selected by `type`.
#[derive(Clone, Debug, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum BoundaryCondition {
    /// No-slip wall; `velocity` for a moving wall, `rotating = true` for a wall turning with the
    /// rotor (velocity ω×r).
    Wall {
        #[serde(default)]
        velocity: [f64; 3],
        #[serde(default)]
        rotating: bool,
    },
}

impl BoundaryCondition {
    /// `key` is the section path, e.g. `boundary.inner`.
    pub fn validate(&self, key: &str) -> Result<(), FieldError> {
        match self {
            BoundaryCondition::Wall { velocity, rotating } => {
                crate::case::error::finite_vector(&format!("{key}.velocity"), *velocity)?;
                if *rotating && velocity.iter().any(|v| *v != 0.0) {
                    return Err(FieldError::new(format!("{key}.velocity"), format!("{velocity:?}"), "no velocity on a rotating wall (its velocity is ω×r)"));
                }
                Ok(())
            }
        }
    }
}

impl BoundaryCondition {
    /// Largest speed this condition imposes, given the largest radius of the mesh (for rotating
    /// walls). `None` when it imposes no velocity.
    pub fn imposed_speed(&self, r_max: f64) -> Option<f64> {
        let _ = r_max;
        match self {
            BoundaryCondition::Wall { velocity, .. } => Some(velocity.iter().map(|v| v * v).sum::<f64>().sqrt()),
        }
    }
}
