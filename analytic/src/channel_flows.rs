//! Sanity closed forms for the fluid solvers: plane Poiseuille and Couette channel flow, the 2-D
//! Taylor–Green vortex, and particle-free / suspension hydrostatics.
//!
//! These are standard incompressible Navier–Stokes solutions (not printed in the spec); they
//! verify the fluid part of fluid-dem-model.md §8 before particles are added. The hydrostatic
//! suspension is fluid-dem-model.md §12 U-33; the packing density is
//! spillage-and-flow-verification.md §2.9 / V14 (thesis Eq. 8.5).

use serde::Serialize;

use crate::error::{finite, in_closed, positive, Result};

/// Steady flow between parallel plates y = 0 (at rest) and y = h (moving with U), driven also by
/// a constant pressure gradient dp/dx: u(y) = U y/h + (−dp/dx)/(2μ) y (h − y).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ChannelFlow {
    /// Gap h [m].
    pub height: f64,
    /// Dynamic viscosity μ [Pa s].
    pub viscosity: f64,
    /// Pressure gradient dp/dx [Pa/m] (negative drives flow in +x).
    pub pressure_gradient: f64,
    /// Upper-wall speed U [m/s] (0 for plane Poiseuille).
    pub wall_speed: f64,
}

impl ChannelFlow {
    pub fn new(height: f64, viscosity: f64, pressure_gradient: f64, wall_speed: f64) -> Result<Self> {
        positive("height", height)?;
        positive("viscosity", viscosity)?;
        finite("pressure_gradient", pressure_gradient)?;
        finite("wall_speed", wall_speed)?;
        Ok(Self { height, viscosity, pressure_gradient, wall_speed })
    }

    /// u(y) for y in [0, h].
    pub fn velocity(&self, y: f64) -> Result<f64> {
        let y = in_closed("y", y, 0.0, self.height, "within [0, height]")?;
        Ok(self.wall_speed * y / self.height - self.pressure_gradient / (2.0 * self.viscosity) * y * (self.height - y))
    }

    /// Flow rate per unit width Q = U h/2 − (dp/dx) h³/(12μ).
    pub fn flow_rate(&self) -> f64 {
        0.5 * self.wall_speed * self.height - self.pressure_gradient * self.height.powi(3) / (12.0 * self.viscosity)
    }

    /// Mean velocity Q/h.
    pub fn mean_velocity(&self) -> f64 {
        self.flow_rate() / self.height
    }

    /// Wall shear stresses (τ at y = 0, τ at y = h) = μ du/dy.
    pub fn wall_shear_stresses(&self) -> (f64, f64) {
        let du = |y: f64| self.wall_speed / self.height - self.pressure_gradient / (2.0 * self.viscosity) * (self.height - 2.0 * y);
        (self.viscosity * du(0.0), self.viscosity * du(self.height))
    }
}

/// The decaying 2-D Taylor–Green vortex on the periodic square [0, 2π/k]²:
/// u = U sin(kx) cos(ky) F(t), v = −U cos(kx) sin(ky) F(t), F = exp(−2νk²t),
/// p = p₀ + (ρU²/4)(cos 2kx + cos 2ky) F(t)².
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TaylorGreen {
    pub amplitude: f64,
    pub wavenumber: f64,
    pub kinematic_viscosity: f64,
    pub density: f64,
}

impl TaylorGreen {
    pub fn new(amplitude: f64, wavenumber: f64, kinematic_viscosity: f64, density: f64) -> Result<Self> {
        finite("amplitude", amplitude)?;
        positive("wavenumber", wavenumber)?;
        positive("kinematic_viscosity", kinematic_viscosity)?;
        positive("density", density)?;
        Ok(Self { amplitude, wavenumber, kinematic_viscosity, density })
    }

    fn decay(&self, t: f64) -> f64 {
        (-2.0 * self.kinematic_viscosity * self.wavenumber.powi(2) * t).exp()
    }

