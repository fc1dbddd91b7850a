//! The Euler-turbine analytical spillage model of Nieuwboer (2022) §4.4.
//!
//! spillage-and-flow-verification.md §2 (thesis Eqs. 4.55–4.92). The head is split axially into a
//! top segment 1 (height w₁, from the ring; outflow Q₁) and a bottom segment 2 (height H − w₁, to
//! the hub; inflow Q₂ = Q₁ + Q_m). Blade pressure rise ΔP_bl,i = (1−α) ρ_i ω² R̄_i² (Eq. 4.70),
//! segment discharge Q_i = α'_i w_i ΔP_i with α'_i = 2π tanφ_i/(ω ρ_i) · α/(1−α) (Eqs. 4.77–4.78),
//! continuity Q₁ − Q₂ + Q_m = 0 (Eq. 4.79) → w₁ = (H f − Q_m/(ΔP_bl,1 α'₂))/(α'₁/α'₂ + f) (Eq. 4.88),
//! with segment-averaged R̄_i² and tanφ_i (Eqs. 4.90–4.92) that depend on w₁.
//!
//! Implementation decisions, all from the spec's "recommended impl. decisions" (§2.8):
//! - Eq. 4.84 is used in its corrected form (erratum §9 item 1): numerator ΔP_bl,1 − βΔP_bl,2.
//! - The singularity-free form w₁ = (H f − q)/(a + f), a = ρ₂t₁/(ρ₁t₂),
//!   q = Q_m ρ₂/(2π α ω ρ₁ R̄₁² t₂) (no division by 1 − α).
//! - No outflow (the map gives w₁ ≤ 0 at w₁ = 0⁺) → w₁ = 0, Q₁ = 0, S = 0.
//! - w₁ is the first upward zero crossing of g(w) = w − F(w) on [0, H], located by a scan and
//!   Brent's method to 1e-12 H; g(H) > 0 always, so w₁ < H (segment 2 keeps height).
//! - Q₁ uses the segment-averaged R̄₁² and t₁ in Eq. 4.59 ([inferred], §9 item 3).
//! - R(s) and φ(s) between the given profile points are linear in s (the thesis gives no
//!   profile; this interpolation is ours).

use serde::{Deserialize, Serialize};

use crate::error::{in_closed, in_open, non_negative, positive, AnalyticError, Result};
use crate::roots::brent;

/// One point of the cutter contour: axial distance s from the ring, contour radius R(s) of the
/// blade outer edges, blade angle φ(s) to the contour tangent (spillage-and-flow-verification.md
/// §2.8 "Inputs").
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ProfilePoint {
    /// s [m], 0 at the ring, H at the hub.
    pub axial_distance: f64,
    /// R(s) [m].
    pub radius: f64,
    /// φ(s) [rad], in (0, π/2).
    pub blade_angle: f64,
}

/// Cutter contour R(s), φ(s) for s in [0, H], piecewise linear between points.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CutterProfile {
    points: Vec<ProfilePoint>,
}

impl CutterProfile {
    /// Validates: ≥ 2 points, first at s = 0, s strictly increasing, R > 0, φ in (0, π/2).
    pub fn new(points: Vec<ProfilePoint>) -> Result<Self> {
        if points.len() < 2 {
            return Err(AnalyticError::Invalid { what: "cutter profile", reason: format!("needs at least 2 points, got {}", points.len()) });
        }
        if points[0].axial_distance != 0.0 {
            return Err(AnalyticError::OutOfRange { name: "profile axial_distance[0]", value: points[0].axial_distance, allowed: "0 (the ring)" });
        }
        for pair in points.windows(2) {
            if !(pair[1].axial_distance > pair[0].axial_distance) || !pair[1].axial_distance.is_finite() {
                return Err(AnalyticError::Invalid {
                    what: "cutter profile",
                    reason: format!("axial distances must increase strictly; {} follows {}", pair[1].axial_distance, pair[0].axial_distance),
                });
            }
        }
        for p in &points {
            positive("profile radius", p.radius)?;
            in_open("profile blade_angle", p.blade_angle, 0.0, std::f64::consts::FRAC_PI_2, "in (0, pi/2) rad")?;
        }
        Ok(Self { points })
    }

