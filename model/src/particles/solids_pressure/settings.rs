//! `[particles.solids_pressure]`: the case section of the KTGF solids pressure (its stage is
//! [`super::SolidsPressure`]).

use serde::Deserialize;

use crate::case::error::{in_range, FieldError};
use crate::closure::solids_pressure::{PACKING_LIMIT, RESTITUTION};

/// `[particles.solids_pressure]`
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SolidsPressureSection {
    /// α_max of Eq. 2.26 (default 0.6).
    #[serde(default = "default_packing_limit")]
    pub packing_limit: f64,
    /// Particle–particle restitution e of Eq. 2.25 (default 0.99).
    #[serde(default = "default_restitution")]
    pub restitution: f64,
    /// `"implicit"` (the default) or `"explicit"` (the thesis' form, module doc).
    #[serde(default)]
    pub treatment: Treatment,
    /// `"per_particle_volume"` (the default) or `"thesis_literal"` ([`KtgfForce`]).
    #[serde(default)]
    pub force: KtgfForce,
}

/// `ktgf_force` of wear-model.md §4.4: how the solids-pressure gradient becomes a particle's
/// acceleration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum KtgfForce {
    /// −∇p_p/(α_p ρ_p): Eq. 2.11 is written per unit particle volume, ∇p_p per unit mixture
    /// volume (§4.4, §13 row 11).
    #[default]
    PerParticleVolume,
    /// −∇p_p/ρ_p: the thesis' printed F_KTGF without the 1/α_p (Eq. 2.12, §2.5), α_p times
    /// weaker. The printed sign (+∇p_p) is not offered: it drives grains up the pressure, into
    /// the packing.
    ThesisLiteral,
}

fn default_packing_limit() -> f64 {
    PACKING_LIMIT
}

fn default_restitution() -> f64 {
    RESTITUTION
}

/// How α_p enters the step's solids-pressure gradient (module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Treatment {
    /// α_p* from the diffusion solve (backward Euler in α_p).
    #[default]
    Implicit,
    /// α_p at the step's start (the thesis).
    Explicit,
}

impl Default for SolidsPressureSection {
    fn default() -> Self {
        Self { packing_limit: PACKING_LIMIT, restitution: RESTITUTION, treatment: Treatment::Implicit, force: KtgfForce::PerParticleVolume }
    }
}

impl SolidsPressureSection {
    pub fn validate(&self) -> Result<(), FieldError> {
        if !(self.packing_limit > 0.0 && self.packing_limit < 1.0) {
            return Err(FieldError::new("particles.solids_pressure.packing_limit", self.packing_limit, "a volume fraction in (0, 1) (the thesis: 0.6)"));
        }
        in_range("particles.solids_pressure.restitution", self.restitution, 0.0, 1.0, "(the thesis: 0.99)")
    }
}
