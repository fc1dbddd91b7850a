//! Erosion laws: the wall volume one particle impact removes (spec wear-model.md §6).
//!
//! Arabnejad et al. (2015b) cutting + deformation is the thesis' law (§6.2–6.4, in the spec's
//! canonical form with the four switches of §6.4). Finnie (1960), Oka & Yoshida (2005), DNV
//! RP-O501 (2007) and E/CRC (Zhang et al. 2007) are the pluggable alternatives of §6.8 and §14
//! item 15; the spec gives their names (and, for E/CRC, Eqs. 2.28–2.29) but not all formulas or
//! constants, so those come from the cited papers and are literature values: check them before
//! quantitative use.
//!
//! Angles are measured from the wall *surface* (§5.3): θ = 0 grazing, θ = π/2 head-on. Every law
//! returns the volume removed by **one real particle**; the caller multiplies by `modifier`
//! (§6.4, §7.1). This is written independently of `spillage-analytic` (which the tests compare
//! against): `model` does not depend on the referee.

use std::f64::consts::FRAC_PI_2;

use super::settings::{AngleFunctionForm, DeformationForm, MassPrefactor, MaterialConstants};

/// One impact as the wear law sees it (angle from the wall surface, rad; 0 grazing, π/2 head-on).
///
/// `speed` is |v_in| relative to the wall and `angle` satisfies sinθ = |v_in·n|/|v_in| (§5.3);
/// `mass` [kg], `diameter` [m] and `density` [kg/m³] are those of one real particle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactInput {
    pub speed: f64,
    pub angle: f64,
    pub mass: f64,
    pub diameter: f64,
    pub density: f64,
}

impl ImpactInput {
    /// The impact the laws evaluate: θ clamped to [0, π/2]; a negative speed, mass, diameter or
    /// density (not a physical impact) counts as 0, so nothing is removed. NaN stays NaN, so a
    /// caller's bug is not hidden as "no wear".
    fn clamped(&self) -> ImpactInput {
        let at_least_zero = |x: f64| if x < 0.0 { 0.0 } else { x };
        ImpactInput {
            speed: at_least_zero(self.speed),
            angle: self.angle.clamp(0.0, FRAC_PI_2),
            mass: at_least_zero(self.mass),
            diameter: at_least_zero(self.diameter),
            density: at_least_zero(self.density),
        }
    }
}

/// Removed wall volume of one impact of one real particle [m³], by mechanism.
///
/// Arabnejad separates micro-cutting (Eq. 2.35) from deformation (Eq. 2.37). The other laws are
/// single-mechanism correlations: their whole result is reported as `cutting` and `deformation`
/// is 0.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RemovedVolume {
    pub cutting: f64,
    pub deformation: f64,
}

impl RemovedVolume {
    /// W_i = cutting + deformation (§6.4).
    pub fn total(&self) -> f64 {
        self.cutting + self.deformation
    }
}

/// The four switches of wear-model.md §6.4 (§13 rows 1–5). `Default` is the canonical form: C
/// included, mass prefactor m, clip-then-square deformation, and the angle function of Eq. 2.36
/// as printed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ArabnejadOptions {
    /// Switch 1: multiply the cutting term by C (Eq. 2.35; the printed Eq. 2.39 drops it).
    pub include_cutting_coefficient: bool,
    /// Switch 2: m (canonical) or ρ_p (the §2.5 summary).
    pub mass_prefactor: MassPrefactor,
    /// Switch 3: how g(θ) treats the threshold speed.
    pub deformation_form: DeformationForm,
    /// Switch 4: Eq. 2.36 literal (jumps at θ_c) or continuous (§6.6).
    pub angle_function: AngleFunctionForm,
}

impl Default for ArabnejadOptions {
    fn default() -> Self {
        Self {
            include_cutting_coefficient: true,
            mass_prefactor: MassPrefactor::ParticleMass,
            deformation_form: DeformationForm::SquaredClipped,
            angle_function: AngleFunctionForm::ThesisLiteral,
        }
    }
}