    /// A cylinder of radius R and height H with constant blade angle φ (§2.12 closed-form case).
    pub fn cylinder(radius: f64, blade_angle: f64, height: f64) -> Result<Self> {
        positive("height", height)?;
        Self::new(vec![ProfilePoint { axial_distance: 0.0, radius, blade_angle }, ProfilePoint { axial_distance: height, radius, blade_angle }])
    }

    /// Illustrative 1:4 laboratory head. **Not the thesis geometry**: R(z), φ(z) exist only in
    /// the drawings of Figs. 5.8/5.16 (spillage-and-flow-verification.md §2.11, §9 item 2). Built
    /// from the text facts of §2.11: ring radius 0.375 m, H = 0.44 m (hub at −0.44 m), contour
    /// inside the r = 400 mm measurement points down to z = −255 mm and inside r = 280 mm at
    /// z = −365 mm. Our assumptions: R = 0.26 m at s = 0.365 m, hub radius 0.25 m, constant blade
    /// angle 30°. With α = 0.375, β = 0.774 this gives Q₁ = 0.079 m³/s at 60 rpm and 0.12 m³/s
    /// (thesis CFD: "about half the suction discharge", §5.2) and +87 % outflow with
    /// ρ₁ = 1254 kg/m³ (thesis model: "≈ 70 % more", §2.9) — plausible, not calibrated.
    pub fn illustrative_lab_head() -> Self {
        let phi = 30f64.to_radians();
        let point = |s: f64, r: f64| ProfilePoint { axial_distance: s, radius: r, blade_angle: phi };
        Self { points: vec![point(0.0, 0.375), point(0.255, 0.375), point(0.365, 0.26), point(0.44, 0.25)] }
    }

    /// H, the axial distance of the last point.
    pub fn height(&self) -> f64 {
        self.points.last().map_or(0.0, |p| p.axial_distance)
    }

    /// The profile points.
    pub fn points(&self) -> &[ProfilePoint] {
        &self.points
    }

    fn interpolate(&self, s: f64) -> (f64, f64) {
        let s = s.clamp(0.0, self.height());
        let i = self.points.partition_point(|p| p.axial_distance <= s).clamp(1, self.points.len() - 1);
        let (a, b) = (self.points[i - 1], self.points[i]);
        let t = (s - a.axial_distance) / (b.axial_distance - a.axial_distance);
        (a.radius + t * (b.radius - a.radius), a.blade_angle + t * (b.blade_angle - a.blade_angle))
    }

    /// R(s), s clamped to [0, H].
    pub fn radius_at(&self, s: f64) -> f64 {
        self.interpolate(s).0
    }

    /// φ(s), s clamped to [0, H].
    pub fn blade_angle_at(&self, s: f64) -> f64 {
        self.interpolate(s).1
    }
}

/// Inputs of the analytical spillage model (spillage-and-flow-verification.md §2.8).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpillageInputs {
    pub profile: CutterProfile,
    /// ω_c [rad/s] ≥ 0.
    pub omega: f64,
    /// Q_m [m³/s] ≥ 0.
    pub suction_discharge: f64,
    /// Flow factor α in (0, 1) (Eq. 4.57; α = 1 makes α' singular).
    pub flow_factor: f64,
    /// Pressure coefficient β in [0, 1] (Eq. 4.75; the thesis: "must not exceed 1").
    pub pressure_coefficient: f64,
    /// ρ₁, mixture density of the top segment [kg/m³].
    pub density_top: f64,
    /// ρ₂, mixture density of the bottom segment [kg/m³].
    pub density_bottom: f64,
}

/// Water density at 20 °C used in the calibration (Tab. 8.1).
pub const WATER_DENSITY: f64 = 998.2;
/// Calibrated flow factor α (Tab. 8.1).
pub const CALIBRATED_FLOW_FACTOR: f64 = 0.375;
/// Calibrated pressure coefficient β (Tab. 8.1).
pub const CALIBRATED_PRESSURE_COEFFICIENT: f64 = 0.774;
/// Cutting-side mixture density of the spillage comparison (Tab. 8.5).
pub const MIXTURE_DENSITY_TOP: f64 = 1254.0;

