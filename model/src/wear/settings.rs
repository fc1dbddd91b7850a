//! `[wear]`: which erosion law turns particle–wall impacts into removed wall volume, the law's
//! own constants (`[wear.arabnejad]`, `[wear.finnie]`, `[wear.oka]`, `[wear.dnv]`,
//! `[wear.ecrc]`) and the wall material's constants (spec wear-model.md §6, §8).
//!
//! The law-specific checks (which sub-section and which material constants a law reads, and
//! their ranges) live with the laws in [`super::laws::ErosionLaw::from_section`], which
//! [`WearSection::validate`] calls: a case that validates always builds its law.

use serde::Deserialize;

use crate::case::error::{positive, FieldError};

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

/// Mass prefactor of the Arabnejad law (wear-model.md §6.4 switch 2).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum MassPrefactor {
    /// The particle mass m (Eqs. 2.35, 2.37, 2.39): the canonical form.
    #[default]
    ParticleMass,
    /// The particle density ρ_p, as the §2.5 summary prints it (dimensionally inconsistent;
    /// thesis-literal reproduction only).
    ParticleDensity,
}

/// Deformation term of the Arabnejad law (wear-model.md §6.4 switch 3, §13 rows 2–3).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum DeformationForm {
    /// (max(0, U sinθ − U_tsh))²: Bitter's clip-then-square, the canonical form.
    #[default]
    SquaredClipped,
    /// max(0, (U sinθ − U_tsh)²) as Eq. 2.38 prints it: never clips, so it wears even below the
    /// threshold speed.
    LiteralSquare,
    /// max(0, U sinθ − U_tsh) as the §2.5 summary prints it (no square).
    LinearClipped,
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
    /// Retired: real particles per simulated one is `[particles] modifier` now, since it counts
    /// in the coupling as well as in the wear. Kept only to say so when a case still sets it.
    #[serde(default)]
    pub modifier: Option<f64>,
    /// Arabnejad cutting angle function (§6.4 switch 4); read by `law = "arabnejad"` only.
    #[serde(default)]
    pub angle_function: AngleFunctionForm,
    pub material: WearMaterial,
    /// `[wear.arabnejad]`: the other three switches of §6.4 (only with `law = "arabnejad"`).
    pub arabnejad: Option<ArabnejadSection>,
    /// `[wear.finnie]` (required with `law = "finnie"`, not allowed otherwise).
    pub finnie: Option<FinnieSection>,
    /// `[wear.oka]` (required with `law = "oka"`, not allowed otherwise).
    pub oka: Option<OkaSection>,
    /// `[wear.dnv]` (optional with `law = "dnv"`: the steel constants are its defaults).
    pub dnv: Option<DnvSection>,
    /// `[wear.ecrc]` (required with `law = "ecrc"`, not allowed otherwise).
    pub ecrc: Option<EcrcSection>,
    /// Damped diffusive smoothing of the wear field (wear-model.md §7.2–7.3). Without it each
    /// impact's volume recedes at once from the three vertices of the triangle hit.
    pub smoothing: Option<SmoothingSection>,
    /// Sliding wear (`super::sliding`, wear-model.md §14 item 12): a contact's normal impulse
    /// beyond its collision's wears as the thesis' point particles' grazing re-collisions would.
    /// Off by default: the impacts alone.
    #[serde(default)]
    pub sliding: bool,
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
    /// `[wear.fluid_mesh]`: the fluid mesh follows a receding wall (wear-model.md §7.4), so
    /// that the water flows into its crater ([`super::fluid_mesh`]).
    pub fluid_mesh: Option<FluidMeshSection>,
}

