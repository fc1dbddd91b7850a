//! Erosion of a ductile wall by one particle impact.
//!
//! wear-model.md §5 (rebound, Eq. 4.4), §6 (Arabnejad et al. 2015b cutting + deformation,
//! Eqs. 2.35–2.39 with the spec's canonical form and its switches), §6.8 (alternative laws) and
//! §15 (checks A1–A16). Angles θ are measured from the wall *surface* (0 = grazing,
//! 90° = head-on), in radians.
//!
//! The alternative laws of §6.8 are given in the spec without constants (E/CRC) or without any
//! formula (Oka, Finnie); their forms and constants here come from the original papers and are
//! marked as literature values: check them before quantitative use.

use serde::{Deserialize, Serialize};

use crate::error::{in_closed, non_negative, positive, AnalyticError, Result};

/// Arabnejad wall-material constants (wear-model.md §6.5, Tables 4.1/5.2, as printed).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ArabnejadMaterial {
    /// Wall density ρ_mat [kg/m³].
    pub density: f64,
    /// Cutting erosion factor C.
    pub cutting_coefficient: f64,
    /// Vickers hardness Hv (the printed "GPa" numbers; a calibration input, §6.7).
    pub vickers_hardness: f64,
    /// Particle sharpness factor F_s (0.5 for the thesis's spherical particles).
    pub sharpness: f64,
    /// Ratio of contact K (0.4 for sand).
    pub contact_ratio: f64,
    /// Deformation erosion factor ε.
    pub deformation_factor: f64,
    /// Threshold normal speed U_tsh [m/s].
    pub threshold_velocity: f64,
}

/// Carbon steel 1018 (Table 4.1).
pub const CARBON_STEEL_1018: ArabnejadMaterial = ArabnejadMaterial {
    density: 7870.0,
    cutting_coefficient: 0.01,
    vickers_hardness: 131.0,
    sharpness: 0.5,
    contact_ratio: 0.4,
    deformation_factor: 4.2e11,
    threshold_velocity: 0.5,
};

/// Stainless steel 316 (Table 5.2).
pub const STAINLESS_STEEL_316: ArabnejadMaterial = ArabnejadMaterial {
    density: 8000.0,
    cutting_coefficient: 0.0125,
    vickers_hardness: 224.0,
    sharpness: 0.5,
    contact_ratio: 0.4,
    deformation_factor: 1.4e11,
    threshold_velocity: 5.7,
};

/// Cutting angle function variant (wear-model.md §6.6, switch 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum AngleFunction {
    /// Eq. 2.36 as printed: cos²θ above θ_c (jumps by a factor 2 at θ_c). Default.
    ThesisLiteral,
    /// High branch ½cos²θ, continuous at θ_c (the spec's deduction, unverified).
    Continuous,
}

/// Deformation term variant (wear-model.md §6.4, switch 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum DeformationForm {
    /// (max(0, U sinθ − U_tsh))² — Bitter's clip-then-square. Default.
    SquaredClipped,
    /// max(0, (U sinθ − U_tsh)²) as printed in Eq. 2.38 (never clips).
    LiteralSquare,
    /// max(0, U sinθ − U_tsh) as in the §2.5 summary (no square).
    LinearClipped,
}

/// Mass prefactor variant (wear-model.md §6.4, switch 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum MassPrefactor {
    /// m, the particle mass (Eqs. 2.35, 2.37, 2.39). Default.
    ParticleMass,
    /// ρ_p, as in the §2.5 summary (dimensionally inconsistent).
    ParticleDensity,
}

/// The four switches of wear-model.md §6.4; `Default` is the canonical form.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct ArabnejadOptions {
    /// Multiply the cutting term by C (Eq. 2.35; dropped in the printed 2.39). Default true.
    pub include_cutting_coefficient: bool,
    pub mass_prefactor: MassPrefactor,
    pub deformation_form: DeformationForm,
    pub angle_function: AngleFunction,
}

impl Default for ArabnejadOptions {
    fn default() -> Self {
        Self {
            include_cutting_coefficient: true,
            mass_prefactor: MassPrefactor::ParticleMass,
            deformation_form: DeformationForm::SquaredClipped,
            angle_function: AngleFunction::ThesisLiteral,
        }
    }
}

