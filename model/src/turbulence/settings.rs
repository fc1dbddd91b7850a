//! `[turbulence]`: which turbulence model the fluid uses, its constants, its initial values and
//! the turbulence of the fluid entering through velocity inlets (spec fluid-dem-model.md §3).

use serde::Deserialize;

use crate::case::error::{in_range, positive, FieldError};

/// The turbulence model (spec §3; `laminar` is the default of the verification ladder).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
pub enum TurbulenceModelName {
    /// No turbulence model: ν_eff = ν.
    #[default]
    #[serde(rename = "laminar")]
    Laminar,
    /// Realizable k–ε of Shih et al. (1995) with standard wall functions (spec §3.2).
    #[serde(rename = "realizable-k-epsilon", alias = "realizable_k_epsilon")]
    RealizableKEpsilon,
}

/// `[turbulence]`
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TurbulenceSection {
    #[serde(default)]
    pub model: TurbulenceModelName,
    /// Initial turbulent kinetic energy k in every cell [m²/s²].
    #[serde(default = "default_initial_k")]
    pub initial_k: f64,
    /// Initial dissipation rate ε in every cell [m²/s³].
    #[serde(default = "default_initial_epsilon")]
    pub initial_epsilon: f64,
    /// Turbulence intensity I of the fluid entering through velocity inlets: k = 1.5 (I|u_b|)².
    #[serde(default = "default_intensity")]
    pub inlet_intensity: f64,
    /// Mixing length L of the inlet turbulence: ε = C_μ^¾ k^{3/2} / L [m].
    #[serde(default = "default_length_scale")]
    pub inlet_length_scale: f64,
    /// Model and wall-function constants (spec §3.2 table, OpenFOAM `realizableKE` defaults).
    #[serde(default)]
    pub constants: RealizableConstants,
}

fn default_initial_k() -> f64 {
    1e-4
}
fn default_initial_epsilon() -> f64 {
    1e-5
}
fn default_intensity() -> f64 {
    0.05
}
fn default_length_scale() -> f64 {
    0.01
}

impl Default for TurbulenceSection {
    fn default() -> Self {
        Self {
            model: TurbulenceModelName::Laminar,
            initial_k: default_initial_k(),
            initial_epsilon: default_initial_epsilon(),
            inlet_intensity: default_intensity(),
            inlet_length_scale: default_length_scale(),
            constants: RealizableConstants::default(),
        }
    }
}

/// `[turbulence.constants]`: Shih et al. (1995) as OpenFOAM's `realizableKE` (spec §3.2, the
/// reconstruction of the unreadable Table 3.1 [R]) and the log-law constants of the standard
/// wall functions (OpenFOAM `nutkWallFunction` defaults).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RealizableConstants {
    #[serde(default = "a0")]
    pub a0: f64,
    #[serde(default = "c2")]
    pub c2: f64,
    #[serde(default = "one")]
    pub sigma_k: f64,
    #[serde(default = "sigma_epsilon")]
    pub sigma_epsilon: f64,
    /// C_μ of the wall functions and the inlet ε (the standard-model value).
    #[serde(default = "c_mu")]
    pub c_mu: f64,
    /// von Kármán constant κ.
    #[serde(default = "kappa")]
    pub kappa: f64,
    /// Log-law roughness parameter E: u⁺ = ln(E y⁺)/κ (E = 9.8 is B = ln(E)/κ = 5.57).
    #[serde(default = "wall_e")]
    pub wall_e: f64,
}

fn a0() -> f64 {
    4.0
}
fn c2() -> f64 {
    1.9
}
fn one() -> f64 {
    1.0
}
fn sigma_epsilon() -> f64 {
    1.2
}
fn c_mu() -> f64 {
    0.09
}
fn kappa() -> f64 {
    0.41
}
fn wall_e() -> f64 {
    9.8
}

impl Default for RealizableConstants {
    fn default() -> Self {
        Self { a0: a0(), c2: c2(), sigma_k: one(), sigma_epsilon: sigma_epsilon(), c_mu: c_mu(), kappa: kappa(), wall_e: wall_e() }
    }
}

impl TurbulenceSection {
    pub fn validate(&self) -> Result<(), FieldError> {
        positive("turbulence.initial_k", self.initial_k, "m²/s²")?;
        positive("turbulence.initial_epsilon", self.initial_epsilon, "m²/s³")?;
        in_range("turbulence.inlet_intensity", self.inlet_intensity, 0.0, 1.0, "(a fraction of the inlet speed)")?;
        positive("turbulence.inlet_length_scale", self.inlet_length_scale, "m")?;
        let c = &self.constants;
        positive("turbulence.constants.a0", c.a0, "")?;
        positive("turbulence.constants.c2", c.c2, "")?;
        positive("turbulence.constants.sigma_k", c.sigma_k, "")?;
        positive("turbulence.constants.sigma_epsilon", c.sigma_epsilon, "")?;
        in_range("turbulence.constants.c_mu", c.c_mu, 1e-3, 1.0, "")?;
        in_range("turbulence.constants.kappa", c.kappa, 0.1, 1.0, "")?;
        // E ≤ 1 would make ln(E y⁺) ≤ 0 at the wall-function switch y⁺ ≈ 11
        in_range("turbulence.constants.wall_e", c.wall_e, 1.01, 100.0, "")?;
        Ok(())
    }

    /// Whether the case solves transport equations for k and ε.
    pub fn is_k_epsilon(&self) -> bool {
        self.model == TurbulenceModelName::RealizableKEpsilon
    }

    /// k and ε of the fluid entering with speed `speed` (inlet intensity and mixing length;
    /// OpenFOAM `turbulentIntensityKineticEnergyInlet` and
    /// `turbulentMixingLengthDissipationRateInlet`). Both are kept above the bound of the
    /// solution (`state::K_MIN`, `state::EPSILON_MIN`) so that a fluid at rest stays well defined.
    pub fn inlet_values(&self, speed: f64) -> (f64, f64) {
        let k = (1.5 * (self.inlet_intensity * speed).powi(2)).max(super::state::K_MIN);
        let epsilon = (self.constants.c_mu.powf(0.75) * k.powf(1.5) / self.inlet_length_scale).max(super::state::EPSILON_MIN);
        (k, epsilon)
    }
}
