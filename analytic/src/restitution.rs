//! Wet (viscous) normal restitution: Legendre et al. (2006) and the rigid-sphere lubrication-only
//! limit.
//!
//! fluid-dem-model.md §7.5 (thesis Eqs. 3.103–3.104) and particle-verification.md §1.5, §5.1–5.3,
//! §8 checks 15, 16 and 27.

use serde::Serialize;

use crate::error::{in_closed, non_negative, positive, Result};

/// Legendre coefficient β_L = 35 (Eq. 3.103). Unrelated to the Di Felice or the spillage-model β.
pub const LEGENDRE_COEFFICIENT: f64 = 35.0;

/// Impact Stokes number with added mass, St_AM = (ρ_p/ρ_f + C_AM) u_n,in d_p/(9ν) (Eq. 3.104).
pub fn stokes_number_with_added_mass(
    particle_density: f64,
    fluid_density: f64,
    normal_speed: f64,
    diameter: f64,
    kinematic_viscosity: f64,
    added_mass_coefficient: f64,
) -> Result<f64> {
    positive("particle_density", particle_density)?;
    positive("fluid_density", fluid_density)?;
    non_negative("normal_speed", normal_speed)?;
    positive("diameter", diameter)?;
    positive("kinematic_viscosity", kinematic_viscosity)?;
    non_negative("added_mass_coefficient", added_mass_coefficient)?;
    Ok((particle_density / fluid_density + added_mass_coefficient) * normal_speed * diameter / (9.0 * kinematic_viscosity))
}

/// Gondret/Joseph Stokes number without added mass, St = ρ_p u d/(9μ) = (ρ_p/ρ_f) Re/9
/// (particle-verification.md §1.5: the one Table 7.1 reports, not the one Eq. 3.103 uses).
pub fn stokes_number_without_added_mass(particle_density: f64, fluid_density: f64, normal_speed: f64, diameter: f64, kinematic_viscosity: f64) -> Result<f64> {
    stokes_number_with_added_mass(particle_density, fluid_density, normal_speed, diameter, kinematic_viscosity, 0.0)
}

/// Legendre wet restitution ε_wet = ε_dry exp(−35/St_AM) (Eq. 3.103). St = 0 gives 0 (the limit);
/// the result stays in [0, ε_dry] as fluid-dem-model.md §7.5 [R] asks.
pub fn legendre_wet_restitution(dry_restitution: f64, stokes: f64) -> Result<f64> {
    in_closed("dry_restitution", dry_restitution, 0.0, 1.0, "in [0, 1]")?;
    non_negative("stokes", stokes)?;
    if stokes == 0.0 {
        return Ok(0.0);
    }
    Ok(dry_restitution * (-LEGENDRE_COEFFICIENT / stokes).exp())
}

/// Outcome of the lubrication-only model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LubricationImpact {
    /// Speed at solid contact over the speed far from the wall (0 if the sphere never touches).
    pub contact_speed_ratio: f64,
    /// Rebound speed far from the wall over the approach speed far from the wall.
    pub restitution: f64,
}

