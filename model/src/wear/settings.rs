//! `[wear]`: which erosion law turns particle–wall impacts into removed wall volume, and the
//! wall material's constants (spec wear-model.md §6, §8).

use serde::Deserialize;

use crate::case::error::{in_range, non_negative, positive, FieldError};

/// Erosion law per impact (wear-model.md §6; Arabnejad is the thesis' law, the others are the
/// pluggable alternatives of §6.8).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ErosionLawName {
    Arabnejad,
    Finnie,
    Oka,
    Dnv,
    Ecrc,
}

/// Variant of the Arabnejad angle function (wear-model.md §6.4 switch 4, §6.6).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum AngleFunctionForm {
    /// Eq. 2.36 as printed (jumps by a factor 2 at the critical angle): the thesis' form.
    #[default]
    ThesisLiteral,
    /// High branch ½cos²θ, continuous at the critical angle (the spec's deduction, §6.6).
    Continuous,
}

/// `[wear]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WearSection {
    pub law: ErosionLawName,
    /// Names of the `[[walls]]` that erode (default: all of them).
    #[serde(default)]
    pub walls: Vec<String>,
    /// Wear-rate acceleration A_acc = T_actual / T_sim ≥ 1 (wear-model.md §8, Eq. 4.10 read as
    /// the multiplier it is used as; the printed ratio is upside down).
    #[serde(default = "one")]
    pub acceleration: f64,
    /// Real particles per simulated particle (Eq. 4.9).
    #[serde(default = "one")]
    pub modifier: f64,
    #[serde(default)]
    pub angle_function: AngleFunctionForm,
    pub material: WearMaterial,
    /// Damped diffusive smoothing of the wear field (wear-model.md §7.2–7.3). Without it each
    /// impact's volume recedes at once from the three vertices of the triangle hit.
    pub smoothing: Option<SmoothingSection>,
    /// Whether the eroding walls recede (move their vertices); `false` is the thesis'
    /// static-boundary mode (§7.4): the wear field is still computed.
    #[serde(default = "yes")]
    pub receding: bool,
    /// Upper edge of the impact-speed histogram [m/s] (10 equal bins; faster impacts count in
    /// the last one).
    #[serde(default = "ten")]
    pub histogram_max_speed: f64,
    /// A line along which `wear_profile.csv` and its plot sample the wear depth.
    pub profile: Option<ProfileSection>,
}

/// `[wear.smoothing]`: κ and λ of ∂w/∂t − ∇·(κ∇w) = −λw + λ Σ W_i δ (§7.2, sign-corrected).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SmoothingSection {
    /// κ_wear [m²/s] (the thesis' "diffusivity factor", 0.001).
    pub diffusivity: f64,
    /// λ [1/s]; never given in the thesis (§13 row 8): spreading length √(κ/λ), time 1/λ.
    pub damping: f64,
}

/// `[wear.profile]`: wear depth along the segment `from` → `to`, averaged over the wall
/// triangles whose centroid lies within `width`/2 of it, in `bins` equal bins.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProfileSection {
    pub from: [f64; 3],
    pub to: [f64; 3],
    pub width: f64,
    #[serde(default = "fifty")]
    pub bins: usize,
}

fn yes() -> bool {
    true
}

fn ten() -> f64 {
    10.0
}

fn fifty() -> usize {
    50
}

fn one() -> f64 {
    1.0
}

/// `[wear.material]`: the eroded wall's constants (wear-model.md §6.5, Table 4.1). Either a
/// `preset` or every constant.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WearMaterial {
    /// `carbon_steel_1018` or `stainless_steel_316` (Table 4.1 as printed).
    pub preset: Option<String>,
    /// ρ_mat [kg/m³].
    pub density: Option<f64>,
    /// Cutting erosion factor C.
    pub cutting_coefficient: Option<f64>,
    /// Vickers hardness coefficient Hv (a calibration input, §6.7).
    pub vickers_hardness: Option<f64>,
    /// Particle sharpness factor F_s ∈ [0.25, 1] (0.5 for spheres).
    pub sharpness: Option<f64>,
    /// Ratio of contact K (0.4 for sand); critical angle atan K.
    pub contact_ratio: Option<f64>,
    /// Deformation erosion factor ε.
    pub deformation_factor: Option<f64>,
    /// Threshold normal speed U_tsh [m/s].
    pub threshold_velocity: Option<f64>,
}

/// The constants of one wall material, resolved from a preset or the case.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaterialConstants {
    pub density: f64,
    pub cutting_coefficient: f64,
    pub vickers_hardness: f64,
    pub sharpness: f64,
    pub contact_ratio: f64,
    pub deformation_factor: f64,
    pub threshold_velocity: f64,
}

/// Table 4.1 of the thesis as printed (wear-model.md §6.5).
pub const PRESETS: [(&str, MaterialConstants); 2] = [
    (
        "carbon_steel_1018",
        MaterialConstants {
            density: 7870.0,
            cutting_coefficient: 0.01,
            vickers_hardness: 131.0,
            sharpness: 0.5,
            contact_ratio: 0.4,
            deformation_factor: 4.2e11,
            threshold_velocity: 0.5,
        },
    ),
    (
        "stainless_steel_316",
        MaterialConstants {
            density: 8000.0,
            cutting_coefficient: 0.0125,
            vickers_hardness: 224.0,
            sharpness: 0.5,
            contact_ratio: 0.4,
            deformation_factor: 1.4e11,
            threshold_velocity: 5.7,
        },
    ),
];