/// Wear from one impact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ImpactWear {
    /// Cutting part of the removed volume [m³, in the printed units].
    pub cutting_volume: f64,
    /// Deformation part.
    pub deformation_volume: f64,
    /// Total removed wall volume W_i.
    pub volume: f64,
    /// Removed wall mass ρ_mat W_i [kg].
    pub mass: f64,
}

fn check_angle(angle: f64) -> Result<f64> {
    in_closed("impact_angle", angle, 0.0, std::f64::consts::FRAC_PI_2, "in [0, pi/2] rad (0 = grazing)")
}

/// Critical angle θ_c = atan K (wear-model.md §6.5, A1: 21.8014094864° for K = 0.4).
pub fn critical_angle(contact_ratio: f64) -> f64 {
    contact_ratio.atan()
}

/// Cutting angle function f(θ) (Eq. 2.36): (K sin2θ − sin²θ)/(2K²) for θ ≤ atan K, cos²θ above
/// (or ½cos²θ for [`AngleFunction::Continuous`]).
pub fn cutting_angle_function(angle: f64, contact_ratio: f64, variant: AngleFunction) -> Result<f64> {
    let theta = check_angle(angle)?;
    let k = positive("contact_ratio", contact_ratio)?;
    Ok(if theta <= critical_angle(k) {
        (k * (2.0 * theta).sin() - theta.sin().powi(2)) / (2.0 * k * k)
    } else {
        // sin(π/2 − θ) instead of cos θ: exactly 0 at normal impact.
        let high = (std::f64::consts::FRAC_PI_2 - theta).sin().powi(2);
        match variant {
            AngleFunction::ThesisLiteral => high,
            AngleFunction::Continuous => 0.5 * high,
        }
    })
}

/// Deformation function g (Eq. 2.38 and its variants).
pub fn deformation_function(speed: f64, angle: f64, threshold: f64, form: DeformationForm) -> Result<f64> {
    non_negative("speed", speed)?;
    let theta = check_angle(angle)?;
    non_negative("threshold_velocity", threshold)?;
    let excess = speed * theta.sin() - threshold;
    Ok(match form {
        DeformationForm::SquaredClipped => excess.max(0.0).powi(2),
        DeformationForm::LiteralSquare => excess * excess,
        DeformationForm::LinearClipped => excess.max(0.0),
    })
}

/// Arabnejad cutting + deformation wear of one impact (wear-model.md §6.4 canonical form):
/// W = (m F_s/2) [C U^2.41 f(θ)/√Hv + g(θ)/ε]. `particle_density` is used only by the
/// [`MassPrefactor::ParticleDensity`] switch.
pub fn arabnejad_wear(
    material: &ArabnejadMaterial,
    options: &ArabnejadOptions,
    particle_mass: f64,
    particle_density: f64,
    speed: f64,
    angle: f64,
) -> Result<ImpactWear> {
    positive("particle_mass", particle_mass)?;
    positive("particle_density", particle_density)?;
    positive("vickers_hardness", material.vickers_hardness)?;
    positive("deformation_factor", material.deformation_factor)?;
    let prefactor = match options.mass_prefactor {
        MassPrefactor::ParticleMass => particle_mass,
        MassPrefactor::ParticleDensity => particle_density,
    } * material.sharpness
        / 2.0;
    let c = if options.include_cutting_coefficient { material.cutting_coefficient } else { 1.0 };
    let f = cutting_angle_function(angle, material.contact_ratio, options.angle_function)?;
    let g = deformation_function(speed, angle, material.threshold_velocity, options.deformation_form)?;
    let cutting_volume = prefactor * c * speed.powf(2.41) * f / material.vickers_hardness.sqrt();
    let deformation_volume = prefactor * g / material.deformation_factor;
    let volume = cutting_volume + deformation_volume;
    Ok(ImpactWear { cutting_volume, deformation_volume, volume, mass: material.density * volume })
}