/// Finnie (1960) constants (I. Finnie, "Erosion of surfaces by solid particles", Wear 3,
/// 87–103); wear-model.md §6.1 restates the mechanism, §6.8 names the law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FinnieConstants {
    /// Horizontal flow pressure p of the wall [Pa].
    pub flow_pressure: f64,
    /// K, ratio of vertical to horizontal force on the particle (≈ 2).
    pub force_ratio: f64,
    /// ψ, ratio of contact depth to depth of cut (≈ 2).
    pub depth_ratio: f64,
    /// c, fraction of particles cutting in the idealised manner.
    pub cutting_fraction: f64,
}

/// Oka & Yoshida (2005) constants (Y.I. Oka, T. Yoshida, "Practical estimation of erosion damage
/// caused by solid particle impact, Part 2", Wear 259, 102–109); named in wear-model.md §6.8.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OkaConstants {
    /// Wall Vickers hardness Hv [GPa].
    pub vickers_hardness_gpa: f64,
    /// K [mm³/kg].
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

/// DNV RP-O501 (2007) "Erosive wear in piping systems" §3 constants (steel: K = 2.0e-9, n = 2.6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DnvConstants {
    /// K [(m/s)^−n].
    pub k: f64,
    /// Velocity exponent n.
    pub n: f64,
}

/// E/CRC constants (wear-model.md §6.8, Eq. 2.28; C and n from Zhang et al. 2007, "Comparison of
/// computed and measured particle velocities and erosion in water and air flows", Wear 263,
/// 330–338: steel C = 2.17e-7, n = 2.41).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EcrcConstants {
    pub c: f64,
    /// Velocity exponent n.
    pub n: f64,
    /// Wall Brinell hardness BH.
    pub brinell_hardness: f64,
    /// Particle sharpness factor F_s.
    pub sharpness: f64,
}

/// Erosion law per impact (wear-model.md §6; the enum is the `ErosionLaw` "trait" of §6.8 as
/// plain data). Built from the case by [`ErosionLaw::from_section`].
#[derive(Clone, Debug, PartialEq)]
pub enum ErosionLaw {
    /// Arabnejad et al. (2015b), canonical form of §6.4 with its switches.
    Arabnejad { material: MaterialConstants, options: ArabnejadOptions },
    /// Finnie (1960) micro-cutting: a volume.
    Finnie { wall_density: f64, constants: FinnieConstants },
    /// Oka & Yoshida (2005): a volume (mm³ per kg of particles, converted to m³).
    Oka { wall_density: f64, constants: OkaConstants },
    /// DNV RP-O501: a removed mass, converted to volume with ρ_mat.
    Dnv { wall_density: f64, constants: DnvConstants },
    /// E/CRC: an erosion ratio (kg/kg) × particle mass, converted to volume with ρ_mat.
    Ecrc { wall_density: f64, constants: EcrcConstants },
}

impl ErosionLaw {
    /// Removed wall volume of one impact of one real particle [m³] (§6.4). Never NaN for finite
    /// input: θ is clamped to [0, π/2], negative magnitudes count as 0, and a zero factor (no
    /// mass, no angle factor) gives exactly 0 even when another factor overflowed.
    pub fn removed_volume(&self, impact: &ImpactInput) -> RemovedVolume {
        let i = impact.clamped();
        match self {
            ErosionLaw::Arabnejad { material, options } => arabnejad_volume(material, options, &i),
            ErosionLaw::Finnie { constants, .. } => RemovedVolume { cutting: constants.volume(&i), deformation: 0.0 },
            ErosionLaw::Oka { constants, .. } => RemovedVolume { cutting: constants.volume(&i), deformation: 0.0 },
            ErosionLaw::Dnv { wall_density, constants } => RemovedVolume { cutting: constants.removed_mass(&i) / wall_density, deformation: 0.0 },
            ErosionLaw::Ecrc { wall_density, constants } => {
                RemovedVolume { cutting: product(&[constants.erosion_ratio(&i), i.mass]) / wall_density, deformation: 0.0 }
            }
        }
    }

    /// Erosion ratio ER = ρ_mat W_i / m [kg of wall per kg of particles] (§6.4, check A15); 0 for
    /// a particle without mass.
    pub fn erosion_ratio(&self, impact: &ImpactInput) -> f64 {
        let mass = impact.clamped().mass;
        if mass > 0.0 {
            self.wall_density() * self.removed_volume(impact).total() / mass
        } else {
            0.0
        }
    }

