//! Circular Couette flow between two coaxial rotating cylinders.
//!
//! spillage-and-flow-verification.md §3.2 (thesis Eqs. 5.1–5.5) and fluid-dem-model.md §12
//! test U-32(b). The steady laminar solution is u_θ = A r + B/r with
//! A = (ω_o R_o² − ω_i R_i²)/(R_o² − R_i²) and B = (ω_i − ω_o) R_i² R_o²/(R_o² − R_i²).
//!
//! Erratum [E] (spillage-and-flow-verification.md §3.2 and §9 item 16): the printed Eq. 5.1 has
//! dp/dr = −ρu²/r; the physical radial balance, used here, is dp/dr = +ρ u_θ²/r (pressure rises
//! outward).

use serde::Serialize;

use crate::error::{finite, in_closed, non_negative, positive, AnalyticError, Result};

/// Geometry and wall rotation rates of a circular Couette cell.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CircularCouette {
    /// Inner cylinder radius R_i [m].
    pub inner_radius: f64,
    /// Outer cylinder radius R_o [m].
    pub outer_radius: f64,
    /// Inner cylinder angular velocity ω_i [rad/s] (positive counter-clockwise).
    pub inner_omega: f64,
    /// Outer cylinder angular velocity ω_o [rad/s].
    pub outer_omega: f64,
}

/// Velocity and pressure at one radius.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CouettePoint {
    pub radius: f64,
    pub tangential_velocity: f64,
    /// Kinematic radial pressure gradient (1/ρ) dp/dr [m/s²].
    pub kinematic_pressure_gradient: f64,
    /// Kinematic pressure rise (p(r) − p(R_i))/ρ [m²/s²].
    pub kinematic_pressure_rise: f64,
}

impl CircularCouette {
    /// Validates radii (0 < R_i < R_o) and finite rotation rates.
    pub fn new(inner_radius: f64, outer_radius: f64, inner_omega: f64, outer_omega: f64) -> Result<Self> {
        positive("inner_radius", inner_radius)?;
        positive("outer_radius", outer_radius)?;
        if outer_radius <= inner_radius {
            return Err(AnalyticError::OutOfRange { name: "outer_radius", value: outer_radius, allowed: "greater than inner_radius" });
        }
        finite("inner_omega", inner_omega)?;
        finite("outer_omega", outer_omega)?;
        Ok(Self { inner_radius, outer_radius, inner_omega, outer_omega })
    }

    /// The thesis case of §3.2 / Tab. 5.1: R_i = 1 m, R_o = 2 m, ω_i = 1 rad/s, outer wall at rest.
    pub fn thesis_case() -> Self {
        Self { inner_radius: 1.0, outer_radius: 2.0, inner_omega: 1.0, outer_omega: 0.0 }
    }

    /// Coefficients (A, B) of u_θ = A r + B/r (fluid-dem-model.md §12 U-32(b)).
    pub fn coefficients(&self) -> (f64, f64) {
        let (ri2, ro2) = (self.inner_radius.powi(2), self.outer_radius.powi(2));
        let a = (self.outer_omega * ro2 - self.inner_omega * ri2) / (ro2 - ri2);
        let b = (self.inner_omega - self.outer_omega) * ri2 * ro2 / (ro2 - ri2);
        (a, b)
    }

    fn check_radius(&self, r: f64) -> Result<f64> {
        in_closed("radius", r, self.inner_radius, self.outer_radius, "within [inner_radius, outer_radius]")
    }

    /// Tangential velocity u_θ(r) (spillage-and-flow-verification.md §3.2, Eq. 5.3 in dimensional form).
    pub fn tangential_velocity(&self, r: f64) -> Result<f64> {
        let r = self.check_radius(r)?;
        let (a, b) = self.coefficients();
        Ok(a * r + b / r)
    }

    /// (1/ρ) dp/dr = u_θ²/r (Eq. 5.1 with the sign erratum corrected).
    pub fn kinematic_pressure_gradient(&self, r: f64) -> Result<f64> {
        let u = self.tangential_velocity(r)?;
        Ok(u * u / r)
    }

    /// (p(r) − p(R_i))/ρ = A²(r² − R_i²)/2 + 2AB ln(r/R_i) − B²(1/r² − 1/R_i²)/2
    /// (spillage-and-flow-verification.md §3.2, "dimensional equivalents").
    pub fn kinematic_pressure_rise(&self, r: f64) -> Result<f64> {
        let r = self.check_radius(r)?;
        let (a, b) = self.coefficients();
        let ri = self.inner_radius;
        Ok(0.5 * a * a * (r * r - ri * ri) + 2.0 * a * b * (r / ri).ln() - 0.5 * b * b * (1.0 / (r * r) - 1.0 / (ri * ri)))
    }

    /// All quantities at radius `r`.
    pub fn point(&self, r: f64) -> Result<CouettePoint> {
        Ok(CouettePoint {
            radius: r,
            tangential_velocity: self.tangential_velocity(r)?,
            kinematic_pressure_gradient: self.kinematic_pressure_gradient(r)?,
            kinematic_pressure_rise: self.kinematic_pressure_rise(r)?,
        })
    }

    /// Gap Reynolds number ω_i R_i (R_o − R_i)/ν (§3.3, Tab. 5.1: Re = 50 for ν = 0.02 m²/s).
    pub fn gap_reynolds(&self, kinematic_viscosity: f64) -> Result<f64> {
        positive("kinematic_viscosity", kinematic_viscosity)?;
        let wall_speed = (self.inner_omega * self.inner_radius).abs();
        Ok(wall_speed * (self.outer_radius - self.inner_radius) / kinematic_viscosity)
    }

