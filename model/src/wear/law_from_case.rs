//! The erosion law a `[wear]` section asks for, with every constant resolved (defaults,
//! preset, given values) and checked: what the case file says, turned into a
//! [`ErosionLaw`] whose equations live in [`super::laws`]. Errors name the full key.

use super::laws::{ArabnejadOptions, DnvConstants, EcrcConstants, ErosionLaw, FinnieConstants, OkaConstants};
use super::settings::{AngleFunctionForm, ErosionLawName, WearSection};
use crate::case::error::{in_range, non_negative, positive, FieldError};

impl ErosionLaw {
    /// The law the `[wear]` section asks for, with every constant resolved (defaults, preset)
    /// and checked. Errors name the full key: a sub-section of another law (`wear.dnv` with
    /// `law = "arabnejad"`), a missing or out-of-range constant (`wear.finnie.flow_pressure`), or
    /// a material constant the law does not read.
    pub fn from_section(section: &WearSection) -> Result<ErosionLaw, FieldError> {
        let own = law_key(section.law);
        let sub_sections = [
            ("arabnejad", section.arabnejad.is_some()),
            ("finnie", section.finnie.is_some()),
            ("oka", section.oka.is_some()),
            ("dnv", section.dnv.is_some()),
            ("ecrc", section.ecrc.is_some()),
        ];
        for (key, present) in sub_sections {
            if present && key != own {
                return Err(FieldError::new(
                    format!("wear.{key}"),
                    format!("(a [wear.{key}] section)"),
                    format!("no [wear.{key}] with law = {own:?}: only [wear.{own}] belongs to it"),
                ));
            }
        }
        if section.law != ErosionLawName::Arabnejad && section.angle_function != AngleFunctionForm::default() {
            return Err(FieldError::new(
                "wear.angle_function",
                "\"continuous\"",
                format!("no `angle_function` with law = {own:?} (it is the Arabnejad switch of wear-model.md §6.4)"),
            ));
        }
        Ok(match section.law {
            ErosionLawName::Arabnejad => arabnejad_from_section(section)?,
            ErosionLawName::Finnie => ErosionLaw::Finnie { wall_density: density_only(section)?, constants: finnie_from_section(section)? },
            ErosionLawName::Oka => ErosionLaw::Oka { wall_density: density_only(section)?, constants: oka_from_section(section)? },
            ErosionLawName::Dnv => ErosionLaw::Dnv { wall_density: density_only(section)?, constants: dnv_from_section(section)? },
            ErosionLawName::Ecrc => ErosionLaw::Ecrc { wall_density: density_only(section)?, constants: ecrc_from_section(section)? },
        })
    }
}

/// Case-file name of a law (the serde names of [`ErosionLawName`]).
fn law_key(law: ErosionLawName) -> &'static str {
    match law {
        ErosionLawName::Arabnejad => "arabnejad",
        ErosionLawName::Finnie => "finnie",
        ErosionLawName::Oka => "oka",
        ErosionLawName::Dnv => "dnv",
        ErosionLawName::Ecrc => "ecrc",
    }
}

/// A required constant of a law's sub-section.
fn required(key: &str, value: Option<f64>, allowed: &str) -> Result<f64, FieldError> {
    value.ok_or_else(|| FieldError::new(key, "(missing)", format!("{allowed} (required with this law; there is no default)")))
}

fn finite(key: &str, value: f64) -> Result<(), FieldError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(FieldError::new(key, value, "a finite number"))
    }
}

