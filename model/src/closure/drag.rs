//! Single-sphere drag and the implicit fluid-force update of a particle
//! (fluid-dem-model.md §5.2, §5.5, §5.7, §5.10).

use nalgebra::Vector3;

use super::elementary::{exp, ln};
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
    /// Stokes, C_d = 24/Re_s: the wear thesis' settling check (wear-model.md §12.2), which is
    /// reproduced only with pure Stokes drag.
    Stokes,
}

/// Drag coefficient C_d(Re_s) as T3.40/T3.41 print it; Re_s = 0 returns +∞. The solvers take K
/// from [`drag_factor_and_reynolds`], the same law written for speed, which a test holds to this.
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
        DragLaw::Stokes => 24.0 / reynolds,
    }
}

/// Di Felice exponent β(Re_p) = 3.7 − 0.65 exp(−(1.5 − log₁₀ Re_p)²/2) (T3.58); 3.7 at Re_p = 0,
/// NaN for a negative Re_p.
pub fn di_felice_exponent(particle_reynolds: f64) -> f64 {
    di_felice_exponent_of_log(ln(particle_reynolds))
}

/// [`di_felice_exponent`] of ln Re_p (−∞ at Re_p = 0, where it gives 3.7).
#[inline(always)]
fn di_felice_exponent_of_log(ln_particle_reynolds: f64) -> f64 {
    let log10 = ln_particle_reynolds * std::f64::consts::LOG10_E;
    3.7 - 0.65 * exp(-0.5 * (1.5 - log10) * (1.5 - log10))
}

/// Hindered-drag factor α_c^{1−β(Re_p)} with Re_p = α_c Re_s (T3.62, the fluid-pressure form
/// the solver uses; spec §11.3: C_d takes Re_s, β takes Re_p). 1 for a lone particle (α_c = 1).
pub fn hindrance(fluid_fraction: f64, slip_reynolds: f64) -> f64 {
    hindrance_of_log(fluid_fraction, ln(slip_reynolds))
}

/// [`hindrance`] of ln Re_s: α^{1−β} = exp((1 − β) ln α), and ln Re_p = ln α + ln Re_s, so the
/// drag law takes one logarithm of Re_s for C_d and β both, and no `powf`. Computed for every
/// α and then chosen, so that a loop over particles has no branch here.
#[inline(always)]
fn hindrance_of_log(fluid_fraction: f64, ln_slip_reynolds: f64) -> f64 {
    let ln_fraction = ln(fluid_fraction);
    let hindered = exp((1.0 - di_felice_exponent_of_log(ln_fraction + ln_slip_reynolds)) * ln_fraction);
    if fluid_fraction >= 1.0 {
        1.0
    } else {
        hindered
    }
}

/// Linearised drag coefficient K = ½ C_d A_p ρ_c |u_c − u_p| α_c^{1−β} [kg/s] such that
/// F_d = K (u_c − u_p) (T3.38 with the hindrance factor of T3.62, §5.10). At zero slip K is the
/// Stokes limit 3π μ d_p α_c^{−2.7}, the limit of ½ C_d A ρ |u| as Re → 0.
pub fn drag_factor(law: DragLaw, diameter: f64, fluid_density: f64, kinematic_viscosity: f64, slip_speed: f64, fluid_fraction: f64) -> f64 {
    drag_factor_and_reynolds(law, diameter, fluid_density, kinematic_viscosity, slip_speed, fluid_fraction).0
}