    /// ρ_mat [kg/m³]: converts removed volume to mass (§6.4) and, for DNV and E/CRC, their removed
    /// mass to volume.
    pub fn wall_density(&self) -> f64 {
        match self {
            ErosionLaw::Arabnejad { material, .. } => material.density,
            ErosionLaw::Finnie { wall_density, .. }
            | ErosionLaw::Oka { wall_density, .. }
            | ErosionLaw::Dnv { wall_density, .. }
            | ErosionLaw::Ecrc { wall_density, .. } => *wall_density,
        }
    }

    /// The case-file name of the law (`law = "…"`).
    pub fn name(&self) -> &'static str {
        match self {
            ErosionLaw::Arabnejad { .. } => "arabnejad",
            ErosionLaw::Finnie { .. } => "finnie",
            ErosionLaw::Oka { .. } => "oka",
            ErosionLaw::Dnv { .. } => "dnv",
            ErosionLaw::Ecrc { .. } => "ecrc",
        }
    }
}

/// Product of factors that is exactly 0 as soon as one factor is 0, even if another overflowed
/// to ∞ (∞·0 would be NaN): an impact without mass or angle factor removes nothing.
fn product(factors: &[f64]) -> f64 {
    if factors.contains(&0.0) {
        0.0
    } else {
        factors.iter().product()
    }
}

/// cos θ for θ ∈ [0, π/2], written sin(π/2 − θ) so that it is exactly 0 at head-on impact
/// (cos(π/2) in floating point is 6e-17, which would leave a spurious cutting term).
fn cos_from_surface(theta: f64) -> f64 {
    (FRAC_PI_2 - theta).sin()
}

// ---------------------------------------------------------------------------------------------
// Arabnejad (wear-model.md §6.2–6.6)

/// Velocity exponent of the cutting term, Vol_C ∝ U^2.41 (Eq. 2.35, empirical).
pub const ARABNEJAD_VELOCITY_EXPONENT: f64 = 2.41;

/// Critical angle θ_c = tan⁻¹K where the cutting angle function changes branch (§6.5; check A1:
/// 0.3805063771 rad for K = 0.4).
pub fn critical_angle(contact_ratio: f64) -> f64 {
    contact_ratio.atan()
}

/// Cutting angle function f(θ), Eq. 2.36: (K sin2θ − sin²θ)/(2K²) for θ ≤ tan⁻¹K, cos²θ above
/// ([`AngleFunctionForm::ThesisLiteral`], which jumps by a factor 2 at θ_c, §6.6 and §13 row 4)
/// or ½cos²θ ([`AngleFunctionForm::Continuous`]). The branch test is the printed θ ≤ tan⁻¹K
/// (§13 row 5: the §6.2.1 prose has it the other way round). θ in [0, π/2].
pub fn arabnejad_angle_function(theta: f64, contact_ratio: f64, form: AngleFunctionForm) -> f64 {
    let k = contact_ratio;
    if theta <= critical_angle(k) {
        let s = theta.sin();
        (k * (2.0 * theta).sin() - s * s) / (2.0 * k * k)
    } else {
        let c = cos_from_surface(theta);
        match form {
            AngleFunctionForm::ThesisLiteral => c * c,
            AngleFunctionForm::Continuous => 0.5 * c * c,
        }
    }
}

/// Deformation function g(θ) (Bitter 1963, Eq. 2.38; §6.4 switch 3, §13 row 3). The normal
/// impact speed is U sinθ; U_tsh is the threshold below which deformation wear vanishes.
pub fn arabnejad_deformation_function(speed: f64, theta: f64, threshold_velocity: f64, form: DeformationForm) -> f64 {
    let excess = speed * theta.sin() - threshold_velocity;
    match form {
        DeformationForm::SquaredClipped => {
            let e = excess.max(0.0);
            e * e
        }
        DeformationForm::LiteralSquare => excess * excess,
        DeformationForm::LinearClipped => excess.max(0.0),
    }
}