/// `[wear.fluid_mesh]`: which fluid patch lies on which eroding plane wall, and how far into
/// the water the mesh bends as the wall recedes ([`super::fluid_mesh::WallFollower`]).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidMeshSection {
    /// The eroding `[[walls]]` entry (a plane, standing still).
    pub wall: String,
    /// The fluid boundary patch lying in the wall's plane.
    pub patch: String,
    /// Distance from the patch over which the points' share of the recession falls linearly
    /// from 1 to 0 [m] (default: across the whole mesh).
    pub depth: Option<f64>,
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
/// triangles whose centroid, on the wall as built, lies within `width`/2 of it, in `bins` equal
/// bins ([`super::profile::wear_profile`]).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProfileSection {
    pub from: [f64; 3],
    pub to: [f64; 3],
    pub width: f64,
    #[serde(default = "fifty")]
    pub bins: usize,
}

/// `[wear.arabnejad]`: switches 1–3 of wear-model.md §6.4 (switch 4 is the top-level
/// `angle_function`, kept there for existing cases). Defaults are the canonical form.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct ArabnejadSection {
    /// Multiply the cutting term by C (Eq. 2.35; the printed Eq. 2.39 drops it, §13 row 1).
    #[serde(default = "yes")]
    pub include_cutting_coefficient: bool,
    #[serde(default)]
    pub mass_prefactor: MassPrefactor,
    #[serde(default)]
    pub deformation_form: DeformationForm,
}

impl Default for ArabnejadSection {
    fn default() -> Self {
        Self { include_cutting_coefficient: true, mass_prefactor: MassPrefactor::default(), deformation_form: DeformationForm::default() }
    }
}

/// `[wear.finnie]`: Finnie (1960) micro-cutting (wear-model.md §6.1 background, §6.8).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FinnieSection {
    /// Horizontal flow pressure p of the wall [Pa] (required; no default exists).
    pub flow_pressure: Option<f64>,
    /// K, ratio of vertical to horizontal force on the particle (Finnie: ≈ 2).
    #[serde(default = "two")]
    pub force_ratio: f64,
    /// ψ, ratio of contact depth to cut depth (Finnie: ≈ 2).
    #[serde(default = "two")]
    pub depth_ratio: f64,
    /// c, fraction of the particles that cut in the idealised manner, in [0, 1].
    #[serde(default = "one")]
    pub cutting_fraction: f64,
}

/// `[wear.oka]`: Oka & Yoshida (2005) (wear-model.md §6.8, formula from the paper). A constant
/// left out takes the paper's SiO₂-sand value ([`super::laws::OkaConstants::silica_sand`], the
/// one place those literature values are written).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct OkaSection {
    /// Wall Vickers hardness Hv in GPa (required; HV number × 9.807e-3).
    pub vickers_hardness_gpa: Option<f64>,
    /// K [mm³/kg] (sand: 65).
    pub k: Option<f64>,
    /// Hardness exponent of E₉₀ (sand: −0.12).
    pub k1: Option<f64>,
    /// Size exponent of E₉₀ (sand: 0.19).
    pub k3: Option<f64>,
    /// n₁ = s₁Hv^q₁ (sand: s₁ = 0.71, q₁ = 0.14).
    pub s1: Option<f64>,
    pub q1: Option<f64>,
    /// n₂ = s₂Hv^q₂ (sand: s₂ = 2.4, q₂ = −0.94).
    pub s2: Option<f64>,
    pub q2: Option<f64>,
    /// U' [m/s] (104).
    pub reference_speed: Option<f64>,
    /// D' [m] (326 µm).
    pub reference_diameter: Option<f64>,
}

/// `[wear.dnv]`: DNV RP-O501 (2007) §3 (wear-model.md §6.8 alternatives). Defaults: steel.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DnvSection {
    /// K [(m/s)^−n] (steel 2.0e-9).
    #[serde(default = "dnv_k")]
    pub k: f64,
    /// Velocity exponent n (steel 2.6).
    #[serde(default = "dnv_n")]
    pub n: f64,
}

impl Default for DnvSection {
    fn default() -> Self {
        Self { k: dnv_k(), n: dnv_n() }
    }
}