/// Arabnejad sliding wear rate [m³/s] of a particle pressed onto a wall by the normal force
/// `normal_force` [N] while sliding at `speed` [m/s] (wear-model.md §14 item 12, the thesis'
/// point particle re-colliding with restitution e at every step).
///
/// Derivation, independent of the solvers: a rebound at normal speed v_n = U sinθ transfers
/// the normal impulse J = (1 + e) m U sinθ. At small θ the cutting angle function is
/// f(θ) = (K sin2θ − sin²θ)/(2K²) = θ/K + O(θ²), so one grazing impact removes
/// W = (m F_s / 2) C U^2.41 θ / (K √Hv) and the deformation term is zero (U sinθ → 0 below any
/// threshold). Per unit impulse W/J = F_s C U^1.41 / (2 K (1 + e) √Hv), whatever θ; a wall
/// that delivers the impulse rate F_n therefore wears at
/// dW/dt = F_s C U^1.41 F_n / (2 K (1 + e) √Hv), per real particle.
pub fn arabnejad_sliding_wear_rate(material: &ArabnejadMaterial, restitution: f64, normal_force: f64, speed: f64) -> Result<f64> {
    non_negative("normal_force", normal_force)?;
    non_negative("speed", speed)?;
    positive("vickers_hardness", material.vickers_hardness)?;
    positive("contact_ratio", material.contact_ratio)?;
    non_negative("restitution", restitution)?;
    Ok(material.sharpness * material.cutting_coefficient * speed.powf(1.41) * normal_force
        / (2.0 * material.contact_ratio * (1.0 + restitution) * material.vickers_hardness.sqrt()))
}

/// Erosion ratio ER = ρ_mat W/m (wear-model.md §6.4, A15).
pub fn erosion_ratio(wall_density: f64, removed_volume: f64, particle_mass: f64) -> Result<f64> {
    positive("particle_mass", particle_mass)?;
    Ok(wall_density * removed_volume / particle_mass)
}

/// Finnie (1960) micro-cutting (literature form; wear-model.md §6.1/§6.8 name it as background):
/// V = c m U²/(p ψ K) f(θ), f = sin2θ − (6/K) sin²θ for tanθ ≤ K/6, (K/6) cos²θ above.
/// K = ratio of vertical to horizontal force (≈ 2), ψ = contact depth / cut depth (≈ 2),
/// c = fraction of particles cutting, p = flow pressure [Pa].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FinnieParameters {
    pub flow_pressure: f64,
    pub force_ratio: f64,
    pub depth_ratio: f64,
    pub cutting_fraction: f64,
}

/// Finnie angle function (see [`FinnieParameters`]).
pub fn finnie_angle_function(angle: f64, force_ratio: f64) -> Result<f64> {
    let theta = check_angle(angle)?;
    let k = positive("force_ratio", force_ratio)?;
    Ok(if theta.tan() <= k / 6.0 { (2.0 * theta).sin() - 6.0 / k * theta.sin().powi(2) } else { k / 6.0 * (std::f64::consts::FRAC_PI_2 - theta).sin().powi(2) })
}

/// Finnie removed volume [m³] for particle mass m [kg] at speed U and angle θ.
pub fn finnie_volume(parameters: &FinnieParameters, particle_mass: f64, speed: f64, angle: f64) -> Result<f64> {
    positive("flow_pressure", parameters.flow_pressure)?;
    positive("depth_ratio", parameters.depth_ratio)?;
    in_closed("cutting_fraction", parameters.cutting_fraction, 0.0, 1.0, "in [0, 1]")?;
    positive("particle_mass", particle_mass)?;
    non_negative("speed", speed)?;
    let f = finnie_angle_function(angle, parameters.force_ratio)?;
    Ok(parameters.cutting_fraction * particle_mass * speed * speed / (parameters.flow_pressure * parameters.depth_ratio * parameters.force_ratio) * f)
}

/// Oka & Yoshida (2005) (literature form, named in wear-model.md §6.8 without formula):
/// E(θ) = g(θ) E₉₀ [mm³/kg], g = sin^n₁θ (1 + Hv(1 − sinθ))^n₂, n₁ = s₁Hv^q₁, n₂ = s₂Hv^q₂,
/// E₉₀ = K Hv^k₁ (U/U')^k₂ (D/D')^k₃, k₂ = 2.3 Hv^0.038; Hv in GPa.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OkaParameters {
    /// Wall Vickers hardness [GPa].
    pub vickers_hardness_gpa: f64,
    pub k: f64,
    pub k1: f64,
    pub k3: f64,
    pub s1: f64,
    pub q1: f64,
    pub s2: f64,
    pub q2: f64,
    /// U' [m/s].
    pub reference_speed: f64,
    /// D' [m].
    pub reference_diameter: f64,
}