/// ω = 2π n/60 (Eq. 2.8).
pub fn rpm_to_omega(rpm: f64) -> f64 {
    2.0 * std::f64::consts::PI * rpm / 60.0
}

impl SpillageInputs {
    /// The calibrated water case of Tab. 8.1 (α = 0.375, β = 0.774, ρ₁ = ρ₂ = 998.2) on `profile`.
    pub fn calibrated_water(profile: CutterProfile, rpm: f64, suction_discharge: f64) -> Self {
        Self {
            profile,
            omega: rpm_to_omega(rpm),
            suction_discharge,
            flow_factor: CALIBRATED_FLOW_FACTOR,
            pressure_coefficient: CALIBRATED_PRESSURE_COEFFICIENT,
            density_top: WATER_DENSITY,
            density_bottom: WATER_DENSITY,
        }
    }

    /// Checks every scalar input; the profile was validated when built.
    pub fn validate(&self) -> Result<()> {
        non_negative("omega", self.omega)?;
        non_negative("suction_discharge", self.suction_discharge)?;
        in_open("flow_factor (alpha)", self.flow_factor, 0.0, 1.0, "in (0, 1)")?;
        in_closed("pressure_coefficient (beta)", self.pressure_coefficient, 0.0, 1.0, "in [0, 1]")?;
        positive("density_top", self.density_top)?;
        positive("density_bottom", self.density_bottom)?;
        Ok(())
    }
}

/// Segment-averaged geometry for a given w₁ (Eqs. 4.90–4.92 and the boundary positions of §2.7).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SegmentGeometry {
    /// R̄₁² = ½(R(0)² + R(w₁)²).
    pub mean_radius_sq_top: f64,
    /// R̄₂² = ½(R(w₁)² + R(H)²).
    pub mean_radius_sq_bottom: f64,
    /// t₁ = ½(tanφ(0) + tanφ(w₁)).
    pub tan_blade_top: f64,
    /// t₂ = ½(tanφ(w₁) + tanφ(H)).
    pub tan_blade_bottom: f64,
}

/// Segment averages at outflow height `w1` (§2.7).
pub fn segment_geometry(profile: &CutterProfile, w1: f64) -> SegmentGeometry {
    let h = profile.height();
    let (r0, rw, rh) = (profile.radius_at(0.0), profile.radius_at(w1), profile.radius_at(h));
    let (t0, tw, th) = (profile.blade_angle_at(0.0).tan(), profile.blade_angle_at(w1).tan(), profile.blade_angle_at(h).tan());
    SegmentGeometry {
        mean_radius_sq_top: 0.5 * (r0 * r0 + rw * rw),
        mean_radius_sq_bottom: 0.5 * (rw * rw + rh * rh),
        tan_blade_top: 0.5 * (t0 + tw),
        tan_blade_bottom: 0.5 * (tw + th),
    }
}

/// The fixed-point map F(w₁) = (H f − q)/(a + f) in the singularity-free form of §2.8.
pub fn outflow_height_map(inputs: &SpillageInputs, w1: f64) -> f64 {
    let g = segment_geometry(&inputs.profile, w1);
    let (rho1, rho2) = (inputs.density_top, inputs.density_bottom);
    let f = pressure_fraction(inputs, &g);
    let a = rho2 * g.tan_blade_top / (rho1 * g.tan_blade_bottom);
    let q =
        inputs.suction_discharge * rho2 / (2.0 * std::f64::consts::PI * inputs.flow_factor * inputs.omega * rho1 * g.mean_radius_sq_top * g.tan_blade_bottom);
    (inputs.profile.height() * f - q) / (a + f)
}

/// f = (ρ₁R̄₁² − βρ₂R̄₂²)/(ρ₁R̄₁²) (Eqs. 4.85, 4.91).
fn pressure_fraction(inputs: &SpillageInputs, g: &SegmentGeometry) -> f64 {
    let top = inputs.density_top * g.mean_radius_sq_top;
    (top - inputs.pressure_coefficient * inputs.density_bottom * g.mean_radius_sq_bottom) / top
}

