//! The erosion laws of `spillage-model` (built from `[wear]` case text) against the independent
//! referee `spillage-analytic::erosion`, for every law and every Arabnejad switch combination
//! (wear-model.md §6.4, §6.8, §15 A1–A15).
//!
//! Grid: θ = 0°…90° in 2.5° steps (90° as the float π/2), plus each law's branch angle exactly
//! and ± 1e-9 rad (Arabnejad θ_c = tan⁻¹K, Finnie tan⁻¹(K/6)); U = 0.1, 1, 3, 10, 30 m/s; two
//! particles (1 mm garnet, 150 µm sand).
//!
//! Tolerance: relative difference ≤ 1e-12. Both codes evaluate the same closed-form formula,
//! written separately, so they can differ only by round-off: a few operations (sin, powf,
//! products in another order) at ~1e-16 each. The one amplifier is DNV's alternating degree-8
//! polynomial F(θ), whose condition number Σ|Aᵢθⁱ|/|F| grows to ≈ 1e4 at 90°: the model sums it
//! in Horner form, the referee term by term, and the two differ by up to 6.6e-13 on this grid
//! (plain IEEE arithmetic, no libm call, so the same on every platform). Arabnejad agrees bit for
//! bit, Finnie/Oka/E/CRC within 1e-14. A wrong constant, exponent, switch or branch shows up at
//! ≥ 1e-6 (a factor 2 at θ_c for the angle-function branch). Zeros (grazing impact, head-on
//! cutting, clipped deformation) must be exactly zero in both.

use std::f64::consts::FRAC_PI_2;

use spillage_analytic::erosion as referee;
use spillage_model::wear::laws::{ErosionLaw, ImpactInput};
use spillage_model::wear::settings::WearSection;

const TOLERANCE: f64 = 1e-12;
const SPEEDS: [f64; 5] = [0.1, 1.0, 3.0, 10.0, 30.0];

/// |a − b| / max(|a|, |b|), 0 when both are equal (including both exactly 0).
fn relative_difference(model: f64, analytic: f64) -> f64 {
    if model == analytic {
        0.0
    } else {
        (model - analytic).abs() / model.abs().max(analytic.abs())
    }
}

fn assert_close(model: f64, analytic: f64, what: &str) {
    let d = relative_difference(model, analytic);
    assert!(d <= TOLERANCE, "{what}: model {model:e} vs analytic {analytic:e} (relative difference {d:e})");
}

/// 0…90° in 2.5° steps, plus each branch angle exactly and ± 1e-9 rad.
fn angles(branch_angles: &[f64]) -> Vec<f64> {
    let mut out: Vec<f64> = (0..36).map(|i| (i as f64 * 2.5).to_radians()).collect();
    out.push(FRAC_PI_2);
    for &b in branch_angles {
        out.extend([b - 1e-9, b, b + 1e-9]);
    }
    out
}

/// 1 mm garnet (2500 kg/m³, the thesis' particle) and 150 µm sand (2650 kg/m³).
fn particles() -> [(f64, f64); 2] {
    [(1e-3, 2500.0), (150e-6, 2650.0)]
}

/// Every (particle, speed, angle) of the grid as a model impact.
fn impacts(branch_angles: &[f64]) -> Vec<ImpactInput> {
    let mut out = Vec::new();
    for (diameter, density) in particles() {
        let mass = density * std::f64::consts::PI * diameter * diameter * diameter / 6.0;
        for speed in SPEEDS {
            for &angle in &angles(branch_angles) {
                out.push(ImpactInput { speed, angle, mass, diameter, density });
            }
        }
    }
    out
}

fn law(text: &str) -> ErosionLaw {
    let section: WearSection = toml::from_str(text).unwrap_or_else(|e| panic!("{text}: {e}"));
    section.validate(&[]).unwrap_or_else(|e| panic!("{text}: {e:?}"));
    ErosionLaw::from_section(&section).unwrap()
}

/// Model erosion ratio ρ_mat W/m against the referee's `erosion_ratio` of its own volume: the
/// building block of a stream check (removed mass / impacting mass).
fn assert_erosion_ratio(law: &ErosionLaw, i: &ImpactInput, analytic_volume: f64, what: &str) {
    let analytic = referee::erosion_ratio(law.wall_density(), analytic_volume, i.mass).unwrap();
    assert_close(law.erosion_ratio(i), analytic, &format!("{what}: erosion ratio"));
}