impl OkaParameters {
    /// SiO₂ sand constants of Oka & Yoshida (2005) (K = 65, k₁ = −0.12, k₃ = 0.19, s₁ = 0.71,
    /// q₁ = 0.14, s₂ = 2.4, q₂ = −0.94, U' = 104 m/s, D' = 326 µm) — literature values.
    pub fn silica_sand(vickers_hardness_gpa: f64) -> Self {
        Self { vickers_hardness_gpa, k: 65.0, k1: -0.12, k3: 0.19, s1: 0.71, q1: 0.14, s2: 2.4, q2: -0.94, reference_speed: 104.0, reference_diameter: 326e-6 }
    }

    /// Angle function g(θ), = 1 at normal impact.
    pub fn angle_function(&self, angle: f64) -> Result<f64> {
        let theta = check_angle(angle)?;
        let hv = positive("vickers_hardness_gpa", self.vickers_hardness_gpa)?;
        let n1 = self.s1 * hv.powf(self.q1);
        let n2 = self.s2 * hv.powf(self.q2);
        Ok(theta.sin().powf(n1) * (1.0 + hv * (1.0 - theta.sin())).powf(n2))
    }

    /// Removed volume [m³] for particle mass m [kg], diameter D [m], speed U, angle θ.
    pub fn volume(&self, particle_mass: f64, diameter: f64, speed: f64, angle: f64) -> Result<f64> {
        positive("particle_mass", particle_mass)?;
        positive("diameter", diameter)?;
        non_negative("speed", speed)?;
        let hv = self.vickers_hardness_gpa;
        let k2 = 2.3 * hv.powf(0.038);
        let e90 = self.k * hv.powf(self.k1) * (speed / self.reference_speed).powf(k2) * (diameter / self.reference_diameter).powf(self.k3);
        // mm³ per kg of particles → m³.
        Ok(self.angle_function(angle)? * e90 * particle_mass * 1e-9)
    }
}

/// DNV RP-O501 (2007) §3 (literature; the thesis does not mention it): E_L = K U^n F(θ)
/// [kg removed per kg of particles], F(θ) = Σᵢ (−1)^(i+1) Aᵢ θⁱ (θ in rad), steel: K = 2.0e-9,
/// n = 2.6, A = 9.370, 42.295, 110.864, 175.804, 170.137, 98.398, 31.211, 4.170 (max ≈ 1).
pub fn dnv_angle_function(angle: f64) -> Result<f64> {
    const A: [f64; 8] = [9.370, 42.295, 110.864, 175.804, 170.137, 98.398, 31.211, 4.170];
    let theta = check_angle(angle)?;
    let mut sum = 0.0;
    for (i, a) in A.iter().enumerate() {
        let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
        sum += sign * a * theta.powi(i as i32 + 1);
    }
    Ok(sum)
}

/// DNV removed mass [kg] for particle mass m at speed U and angle θ; `k` and `n` default to the
/// steel values 2.0e-9 and 2.6 in [`DNV_STEEL_K`], [`DNV_STEEL_N`].
pub fn dnv_removed_mass(k: f64, n: f64, particle_mass: f64, speed: f64, angle: f64) -> Result<f64> {
    positive("k", k)?;
    positive("n", n)?;
    positive("particle_mass", particle_mass)?;
    non_negative("speed", speed)?;
    Ok(k * speed.powf(n) * dnv_angle_function(angle)? * particle_mass)
}

/// DNV RP-O501 steel constant K [(m/s)^−n].
pub const DNV_STEEL_K: f64 = 2.0e-9;
/// DNV RP-O501 steel velocity exponent n.
pub const DNV_STEEL_N: f64 = 2.6;

/// E/CRC angle function F(θ) = 5.4θ − 10.11θ² + 10.93θ³ − 6.33θ⁴ + 1.42θ⁵ (Eq. 2.29, θ in rad
/// as the spec notes is usual).
pub fn ecrc_angle_function(angle: f64) -> Result<f64> {
    let t = check_angle(angle)?;
    Ok(t * (5.4 + t * (-10.11 + t * (10.93 + t * (-6.33 + t * 1.42)))))
}

