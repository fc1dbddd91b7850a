//! Single-sphere drag and the implicit fluid-force update of a particle
//! (fluid-dem-model.md §5.2, §5.5, §5.7, §5.10).

use nalgebra::Vector3;

use super::restitution::ADDED_MASS_COEFFICIENT;

type Vec3 = Vector3<f64>;

/// Which single-sphere drag coefficient to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DragLaw {
    /// Brown & Lawler (2003), the thesis' choice (T3.41).
    #[default]
    BrownLawler,
    /// Schiller–Naumann (T3.40), for comparison.
    SchillerNaumann,
}

/// Drag coefficient C_d(Re_s); Re_s = 0 returns +∞ (the Stokes limit, handled by the caller).
pub fn drag_coefficient(law: DragLaw, reynolds: f64) -> f64 {
    match law {
        // (T3.41)
        DragLaw::BrownLawler => 24.0 / reynolds * (1.0 + 0.150 * reynolds.powf(0.681)) + 0.407 / (1.0 + 8710.0 / reynolds),
        // (T3.40)
        DragLaw::SchillerNaumann => {
            if reynolds <= 1000.0 {
                24.0 / reynolds * (1.0 + 0.150 * reynolds.powf(0.687))
            } else {
                0.44
            }
        }
    }
}

/// Linearised drag coefficient K = ½ C_d A_p ρ_c |u_c − u_p| h [kg/s] such that F_d = K (u_c − u_p)
/// (T3.38 with the hindrance factor h = α_c^{1−β}, §5.10). At zero slip K is the Stokes limit
/// 3π μ d_p h, the limit of ½ C_d A ρ |u| as Re → 0.
pub fn drag_factor(law: DragLaw, diameter: f64, fluid_density: f64, kinematic_viscosity: f64, slip_speed: f64, hindrance: f64) -> f64 {
    let reynolds = slip_speed * diameter / kinematic_viscosity;
    if reynolds <= 1e-12 {
        return 3.0 * std::f64::consts::PI * fluid_density * kinematic_viscosity * diameter * hindrance;
    }
    let area = std::f64::consts::PI * diameter * diameter / 4.0;
    0.5 * drag_coefficient(law, reynolds) * area * fluid_density * slip_speed * hindrance
}

/// What a particle sees of the fluid around it (sampled by the coupling, or a still ambient fluid).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FluidAtParticle {
    pub density: f64,
    pub kinematic_viscosity: f64,
    /// Undisturbed fluid velocity u_c|p [m/s].
    pub velocity: Vec3,
    /// Material acceleration Du_c|p/Dt [m/s²].
    pub material_acceleration: Vec3,
    /// Hindered-settling factor α_c^{1−β} (1 for a single particle).
    pub hindrance: f64,
}

impl FluidAtParticle {
    /// A fluid at rest, without hindrance.
    pub fn still(density: f64, kinematic_viscosity: f64) -> Self {
        Self { density, kinematic_viscosity, velocity: Vec3::zeros(), material_acceleration: Vec3::zeros(), hindrance: 1.0 }
    }
}

/// One implicit fluid-force update of the particle velocity over `dt` (§5.10, "recommended
/// linearised implicit update"), from the solvable form of (T3.68) in §5.7:
///
/// u_new = (m_eff u + Δt [K u_c + (1+C_AM) V ρ_c Du_c/Dt + V(ρ_p−ρ_c) g]) / (m_eff + K Δt),
/// m_eff = V(ρ_p + C_AM ρ_c), K from [`drag_factor`] at the start of the update.
///
/// Without a fluid (`fluid = None`) this is u + Δt g.
pub fn fluid_force_update(law: DragLaw, velocity: Vec3, diameter: f64, particle_density: f64, fluid: Option<&FluidAtParticle>, gravity: Vec3, dt: f64) -> Vec3 {
    let Some(fluid) = fluid else {
        return velocity + dt * gravity;
    };
    let volume = std::f64::consts::PI * diameter.powi(3) / 6.0;
    let effective_mass = volume * (particle_density + ADDED_MASS_COEFFICIENT * fluid.density);
    let slip = (fluid.velocity - velocity).norm();
    let k = drag_factor(law, diameter, fluid.density, fluid.kinematic_viscosity, slip, fluid.hindrance);
    let explicit = k * fluid.velocity
        + (1.0 + ADDED_MASS_COEFFICIENT) * volume * fluid.density * fluid.material_acceleration
        + volume * (particle_density - fluid.density) * gravity;
    (effective_mass * velocity + dt * explicit) / (effective_mass + k * dt)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// fluid-dem-model.md §12 U-01 and particle-verification.md §8 checks 1–2.
    #[test]
    fn drag_coefficients() {
        for (re, cd) in [(1.0, 27.600047), (10.0, 4.127507), (100.0, 1.073139), (1000.0, 0.463384), (1e5, 0.466106)] {
            assert_relative_eq!(drag_coefficient(DragLaw::BrownLawler, re), cd, max_relative = 1e-6);
        }
        assert_relative_eq!(drag_coefficient(DragLaw::BrownLawler, 7000.0), 0.398435, max_relative = 1e-5);
        assert_relative_eq!(drag_coefficient(DragLaw::SchillerNaumann, 7000.0), 0.44);
        assert_relative_eq!(drag_coefficient(DragLaw::SchillerNaumann, 1000.0), 0.43829, max_relative = 1e-5);
    }

    /// U-10: initial acceleration from rest, (ρ_p−ρ_c) g / (ρ_p + C_AM ρ_c) = 5.14565 m/s².
    #[test]
    fn release_from_rest() {
        let fluid = FluidAtParticle::still(998.2, 1.0034e-6);
        let dt = 1e-9;
        let u = fluid_force_update(DragLaw::BrownLawler, Vec3::zeros(), 0.01, 2650.0, Some(&fluid), Vec3::new(0.0, 0.0, -9.81), dt);
        assert_relative_eq!(-u.z / dt, 5.14565, max_relative = 1e-5);
    }
}