    /// Velocity (u, v) at (x, y, t).
    pub fn velocity(&self, x: f64, y: f64, t: f64) -> (f64, f64) {
        let (k, f) = (self.wavenumber, self.decay(t));
        (self.amplitude * (k * x).sin() * (k * y).cos() * f, -self.amplitude * (k * x).cos() * (k * y).sin() * f)
    }

    /// Pressure relative to p₀.
    pub fn pressure(&self, x: f64, y: f64, t: f64) -> f64 {
        let k = self.wavenumber;
        0.25 * self.density * self.amplitude.powi(2) * ((2.0 * k * x).cos() + (2.0 * k * y).cos()) * self.decay(t).powi(2)
    }

    /// Domain-averaged kinetic energy per unit mass ½⟨u² + v²⟩ = (U²/4) exp(−4νk²t).
    pub fn mean_kinetic_energy(&self, t: f64) -> f64 {
        0.25 * self.amplitude.powi(2) * self.decay(t).powi(2)
    }
}

/// Hydrostatic pressure p(depth) = p_surface + ρ g depth.
pub fn hydrostatic_pressure(surface_pressure: f64, density: f64, gravity: f64, depth: f64) -> Result<f64> {
    finite("surface_pressure", surface_pressure)?;
    positive("density", density)?;
    positive("gravity", gravity)?;
    finite("depth", depth)?;
    Ok(surface_pressure + density * gravity * depth)
}

/// Mixture density ρ_m = α_c ρ_c + α_p ρ_p (fluid-dem-model.md U-33: the converged pressure
/// gradient of a held suspension is ρ_m g).
pub fn mixture_density(particle_fraction: f64, particle_density: f64, fluid_density: f64) -> Result<f64> {
    in_closed("particle_fraction", particle_fraction, 0.0, 1.0, "in [0, 1]")?;
    positive("particle_density", particle_density)?;
    positive("fluid_density", fluid_density)?;
    Ok((1.0 - particle_fraction) * fluid_density + particle_fraction * particle_density)
}