/// `[wear.ecrc]`: E/CRC (wear-model.md §6.8, Eqs. 2.28–2.29). Defaults: Zhang et al. (2007)
/// steel. The sharpness F_s is `wear.material.sharpness`.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct EcrcSection {
    /// C (steel 2.17e-7).
    #[serde(default = "ecrc_c")]
    pub c: f64,
    /// Velocity exponent n (steel 2.41).
    #[serde(default = "ecrc_n")]
    pub n: f64,
    /// Wall Brinell hardness BH (required).
    pub brinell_hardness: Option<f64>,
}

fn two() -> f64 {
    2.0
}

fn dnv_k() -> f64 {
    2.0e-9
}

fn dnv_n() -> f64 {
    2.6
}

fn ecrc_c() -> f64 {
    2.17e-7
}

fn ecrc_n() -> f64 {
    2.41
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

/// `[wear.material]`: the eroded wall's constants (wear-model.md §6.5, Table 4.1). The Arabnejad
/// law needs a `preset` or every constant; the other laws read only `density` (E/CRC also
/// `sharpness`), from the preset or given.
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
    /// The named preset's constants (`None` without a preset).
    pub fn preset_constants(&self) -> Result<Option<MaterialConstants>, FieldError> {
        match &self.preset {
            Some(name) => Ok(Some(PRESETS.iter().find(|(n, _)| n == name).map(|(_, c)| *c).ok_or_else(|| {
                FieldError::new("wear.material.preset", format!("{name:?}"), format!("one of {}", PRESETS.map(|(n, _)| format!("{n:?}")).join(", ")))
            })?)),
            None => Ok(None),
        }
    }

    /// ρ_mat: given, or the preset's. All that the laws other than Arabnejad need.
    pub fn density(&self) -> Result<f64, FieldError> {
        let base = self.preset_constants()?;
        self.density
            .or(base.map(|c| c.density))
            .ok_or_else(|| FieldError::new("wear.material.density", "(missing)", "a value in kg/m³, or a `preset` that provides it"))
    }

    /// The constants: the preset's, each overridden by a value given in the case; without a
    /// preset every constant must be given.
    pub fn constants(&self) -> Result<MaterialConstants, FieldError> {
        let base = self.preset_constants()?;
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
        if let Some(m) = self.modifier {
            return Err(FieldError::new(
                "wear.modifier",
                m,
                format!("nothing here: move `modifier = {m}` to [particles] (real particles per simulated one; it counts in the coupling too)"),
            ));
        }
        // The law's sub-section, the material constants it reads and their ranges.
        super::laws::ErosionLaw::from_section(self)?;
        if let Some(sm) = &self.smoothing {
            positive("wear.smoothing.diffusivity", sm.diffusivity, "m²/s")?;
            positive("wear.smoothing.damping", sm.damping, "1/s (spreading time 1/λ)")?;
        }
        positive("wear.histogram_max_speed", self.histogram_max_speed, "m/s")?;
        if let Some(f) = &self.fluid_mesh {
            if !self.walls.is_empty() && !self.walls.contains(&f.wall) || !wall_names.contains(&f.wall.as_str()) {
                let eroding: Vec<&str> = if self.walls.is_empty() { wall_names.to_vec() } else { self.walls.iter().map(String::as_str).collect() };
                return Err(FieldError::new("wear.fluid_mesh.wall", format!("{:?}", f.wall), format!("an eroding wall: {}", eroding.join(", "))));
            }
            if let Some(depth) = f.depth {
                positive("wear.fluid_mesh.depth", depth, "m (how far into the water the mesh bends)")?;
            }
        }
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

    /// The key moved to `[particles]` (it counts in the coupling too): a case that still sets it
    /// is told where it went, not silently given a modifier of 1.
    #[test]
    fn the_retired_wear_modifier_says_where_it_went() {
        let err = parse("law = \"arabnejad\"\nmodifier = 100.0\n[material]\npreset = \"carbon_steel_1018\"\n").validate(&["box"]).unwrap_err();
        assert_eq!(err.key, "wear.modifier");
        assert!(err.allowed.contains("[particles]"), "{}", err.allowed);
    }
}