/// Everything the model returns (§2.8 "Outputs" and "Diagnostics").
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpillageSolution {
    /// w₁ [m], 0 when there is no outflow.
    pub outflow_height: f64,
    /// w₂ = H − w₁ [m].
    pub inflow_height: f64,
    /// Q₁ [m³/s] (Eq. 4.59, segment averaged).
    pub outflow_discharge: f64,
    /// Q₂ = Q₁ + Q_m [m³/s] (Eq. 4.79).
    pub inflow_discharge: f64,
    /// Q₂ from the pressure relation α'₂ w₂ (ΔP_bl,1 − βΔP_bl,2) (Eq. 4.81); equals
    /// `inflow_discharge` whenever there is outflow.
    pub inflow_discharge_from_pressure: f64,
    /// S% = Q₁/(Q_m + Q₁) (Eq. 4.55), as a fraction.
    pub spillage_fraction: f64,
    /// P% = Q_m/(Q_m + Q₁), as a fraction.
    pub production_fraction: f64,
    /// f (Eq. 4.85/4.91).
    pub pressure_fraction: f64,
    /// ΔP_bl,1 [Pa] (Eq. 4.70).
    pub blade_pressure_top: f64,
    /// ΔP_bl,2 [Pa].
    pub blade_pressure_bottom: f64,
    /// α'₁ [s·m³/kg] (Eq. 4.78).
    pub alpha_prime_top: f64,
    /// α'₂ [s·m³/kg].
    pub alpha_prime_bottom: f64,
    /// Mean outflow velocity u_rad,1 = α ω R̄₁ t₁ [m/s] (Eq. 4.57, segment averaged); 0 without outflow.
    pub outflow_velocity: f64,
    pub geometry: SegmentGeometry,
    /// Whether outflow exists (w₁ > 0).
    pub has_outflow: bool,
}

/// Solves the model (spillage-and-flow-verification.md §2.8).
pub fn solve(inputs: &SpillageInputs) -> Result<SpillageSolution> {
    inputs.validate()?;
    let h = inputs.profile.height();
    let w1 = if inputs.omega == 0.0 || outflow_height_map(inputs, 0.0) <= 0.0 {
        0.0
    } else {
        let g = |w: f64| w - outflow_height_map(inputs, w);
        // g(0) < 0 here and g(H) > 0 always (F(H) < H because a > 0 and q ≥ 0); scan for the
        // first upward crossing, which is the stable fixed point of the thesis iteration.
        const SCAN: usize = 256;
        let mut lower = 0.0;
        let mut upper = h;
        for i in 1..=SCAN {
            let w = h * i as f64 / SCAN as f64;
            if g(w) >= 0.0 {
                upper = w;
                break;
            }
            lower = w;
        }
        brent("spillage model outflow height (Eq. 4.88)", g, lower, upper, 1e-12 * h)?
    };
    Ok(evaluate(inputs, w1))
}

/// All outputs at a given outflow height (used by [`solve`] and by tests of the invariants).
pub fn evaluate(inputs: &SpillageInputs, w1: f64) -> SpillageSolution {
    let h = inputs.profile.height();
    let g = segment_geometry(&inputs.profile, w1);
    let (alpha, beta, omega) = (inputs.flow_factor, inputs.pressure_coefficient, inputs.omega);
    let (rho1, rho2) = (inputs.density_top, inputs.density_bottom);
    let two_pi = 2.0 * std::f64::consts::PI;
    let blade_pressure_top = (1.0 - alpha) * rho1 * omega * omega * g.mean_radius_sq_top;
    let blade_pressure_bottom = (1.0 - alpha) * rho2 * omega * omega * g.mean_radius_sq_bottom;
    let (alpha_prime_top, alpha_prime_bottom) = if omega > 0.0 {
        (two_pi * g.tan_blade_top / (omega * rho1) * alpha / (1.0 - alpha), two_pi * g.tan_blade_bottom / (omega * rho2) * alpha / (1.0 - alpha))
    } else {
        (f64::INFINITY, f64::INFINITY)
    };
    let outflow_discharge = two_pi * g.mean_radius_sq_top * w1 * alpha * omega * g.tan_blade_top;
    let qm = inputs.suction_discharge;
    let total = qm + outflow_discharge;
    let spillage_fraction = if total > 0.0 { outflow_discharge / total } else { 0.0 };
    let inflow_discharge_from_pressure = if omega > 0.0 { alpha_prime_bottom * (h - w1) * (blade_pressure_top - beta * blade_pressure_bottom) } else { 0.0 };
    SpillageSolution {
        outflow_height: w1,
        inflow_height: h - w1,
        outflow_discharge,
        inflow_discharge: outflow_discharge + qm,
        inflow_discharge_from_pressure,
        spillage_fraction,
        production_fraction: 1.0 - spillage_fraction,
        pressure_fraction: pressure_fraction(inputs, &g),
        blade_pressure_top,
        blade_pressure_bottom,
        alpha_prime_top,
        alpha_prime_bottom,
        outflow_velocity: if w1 > 0.0 { alpha * omega * g.mean_radius_sq_top.sqrt() * g.tan_blade_top } else { 0.0 },
        geometry: g,
        has_outflow: w1 > 0.0,
    }
}