#[test]
fn arabnejad_matches_the_referee_for_every_switch_combination() {
    let materials = [
        ("preset = \"carbon_steel_1018\"", referee::CARBON_STEEL_1018),
        ("preset = \"stainless_steel_316\"", referee::STAINLESS_STEEL_316),
        // Glass-bead contact ratio K = 1 (θ_c = 45°, on the 2.5° grid) and a sharper particle.
        (
            "density = 7500.0\ncutting_coefficient = 0.02\nvickers_hardness = 180.0\nsharpness = 1.0\ncontact_ratio = 1.0\ndeformation_factor = 2e11\nthreshold_velocity = 2.0",
            referee::ArabnejadMaterial {
                density: 7500.0,
                cutting_coefficient: 0.02,
                vickers_hardness: 180.0,
                sharpness: 1.0,
                contact_ratio: 1.0,
                deformation_factor: 2e11,
                threshold_velocity: 2.0,
            },
        ),
    ];
    let mass_prefactors = [("particle_mass", referee::MassPrefactor::ParticleMass), ("particle_density", referee::MassPrefactor::ParticleDensity)];
    let deformation_forms = [
        ("squared_clipped", referee::DeformationForm::SquaredClipped),
        ("literal_square", referee::DeformationForm::LiteralSquare),
        ("linear_clipped", referee::DeformationForm::LinearClipped),
    ];
    let angle_functions = [("thesis_literal", referee::AngleFunction::ThesisLiteral), ("continuous", referee::AngleFunction::Continuous)];
    let mut compared = 0;
    let mut combinations = 0;
    for (material_text, material) in &materials {
        let impacts = impacts(&[referee::critical_angle(material.contact_ratio)]);
        for include_c in [true, false] {
            for (prefactor_text, mass_prefactor) in mass_prefactors {
                for (deformation_text, deformation_form) in deformation_forms {
                    for (angle_text, angle_function) in angle_functions {
                        let text = format!(
                            "law = \"arabnejad\"\nangle_function = \"{angle_text}\"\n[material]\n{material_text}\n[arabnejad]\ninclude_cutting_coefficient = {include_c}\nmass_prefactor = \"{prefactor_text}\"\ndeformation_form = \"{deformation_text}\"\n"
                        );
                        let model = law(&text);
                        assert_eq!((model.name(), model.wall_density()), ("arabnejad", material.density));
                        let options = referee::ArabnejadOptions { include_cutting_coefficient: include_c, mass_prefactor, deformation_form, angle_function };
                        combinations += 1;
                        for i in &impacts {
                            let what = format!("{text} {i:?}");
                            let w = model.removed_volume(i);
                            let a = referee::arabnejad_wear(material, &options, i.mass, i.density, i.speed, i.angle).unwrap();
                            assert_close(w.cutting, a.cutting_volume, &format!("{what}: cutting"));
                            assert_close(w.deformation, a.deformation_volume, &format!("{what}: deformation"));
                            assert_close(w.total(), a.volume, &format!("{what}: total"));
                            assert_close(model.wall_density() * w.total(), a.mass, &format!("{what}: removed mass"));
                            assert_erosion_ratio(&model, i, a.volume, &what);
                            compared += 1;
                        }
                    }
                }
            }
        }
    }
    // 3 materials × 24 switch combinations, each over 2 particles × 5 speeds × 40 angles.
    assert_eq!((combinations, compared), (72, 72 * 2 * 5 * 40));
}

#[test]
fn the_canonical_defaults_are_the_referees_defaults() {
    // No [wear.arabnejad] and no angle_function: the canonical form of §6.4.
    let default = law("law = \"arabnejad\"\n[material]\npreset = \"carbon_steel_1018\"\n");
    let options = referee::ArabnejadOptions::default();
    for i in impacts(&[referee::critical_angle(0.4)]) {
        let a = referee::arabnejad_wear(&referee::CARBON_STEEL_1018, &options, i.mass, i.density, i.speed, i.angle).unwrap();
        assert_close(default.removed_volume(&i).total(), a.volume, &format!("{i:?}"));
    }
}