/// Canonical Arabnejad wear of one impact (boxed equation of §6.4, from Eqs. 2.35 + 2.37):
/// W = (m F_s/2)·C U^2.41 f(θ)/√Hv (cutting) + (m F_s/2)·g(θ)/ε (deformation), each factor
/// behind its switch.
fn arabnejad_volume(material: &MaterialConstants, options: &ArabnejadOptions, i: &ImpactInput) -> RemovedVolume {
    let carrier = match options.mass_prefactor {
        MassPrefactor::ParticleMass => i.mass,
        MassPrefactor::ParticleDensity => i.density,
    };
    let half = 0.5 * carrier * material.sharpness;
    let c = if options.include_cutting_coefficient { material.cutting_coefficient } else { 1.0 };
    let f = arabnejad_angle_function(i.angle, material.contact_ratio, options.angle_function);
    let g = arabnejad_deformation_function(i.speed, i.angle, material.threshold_velocity, options.deformation_form);
    RemovedVolume {
        cutting: product(&[half, c, i.speed.powf(ARABNEJAD_VELOCITY_EXPONENT), f]) / material.vickers_hardness.sqrt(),
        deformation: product(&[half, g]) / material.deformation_factor,
    }
}

// ---------------------------------------------------------------------------------------------
// Finnie (1960)

/// Finnie's angle function (Finnie 1960): sin2θ − (6/K) sin²θ while tanθ ≤ K/6, (K/6) cos²θ
/// above (continuous at tanθ = K/6). θ in [0, π/2].
pub fn finnie_angle_function(theta: f64, force_ratio: f64) -> f64 {
    let k = force_ratio;
    if theta.tan() <= k / 6.0 {
        let s = theta.sin();
        (2.0 * theta).sin() - 6.0 / k * s * s
    } else {
        let c = cos_from_surface(theta);
        k / 6.0 * c * c
    }
}

impl FinnieConstants {
    /// V = c m U² f(θ) / (p ψ K) [m³] (Finnie 1960, micro-cutting by a rigid particle).
    pub fn volume(&self, i: &ImpactInput) -> f64 {
        let f = finnie_angle_function(i.angle, self.force_ratio);
        product(&[self.cutting_fraction, i.mass, i.speed * i.speed, f]) / (self.flow_pressure * self.depth_ratio * self.force_ratio)
    }
}

// ---------------------------------------------------------------------------------------------
// Oka & Yoshida (2005)

/// mm³ → m³.
const CUBIC_MILLIMETRE: f64 = 1e-9;

impl OkaConstants {
    /// The paper's SiO₂-sand constants: K = 65 mm³/kg, k₁ = −0.12, k₃ = 0.19, s₁ = 0.71,
    /// q₁ = 0.14, s₂ = 2.4, q₂ = −0.94, U' = 104 m/s, D' = 326 µm (Oka & Yoshida 2005).
    pub fn silica_sand(vickers_hardness_gpa: f64) -> Self {
        Self { vickers_hardness_gpa, k: 65.0, k1: -0.12, k3: 0.19, s1: 0.71, q1: 0.14, s2: 2.4, q2: -0.94, reference_speed: 104.0, reference_diameter: 326e-6 }
    }

    /// g(θ) = (sinθ)^n₁ (1 + Hv(1 − sinθ))^n₂ with n₁ = s₁Hv^q₁, n₂ = s₂Hv^q₂ (Oka et al. 2005);
    /// g(π/2) = 1.
    pub fn angle_function(&self, theta: f64) -> f64 {
        let hv = self.vickers_hardness_gpa;
        let s = theta.sin();
        s.powf(self.s1 * hv.powf(self.q1)) * (1.0 + hv * (1.0 - s)).powf(self.s2 * hv.powf(self.q2))
    }

    /// E(θ) = g(θ) E₉₀, E₉₀ = K Hv^k₁ (U/U')^k₂ (D/D')^k₃ with k₂ = 2.3 Hv^0.038 (Oka & Yoshida
    /// 2005) in mm³ per kg of particles, times the particle mass, in m³.
    pub fn volume(&self, i: &ImpactInput) -> f64 {
        let hv = self.vickers_hardness_gpa;
        let k2 = 2.3 * hv.powf(0.038);
        let normal_erosion = [self.k * hv.powf(self.k1), (i.speed / self.reference_speed).powf(k2), (i.diameter / self.reference_diameter).powf(self.k3)];
        product(&[normal_erosion[0], normal_erosion[1], normal_erosion[2], self.angle_function(i.angle), i.mass]) * CUBIC_MILLIMETRE
    }
}