/// E/CRC erosion ratio ER = C (BH)^−0.59 F_s U^n F(θ) (Eq. 2.28) [kg/kg]. The spec gives no C, n;
/// Zhang et al. (2007) use C = 2.17e-7, n = 2.41 for steel ([`ECRC_STEEL_C`], [`ECRC_STEEL_N`]).
pub fn ecrc_erosion_ratio(c: f64, n: f64, brinell_hardness: f64, sharpness: f64, speed: f64, angle: f64) -> Result<f64> {
    positive("c", c)?;
    positive("n", n)?;
    positive("brinell_hardness", brinell_hardness)?;
    non_negative("sharpness", sharpness)?;
    non_negative("speed", speed)?;
    Ok(c * brinell_hardness.powf(-0.59) * sharpness * speed.powf(n) * ecrc_angle_function(angle)?)
}

/// E/CRC constant C for steel (Zhang et al. 2007; literature).
pub const ECRC_STEEL_C: f64 = 2.17e-7;
/// E/CRC velocity exponent for steel (Zhang et al. 2007; literature).
pub const ECRC_STEEL_N: f64 = 2.41;

/// Rebound at a wall, v_out = v_in − (1 + e)(v_in·n) n (wear-model.md Eq. 4.4); the tangential
/// part is kept. Works for either orientation of the unit normal `normal`.
pub fn rebound_velocity(incoming: [f64; 3], normal: [f64; 3], restitution: f64) -> Result<[f64; 3]> {
    in_closed("restitution", restitution, 0.0, 1.0, "in [0, 1]")?;
    let norm = (normal[0].powi(2) + normal[1].powi(2) + normal[2].powi(2)).sqrt();
    if !((norm - 1.0).abs() < 1e-9) {
        return Err(AnalyticError::OutOfRange { name: "normal length", value: norm, allowed: "1 (a unit vector)" });
    }
    let vn = incoming[0] * normal[0] + incoming[1] * normal[1] + incoming[2] * normal[2];
    Ok([0, 1, 2].map(|i| incoming[i] - (1.0 + restitution) * vn * normal[i]))
}

/// Impact speed U = |v_in| and angle θ with sinθ = |v_in·n|/|v_in| (wear-model.md §5.3).
pub fn impact_speed_and_angle(incoming: [f64; 3], normal: [f64; 3]) -> Result<(f64, f64)> {
    let speed = (incoming[0].powi(2) + incoming[1].powi(2) + incoming[2].powi(2)).sqrt();
    positive("impact speed", speed)?;
    let norm = (normal[0].powi(2) + normal[1].powi(2) + normal[2].powi(2)).sqrt();
    positive("normal length", norm)?;
    let vn = (incoming[0] * normal[0] + incoming[1] * normal[1] + incoming[2] * normal[2]).abs() / norm;
    Ok((speed, (vn / speed).clamp(0.0, 1.0).asin()))
}

#[cfg(test)]
mod tests {
    use super::*;

    const DEG: f64 = std::f64::consts::PI / 180.0;

    /// Garnet 1 mm: m = ρ π d³/6 with ρ = 2500 (A9: 1.3089969e-6 kg).
    fn garnet_mass() -> f64 {
        2500.0 * std::f64::consts::PI * 1e-9 / 6.0
    }

    /// The sliding rate is the grazing limit of the impact law per unit normal impulse: the
    /// quotient W(U, θ)/((1 + e) m U sinθ) approaches it linearly in θ, with slope −1/(2K)
    /// relative (f(θ)/(θ/K) = 1 − θ/(2K) + O(θ²)).
    #[test]
    fn sliding_rate_is_the_grazing_limit_of_the_impact_law() {
        let (material, options) = (CARBON_STEEL_1018, ArabnejadOptions::default());
        let (m, u, e) = (garnet_mass(), 10.0, 0.99);
        let per_impulse = arabnejad_sliding_wear_rate(&material, e, 1.0, u).unwrap();
        for theta in [1e-2, 1e-3, 1e-4] {
            let w = arabnejad_wear(&material, &options, m, 2500.0, u, theta).unwrap().volume;
            let quotient = w / ((1.0 + e) * m * u * theta.sin());
            let relative = quotient / per_impulse - 1.0;
            // the first-order term to its O(θ²) remainder
            assert!((relative + theta / (2.0 * material.contact_ratio)).abs() < theta * theta, "θ {theta}: {relative:e}");
        }
        assert_eq!(arabnejad_sliding_wear_rate(&material, e, 0.0, u).unwrap(), 0.0);
        assert!(arabnejad_sliding_wear_rate(&material, e, -1.0, u).is_err());
    }