/// Arabnejad: every material constant (preset and/or given), the three `[wear.arabnejad]`
/// switches and the top-level `angle_function` (§6.4, §6.5).
fn arabnejad_from_section(section: &WearSection) -> Result<ErosionLaw, FieldError> {
    let c = section.material.constants()?;
    positive("wear.material.density", c.density, "kg/m³")?;
    non_negative("wear.material.cutting_coefficient", c.cutting_coefficient, "")?;
    positive("wear.material.vickers_hardness", c.vickers_hardness, "")?;
    in_range("wear.material.sharpness", c.sharpness, 0.25, 1.0, "(0.25 rounded … 1 fully sharp, wear-model.md §6.5)")?;
    positive("wear.material.contact_ratio", c.contact_ratio, "")?;
    positive("wear.material.deformation_factor", c.deformation_factor, "")?;
    non_negative("wear.material.threshold_velocity", c.threshold_velocity, "m/s")?;
    let switches = section.arabnejad.unwrap_or_default();
    let options = ArabnejadOptions {
        include_cutting_coefficient: switches.include_cutting_coefficient,
        mass_prefactor: switches.mass_prefactor,
        deformation_form: switches.deformation_form,
        angle_function: section.angle_function,
    };
    Ok(ErosionLaw::Arabnejad { material: c, options })
}

/// The other laws read only ρ_mat from `[wear.material]` (and E/CRC the sharpness F_s): a given
/// Arabnejad constant would be silently ignored, so it is an error that says where the law's
/// constants go.
fn density_only(section: &WearSection) -> Result<f64, FieldError> {
    let own = law_key(section.law);
    let m = &section.material;
    let sharpness = if section.law == ErosionLawName::Ecrc { None } else { m.sharpness };
    let unread = [
        ("cutting_coefficient", m.cutting_coefficient),
        ("vickers_hardness", m.vickers_hardness),
        ("sharpness", sharpness),
        ("contact_ratio", m.contact_ratio),
        ("deformation_factor", m.deformation_factor),
        ("threshold_velocity", m.threshold_velocity),
    ];
    for (key, value) in unread {
        if let Some(value) = value {
            let reads = if section.law == ErosionLawName::Ecrc { "`density` and `sharpness`" } else { "`density`" };
            return Err(FieldError::new(
                format!("wear.material.{key}"),
                value,
                format!("no `{key}` with law = {own:?}: it reads only {reads} of [wear.material]; its constants go in [wear.{own}]"),
            ));
        }
    }
    let density = m.density()?;
    positive("wear.material.density", density, "kg/m³")?;
    Ok(density)
}

fn finnie_from_section(section: &WearSection) -> Result<FinnieConstants, FieldError> {
    let Some(s) = section.finnie else {
        return Err(FieldError::new(
            "wear.finnie.flow_pressure",
            "(missing)",
            "the wall's flow pressure in Pa, in a [wear.finnie] section (required with law = \"finnie\")",
        ));
    };
    let flow_pressure = required("wear.finnie.flow_pressure", s.flow_pressure, "the wall's flow pressure in Pa (a finite number > 0)")?;
    positive("wear.finnie.flow_pressure", flow_pressure, "Pa")?;
    positive("wear.finnie.force_ratio", s.force_ratio, "(Finnie: ≈ 2)")?;
    positive("wear.finnie.depth_ratio", s.depth_ratio, "(Finnie: ≈ 2)")?;
    in_range("wear.finnie.cutting_fraction", s.cutting_fraction, 0.0, 1.0, "(fraction of particles that cut)")?;
    Ok(FinnieConstants { flow_pressure, force_ratio: s.force_ratio, depth_ratio: s.depth_ratio, cutting_fraction: s.cutting_fraction })
}

/// Upper bound of a plausible Vickers hardness [GPa] (diamond is ~100 GPa): catches an HV number
/// (e.g. 131) given where GPa are meant.
const MAX_VICKERS_GPA: f64 = 100.0;