// ---------------------------------------------------------------------------------------------
// DNV RP-O501 (2007)

/// A₁…A₈ of the DNV angle function (DNV RP-O501 §3, steel and other ductile materials).
const DNV_ANGLE_COEFFICIENTS: [f64; 8] = [9.370, 42.295, 110.864, 175.804, 170.137, 98.398, 31.211, 4.170];

/// F(θ) = Σᵢ₌₁⁸ (−1)^(i+1) Aᵢ θⁱ, θ in rad (DNV RP-O501 §3; maximum ≈ 1 near 36°), evaluated
/// in Horner form θ(A₁ − θ(A₂ − θ(A₃ − …))).
pub fn dnv_angle_function(theta: f64) -> f64 {
    DNV_ANGLE_COEFFICIENTS.iter().rev().fold(0.0, |inner, a| theta * (a - inner))
}

impl DnvConstants {
    /// Removed wall mass E_L·m = K U^n F(θ) m [kg] (DNV RP-O501 §3: E_L in kg per kg of particles).
    pub fn removed_mass(&self, i: &ImpactInput) -> f64 {
        product(&[self.k, i.speed.powf(self.n), dnv_angle_function(i.angle), i.mass])
    }
}

// ---------------------------------------------------------------------------------------------
// E/CRC (wear-model.md §6.8)

/// F(θ) = 5.4θ − 10.11θ² + 10.93θ³ − 6.33θ⁴ + 1.42θ⁵, θ in rad (Eq. 2.29; the spec notes the
/// thesis gives no unit and radians are usual).
pub fn ecrc_angle_function(theta: f64) -> f64 {
    const A: [f64; 5] = [5.4, -10.11, 10.93, -6.33, 1.42];
    let mut power = 1.0;
    let mut sum = 0.0;
    for a in A {
        power *= theta;
        sum += a * power;
    }
    sum
}