/// [`drag_factor`] and the slip Reynolds number Re_s = |u_c − u_p| d/ν it was taken at.
///
/// The laws' 24/Re_s part is written as the Stokes drag it is, ½ (24/Re_s) A ρ |u| = 3π ρ ν d,
/// and Brown–Lawler's 0.407/(1 + 8710/Re_s) as 0.407 Re_s/(Re_s + 8 710): the same K without
/// dividing by Re_s, so zero slip needs no branch (Re_s^0.681 = exp(0.681 ln 0) = 0), and
/// Re_s^0.681 is exp(0.681 ln Re_s) with the ln β needs too. This is the particles' hottest
/// formula (P3 fine: two updates per particle per DEM sub-step, 62 sub-steps a fluid step);
/// written this way, with [`super::elementary`]'s `exp` and `ln`, it calls nothing, its
/// choices (the law, Schiller–Naumann's switch at Re_s = 1000, α_c ≥ 1) are selects between
/// computed values, and the fast particle phase runs it in SIMD lanes.
#[inline(always)]
pub fn drag_factor_and_reynolds(law: DragLaw, diameter: f64, fluid_density: f64, kinematic_viscosity: f64, slip_speed: f64, fluid_fraction: f64) -> (f64, f64) {
    let reynolds = slip_speed * diameter / kinematic_viscosity;
    let ln_reynolds = ln(reynolds);
    let stokes = 3.0 * std::f64::consts::PI * fluid_density * kinematic_viscosity * diameter;
    // the inertial part, ½ C A ρ |u| for a coefficient C that does not grow as 1/Re_s
    let form = |c: f64| 0.5 * c * (0.25 * std::f64::consts::PI * diameter * diameter) * fluid_density * slip_speed;
    let single = match law {
        // (T3.41)
        DragLaw::BrownLawler => stokes * (1.0 + 0.150 * exp(0.681 * ln_reynolds)) + form(0.407 * reynolds / (reynolds + 8710.0)),
        // (T3.40)
        DragLaw::SchillerNaumann if reynolds <= 1000.0 => stokes * (1.0 + 0.150 * exp(0.687 * ln_reynolds)),
        DragLaw::SchillerNaumann => form(0.44),
        DragLaw::Stokes => stokes,
    };
    (single * hindrance_of_log(fluid_fraction, ln_reynolds), reynolds)
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
    /// Fluid fraction α_c|p at the particle (1 for a lone particle; §6.5 T3.86): it sets the
    /// hindered-drag factor α_c^{1−β}.
    pub fluid_fraction: f64,
}

impl FluidAtParticle {
    /// A fluid at rest, without hindrance.
    pub fn still(density: f64, kinematic_viscosity: f64) -> Self {
        Self { density, kinematic_viscosity, velocity: Vec3::zeros(), material_acceleration: Vec3::zeros(), fluid_fraction: 1.0 }
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
    match fluid {
        Some(fluid) => fluid_force_step(law, velocity, diameter, particle_density, fluid, gravity, dt).velocity,
        None => velocity + dt * gravity,
    }
}

/// One implicit fluid-force update (see [`fluid_force_update`]) with what the fluid receives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FluidForceStep {
    /// The particle velocity after the update.
    pub velocity: Vec3,
    /// K [kg/s], evaluated at the start of the update.
    pub drag_factor: f64,
    /// Drag on the particle F_d = K (u_c|p − u_new) [N].
    pub drag: Vec3,
    /// Added-mass plus fluid-acceleration force on the particle over the update,
    /// F_AM + F_pg = (1 + C_AM) V ρ_c Du_c/Dt − C_AM V ρ_c (u_new − u)/Δt [N] (T3.43, T3.45).
    pub fluid_acceleration_force: Vec3,
    /// Slip Reynolds number |u_c|p − u| d/ν at the start of the update (T3.42).
    pub slip_reynolds: f64,
}

impl FluidForceStep {
    /// Explicit part of the coupled force on the fluid, K u_new − (F_AM + F_pg) (spec §8.4,
    /// sign corrected): with −K u_cell implicit in the fluid, the fluid receives −(F_d + F_AM +
    /// F_pg) once u_cell = u_c|p (§2.6).
    #[inline(always)]
    pub fn explicit_feedback(&self) -> Vec3 {
        self.drag_factor * self.velocity - self.fluid_acceleration_force
    }
}