/// Rigid-sphere lubrication-only limit (Davis, Serayssol & Hinch 1986; Joseph et al. 2001; not in
/// the spec, added as the classical bound of the wet-restitution law): with only the lubrication
/// force F = 6πμa² v/h acting between gap h₀ and the roughness height h_r, and St = m v₀/(6πμa²)
/// (= ρ_p v₀ d/(9μ), i.e. the Stokes number of Eq. 3.104 when m includes added mass),
/// momentum gives v(h) = v₀ [1 − ln(h₀/h)/St]. The sphere touches with v₀(1 − L/St),
/// L = ln(h₀/h_r), rebounds with ε_dry times that, and loses v₀ L/St again on the way out:
/// ε = max(0, ε_dry (1 − L/St) − L/St); ε = 0 if St ≤ L (it stops before touching).
pub fn lubrication_restitution(dry_restitution: f64, stokes: f64, log_gap_ratio: f64) -> Result<LubricationImpact> {
    in_closed("dry_restitution", dry_restitution, 0.0, 1.0, "in [0, 1]")?;
    non_negative("stokes", stokes)?;
    non_negative("log_gap_ratio", log_gap_ratio)?;
    if stokes <= log_gap_ratio {
        return Ok(LubricationImpact { contact_speed_ratio: 0.0, restitution: 0.0 });
    }
    let loss = log_gap_ratio / stokes;
    let contact = 1.0 - loss;
    Ok(LubricationImpact { contact_speed_ratio: contact, restitution: (dry_restitution * contact - loss).max(0.0) })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn legendre_ratio_matches_spec_at_several_stokes_numbers() {
        // particle-verification.md §8 check 15 (printed to 6 decimals).
        let cases = [(10.0, 0.030197), (35.0, 0.367879), (100.0, 0.704688), (152.0, 0.794325), (360.0, 0.907354), (1000.0, 0.965605), (1e4, 0.996506)];
        for (st, ratio) in cases {
            let got = legendre_wet_restitution(1.0, st).unwrap();
            assert!((got - ratio).abs() < 5e-7, "St={st}: {got}");
        }
        // U-28: St = 35 with ε_dry = 0.97 gives 0.97/e = 0.356843; St → ∞ gives ε_dry.
        assert!((legendre_wet_restitution(0.97, 35.0).unwrap() - 0.356843).abs() < 5e-7);
        assert!((legendre_wet_restitution(0.97, 1e12).unwrap() - 0.97).abs() < 1e-10);
        assert_eq!(legendre_wet_restitution(0.97, 0.0).unwrap(), 0.0);
        // Check 27: C3 wet restitution from the tabulated St (360, 1064).
        assert!((legendre_wet_restitution(0.97, 360.0).unwrap() - 0.880134).abs() < 5e-7);
        assert!((legendre_wet_restitution(0.97, 1064.0).unwrap() - 0.938611).abs() < 5e-7);
    }

    #[test]
    fn added_mass_stokes_numbers_match_spec() {
        // Check 16 / U-28: steel in silicone oil (Table 7.1): Re = 162.69, St_AM = 159.838,
        // ε_wet = 0.77924; St without added mass 150.8.
        let st_am = stokes_number_with_added_mass(7800.0, 935.0, 0.58, 3e-3, 1.06952e-5, 0.5).unwrap();
        assert!((st_am - 159.838).abs() < 5e-4, "{st_am}");
        let re: f64 = 0.58 * 3e-3 / 1.06952e-5;
        assert!((re - 162.69).abs() < 5e-3);
        let st = stokes_number_without_added_mass(7800.0, 935.0, 0.58, 3e-3, 1.06952e-5).unwrap();
        assert!((st - 150.8).abs() < 0.05);
        assert!((legendre_wet_restitution(0.97, st_am).unwrap() - 0.77924).abs() < 5e-6);
        // §5.3: raw C3 inputs give St_AM = 352.5 (glass) and 1050.0 (steel).
        let glass = stokes_number_with_added_mass(2540.0, 998.0, 0.37, 12.7e-3, 4.51e-6, 0.5).unwrap();
        let steel = stokes_number_with_added_mass(7780.0, 998.0, 0.27, 12.7e-3, 3.01e-6, 0.5).unwrap();
        assert!((glass - 352.5).abs() < 0.05 && (steel - 1050.0).abs() < 0.05, "{glass} {steel}");
        // §1.5: glass in water St_AM/St = (2.54 + 0.5)/2.54 = 1.197.
        let ratio = stokes_number_with_added_mass(2540.0, 1000.0, 1.0, 1e-3, 1e-6, 0.5).unwrap()
            / stokes_number_without_added_mass(2540.0, 1000.0, 1.0, 1e-3, 1e-6).unwrap();
        assert!((ratio - 1.197).abs() < 5e-4);
    }

    #[test]
    fn lubrication_limit_matches_direct_integration() {
        // Integrate the equation of motion in time, m dv/dt = −6πμa² v/h, nondimensionalised
        // with m v₀/(6πμa²) = St, h₀ = 1, v₀ = 1: dh/dt = −v, dv/dt = −v/(St h). Approach until
        // h = h_r, bounce with ε_dry, then move out (dh/dt = +v) until h = h₀.
        use crate::ode::rk4_until_event;
        let (e_dry, st, hr): (f64, f64, f64) = (0.9, 30.0, 1e-2);
        let log_ratio = (1.0 / hr).ln();
        let approach = move |_t: f64, y: &[f64; 2]| [-y[1], -y[1] / (st * y[0])];
        let hit = rk4_until_event(&approach, 0.0, [1.0, 1.0], 1e-5, 10.0, |y| y[0] - hr, |y| y[1]).unwrap();
        let contact = hit.state[1];
        let rebound = move |_t: f64, y: &[f64; 2]| [y[1], -y[1] / (st * y[0])];
        let out = rk4_until_event(&rebound, 0.0, [hr, e_dry * contact], 1e-5, 10.0, |y| 1.0 - y[0], |y| y[1]).unwrap();
        let model = lubrication_restitution(e_dry, st, log_ratio).unwrap();
        // RK4 at Δt = 1e-5 with gap scales ≥ 1e-2: errors ~1e-12; event location to round-off.
        assert!((model.contact_speed_ratio - contact).abs() < 1e-9, "{contact}");
        assert!((model.restitution - out.state[1]).abs() < 1e-9, "{}", out.state[1]);
        // Below St = L the sphere never touches; between L and L(1+ε)/ε it touches but cannot
        // escape the lubrication layer.
        assert_eq!(lubrication_restitution(e_dry, 0.9 * log_ratio, log_ratio).unwrap().restitution, 0.0);
        let critical = log_ratio * (1.0 + e_dry) / e_dry;
        assert_eq!(lubrication_restitution(e_dry, 0.999 * critical, log_ratio).unwrap().restitution, 0.0);
        assert!(lubrication_restitution(e_dry, 1.001 * critical, log_ratio).unwrap().restitution > 0.0);
        // Large-St limit: ε → ε_dry.
        assert!((lubrication_restitution(e_dry, 1e12, log_ratio).unwrap().restitution - e_dry).abs() < 1e-9);
    }

    #[test]
    fn bad_inputs_are_rejected() {
        assert!(legendre_wet_restitution(1.1, 10.0).is_err());
        assert!(legendre_wet_restitution(0.9, -1.0).is_err());
        assert!(stokes_number_with_added_mass(2500.0, 0.0, 1.0, 1e-3, 1e-6, 0.5).is_err());
    }
}