impl EcrcConstants {
    /// ER = C (BH)^−0.59 F_s U^n F(θ) [kg of wall per kg of particles] (Eq. 2.28).
    pub fn erosion_ratio(&self, i: &ImpactInput) -> f64 {
        product(&[self.c, self.brinell_hardness.powf(-0.59), self.sharpness, i.speed.powf(self.n), ecrc_angle_function(i.angle)])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wear::test_support::{arabnejad, law};

    const DEG: f64 = std::f64::consts::PI / 180.0;
    const K: f64 = 0.4;

    /// A 1 mm garnet (ρ = 2500 kg/m³): m = ρπd³/6 = 1.3089969e-6 kg (A9).
    fn garnet(speed: f64, angle_deg: f64) -> ImpactInput {
        let diameter: f64 = 1e-3;
        ImpactInput { speed, angle: angle_deg * DEG, mass: 2500.0 * std::f64::consts::PI * diameter.powi(3) / 6.0, diameter, density: 2500.0 }
    }

    fn rel(got: f64, expected: f64) -> f64 {
        ((got - expected) / expected).abs()
    }

    #[test]
    fn a1_the_angle_function_switches_branch_at_the_critical_angle() {
        // The literal and continuous forms agree below θ_c and differ by a factor 2 above it, so
        // bisecting on "the two laws differ" finds the branch switch of the law itself.
        let literal = arabnejad("carbon_steel_1018", "");
        let continuous = arabnejad("carbon_steel_1018", "angle_function = \"continuous\"");
        let differ = |theta: f64| {
            let i = ImpactInput { angle: theta, ..garnet(10.0, 0.0) };
            literal.removed_volume(&i).cutting != continuous.removed_volume(&i).cutting
        };
        let (mut below, mut above) = (10.0 * DEG, 30.0 * DEG);
        assert!(!differ(below) && differ(above));
        while above - below > 1e-13 {
            let mid = 0.5 * (below + above);
            if differ(mid) {
                above = mid;
            } else {
                below = mid;
            }
        }
        // A1: θ_c = atan 0.4 = 0.3805063771 rad = 21.8014094864°, abs 1e-9.
        assert!((below - 0.3805063771).abs() < 1e-9, "{below}");
        assert!((below / DEG - 21.8014094864).abs() < 1e-9, "{}", below / DEG);
        assert!((critical_angle(K) - 0.3805063771).abs() < 1e-9);
    }

    #[test]
    fn a2_to_a5_angle_function_values() {
        let literal = AngleFunctionForm::ThesisLiteral;
        let continuous = AngleFunctionForm::Continuous;
        // A2: low branch, abs 1e-9 (both forms share it).
        for (deg, f) in [(5.0, 0.193322336), (10.0, 0.333294899), (15.0, 0.415664693), (20.0, 0.437928954)] {
            assert!((arabnejad_angle_function(deg * DEG, K, literal) - f).abs() < 1e-9, "{deg}°");
            assert!((arabnejad_angle_function(deg * DEG, K, continuous) - f).abs() < 1e-9, "{deg}°");
        }
        // A3: high branch, literal cos²θ, abs 1e-12 (continuous: half of it, §6.6).
        for (deg, f) in [(30.0, 0.75), (45.0, 0.5), (60.0, 0.25), (90.0, 0.0)] {
            assert!((arabnejad_angle_function(deg * DEG, K, literal) - f).abs() < 1e-12, "{deg}°");
            assert!((arabnejad_angle_function(deg * DEG, K, continuous) - 0.5 * f).abs() < 1e-12, "{deg}°");
        }
        assert_eq!(arabnejad_angle_function(FRAC_PI_2, K, literal), 0.0);
        // A4: limits at θ_c, abs 1e-9: left 1/(2(1+K²)), right 1/(1+K²) literal, continuous = left.
        let tc = critical_angle(K);
        let right = tc + 1e-12;
        assert!((arabnejad_angle_function(tc, K, literal) - 0.431034483).abs() < 1e-9);
        assert!((arabnejad_angle_function(right, K, literal) - 0.862068966).abs() < 1e-9);
        assert!((arabnejad_angle_function(right, K, continuous) - 0.431034483).abs() < 1e-9);
        // A5: low-branch peak θ* = ½ atan 2K = 19.329904°, f = 0.438476324, abs 1e-6; and it is a
        // maximum of the law's f.
        let peak = 0.5 * (2.0 * K).atan();
        assert!((peak / DEG - 19.329904).abs() < 1e-6);
        let f_peak = arabnejad_angle_function(peak, K, literal);
        assert!((f_peak - 0.438476324).abs() < 1e-6);
        for step in [-1e-3, 1e-3] {
            assert!(arabnejad_angle_function(peak + step, K, literal) < f_peak);
        }
    }

    #[test]
    fn a6_a_grazing_impact_removes_nothing_in_the_canonical_form() {
        let canonical = arabnejad("carbon_steel_1018", "");
        for speed in [0.1, 1.0, 10.0, 30.0] {
            // A6: exact.
            assert_eq!(canonical.removed_volume(&garnet(speed, 0.0)), RemovedVolume::default());
        }
        // The literal Eq. 2.38 instead leaves (m F_s/2) U_tsh²/ε at θ = 0 (§15 A6 note).
        let literal = arabnejad("carbon_steel_1018", "[arabnejad]\ndeformation_form = \"literal_square\"");
        let i = garnet(10.0, 0.0);
        let expected = i.mass * 0.5 / 2.0 * 0.5 * 0.5 / 4.2e11;
        assert!(rel(literal.removed_volume(&i).deformation, expected) < 1e-14);
    }

    #[test]
    fn a7_a8_deformation_threshold_and_value() {
        // A7: SS316, U = 10, θ = 30°: U sinθ = 5 < U_tsh = 5.7 ⇒ g = 0 exactly.
        assert_eq!(arabnejad_deformation_function(10.0, 30.0 * DEG, 5.7, DeformationForm::SquaredClipped), 0.0);
        assert_eq!(arabnejad("stainless_steel_316", "").removed_volume(&garnet(10.0, 30.0)).deformation, 0.0);
        // A8: CS1018 (U_tsh = 0.5): g = (5 − 0.5)² = 20.25, abs 1e-12.
        assert!((arabnejad_deformation_function(10.0, 30.0 * DEG, 0.5, DeformationForm::SquaredClipped) - 20.25).abs() < 1e-12);
        // The other forms (§6.4 switch 3): literal never clips, (5 − 5.7)² = 0.49; linear 4.5.
        assert!((arabnejad_deformation_function(10.0, 30.0 * DEG, 5.7, DeformationForm::LiteralSquare) - 0.49).abs() < 1e-12);
        assert!((arabnejad_deformation_function(10.0, 30.0 * DEG, 0.5, DeformationForm::LinearClipped) - 4.5).abs() < 1e-12);
        assert_eq!(arabnejad_deformation_function(10.0, 30.0 * DEG, 5.7, DeformationForm::LinearClipped), 0.0);
    }

    #[test]
    fn a9_to_a15_single_impact_volumes() {
        let cs = arabnejad("carbon_steel_1018", "");
        let ss = arabnejad("stainless_steel_316", "");
        assert!((garnet(1.0, 0.0).mass - 1.3089969e-6).abs() < 1e-13);
        // A9: 90°, deformation only (f(90°) = 0 exactly): 7.031963e-17 m³, rel 1e-6.
        let w90 = cs.removed_volume(&garnet(10.0, 90.0));
        assert_eq!(w90.cutting, 0.0);
        assert!(rel(w90.total(), 7.031963e-17) < 1e-6);
        // A15: ER = ρ_mat W/m = 4.2278e-7, rel 1e-4.
        assert!(rel(cs.erosion_ratio(&garnet(10.0, 90.0)), 4.2278e-7) < 1e-4);
        // A10: canonical (with C), 30°: 5.511937e-8, rel 1e-6.
        let w30 = cs.removed_volume(&garnet(10.0, 30.0));
        assert!(rel(w30.total(), 5.511937e-8) < 1e-6);
        // A11: thesis-literal Eq. 2.39 (no C): 5.511937e-6, rel 1e-6.
        let no_c = arabnejad("carbon_steel_1018", "[arabnejad]\ninclude_cutting_coefficient = false");
        assert!(rel(no_c.removed_volume(&garnet(10.0, 30.0)).total(), 5.511937e-6) < 1e-6);
        // A12: SS316 5.268972e-8, rel 1e-6; cutting ratio to A10 1.25√(131/224) = 0.955920228.
        let s30 = ss.removed_volume(&garnet(10.0, 30.0));
        assert!(rel(s30.total(), 5.268972e-8) < 1e-6);
        assert!(rel(s30.cutting / w30.cutting, 0.955920228) < 1e-6);
        // A13: U → 2U multiplies cutting by 2^2.41 = 5.314743256, rel 1e-8.
        let w30x2 = cs.removed_volume(&garnet(20.0, 30.0));
        assert!(rel(w30x2.cutting / w30.cutting, 5.314743256) < 1e-8);
        // A14: 10°, with C: 2.449467e-8, rel 1e-6.
        assert!(rel(cs.removed_volume(&garnet(10.0, 10.0)).total(), 2.449467e-8) < 1e-6);
        // §6.4 switch 2: ρ_p in place of m scales both mechanisms by ρ_p/m.
        let rho = arabnejad("carbon_steel_1018", "[arabnejad]\nmass_prefactor = \"particle_density\"");
        let i = garnet(10.0, 30.0);
        assert!(rel(rho.removed_volume(&i).total() / w30.total(), i.density / i.mass) < 1e-12);
    }

    #[test]
    fn alternative_laws_have_their_literature_forms() {
        let i = garnet(10.0, 90.0);
        // DNV: W = K U^n F(θ) m / ρ_mat; F(0) = 0, max ≈ 1 near 36°, F(90°) = 0.5685.
        let dnv = law("law = \"dnv\"\n[material]\npreset = \"carbon_steel_1018\"\n");
        assert_eq!(dnv.name(), "dnv");
        assert_eq!(dnv.wall_density(), 7870.0);
        assert_eq!(dnv_angle_function(0.0), 0.0);
        assert!((dnv_angle_function(FRAC_PI_2) - 0.5685).abs() < 1e-4);
        let max = (0..=900).map(|k| dnv_angle_function(k as f64 * 0.1 * DEG)).fold(0.0, f64::max);
        assert!((max - 1.0).abs() < 3e-3, "{max}");
        let expected = 2.0e-9 * 10f64.powf(2.6) * dnv_angle_function(FRAC_PI_2) * i.mass / 7870.0;
        assert!(rel(dnv.removed_volume(&i).cutting, expected) < 1e-12);
        assert_eq!(dnv.removed_volume(&i).deformation, 0.0);
        // E/CRC: F(1 rad) = 5.4 − 10.11 + 10.93 − 6.33 + 1.42 = 1.31; ER = C BH^−0.59 F_s U^n F.
        assert!((ecrc_angle_function(1.0) - 1.31).abs() < 1e-12);
        let ecrc = law("law = \"ecrc\"\n[material]\ndensity = 7800.0\n[ecrc]\nbrinell_hardness = 120.0\n");
        let er = 2.17e-7 * 120f64.powf(-0.59) * 0.5 * 10f64.powf(2.41) * ecrc_angle_function(FRAC_PI_2);
        assert!(rel(ecrc.erosion_ratio(&i), er) < 1e-12);
        // Oka: g(90°) = 1; at U', D' the normal erosion is K Hv^k₁ mm³/kg.
        let oka = law("law = \"oka\"\n[material]\ndensity = 7800.0\n[oka]\nvickers_hardness_gpa = 1.83\n");
        let ErosionLaw::Oka { constants, .. } = &oka else { panic!("{oka:?}") };
        assert_eq!(*constants, OkaConstants::silica_sand(1.83));
        assert!((constants.angle_function(FRAC_PI_2) - 1.0).abs() < 1e-15);
        assert!(constants.angle_function(30.0 * DEG) > 1.0, "ductile: peak below 90°");
        let reference = ImpactInput { speed: 104.0, angle: FRAC_PI_2, mass: 1.0, diameter: 326e-6, density: 2500.0 };
        assert!(rel(oka.removed_volume(&reference).cutting, 65.0 * 1.83f64.powf(-0.12) * 1e-9) < 1e-12);
        // Finnie (K = 2): continuous at tanθ = K/6 (f = 0.3), zero at 90°.
        let tc = (2.0f64 / 6.0).atan();
        assert!((finnie_angle_function(tc, 2.0) - 0.3).abs() < 1e-12);
        assert!((finnie_angle_function(tc + 1e-12, 2.0) - 0.3).abs() < 1e-10);
        assert_eq!(finnie_angle_function(FRAC_PI_2, 2.0), 0.0);
        let finnie = law("law = \"finnie\"\n[material]\ndensity = 7800.0\n[finnie]\nflow_pressure = 1e9\ncutting_fraction = 0.5\n");
        let j = garnet(10.0, 15.0);
        let expected = 0.5 * j.mass * 100.0 / (1e9 * 2.0 * 2.0) * finnie_angle_function(15.0 * DEG, 2.0);
        assert!(rel(finnie.removed_volume(&j).cutting, expected) < 1e-12);
    }

    #[test]
    fn removed_volume_is_never_nan_for_finite_input() {
        let laws = [
            arabnejad("carbon_steel_1018", ""),
            arabnejad("stainless_steel_316", "angle_function = \"continuous\"\n[arabnejad]\ndeformation_form = \"literal_square\""),
            law("law = \"finnie\"\n[material]\ndensity = 7800.0\n[finnie]\nflow_pressure = 1e9\n"),
            law("law = \"oka\"\n[material]\ndensity = 7800.0\n[oka]\nvickers_hardness_gpa = 1.83\n"),
            law("law = \"dnv\"\n[material]\ndensity = 7800.0\n"),
            law("law = \"ecrc\"\n[material]\ndensity = 7800.0\n[ecrc]\nbrinell_hardness = 120.0\n"),
        ];
        let values = [-1e300, -1.0, 0.0, 1e-300, 1.0, 1e300];
        let angles = [-10.0, -FRAC_PI_2, 0.0, 1e-300, 0.3, FRAC_PI_2, 2.0, 1e300];
        for law in &laws {
            for &speed in &values {
                for &angle in &angles {
                    for &mass in &values {
                        for &diameter in &values {
                            let i = ImpactInput { speed, angle, mass, diameter, density: mass };
                            let w = law.removed_volume(&i);
                            assert!(!w.cutting.is_nan() && !w.deformation.is_nan() && !law.erosion_ratio(&i).is_nan(), "{} {i:?}", law.name());
                            assert!(w.cutting >= 0.0 && w.deformation >= 0.0, "{} {i:?}", law.name());
                        }
                    }
                }
            }
        }
    }
}