fn oka_from_section(section: &WearSection) -> Result<OkaConstants, FieldError> {
    let Some(s) = section.oka else {
        return Err(FieldError::new(
            "wear.oka.vickers_hardness_gpa",
            "(missing)",
            "the wall's Vickers hardness in GPa, in a [wear.oka] section (required with law = \"oka\")",
        ));
    };
    let hv = required("wear.oka.vickers_hardness_gpa", s.vickers_hardness_gpa, "the wall's Vickers hardness in GPa")?;
    if !(hv.is_finite() && hv > 0.0 && hv <= MAX_VICKERS_GPA) {
        return Err(FieldError::new(
            "wear.oka.vickers_hardness_gpa",
            hv,
            format!("a hardness in GPa in (0, {MAX_VICKERS_GPA}] (Oka's Hv is in GPa: HV 131 is 1.28 GPa)"),
        ));
    }
    let sand = OkaConstants::silica_sand(hv);
    let c = OkaConstants {
        vickers_hardness_gpa: hv,
        k: s.k.unwrap_or(sand.k),
        k1: s.k1.unwrap_or(sand.k1),
        k3: s.k3.unwrap_or(sand.k3),
        s1: s.s1.unwrap_or(sand.s1),
        q1: s.q1.unwrap_or(sand.q1),
        s2: s.s2.unwrap_or(sand.s2),
        q2: s.q2.unwrap_or(sand.q2),
        reference_speed: s.reference_speed.unwrap_or(sand.reference_speed),
        reference_diameter: s.reference_diameter.unwrap_or(sand.reference_diameter),
    };
    positive("wear.oka.k", c.k, "mm³/kg")?;
    positive("wear.oka.s1", c.s1, "(n₁ = s₁Hv^q₁ > 0 makes grazing impacts remove nothing)")?;
    for (key, value) in [("wear.oka.k1", c.k1), ("wear.oka.k3", c.k3), ("wear.oka.q1", c.q1), ("wear.oka.s2", c.s2), ("wear.oka.q2", c.q2)] {
        finite(key, value)?;
    }
    positive("wear.oka.reference_speed", c.reference_speed, "m/s")?;
    positive("wear.oka.reference_diameter", c.reference_diameter, "m")?;
    Ok(c)
}

fn dnv_from_section(section: &WearSection) -> Result<DnvConstants, FieldError> {
    let s = section.dnv.unwrap_or_default();
    positive("wear.dnv.k", s.k, "(m/s)^-n (steel: 2.0e-9)")?;
    positive("wear.dnv.n", s.n, "(steel: 2.6)")?;
    Ok(DnvConstants { k: s.k, n: s.n })
}

/// F_s when neither the case nor a preset gives one: the thesis' spherical particles (§6.5,
/// §9 assumption 6).
const DEFAULT_SHARPNESS: f64 = 0.5;