    #[test]
    fn angle_function_matches_section_15() {
        // A1: θ_c = atan 0.4.
        assert!((critical_angle(0.4) - 0.3805063771).abs() < 1e-9);
        assert!((critical_angle(0.4) / DEG - 21.8014094864).abs() < 1e-9);
        // A2, A3.
        for (deg, f) in [(5.0, 0.193322336), (10.0, 0.333294899), (15.0, 0.415664693), (20.0, 0.437928954)] {
            let got = cutting_angle_function(deg * DEG, 0.4, AngleFunction::ThesisLiteral).unwrap();
            assert!((got - f).abs() < 1e-9, "{deg}°: {got}");
        }
        for (deg, f) in [(30.0, 0.75), (45.0, 0.5), (60.0, 0.25), (90.0, 0.0)] {
            let got = cutting_angle_function(deg * DEG, 0.4, AngleFunction::ThesisLiteral).unwrap();
            assert!((got - f).abs() < 1e-12, "{deg}°");
            let cont = cutting_angle_function(deg * DEG, 0.4, AngleFunction::Continuous).unwrap();
            assert!((cont - 0.5 * f).abs() < 1e-12);
        }
        // A4: branch limits at θ_c.
        let tc = critical_angle(0.4);
        let left = cutting_angle_function(tc, 0.4, AngleFunction::ThesisLiteral).unwrap();
        let right = cutting_angle_function(tc + 1e-13, 0.4, AngleFunction::ThesisLiteral).unwrap();
        let right_cont = cutting_angle_function(tc + 1e-13, 0.4, AngleFunction::Continuous).unwrap();
        assert!((left - 0.431034483).abs() < 1e-9 && (right - 0.862068966).abs() < 1e-9);
        assert!((right_cont - 0.431034483).abs() < 1e-9);
        // A5: low-branch peak at ½ atan(2K) = 19.329904°, f = 0.438476324.
        let peak = 0.5 * (0.8f64).atan();
        assert!((peak / DEG - 19.329904).abs() < 1e-6);
        assert!((cutting_angle_function(peak, 0.4, AngleFunction::ThesisLiteral).unwrap() - 0.438476324).abs() < 1e-6);
    }

    #[test]
    fn deformation_threshold_and_values() {
        // A7: SS316 at 10 m/s, 30°: normal speed 5 < 5.7 → g = 0; A8: CS1018 → (5 − 0.5)² = 20.25.
        assert_eq!(deformation_function(10.0, 30.0 * DEG, 5.7, DeformationForm::SquaredClipped).unwrap(), 0.0);
        assert!((deformation_function(10.0, 30.0 * DEG, 0.5, DeformationForm::SquaredClipped).unwrap() - 20.25).abs() < 1e-12);
        // The literal Eq. 2.38 never clips: (5 − 5.7)² = 0.49.
        assert!((deformation_function(10.0, 30.0 * DEG, 5.7, DeformationForm::LiteralSquare).unwrap() - 0.49).abs() < 1e-12);
        // A6: grazing impact gives zero wear with the canonical form.
        let w = arabnejad_wear(&CARBON_STEEL_1018, &ArabnejadOptions::default(), garnet_mass(), 2500.0, 10.0, 0.0).unwrap();
        assert_eq!(w.volume, 0.0);
    }