impl WearMaterial {
    /// The constants: the preset's, each overridden by a value given in the case; without a
    /// preset every constant must be given.
    pub fn constants(&self) -> Result<MaterialConstants, FieldError> {
        let base = match &self.preset {
            Some(name) => Some(PRESETS.iter().find(|(n, _)| n == name).map(|(_, c)| *c).ok_or_else(|| {
                FieldError::new("wear.material.preset", format!("{name:?}"), format!("one of {}", PRESETS.map(|(n, _)| format!("{n:?}")).join(", ")))
            })?),
            None => None,
        };
        let pick = |key: &str, given: Option<f64>, from: fn(&MaterialConstants) -> f64| -> Result<f64, FieldError> {
            given
                .or(base.as_ref().map(from))
                .ok_or_else(|| FieldError::new(format!("wear.material.{key}"), "(missing)", "a value, or a `preset` that provides it"))
        };
        Ok(MaterialConstants {
            density: pick("density", self.density, |c| c.density)?,
            cutting_coefficient: pick("cutting_coefficient", self.cutting_coefficient, |c| c.cutting_coefficient)?,
            vickers_hardness: pick("vickers_hardness", self.vickers_hardness, |c| c.vickers_hardness)?,
            sharpness: pick("sharpness", self.sharpness, |c| c.sharpness)?,
            contact_ratio: pick("contact_ratio", self.contact_ratio, |c| c.contact_ratio)?,
            deformation_factor: pick("deformation_factor", self.deformation_factor, |c| c.deformation_factor)?,
            threshold_velocity: pick("threshold_velocity", self.threshold_velocity, |c| c.threshold_velocity)?,
        })
    }
}

impl WearSection {
    /// `wall_names` are the names of the case's `[[walls]]`.
    pub fn validate(&self, wall_names: &[&str]) -> Result<(), FieldError> {
        for (i, name) in self.walls.iter().enumerate() {
            if !wall_names.contains(&name.as_str()) {
                return Err(FieldError::new(
                    format!("wear.walls.{i}"),
                    format!("{name:?}"),
                    format!("the name of a [[walls]] entry: {}", wall_names.join(", ")),
                ));
            }
        }
        if !(self.acceleration.is_finite() && self.acceleration >= 1.0) {
            return Err(FieldError::new("wear.acceleration", self.acceleration, "a factor ≥ 1 (T_actual / T_sim, wear-model.md §8)"));
        }
        positive("wear.modifier", self.modifier, "(real particles per simulated one)")?;
        let c = self.material.constants()?;
        positive("wear.material.density", c.density, "kg/m³")?;
        non_negative("wear.material.cutting_coefficient", c.cutting_coefficient, "")?;
        positive("wear.material.vickers_hardness", c.vickers_hardness, "")?;
        in_range("wear.material.sharpness", c.sharpness, 0.25, 1.0, "(0.25 rounded … 1 fully sharp, wear-model.md §6.5)")?;
        positive("wear.material.contact_ratio", c.contact_ratio, "")?;
        positive("wear.material.deformation_factor", c.deformation_factor, "")?;
        non_negative("wear.material.threshold_velocity", c.threshold_velocity, "m/s")?;
        if let Some(sm) = &self.smoothing {
            positive("wear.smoothing.diffusivity", sm.diffusivity, "m²/s")?;
            positive("wear.smoothing.damping", sm.damping, "1/s (spreading time 1/λ)")?;
        }
        positive("wear.histogram_max_speed", self.histogram_max_speed, "m/s")?;
        if let Some(p) = &self.profile {
            crate::case::error::finite_vector("wear.profile.from", p.from)?;
            crate::case::error::finite_vector("wear.profile.to", p.to)?;
            let length = (0..3).map(|k| (p.to[k] - p.from[k]).powi(2)).sum::<f64>().sqrt();
            positive("wear.profile.to", length, "m away from `from` (a segment of positive length)")?;
            positive("wear.profile.width", p.width, "m")?;
            if !(1..=100_000).contains(&p.bins) {
                return Err(FieldError::new("wear.profile.bins", p.bins, "1 … 100000 bins"));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> WearSection {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn a_preset_gives_table_4_1_and_values_override_it() {
        let w = parse("law = \"arabnejad\"\n[material]\npreset = \"stainless_steel_316\"\nthreshold_velocity = 3.0\n");
        w.validate(&[]).unwrap();
        let c = w.material.constants().unwrap();
        assert_eq!((c.density, c.vickers_hardness, c.threshold_velocity), (8000.0, 224.0, 3.0));
    }

    #[test]
    fn bad_wear_input_names_the_key() {
        let cases = [
            ("law = \"arabnejad\"\n[material]\npreset = \"brass\"\n", "wear.material.preset"),
            ("law = \"arabnejad\"\n[material]\ndensity = 7000.0\n", "wear.material.cutting_coefficient"),
            ("law = \"arabnejad\"\nacceleration = 0.5\n[material]\npreset = \"carbon_steel_1018\"\n", "wear.acceleration"),
            ("law = \"arabnejad\"\nwalls = [\"blade\"]\n[material]\npreset = \"carbon_steel_1018\"\n", "wear.walls.0"),
            ("law = \"arabnejad\"\n[material]\npreset = \"carbon_steel_1018\"\nsharpness = 2.0\n", "wear.material.sharpness"),
        ];
        for (text, key) in cases {
            let err = parse(text).validate(&["box"]).unwrap_err();
            assert_eq!(err.key, key, "{text}");
        }
    }
}