fn ecrc_from_section(section: &WearSection) -> Result<EcrcConstants, FieldError> {
    let Some(s) = section.ecrc else {
        return Err(FieldError::new(
            "wear.ecrc.brinell_hardness",
            "(missing)",
            "the wall's Brinell hardness, in a [wear.ecrc] section (required with law = \"ecrc\")",
        ));
    };
    let brinell_hardness = required("wear.ecrc.brinell_hardness", s.brinell_hardness, "the wall's Brinell hardness (a finite number > 0)")?;
    positive("wear.ecrc.brinell_hardness", brinell_hardness, "(Brinell hardness number)")?;
    positive("wear.ecrc.c", s.c, "(steel: 2.17e-7)")?;
    positive("wear.ecrc.n", s.n, "(steel: 2.41)")?;
    let preset = section.material.preset_constants()?;
    let sharpness = section.material.sharpness.or(preset.map(|c| c.sharpness)).unwrap_or(DEFAULT_SHARPNESS);
    if !(sharpness.is_finite() && sharpness > 0.0 && sharpness <= 1.0) {
        return Err(FieldError::new("wear.material.sharpness", sharpness, "a number in (0, 1] (F_s: 1 fully sharp, smaller for rounded particles)"));
    }
    Ok(EcrcConstants { c: s.c, n: s.n, brinell_hardness, sharpness })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wear::test_support::{arabnejad, law, section};

    #[test]
    fn each_law_builds_with_its_defaults() {
        let finnie = law("law = \"finnie\"\n[material]\npreset = \"stainless_steel_316\"\n[finnie]\nflow_pressure = 2e9\n");
        assert_eq!(
            finnie,
            ErosionLaw::Finnie {
                wall_density: 8000.0,
                constants: FinnieConstants { flow_pressure: 2e9, force_ratio: 2.0, depth_ratio: 2.0, cutting_fraction: 1.0 }
            }
        );
        assert_eq!(
            law("law = \"dnv\"\n[material]\ndensity = 7000.0\n"),
            ErosionLaw::Dnv { wall_density: 7000.0, constants: DnvConstants { k: 2.0e-9, n: 2.6 } }
        );
        assert_eq!(
            law("law = \"ecrc\"\n[material]\ndensity = 7000.0\nsharpness = 1.0\n[ecrc]\nbrinell_hardness = 150.0\n"),
            ErosionLaw::Ecrc { wall_density: 7000.0, constants: EcrcConstants { c: 2.17e-7, n: 2.41, brinell_hardness: 150.0, sharpness: 1.0 } }
        );
        let a = arabnejad("carbon_steel_1018", "");
        assert_eq!((a.name(), a.wall_density()), ("arabnejad", 7870.0));
        let ErosionLaw::Arabnejad { options, .. } = a else { panic!() };
        assert_eq!(options, ArabnejadOptions::default());
        let names: Vec<&str> = ["finnie", "oka", "dnv", "ecrc"].to_vec();
        assert_eq!(
            names,
            [
                law("law = \"finnie\"\n[material]\ndensity = 1.0\n[finnie]\nflow_pressure = 1.0\n").name(),
                law("law = \"oka\"\n[material]\ndensity = 1.0\n[oka]\nvickers_hardness_gpa = 1.0\n").name(),
                law("law = \"dnv\"\n[material]\ndensity = 1.0\n").name(),
                law("law = \"ecrc\"\n[material]\ndensity = 1.0\n[ecrc]\nbrinell_hardness = 1.0\n").name(),
            ]
        );
    }

    #[test]
    fn bad_law_input_names_the_key() {
        let cs = "[material]\npreset = \"carbon_steel_1018\"\n";
        let cases = [
            // Another law's sub-section.
            (format!("law = \"arabnejad\"\n{cs}[dnv]\nk = 1e-9\n"), "wear.dnv"),
            (format!("law = \"dnv\"\n{cs}[arabnejad]\ninclude_cutting_coefficient = false\n"), "wear.arabnejad"),
            (format!("law = \"oka\"\n{cs}[oka]\nvickers_hardness_gpa = 1.0\n[finnie]\nflow_pressure = 1e9\n"), "wear.finnie"),
            (format!("law = \"dnv\"\nangle_function = \"continuous\"\n{cs}"), "wear.angle_function"),
            // Required constants.
            (format!("law = \"finnie\"\n{cs}"), "wear.finnie.flow_pressure"),
            (format!("law = \"finnie\"\n{cs}[finnie]\nforce_ratio = 2.0\n"), "wear.finnie.flow_pressure"),
            (format!("law = \"oka\"\n{cs}"), "wear.oka.vickers_hardness_gpa"),
            (format!("law = \"oka\"\n{cs}[oka]\nk = 65.0\n"), "wear.oka.vickers_hardness_gpa"),
            (format!("law = \"ecrc\"\n{cs}"), "wear.ecrc.brinell_hardness"),
            (format!("law = \"ecrc\"\n{cs}[ecrc]\nc = 1e-7\n"), "wear.ecrc.brinell_hardness"),
            ("law = \"dnv\"\n[material]\n".to_string(), "wear.material.density"),
            // Ranges.
            (format!("law = \"finnie\"\n{cs}[finnie]\nflow_pressure = -1e9\n"), "wear.finnie.flow_pressure"),
            (format!("law = \"finnie\"\n{cs}[finnie]\nflow_pressure = 1e9\ncutting_fraction = 1.5\n"), "wear.finnie.cutting_fraction"),
            (format!("law = \"finnie\"\n{cs}[finnie]\nflow_pressure = 1e9\nforce_ratio = 0.0\n"), "wear.finnie.force_ratio"),
            (format!("law = \"finnie\"\n{cs}[finnie]\nflow_pressure = 1e9\ndepth_ratio = nan\n"), "wear.finnie.depth_ratio"),
            (format!("law = \"oka\"\n{cs}[oka]\nvickers_hardness_gpa = 0.0\n"), "wear.oka.vickers_hardness_gpa"),
            (format!("law = \"oka\"\n{cs}[oka]\nvickers_hardness_gpa = 131.0\n"), "wear.oka.vickers_hardness_gpa"),
            (format!("law = \"oka\"\n{cs}[oka]\nvickers_hardness_gpa = 1.8\ns1 = 0.0\n"), "wear.oka.s1"),
            (format!("law = \"oka\"\n{cs}[oka]\nvickers_hardness_gpa = 1.8\nq2 = inf\n"), "wear.oka.q2"),
            (format!("law = \"oka\"\n{cs}[oka]\nvickers_hardness_gpa = 1.8\nreference_diameter = 0.0\n"), "wear.oka.reference_diameter"),
            (format!("law = \"dnv\"\n{cs}[dnv]\nn = 0.0\n"), "wear.dnv.n"),
            (format!("law = \"dnv\"\n{cs}[dnv]\nk = -2e-9\n"), "wear.dnv.k"),
            (format!("law = \"ecrc\"\n{cs}[ecrc]\nbrinell_hardness = -1.0\n"), "wear.ecrc.brinell_hardness"),
            (format!("law = \"ecrc\"\n{cs}[ecrc]\nbrinell_hardness = 120.0\nc = 0.0\n"), "wear.ecrc.c"),
            (format!("law = \"ecrc\"\n{cs}[ecrc]\nbrinell_hardness = 120.0\nn = -2.41\n"), "wear.ecrc.n"),
            ("law = \"ecrc\"\n[material]\ndensity = 7800.0\nsharpness = 1.5\n[ecrc]\nbrinell_hardness = 120.0\n".to_string(), "wear.material.sharpness"),
            ("law = \"dnv\"\n[material]\ndensity = -7800.0\n".to_string(), "wear.material.density"),
            // A material constant the law does not read.
            (
                "law = \"oka\"\n[material]\ndensity = 7800.0\nvickers_hardness = 131.0\n[oka]\nvickers_hardness_gpa = 1.3\n".to_string(),
                "wear.material.vickers_hardness",
            ),
            ("law = \"dnv\"\n[material]\ndensity = 7800.0\nsharpness = 0.5\n".to_string(), "wear.material.sharpness"),
            (
                "law = \"finnie\"\n[material]\ndensity = 7800.0\nthreshold_velocity = 1.0\n[finnie]\nflow_pressure = 1e9\n".to_string(),
                "wear.material.threshold_velocity",
            ),
            // Arabnejad: every material constant, as before.
            ("law = \"arabnejad\"\n[material]\ndensity = 7000.0\n".to_string(), "wear.material.cutting_coefficient"),
            ("law = \"arabnejad\"\n[material]\npreset = \"carbon_steel_1018\"\ndeformation_factor = 0.0\n".to_string(), "wear.material.deformation_factor"),
            ("law = \"dnv\"\n[material]\npreset = \"brass\"\n".to_string(), "wear.material.preset"),
        ];
        for (text, key) in &cases {
            let err = ErosionLaw::from_section(&section(text)).unwrap_err();
            assert_eq!(err.key, *key, "{text}");
            // `validate` reports the same error.
            assert_eq!(section(text).validate(&[]).unwrap_err(), err, "{text}");
        }
    }

    #[test]
    fn sub_sections_reject_unknown_keys_and_values() {
        for (text, word) in [
            ("law = \"dnv\"\n[material]\ndensity = 1.0\n[dnv]\nexponent = 2.6\n", "exponent"),
            ("law = \"finnie\"\n[material]\ndensity = 1.0\n[finnie]\nflow_pressure = 1.0\nK = 2.0\n", "K"),
            ("law = \"arabnejad\"\n[material]\npreset = \"carbon_steel_1018\"\n[arabnejad]\nmass_prefactor = \"rho_p\"\n", "rho_p"),
            ("law = \"arabnejad\"\n[material]\npreset = \"carbon_steel_1018\"\n[arabnejad]\ndeformation_form = \"squared\"\n", "squared"),
        ] {
            let err = toml::from_str::<WearSection>(text).unwrap_err().to_string();
            assert!(err.contains(word), "{err}");
        }
    }
}
