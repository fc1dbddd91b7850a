//! `[coupling]`: how particles and the fluid exchange volume and momentum (spec
//! fluid-dem-model.md §2.6, §6). Without the section a case with a fluid and particles is
//! one-way coupled: the particles feel the fluid, the fluid does not feel them.

use serde::Deserialize;

use crate::case::error::{in_range, positive, FieldError};
use crate::closure::drag::DragLaw;

/// How particle volume and forces reach the cells, and how the fluid is sampled back (§6.8).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MappingMethod {
    /// Host cell only (T3.69); the particle sees its own cell. Fails once V_p/V_cell ≳ 0.1 (§6.1).
    Centroid,
    /// Gaussian φ out, quadratic ψ back, σ = γ d_p, renormalised, wall ghosts, truncated at the
    /// sliding interface (T3.74–T3.86, T4.45–T4.54).
    Kernel,
    /// Centroid deposit diffused over T = Δt with D = (γ d_p)²/(2Δt) (T3.78–T3.81, T3.87, T4.46).
    Diffusion,
}

/// Which particle forces the fluid receives (§2.6).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Feedback {
    /// −(F_d + F_AM + F_pg): gravity and buoyancy are not fed back, so a suspension at rest
    /// carries its submerged weight through the fluid pressure (§2.6 [R], OpenFOAM's choice).
    #[default]
    DragAndFluidAcceleration,
    /// −(F_d + F_AM + F_pg + F_g + F_b), T3.2 as printed: kept to show that it fails the
    /// hydrostatic suspension (§12 U-33).
    Literal,
}

/// Where a kernel may reach at a sliding interface (fluid-dem-model.md §6.7, Table 4.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum InterfaceTreatment {
    /// Only the cells of the particle's own zone, normalised over them (T4.48*, the thesis):
    /// a crossing particle's footprint jumps from one side to the other, so ∂α_c/∂t is masked
    /// next to the interface by default.
    #[default]
    Truncate,
    /// The cells of both zones at their current pose, by distance as anywhere else [R,
    /// deviation]: the footprint moves smoothly through the interface and no mask is needed.
    /// The thesis truncated for reasons of its implementation (§6.7: OpenFOAM keeps the
    /// interface on one processor for the DEM, and the adjacency across it changes in time),
    /// which a kernel found by distance does not have. The kernel method only.
    Span,
}

fn default_distance_factor() -> f64 {
    1.0
}
fn default_min_fluid_fraction() -> f64 {
    0.05
}

/// `[coupling]`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CouplingSection {
    /// `"centroid"`, `"kernel"` or `"diffusion"`.
    pub method: MappingMethod,
    /// Distance factor γ: kernel width σ = γ d_p (T4.45). The thesis' cutter heads use 1.
    #[serde(default = "default_distance_factor")]
    pub distance_factor: f64,
    #[serde(default)]
    pub feedback: Feedback,
    /// `"truncate"` (default, the thesis) or `"span"`: where a kernel may reach at a sliding
    /// interface ([`InterfaceTreatment`]).
    #[serde(default)]
    pub interface: InterfaceTreatment,
    /// Mask ∂α_c/∂t in the pressure equation within the kernel support 3σ of a sliding
    /// interface (T4.54, §6.7): the band keeps only its net rate ([`super::mask`]). Default on
    /// with `interface = "truncate"`, as in the thesis, off with `"span"` ([`Self::masks_interface`]).
    #[serde(default)]
    pub interface_mask: Option<bool>,
    /// Single-sphere drag law (`"brown_lawler"`, the thesis' choice; `"schiller_naumann"`;
    /// `"stokes"`).
    #[serde(default)]
    pub drag: DragLaw,
    /// Lower bound of α_c = 1 − α_p in the fluid equations [R, OpenFOAM DPMFoam's alphacMin]:
    /// the centroid method maps α_p > 1 into cells smaller than a particle (§6.1). Every step
    /// reports how many cells were held at the bound (`alpha_c_clamped` in series.csv).
    #[serde(default = "default_min_fluid_fraction")]
    pub min_fluid_fraction: f64,
}

impl CouplingSection {
    /// Whether ∂α_c/∂t is masked next to a sliding interface: as the case says, else only where
    /// the kernel stops at it.
    pub fn masks_interface(&self) -> bool {
        self.interface_mask.unwrap_or(self.interface == InterfaceTreatment::Truncate)
    }

    pub fn validate(&self) -> Result<(), FieldError> {
        if self.interface == InterfaceTreatment::Span && self.method != MappingMethod::Kernel {
            return Err(FieldError::new(
                "coupling.interface",
                "\"span\"",
                "\"truncate\" with this method: only the kernel method can reach across a sliding interface (the centroid method deposits in the host cell, the diffusion method's smoothing stops at the interface)",
            ));
        }
        positive("coupling.distance_factor", self.distance_factor, "(σ = γ d_p)")?;
        in_range("coupling.distance_factor", self.distance_factor, 0.0, 20.0, "(σ = γ d_p)")?;
        if self.method == MappingMethod::Diffusion && self.distance_factor < super::mapping::SPHERE_WIDTH_FACTOR {
            return Err(FieldError::new(
                "coupling.distance_factor",
                self.distance_factor,
                format!(
                    "with method = \"diffusion\", a number ≥ {:.4}: the diffusion starts from the sphere's own width d_p/(2√5) and can only widen it",
                    super::mapping::SPHERE_WIDTH_FACTOR
                ),
            ));
        }
        if !(self.min_fluid_fraction.is_finite() && self.min_fluid_fraction > 0.0 && self.min_fluid_fraction < 1.0) {
            return Err(FieldError::new("coupling.min_fluid_fraction", self.min_fluid_fraction, "a fluid fraction in (0, 1)"));
        }
        Ok(())
    }
}