/// [`fluid_force_update`] with the forces it applied.
#[inline(always)]
pub fn fluid_force_step(law: DragLaw, velocity: Vec3, diameter: f64, particle_density: f64, fluid: &FluidAtParticle, gravity: Vec3, dt: f64) -> FluidForceStep {
    // the new velocity and the particle's acceleration each take one reciprocal instead of three
    // divisions: this runs twice per particle per DEM sub-step. The volume is written as
    // `Particle::volume` writes it, so that a particle has one volume to the bit.
    let volume = std::f64::consts::PI * diameter.powi(3) / 6.0;
    let effective_mass = volume * (particle_density + ADDED_MASS_COEFFICIENT * fluid.density);
    let slip = (fluid.velocity - velocity).norm();
    let (k, slip_reynolds) = drag_factor_and_reynolds(law, diameter, fluid.density, fluid.kinematic_viscosity, slip, fluid.fluid_fraction);
    let fluid_acceleration = (1.0 + ADDED_MASS_COEFFICIENT) * volume * fluid.density * fluid.material_acceleration;
    let explicit = k * fluid.velocity + fluid_acceleration + volume * (particle_density - fluid.density) * gravity;
    let new = (effective_mass * velocity + dt * explicit) * (1.0 / (effective_mass + k * dt));
    FluidForceStep {
        velocity: new,
        drag_factor: k,
        drag: k * (fluid.velocity - new),
        fluid_acceleration_force: fluid_acceleration - (ADDED_MASS_COEFFICIENT * volume * fluid.density / dt) * (new - velocity),
        slip_reynolds,
    }
}