#[test]
fn finnie_matches_the_referee() {
    for (text, parameters) in [
        ("flow_pressure = 2e9", referee::FinnieParameters { flow_pressure: 2e9, force_ratio: 2.0, depth_ratio: 2.0, cutting_fraction: 1.0 }),
        (
            "flow_pressure = 5e8\nforce_ratio = 3.0\ndepth_ratio = 1.5\ncutting_fraction = 0.4",
            referee::FinnieParameters { flow_pressure: 5e8, force_ratio: 3.0, depth_ratio: 1.5, cutting_fraction: 0.4 },
        ),
    ] {
        let model = law(&format!("law = \"finnie\"\n[material]\ndensity = 7800.0\n[finnie]\n{text}\n"));
        assert_eq!(model.name(), "finnie");
        for i in impacts(&[(parameters.force_ratio / 6.0).atan()]) {
            let w = model.removed_volume(&i);
            let a = referee::finnie_volume(&parameters, i.mass, i.speed, i.angle).unwrap();
            assert_close(w.cutting, a, &format!("{text} {i:?}"));
            assert_eq!(w.deformation, 0.0);
            assert_erosion_ratio(&model, &i, a, text);
        }
    }
}

#[test]
fn oka_matches_the_referee() {
    let custom = referee::OkaParameters {
        vickers_hardness_gpa: 1.3,
        k: 50.0,
        k1: -0.1,
        k3: 0.2,
        s1: 0.8,
        q1: 0.1,
        s2: 2.0,
        q2: -0.9,
        reference_speed: 100.0,
        reference_diameter: 300e-6,
    };
    for (text, parameters) in [
        ("vickers_hardness_gpa = 1.83", referee::OkaParameters::silica_sand(1.83)),
        (
            "vickers_hardness_gpa = 1.3\nk = 50.0\nk1 = -0.1\nk3 = 0.2\ns1 = 0.8\nq1 = 0.1\ns2 = 2.0\nq2 = -0.9\nreference_speed = 100.0\nreference_diameter = 300e-6",
            custom,
        ),
    ] {
        let model = law(&format!("law = \"oka\"\n[material]\ndensity = 7800.0\n[oka]\n{text}\n"));
        assert_eq!(model.name(), "oka");
        for i in impacts(&[]) {
            let w = model.removed_volume(&i);
            let a = parameters.volume(i.mass, i.diameter, i.speed, i.angle).unwrap();
            assert_close(w.cutting, a, &format!("{text} {i:?}"));
            assert_eq!(w.deformation, 0.0);
            assert_erosion_ratio(&model, &i, a, text);
        }
    }
}

#[test]
fn dnv_matches_the_referee() {
    for (text, k, n) in [("", referee::DNV_STEEL_K, referee::DNV_STEEL_N), ("[dnv]\nk = 1e-9\nn = 2.2\n", 1e-9, 2.2)] {
        let model = law(&format!("law = \"dnv\"\n[material]\npreset = \"stainless_steel_316\"\n{text}"));
        assert_eq!((model.name(), model.wall_density()), ("dnv", 8000.0));
        for i in impacts(&[]) {
            let w = model.removed_volume(&i);
            // DNV gives a removed mass; the model converts it with ρ_mat.
            let removed_mass = referee::dnv_removed_mass(k, n, i.mass, i.speed, i.angle).unwrap();
            assert_close(w.cutting, removed_mass / 8000.0, &format!("{text} {i:?}"));
            assert_eq!(w.deformation, 0.0);
            assert_close(model.erosion_ratio(&i), removed_mass / i.mass, &format!("{text} {i:?}: erosion ratio"));
            assert_erosion_ratio(&model, &i, removed_mass / 8000.0, text);
        }
    }
}

#[test]
fn ecrc_matches_the_referee() {
    for (text, c, n, brinell, sharpness) in [
        // Steel defaults; F_s = 0.5 from the preset.
        ("[material]\npreset = \"carbon_steel_1018\"\n[ecrc]\nbrinell_hardness = 120.0\n", referee::ECRC_STEEL_C, referee::ECRC_STEEL_N, 120.0, 0.5),
        ("[material]\ndensity = 7870.0\nsharpness = 1.0\n[ecrc]\nbrinell_hardness = 200.0\nc = 1e-7\nn = 2.0\n", 1e-7, 2.0, 200.0, 1.0),
    ] {
        let model = law(&format!("law = \"ecrc\"\n{text}"));
        assert_eq!((model.name(), model.wall_density()), ("ecrc", 7870.0));
        for i in impacts(&[]) {
            let w = model.removed_volume(&i);
            // E/CRC gives an erosion ratio (kg/kg): the model's ρ_mat W/m must be it.
            let ratio = referee::ecrc_erosion_ratio(c, n, brinell, sharpness, i.speed, i.angle).unwrap();
            assert_close(model.erosion_ratio(&i), ratio, &format!("{text} {i:?}: erosion ratio"));
            assert_close(w.cutting, ratio * i.mass / 7870.0, &format!("{text} {i:?}"));
            assert_eq!(w.deformation, 0.0);
        }
    }
}