    /// Wall shear stress magnitude on the inner cylinder per unit density,
    /// ν |r d(u_θ/r)/dr| at R_i = 2ν|B|/R_i² (independent check of the viscous balance).
    pub fn inner_wall_kinematic_shear(&self, kinematic_viscosity: f64) -> Result<f64> {
        non_negative("kinematic_viscosity", kinematic_viscosity)?;
        let (_, b) = self.coefficients();
        Ok(2.0 * kinematic_viscosity * b.abs() / self.inner_radius.powi(2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// spillage-and-flow-verification.md §3.2 reference table (R_i = 1, R_o = 2, ω_i = 1), printed
    /// to 6 decimals; tolerance 5e-7 = half a unit in the last printed digit.
    #[test]
    fn reproduces_spec_table() {
        let cell = CircularCouette::thesis_case();
        let table = [
            (1.0, 1.000000, 1.000000),
            (1.125, 0.810185, 0.583467),
            (1.25, 0.650000, 0.338000),
            (1.5, 0.388889, 0.100823),
            (1.75, 0.178571, 0.018222),
            (2.0, 0.000000, 0.000000),
        ];
        for (r, u, dpdr) in table {
            let p = cell.point(r).unwrap();
            assert!((p.tangential_velocity - u).abs() < 5e-7, "u({r}) = {}", p.tangential_velocity);
            assert!((p.kinematic_pressure_gradient - dpdr).abs() < 5e-7, "dp/dr({r})");
        }
    }

    #[test]
    fn coefficients_match_spec_and_dimensionless_form() {
        let cell = CircularCouette::thesis_case();
        let (a, b) = cell.coefficients();
        assert!((a + 1.0 / 3.0).abs() < 1e-15 && (b - 4.0 / 3.0).abs() < 1e-15);
        // Eq. 5.3: Ũ = (η/R̃)(1 − R̃²)/(1 − η²) with R̃ = r/R_o, η = R_i/R_o, Ũ = u/(ω_i R_i).
        let eta: f64 = 0.5;
        for r in [1.1, 1.37, 1.9] {
            let rt = r / 2.0;
            let u_tilde = eta / rt * (1.0 - rt * rt) / (1.0 - eta * eta);
            assert!((cell.tangential_velocity(r).unwrap() - u_tilde).abs() < 1e-14);
        }
    }

    #[test]
    fn pressure_rise_integrates_gradient_and_is_positive_outward() {
        let cell = CircularCouette::new(0.3, 0.7, 2.0, -0.5).unwrap();
        let integral = crate::special::integrate(|r| cell.kinematic_pressure_gradient(r).unwrap(), 0.3, 0.61, 8);
        assert!((cell.kinematic_pressure_rise(0.61).unwrap() - integral).abs() < 1e-13);
        // Sign erratum: the pressure must rise outward.
        let thesis = CircularCouette::thesis_case();
        assert!(thesis.kinematic_pressure_rise(2.0).unwrap() > 0.0);
    }

    #[test]
    fn outer_rotation_and_solid_body_limit() {
        // Both walls at the same ω: solid-body rotation u = ωr, dp/dr = ω²r.
        let solid = CircularCouette::new(1.0, 2.0, 3.0, 3.0).unwrap();
        assert!((solid.tangential_velocity(1.6).unwrap() - 4.8).abs() < 1e-14);
        assert!((solid.kinematic_pressure_gradient(1.6).unwrap() - 9.0 * 1.6).abs() < 1e-12);
        // Outer wall only: boundary values hold.
        let outer = CircularCouette::new(1.0, 2.0, 0.0, 1.5).unwrap();
        assert!(outer.tangential_velocity(1.0).unwrap().abs() < 1e-15);
        assert!((outer.tangential_velocity(2.0).unwrap() - 3.0).abs() < 1e-14);
    }

    #[test]
    fn viscous_balance_and_reynolds_number() {
        let cell = CircularCouette::thesis_case();
        // Tab. 5.1: ν = 0.02 m²/s gives Re = 50.
        assert!((cell.gap_reynolds(0.02).unwrap() - 50.0).abs() < 1e-12);
        // Eq. 5.2 residual by central differences: u'' + u'/r − u/r² = 0.
        let h = 1e-4;
        for r in [1.2, 1.5, 1.8] {
            let u = |x: f64| cell.tangential_velocity(x).unwrap();
            let d2 = (u(r + h) - 2.0 * u(r) + u(r - h)) / (h * h);
            let d1 = (u(r + h) - u(r - h)) / (2.0 * h);
            assert!((d2 + d1 / r - u(r) / (r * r)).abs() < 1e-6);
        }
        // Torque balance: the same torque r² τ crosses every radius; check 2νB/R_i².
        assert!((cell.inner_wall_kinematic_shear(0.02).unwrap() - 2.0 * 0.02 * 4.0 / 3.0).abs() < 1e-15);
    }

    #[test]
    fn bad_inputs_are_rejected() {
        assert!(CircularCouette::new(2.0, 1.0, 1.0, 0.0).is_err());
        assert!(CircularCouette::new(-1.0, 1.0, 1.0, 0.0).is_err());
        assert!(CircularCouette::thesis_case().tangential_velocity(2.5).is_err());
    }
}