    #[test]
    fn single_impact_volumes_match_section_15() {
        let m = garnet_mass();
        assert!((m - 1.3089969e-6).abs() < 1e-13);
        let canonical = ArabnejadOptions::default();
        // A9: deformation only at 90° (cutting f(90°) = 0): 7.031963e-17 m³; A15: ER = 4.2278e-7.
        let w90 = arabnejad_wear(&CARBON_STEEL_1018, &canonical, m, 2500.0, 10.0, 90.0 * DEG).unwrap();
        assert!(w90.cutting_volume.abs() < 1e-30);
        assert!(((w90.volume - 7.031963e-17) / 7.031963e-17).abs() < 1e-6);
        let er = erosion_ratio(CARBON_STEEL_1018.density, w90.volume, m).unwrap();
        assert!(((er - 4.2278e-7) / 4.2278e-7).abs() < 1e-4);
        assert!(((w90.mass - 7870.0 * w90.volume) / w90.mass).abs() < 1e-15);
        // A10: canonical with C at 30°: 5.511937e-8; A11: literal 2.39 without C: 5.511937e-6.
        let w30 = arabnejad_wear(&CARBON_STEEL_1018, &canonical, m, 2500.0, 10.0, 30.0 * DEG).unwrap();
        assert!(((w30.volume - 5.511937e-8) / 5.511937e-8).abs() < 1e-6);
        let literal = ArabnejadOptions { include_cutting_coefficient: false, ..canonical };
        let w30l = arabnejad_wear(&CARBON_STEEL_1018, &literal, m, 2500.0, 10.0, 30.0 * DEG).unwrap();
        assert!(((w30l.volume - 5.511937e-6) / 5.511937e-6).abs() < 1e-6);
        // §6.7: cutting/deformation ratio ≈ 3.5e9 for this impact.
        assert!((w30.cutting_volume / w30.deformation_volume / 3.5e9 - 1.0).abs() < 0.05);
        // A12: SS316 5.268972e-8; cutting ratio 1.25 √(131/224) = 0.955920228.
        let s30 = arabnejad_wear(&STAINLESS_STEEL_316, &canonical, m, 2500.0, 10.0, 30.0 * DEG).unwrap();
        assert!(((s30.volume - 5.268972e-8) / 5.268972e-8).abs() < 1e-6);
        assert!((s30.cutting_volume / w30.cutting_volume - 0.955920228).abs() < 1e-9);
        // A13: doubling U multiplies cutting by 2^2.41.
        let w30x2 = arabnejad_wear(&CARBON_STEEL_1018, &canonical, m, 2500.0, 20.0, 30.0 * DEG).unwrap();
        assert!((w30x2.cutting_volume / w30.cutting_volume - 5.314743256).abs() < 1e-8);
        // A14: 10°: 2.449467e-8.
        let w10 = arabnejad_wear(&CARBON_STEEL_1018, &canonical, m, 2500.0, 10.0, 10.0 * DEG).unwrap();
        assert!(((w10.volume - 2.449467e-8) / 2.449467e-8).abs() < 1e-6);
        // §2.5 prefactor switch: ρ_p replaces m.
        let rho = ArabnejadOptions { mass_prefactor: MassPrefactor::ParticleDensity, ..canonical };
        let wr = arabnejad_wear(&CARBON_STEEL_1018, &rho, m, 2500.0, 10.0, 30.0 * DEG).unwrap();
        assert!((wr.volume / w30.volume - 2500.0 / m).abs() / (2500.0 / m) < 1e-12);
    }

    #[test]
    fn rebound_matches_section_15() {
        // A16–A18.
        let out = rebound_velocity([3.0, -4.0, 0.0], [0.0, 1.0, 0.0], 0.99).unwrap();
        assert!((out[0] - 3.0).abs() < 1e-12 && (out[1] - 3.96).abs() < 1e-12 && out[2] == 0.0);
        let flipped = rebound_velocity([3.0, -4.0, 0.0], [0.0, -1.0, 0.0], 0.99).unwrap();
        assert_eq!(out, flipped);
        let (u, theta) = impact_speed_and_angle([3.0, -4.0, 0.0], [0.0, 1.0, 0.0]).unwrap();
        assert!((u - 5.0).abs() < 1e-12 && (theta / DEG - 53.130102354).abs() < 1e-9);
        let ke = (out[0].powi(2) + out[1].powi(2)) / 25.0;
        assert!((ke - 0.987264).abs() < 1e-12);
        let elastic = rebound_velocity([3.0, -4.0, 0.0], [0.0, 1.0, 0.0], 1.0).unwrap();
        assert!(((elastic[0].powi(2) + elastic[1].powi(2)).sqrt() - 5.0).abs() < 1e-14);
        let plastic = rebound_velocity([3.0, -4.0, 0.0], [0.0, 1.0, 0.0], 0.0).unwrap();
        assert!(plastic[1].abs() < 1e-14);
        assert!(rebound_velocity([1.0, 0.0, 0.0], [0.0, 2.0, 0.0], 0.5).is_err());
    }