/// Particle fraction of a simple-cubic lattice of spheres, α_p = (π/6) d³/d_inter³ (thesis
/// Eq. 8.5, spillage-and-flow-verification.md §2.9).
pub fn lattice_particle_fraction(diameter: f64, spacing: f64) -> Result<f64> {
    positive("diameter", diameter)?;
    positive("spacing", spacing)?;
    if spacing < diameter {
        return Err(crate::error::AnalyticError::OutOfRange { name: "spacing", value: spacing, allowed: ">= diameter (no overlap)" });
    }
    Ok(std::f64::consts::PI / 6.0 * (diameter / spacing).powi(3))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::special::integrate;

    #[test]
    fn poiseuille_profile_satisfies_momentum_and_flux() {
        let flow = ChannelFlow::new(0.02, 1e-3, -12.0, 0.0).unwrap();
        // μ u'' = dp/dx at interior points (central differences of a quadratic are exact).
        let h = 1e-4;
        for y in [0.003, 0.01, 0.017] {
            let u = |y: f64| flow.velocity(y).unwrap();
            let second = (u(y + h) - 2.0 * u(y) + u(y - h)) / (h * h);
            assert!((flow.viscosity * second - flow.pressure_gradient).abs() < 1e-5);
        }
        // Flux by quadrature, u_max = 1.5 ū, no slip.
        let q = integrate(|y| flow.velocity(y).unwrap(), 0.0, 0.02, 1);
        assert!((q - flow.flow_rate()).abs() < 1e-15);
        assert!((flow.velocity(0.01).unwrap() - 1.5 * flow.mean_velocity()).abs() < 1e-14);
        assert_eq!(flow.velocity(0.0).unwrap(), 0.0);
        // Force balance per unit length: wall shear on both walls balances the pressure drop.
        let (bottom, top) = flow.wall_shear_stresses();
        assert!((bottom - top + flow.pressure_gradient * flow.height).abs() < 1e-14);
    }

    #[test]
    fn couette_channel_is_linear() {
        let flow = ChannelFlow::new(0.5, 2.0, 0.0, 3.0).unwrap();
        assert!((flow.velocity(0.2).unwrap() - 1.2).abs() < 1e-15);
        assert!((flow.flow_rate() - 0.75).abs() < 1e-15);
        let (bottom, top) = flow.wall_shear_stresses();
        assert!((bottom - 12.0).abs() < 1e-14 && (top - 12.0).abs() < 1e-14);
        assert!(flow.velocity(0.6).is_err());
    }

    #[test]
    fn taylor_green_solves_navier_stokes() {
        let tg = TaylorGreen::new(1.3, 2.0, 0.01, 1000.0).unwrap();
        let (x, y, t) = (0.37, 1.21, 0.8);
        let e = 1e-5;
        let u = |x: f64, y: f64, t: f64| tg.velocity(x, y, t);
        // Continuity.
        let div = (u(x + e, y, t).0 - u(x - e, y, t).0 + u(x, y + e, t).1 - u(x, y - e, t).1) / (2.0 * e);
        assert!(div.abs() < 1e-9);
        // x-momentum: ∂u/∂t + u ∂u/∂x + v ∂u/∂y = −(1/ρ) ∂p/∂x + ν ∇²u.
        let (u0, v0) = u(x, y, t);
        let dudt = (u(x, y, t + e).0 - u(x, y, t - e).0) / (2.0 * e);
        let dudx = (u(x + e, y, t).0 - u(x - e, y, t).0) / (2.0 * e);
        let dudy = (u(x, y + e, t).0 - u(x, y - e, t).0) / (2.0 * e);
        let lap = (u(x + e, y, t).0 + u(x - e, y, t).0 + u(x, y + e, t).0 + u(x, y - e, t).0 - 4.0 * u0) / (e * e);
        let dpdx = (tg.pressure(x + e, y, t) - tg.pressure(x - e, y, t)) / (2.0 * e);
        let residual = dudt + u0 * dudx + v0 * dudy + dpdx / tg.density - tg.kinematic_viscosity * lap;
        // Central differences with ε = 1e-5: truncation ~1e-10, round-off in the Laplacian ~1e-6.
        assert!(residual.abs() < 1e-5, "residual {residual:e}");
        // Kinetic energy: domain average by quadrature equals (U²/4) e^(−4νk²t).
        let l = 2.0 * std::f64::consts::PI / tg.wavenumber;
        let ke = integrate(
            |x| {
                integrate(
                    |y| {
                        let (a, b) = tg.velocity(x, y, t);
                        0.5 * (a * a + b * b)
                    },
                    0.0,
                    l,
                    4,
                )
            },
            0.0,
            l,
            4,
        ) / (l * l);
        assert!((ke - tg.mean_kinetic_energy(t)).abs() < 1e-13);
        assert!((tg.mean_kinetic_energy(t) / tg.mean_kinetic_energy(0.0) - (-4.0 * 0.01 * 4.0 * t).exp()).abs() < 1e-15);
    }

    #[test]
    fn hydrostatics_and_packing_match_spec() {
        assert!((hydrostatic_pressure(1e5, 998.2, 9.81, 2.0).unwrap() - (1e5 + 998.2 * 9.81 * 2.0)).abs() < 1e-9);
        // V14: d_inter = 1.5 d_p gives α_p = 0.1551 and ρ_m ≈ 1254.5 kg/m³ (Tab. 8.3/8.5: 1254).
        let alpha_p = lattice_particle_fraction(0.02, 0.03).unwrap();
        assert!((alpha_p - 0.1551).abs() < 5e-5);
        let rho_m = mixture_density(alpha_p, 2650.0, 998.2).unwrap();
        assert!((rho_m - 1254.5).abs() < 0.05, "{rho_m}");
        assert!(lattice_particle_fraction(0.03, 0.02).is_err());
    }
}
