//! Wet normal restitution (Legendre et al. 2006; fluid-dem-model.md §7.5, T3.103–T3.104).

/// Added-mass coefficient C_AM = 0.5 (T3.43).
pub const ADDED_MASS_COEFFICIENT: f64 = 0.5;

/// Legendre coefficient β = 35 in (T3.103).
pub const LEGENDRE_BETA: f64 = 35.0;

/// Stokes number with added mass, St_AM = (ρ_p/ρ_f + C_AM) u_n,in d_p / (9ν) (T3.104).
pub fn stokes_number(particle_density: f64, fluid_density: f64, approach_speed: f64, diameter: f64, kinematic_viscosity: f64) -> f64 {
    (particle_density / fluid_density + ADDED_MASS_COEFFICIENT) * approach_speed.abs() * diameter / (9.0 * kinematic_viscosity)
}

/// Wet restitution ε_wet = ε_dry exp(−35/St_AM) (T3.103).
///
/// Guards (§7.5 [R], §11.3): St ≤ 0 or NaN (a contact formed with no approach speed) gives 0;
/// the result is clamped to [0, ε_dry]. The damping law maps 0 to its limit √5
/// ([`super::contact::damping_ratio`]).
pub fn wet_restitution(dry_restitution: f64, stokes_number: f64) -> f64 {
    if !(stokes_number > 0.0) {
        return 0.0;
    }
    (dry_restitution * (-LEGENDRE_BETA / stokes_number).exp()).clamp(0.0, dry_restitution)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// particle-verification.md §8 check 15 (ratios ε_wet/ε_dry).
    #[test]
    fn legendre_ratios() {
        for (st, ratio) in [(10.0, 0.030197), (35.0, 0.367879), (100.0, 0.704688), (152.0, 0.794325), (360.0, 0.907354), (1000.0, 0.965605), (1e4, 0.996506)] {
            assert_relative_eq!(wet_restitution(1.0, st), ratio, max_relative = 2e-5);
        }
        assert_eq!(wet_restitution(0.97, 0.0), 0.0);
        assert_eq!(wet_restitution(0.97, f64::NAN), 0.0);
        assert_eq!(wet_restitution(0.97, 1e-3), 0.0);
    }

    /// particle-verification.md §8 check 16 (steel in silicone oil, Table 7.1).
    #[test]
    fn stokes_number_of_gondret_steel() {
        assert_relative_eq!(stokes_number(7800.0, 935.0, 0.58, 0.003, 1.06952e-5), 159.84, max_relative = 1e-3);
    }
}