/// The thesis procedure of §2.8 literally: plain fixed-point iteration of Eq. 4.88 from
/// w₁ = H/2 until |Δw₁| < 1e-9 H (negative iterates clipped to 0). Returns (w₁, iterations).
/// Kept to show that the bracketing solver finds the same state when the iteration contracts.
pub fn solve_by_fixed_point(inputs: &SpillageInputs, max_iterations: usize) -> Result<(f64, usize)> {
    inputs.validate()?;
    let h = inputs.profile.height();
    let mut w1 = 0.5 * h;
    for iteration in 1..=max_iterations {
        let next = outflow_height_map(inputs, w1).max(0.0);
        if (next - w1).abs() < 1e-9 * h {
            return Ok((next, iteration));
        }
        w1 = next;
    }
    Err(AnalyticError::NoConvergence { what: "fixed-point iteration of Eq. 4.88", iterations: max_iterations, residual: outflow_height_map(inputs, w1) - w1 })
}

/// Rotation rate at which outflow starts (§2.12 item 2, [derived]):
/// ω_onset = Q_m ρ₂/(2π α H f₀ ρ₁ R(0)² t₂,₀) with segment 2 spanning the whole head.
/// Returns +∞ when f₀ ≤ 0 (no outflow at any ω). `inputs.omega` is ignored.
pub fn onset_omega(inputs: &SpillageInputs) -> Result<f64> {
    let mut probe = inputs.clone();
    probe.omega = 1.0;
    probe.validate()?;
    let g = segment_geometry(&inputs.profile, 0.0);
    let f0 = pressure_fraction(inputs, &g);
    if f0 <= 0.0 {
        return Ok(f64::INFINITY);
    }
    let r0 = inputs.profile.radius_at(0.0);
    Ok(inputs.suction_discharge * inputs.density_bottom
        / (2.0 * std::f64::consts::PI * inputs.flow_factor * inputs.profile.height() * f0 * inputs.density_top * r0 * r0 * g.tan_blade_bottom))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cylinder_case(rpm: f64, qm: f64, beta: f64) -> SpillageInputs {
        let mut inputs = SpillageInputs::calibrated_water(CutterProfile::cylinder(0.375, 0.7, 0.44).unwrap(), rpm, qm);
        inputs.pressure_coefficient = beta;
        inputs
    }

    #[test]
    fn cylinder_matches_closed_form() {
        // §2.12 item 1: w₁ = (H(1−β) − q)/(2−β), Q₁ = ((1−β)Q_pump − Q_m)/(2−β).
        for (rpm, qm) in [(60.0, 0.12), (90.0, 0.06), (45.0, 0.03)] {
            let inputs = cylinder_case(rpm, qm, 0.774);
            let (r, phi, h, a, b) = (0.375f64, 0.7f64, 0.44, 0.375, 0.774);
            let omega = rpm_to_omega(rpm);
            let q = qm / (2.0 * std::f64::consts::PI * a * omega * r * r * phi.tan());
            let q_pump = 2.0 * std::f64::consts::PI * a * omega * r * r * h * phi.tan();
            let w1 = (h * (1.0 - b) - q) / (2.0 - b);
            let q1 = ((1.0 - b) * q_pump - qm) / (2.0 - b);
            let sol = solve(&inputs).unwrap();
            assert!(w1 > 0.0, "test points must be above onset");
            assert!((sol.outflow_height - w1).abs() < 1e-11, "rpm {rpm}");
            assert!((sol.outflow_discharge - q1).abs() < 1e-12);
            assert!((sol.pressure_fraction - (1.0 - b)).abs() < 1e-15);
        }
    }

    #[test]
    fn continuity_and_identities_hold_to_round_off() {
        // §2.8 invariant tests on a non-trivial profile with unequal densities.
        for rpm in [30.0, 60.0, 90.0] {
            let mut inputs = SpillageInputs::calibrated_water(CutterProfile::illustrative_lab_head(), rpm, 0.12);
            inputs.density_top = MIXTURE_DENSITY_TOP;
            let sol = solve(&inputs).unwrap();
            if !sol.has_outflow {
                continue;
            }
            let residual = sol.outflow_discharge - sol.inflow_discharge_from_pressure + inputs.suction_discharge;
            assert!(residual.abs() < 1e-14, "Eq. 4.79 residual {residual:e} at {rpm} rpm");
            // α'₁ w₁ ΔP_bl,1 = 2π α ω R̄₁² w₁ t₁ (Eq. 4.80 = Eq. 4.59).
            let via_pressure = sol.alpha_prime_top * sol.outflow_height * sol.blade_pressure_top;
            assert!(((via_pressure - sol.outflow_discharge) / sol.outflow_discharge).abs() < 1e-13);
            // The solution is a fixed point of Eq. 4.88 in its original (α'-ratio) form.
            let w1_488 = (inputs.profile.height() * sol.pressure_fraction - inputs.suction_discharge / (sol.blade_pressure_top * sol.alpha_prime_bottom))
                / (sol.alpha_prime_top / sol.alpha_prime_bottom + sol.pressure_fraction);
            assert!((w1_488 - sol.outflow_height).abs() < 1e-11);
            // Eq. 4.89: α'₁/α'₂ = ρ₂ tanφ₁/(ρ₁ tanφ₂).
            let ratio = inputs.density_bottom * sol.geometry.tan_blade_top / (inputs.density_top * sol.geometry.tan_blade_bottom);
            assert!((sol.alpha_prime_top / sol.alpha_prime_bottom - ratio).abs() < 1e-14);
            assert!((sol.spillage_fraction + sol.production_fraction - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn onset_separates_no_outflow_from_outflow() {
        let inputs = SpillageInputs::calibrated_water(CutterProfile::illustrative_lab_head(), 0.0, 0.12);
        let onset = onset_omega(&inputs).unwrap();
        let mut below = inputs.clone();
        below.omega = 0.999 * onset;
        let mut above = inputs.clone();
        above.omega = 1.001 * onset;
        let (sol_below, sol_above) = (solve(&below).unwrap(), solve(&above).unwrap());
        assert!(!sol_below.has_outflow && sol_below.spillage_fraction == 0.0);
        assert!(sol_above.has_outflow && sol_above.outflow_height < 0.01 * inputs.profile.height());
        // Cylinder onset from the closed form: ω = Q_m/(2π α H (1−β) R² tanφ).
        let cyl = cylinder_case(0.0, 0.12, 0.774);
        let expected = 0.12 / (2.0 * std::f64::consts::PI * 0.375 * 0.44 * (1.0 - 0.774) * 0.375f64.powi(2) * 0.7f64.tan());
        assert!((onset_omega(&cyl).unwrap() - expected).abs() < 1e-12 * expected);
    }

    #[test]
    fn limits_of_section_2_12() {
        // Item 4: β = 1 on a cylinder gives f = 0: no outflow at any ω.
        for rpm in [20.0, 90.0, 500.0] {
            let sol = solve(&cylinder_case(rpm, 0.12, 1.0)).unwrap();
            assert!(!sol.has_outflow && sol.outflow_discharge == 0.0);
        }
        // α → 0 gives Q₁ → 0.
        let mut small = cylinder_case(90.0, 0.0, 0.774);
        small.flow_factor = 1e-9;
        assert!(solve(&small).unwrap().outflow_discharge < 1e-9);
        // ω = 0: no pumping.
        let still = solve(&cylinder_case(0.0, 0.12, 0.5)).unwrap();
        assert!(!still.has_outflow && still.production_fraction == 1.0);
        // Zero suction: the outflow is the whole circulation, S = 1.
        let no_suction = solve(&cylinder_case(60.0, 0.0, 0.5)).unwrap();
        assert!((no_suction.spillage_fraction - 1.0).abs() < 1e-15);
        // §2.9: a heavier top segment increases w₁ and Q₁.
        let water = solve(&SpillageInputs::calibrated_water(CutterProfile::illustrative_lab_head(), 60.0, 0.12)).unwrap();
        let mut mixture_inputs = SpillageInputs::calibrated_water(CutterProfile::illustrative_lab_head(), 60.0, 0.12);
        mixture_inputs.density_top = MIXTURE_DENSITY_TOP;
        let mixture = solve(&mixture_inputs).unwrap();
        assert!(mixture.outflow_discharge > water.outflow_discharge && mixture.outflow_height > water.outflow_height);
    }

    #[test]
    fn dimensions_and_linearity_in_omega() {
        // §2.12 item 3: Q_m/(ΔP_bl,1 α'₂) is a length: doubling every length doubles it. Check via
        // scaling the head by 2 at constant α, β, ρ and Q_m scaled by 2³ (Froude-free geometric
        // similarity at fixed ω): w₁ doubles, Q₁ scales by 8.
        let base = cylinder_case(60.0, 0.12, 0.774);
        let mut scaled = base.clone();
        scaled.profile = CutterProfile::cylinder(0.75, 0.7, 0.88).unwrap();
        scaled.suction_discharge = 0.96;
        let (a, b) = (solve(&base).unwrap(), solve(&scaled).unwrap());
        assert!((b.outflow_height / a.outflow_height - 2.0).abs() < 1e-12);
        assert!((b.outflow_discharge / a.outflow_discharge - 8.0).abs() < 1e-11);
        // Above onset Q₁ is linear in ω for a cylinder (Fig. 8.1 behaviour).
        let q = |rpm: f64| solve(&cylinder_case(rpm, 0.12, 0.774)).unwrap().outflow_discharge;
        let (q60, q75, q90) = (q(60.0), q(75.0), q(90.0));
        assert!(((q90 - q75) - (q75 - q60)).abs() < 1e-14);
    }

    #[test]
    fn thesis_fixed_point_iteration_agrees_with_bracketing() {
        for rpm in [45.0, 60.0, 90.0] {
            let inputs = SpillageInputs::calibrated_water(CutterProfile::illustrative_lab_head(), rpm, 0.12);
            let sol = solve(&inputs).unwrap();
            let (w1, iterations) = solve_by_fixed_point(&inputs, 10_000).unwrap();
            assert!(iterations > 1);
            // The iteration stops at |Δw| < 1e-9 H; with contraction factor < 1 the distance to the
            // fixed point is within a few times that.
            assert!((w1 - sol.outflow_height).abs() < 1e-7 * inputs.profile.height(), "rpm {rpm}");
        }
    }

    #[test]
    fn bad_inputs_name_the_parameter() {
        let mut inputs = SpillageInputs::calibrated_water(CutterProfile::illustrative_lab_head(), 60.0, 0.12);
        inputs.flow_factor = 1.0;
        let message = solve(&inputs).unwrap_err().to_string();
        assert!(message.contains("alpha") && message.contains("(0, 1)"), "{message}");
        inputs.flow_factor = 0.375;
        inputs.pressure_coefficient = 1.2;
        assert!(solve(&inputs).unwrap_err().to_string().contains("beta"));
        inputs.pressure_coefficient = 0.774;
        inputs.suction_discharge = -0.1;
        assert!(solve(&inputs).unwrap_err().to_string().contains("suction_discharge"));
        assert!(CutterProfile::cylinder(0.4, 1.6, 0.4).is_err());
        assert!(CutterProfile::new(vec![
            ProfilePoint { axial_distance: 0.0, radius: 0.3, blade_angle: 0.5 },
            ProfilePoint { axial_distance: 0.0, radius: 0.3, blade_angle: 0.5 },
        ])
        .is_err());
    }
}