    #[test]
    fn alternative_laws_have_their_defining_properties() {
        // Finnie (K = 2): continuous at tanθ = K/6, maximum at tan2θ = K/3 (16.85°), zero at 90°.
        let tc = (2.0f64 / 6.0).atan();
        let below = finnie_angle_function(tc, 2.0).unwrap();
        let above = finnie_angle_function(tc + 1e-12, 2.0).unwrap();
        assert!((below - above).abs() < 1e-10 && (below - 0.3).abs() < 1e-12);
        let peak = 0.5 * (2.0f64 / 3.0).atan();
        let f_peak = finnie_angle_function(peak, 2.0).unwrap();
        for deg in [10.0, 15.0, 18.0, 30.0] {
            assert!(finnie_angle_function(deg * DEG, 2.0).unwrap() < f_peak);
        }
        assert!(finnie_angle_function(90.0 * DEG, 2.0).unwrap().abs() < 1e-15);
        let p = FinnieParameters { flow_pressure: 1e9, force_ratio: 2.0, depth_ratio: 2.0, cutting_fraction: 0.5 };
        let v = finnie_volume(&p, 1e-6, 10.0, 15.0 * DEG).unwrap();
        let expected = 0.5 * 1e-6 * 100.0 / (1e9 * 4.0) * ((30.0 * DEG).sin() - 3.0 * (15.0 * DEG).sin().powi(2));
        assert!((v - expected).abs() < 1e-30);
        // DNV: F(0) = 0, normalised so that its maximum is ≈ 1 (near 36°), F(90°) = 0.5685.
        assert_eq!(dnv_angle_function(0.0).unwrap(), 0.0);
        let max = (1..=900).map(|i| dnv_angle_function(i as f64 * 0.1 * DEG).unwrap()).fold(0.0, f64::max);
        assert!((max - 1.0).abs() < 0.003, "{max}");
        assert!((dnv_angle_function(90.0 * DEG).unwrap() - 0.5685).abs() < 1e-4);
        let dnv = dnv_removed_mass(DNV_STEEL_K, DNV_STEEL_N, 1.0, 10.0, 90.0 * DEG).unwrap();
        // powf may be constant-folded with a different libm than at run time: 1e-12 relative.
        let expected_dnv = 2.0e-9 * 10f64.powf(2.6) * dnv_angle_function(90.0 * DEG).unwrap();
        assert!(((dnv - expected_dnv) / expected_dnv).abs() < 1e-12, "{dnv} {expected_dnv}");
        // Oka: g(90°) = 1 exactly; E₉₀ at the reference speed and size equals K Hv^k₁ (mm³/kg).
        let oka = OkaParameters::silica_sand(1.83);
        assert!((oka.angle_function(90.0 * DEG).unwrap() - 1.0).abs() < 1e-15);
        let vol = oka.volume(1.0, 326e-6, 104.0, 90.0 * DEG).unwrap();
        let e90_reference = 65.0 * 1.83f64.powf(-0.12) * 1e-9;
        assert!(((vol - e90_reference) / e90_reference).abs() < 1e-12);
        // Ductile peak below 90°: g > 1 at 30°.
        assert!(oka.angle_function(30.0 * DEG).unwrap() > 1.0);
        // E/CRC polynomial (Eq. 2.29) at 1 rad: 5.4 − 10.11 + 10.93 − 6.33 + 1.42 = 1.31.
        assert!((ecrc_angle_function(1.0).unwrap() - 1.31).abs() < 1e-12);
        let er = ecrc_erosion_ratio(ECRC_STEEL_C, ECRC_STEEL_N, 120.0, 0.5, 10.0, 1.0).unwrap();
        let er_expected = 2.17e-7 * 120f64.powf(-0.59) * 0.5 * 10f64.powf(2.41) * 1.31;
        assert!(((er - er_expected) / er_expected).abs() < 1e-12);
        assert!(ecrc_angle_function(2.0).is_err());
    }
}