/// The fluid forces on a particle held at `velocity` (`[particles] motion = "held"`): drag
/// K (u_c|p − u_p) with K at the held slip, and the fluid-acceleration force
/// (1 + C_AM) V ρ_c Du_c/Dt without the added mass of the particle's own acceleration, which
/// is zero. The velocity stays; the forces are what the fluid receives in return (§8.4).
pub fn held_fluid_force(law: DragLaw, velocity: Vec3, diameter: f64, fluid: &FluidAtParticle) -> FluidForceStep {
    let volume = std::f64::consts::PI * diameter.powi(3) / 6.0;
    let slip = (fluid.velocity - velocity).norm();
    let (k, slip_reynolds) = drag_factor_and_reynolds(law, diameter, fluid.density, fluid.kinematic_viscosity, slip, fluid.fluid_fraction);
    FluidForceStep {
        velocity,
        drag_factor: k,
        drag: k * (fluid.velocity - velocity),
        fluid_acceleration_force: (1.0 + ADDED_MASS_COEFFICIENT) * volume * fluid.density * fluid.material_acceleration,
        slip_reynolds,
    }
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

    /// U-04 and U-06 (§12): β minimum 3.05 at Re_p = 10^1.5, symmetric in log Re_p; the
    /// factor is 1 at α_c = 1.
    #[test]
    fn di_felice_exponent_and_hindrance() {
        assert_relative_eq!(di_felice_exponent(10f64.powf(1.5)), 3.05, max_relative = 1e-12);
        assert_relative_eq!(di_felice_exponent(10.0), 3.126377, max_relative = 1e-6);
        assert_relative_eq!(di_felice_exponent(100.0), 3.126377, max_relative = 1e-6);
        assert_relative_eq!(di_felice_exponent(7332.78), 3.660365, max_relative = 1e-6);
        assert_eq!(hindrance(1.0, 500.0), 1.0);
        // α_c = 0.9, Re_s = 100/0.9 → Re_p = 100, β = 3.126377: 0.9^(−2.126377)
        assert_relative_eq!(hindrance(0.9, 100.0 / 0.9), 0.9f64.powf(1.0 - 3.126377), max_relative = 1e-6);
    }

    /// K as written for speed (Stokes part apart, one ln shared by C_d and β) is the literal
    /// ½ C_d(Re_s) A ρ |u| α^{1−β(α Re_s)} of T3.38/T3.40/T3.41/T3.62 with `powf` and `log10`,
    /// to a few units in the last place (bound 1e-14: each form rounds a dozen operations, and
    /// exp(0.681 ln Re) carries ln Re's rounding × 0.681 ln Re ≤ 8 ulp at Re = 10⁵), from
    /// creeping flow to past the drag crisis' onset, dense to lone; zero slip is the Stokes
    /// limit.
    #[test]
    fn drag_factor_is_the_literal_law() {
        let (d, rho, nu) = (0.01, 998.2, 1.0034e-6);
        let literal = |law: DragLaw, slip: f64, alpha: f64| {
            let re = slip * d / nu;
            let beta = if alpha * re <= 0.0 { 3.7 } else { 3.7 - 0.65 * (-(1.5 - (alpha * re).log10()).powi(2) / 2.0).exp() };
            // a mapping's round-off above α_c = 1 is a lone particle: no hindrance
            let hindrance = if alpha >= 1.0 { 1.0 } else { alpha.powf(1.0 - beta) };
            0.5 * drag_coefficient(law, re) * std::f64::consts::PI * d * d / 4.0 * rho * slip * hindrance
        };
        for law in [DragLaw::BrownLawler, DragLaw::SchillerNaumann, DragLaw::Stokes] {
            for re in [1e-9, 1e-3, 0.5, 1.0, 24.0, 999.0, 1000.0, 1001.0, 7332.78, 1e5] {
                for alpha in [0.5, 0.692, 0.9, 0.999_999, 1.0, 1.0 + 1e-12] {
                    let slip = re * nu / d;
                    let (k, reynolds) = drag_factor_and_reynolds(law, d, rho, nu, slip, alpha);
                    assert_relative_eq!(k, literal(law, slip, alpha), max_relative = 1e-14);
                    assert_eq!(reynolds, slip * d / nu);
                }
            }
            // a lone particle: exactly; a hindered one: to the rounding of α^{−2.7} taken as
            // exp(−2.7 ln α) against `powf` (a few ulp)
            let stokes = 3.0 * std::f64::consts::PI * rho * nu * d;
            assert_eq!(drag_factor(law, d, rho, nu, 0.0, 1.0), stokes);
            assert_relative_eq!(drag_factor(law, d, rho, nu, 0.0, 0.6), stokes * 0.6f64.powf(1.0 - 3.7), max_relative = 1e-15);
        }
        assert!(drag_factor(DragLaw::BrownLawler, d, rho, nu, f64::NAN, 0.8).is_nan(), "a NaN slip is not hidden");
    }

    /// The fluid receives exactly what the update took from the particle: m_p Δu/Δt =
    /// F_d + F_AM + F_pg + V(ρ_p − ρ_c) g (§5.7), whatever the fluid's motion.
    #[test]
    fn forces_of_the_update_balance_the_momentum_change() {
        let fluid = FluidAtParticle {
            density: 998.2,
            kinematic_viscosity: 1.0034e-6,
            velocity: Vec3::new(0.2, -0.1, 0.05),
            material_acceleration: Vec3::new(-1.0, 0.3, 2.0),
            fluid_fraction: 0.8,
        };
        let (d, rho, g, dt) = (0.01, 2650.0, Vec3::new(0.0, 0.0, -9.81), 1e-3);
        let u = Vec3::new(-0.3, 0.4, -0.6);
        let step = fluid_force_step(DragLaw::BrownLawler, u, d, rho, &fluid, g, dt);
        let volume = std::f64::consts::PI * d.powi(3) / 6.0;
        let lhs = rho * volume * (step.velocity - u) / dt;
        let rhs = step.drag + step.fluid_acceleration_force + volume * (rho - fluid.density) * g;
        assert!((lhs - rhs).norm() < 1e-12 * lhs.norm(), "{lhs} vs {rhs}");
    }

    /// A held particle keeps its velocity; at its hindered terminal slip the drag carries its
    /// submerged weight, and at any slip the fluid receives −(F_d + F_AM + F_pg).
    #[test]
    fn a_held_particle_keeps_its_velocity_and_feels_the_drag() {
        let fluid = FluidAtParticle { fluid_fraction: 0.9, ..FluidAtParticle::still(998.2, 1.0034e-6) };
        let u = Vec3::new(0.0, -0.5, 0.0);
        let step = held_fluid_force(DragLaw::BrownLawler, u, 0.01, &fluid);
        assert_eq!(step.velocity, u);
        assert_eq!(step.fluid_acceleration_force, Vec3::zeros());
        assert!((step.drag - step.drag_factor * (-u)).norm() < 1e-15);
        assert!(step.drag.y > 0.0, "the drag opposes the held settling");
        // the fluid receives K u_p − F_fa, minus K u_c implicit: −F_d at u_c = 0
        assert!((step.explicit_feedback() + step.drag).norm() < 1e-15);
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
