//! Hertz–Mindlin–Tsuji soft-sphere contact (fluid-dem-model.md §7.1–§7.4, §7.8).

use nalgebra::Vector3;

type Vec3 = Vector3<f64>;

/// Shear modulus from Young's modulus and Poisson ratio, E = 2G(1+ν) (T3.99).
pub fn shear_modulus(youngs_modulus: f64, poisson_ratio: f64) -> f64 {
    youngs_modulus / (2.0 * (1.0 + poisson_ratio))
}

/// Effective Young's modulus, 1/E* = (1−ν_i²)/E_i + (1−ν_j²)/E_j (T3.98).
pub fn effective_youngs_modulus(e_i: f64, nu_i: f64, e_j: f64, nu_j: f64) -> f64 {
    1.0 / ((1.0 - nu_i * nu_i) / e_i + (1.0 - nu_j * nu_j) / e_j)
}

/// Effective shear modulus, 1/G* = (2−ν_i)/G_i + (2−ν_j)/G_j (T3.98).
pub fn effective_shear_modulus(e_i: f64, nu_i: f64, e_j: f64, nu_j: f64) -> f64 {
    let g_i = shear_modulus(e_i, nu_i);
    let g_j = shear_modulus(e_j, nu_j);
    1.0 / ((2.0 - nu_i) / g_i + (2.0 - nu_j) / g_j)
}

/// Harmonic combination 1/x* = 1/x_i + 1/x_j used for R* and M* (T3.98); an infinite partner
/// (a wall, §7.4) gives x* = x_i.
pub fn harmonic(x_i: f64, x_j: f64) -> f64 {
    if x_j.is_infinite() {
        x_i
    } else {
        1.0 / (1.0 / x_i + 1.0 / x_j)
    }
}

/// Hertz normal stiffness k_n = (4/3) √R* E* [N/m^1.5] (T3.97).
pub fn normal_stiffness(effective_radius: f64, effective_youngs: f64) -> f64 {
    4.0 / 3.0 * effective_radius.sqrt() * effective_youngs
}

/// Mindlin tangential stiffness prefactor k_t = 8 √R* G* (T3.97); the spring is k_t √δ_n.
pub fn tangential_stiffness(effective_radius: f64, effective_shear: f64) -> f64 {
    8.0 * effective_radius.sqrt() * effective_shear
}

/// Damping ratio α_η from the normal restitution coefficient (Antypov & Elliott; T3.101):
/// α_η = −√5 ln ε / √(ln² ε + π²).
///
/// Guards (fluid-dem-model.md §7.5 [R], §11.3): ε ≥ 1 gives 0 (no damping); ε ≤ 0 or NaN (the
/// St → 0 limit of the wet law) gives the limit √5 instead of ln 0.
pub fn damping_ratio(restitution: f64) -> f64 {
    if restitution >= 1.0 {
        return 0.0;
    }
    if !(restitution > 0.0) {
        return 5f64.sqrt();
    }
    let ln_e = restitution.ln();
    if !ln_e.is_finite() {
        return 5f64.sqrt();
    }
    -5f64.sqrt() * ln_e / (ln_e * ln_e + std::f64::consts::PI * std::f64::consts::PI).sqrt()
}

/// Elastic energy stored in a Hertz contact, ∫ k_n δ^{3/2} dδ = (2/5) k_n δ^{5/2} [J].
pub fn hertz_energy(normal_stiffness: f64, overlap: f64) -> f64 {
    0.4 * normal_stiffness * overlap.max(0.0).powf(2.5)
}

/// How the Coulomb limit is tested (fluid-dem-model.md §7.8 step 5, erratum list §10 item 18).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize, serde::Serialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum SlipTest {
    /// The thesis (T3.95): the full trial force (spring + dashpot) against μ_f|F_n|; on slip the
    /// spring overlap δ_t is rescaled so the spring alone carries μ_f|F_n| (recommended, §7.8).
    #[default]
    Thesis,
    /// OpenFOAM: only the spring part k_t√δ_n|δ_t| against μ_f|F_n|; δ_t is reset to 0 on slip.
    Spring,
}

/// Material constants of one contact pair, combined once (T3.97–T3.98, §7.4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairConstants {
    /// Hertz normal stiffness k_n [N/m^1.5].
    pub normal_stiffness: f64,
    /// Mindlin tangential stiffness prefactor k_t [N/m^1.5].
    pub tangential_stiffness: f64,
    /// Effective mass M* [kg].
    pub effective_mass: f64,
    /// √(M* k_n), the damping coefficient's pair factor (T3.100) [kg/(s m^{1/4})].
    pub damping_scale: f64,
    /// Coulomb friction coefficient μ_f.
    pub friction: f64,
    pub slip_test: SlipTest,
}

/// The forces of one contact on particle i, at one DEM sub-step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactForce {
    /// Normal force on i [N].
    pub normal: Vec3,
    /// Tangential force on i [N], applied at the contact point.
    pub tangential: Vec3,
    /// True when the Coulomb limit capped the tangential force.
    pub sliding: bool,
}

/// Hertz–Mindlin–Tsuji force on particle i (T3.94–T3.96, algorithm of §7.8 steps 2, 4, 5, 8).
///
/// * `normal`: unit vector from i towards its partner.
/// * `overlap`: δ_n > 0.
/// * `relative_velocity`: v_rel at the contact point (i minus partner, including spin).
/// * `tangential_overlap`: δ_t, updated in place (+= u_t Δt, projected into the current tangent
///   plane with its length kept, and rescaled/reset on slip).
/// * `damping_ratio`: α_η of this contact (fixed at first touch, §7.5 [R]).
pub fn hertz_mindlin_force(
    constants: &PairConstants,
    damping_ratio: f64,
    normal: Vec3,
    overlap: f64,
    relative_velocity: Vec3,
    tangential_overlap: &mut Vec3,
    dt: f64,
) -> ContactForce {
    let approach_speed = relative_velocity.dot(&normal);
    let u_n = normal * approach_speed;
    let u_t = relative_velocity - u_n;
    // δ^{1/2}, δ^{3/2} and δ^{1/4} from one square root (two `powf` cost as much as the rest of
    // the contact)
    let root = overlap.max(0.0).sqrt();
    // (T3.100): η = α_η √(M* k_n) δ_n^{1/4}, the same in both directions (§7.1).
    let eta = damping_ratio * constants.damping_scale * root.sqrt();
    // (T3.94): F_n = −k_n δ^{3/2} n − η u_n, not clipped at zero (the damping law T3.101 is exact
    // only for the unclipped force; particle-verification.md §7 item 10).
    let f_n = -constants.normal_stiffness * (overlap * root) * normal - eta * u_n;

    // §7.8 step 8: keep δ_t in the current tangent plane (rotate, keeping its length).
    let old_length_sq = tangential_overlap.norm_squared();
    let mut in_plane = *tangential_overlap - normal * tangential_overlap.dot(&normal);
    let in_plane_length_sq = in_plane.norm_squared();
    if in_plane_length_sq > 0.0 {
        in_plane *= (old_length_sq / in_plane_length_sq).sqrt();
    }
    // (T3.96): accumulate the tangential displacement.
    *tangential_overlap = in_plane + u_t * dt;

    let spring = constants.tangential_stiffness * root;
    let spring_force = -spring * *tangential_overlap;
    let trial = spring_force - eta * u_t;
    // the Coulomb test on squares: the square roots are needed only when the contact slips
    let friction = constants.friction;
    let limit_sq = friction * friction * f_n.norm_squared();
    let exceeds = match constants.slip_test {
        SlipTest::Thesis => trial.norm_squared() > limit_sq,
        SlipTest::Spring => spring_force.norm_squared() > limit_sq,
    };
    if !exceeds {
        return ContactForce { normal: f_n, tangential: trial, sliding: false };
    }
    let limit = friction * f_n.norm();
    // (T3.95) slip branch: |F_t| = μ_f|F_n| opposing the motion. The direction is that of the
    // trial force, which is along −u_t when sliding and stays defined when u_t → 0 (§11.3).
    let direction = if trial.norm() > 0.0 { trial / trial.norm() } else { Vec3::zeros() };
    let tangential = limit * direction;
    match constants.slip_test {
        SlipTest::Thesis => {
            let length = tangential_overlap.norm();
            if spring > 0.0 && length > 0.0 && spring * length > limit {
                *tangential_overlap *= limit / (spring * length);
            }
        }
        SlipTest::Spring => *tangential_overlap = Vec3::zeros(),
    }
    ContactForce { normal: f_n, tangential, sliding: true }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// particle-verification.md §8 check 23 (two glass spheres, R = 5 mm).
    #[test]
    fn effective_properties_of_two_glass_spheres() {
        let (e, nu, r) = (60e9, 0.23, 0.005);
        let e_star = effective_youngs_modulus(e, nu, e, nu);
        let g_star = effective_shear_modulus(e, nu, e, nu);
        let r_star = harmonic(r, r);
        assert_relative_eq!(e_star, 3.16756e10, max_relative = 1e-5);
        assert_relative_eq!(shear_modulus(e, nu), 2.43902e10, max_relative = 1e-5);
        assert_relative_eq!(g_star, 6.88990e9, max_relative = 1e-5);
        assert_relative_eq!(normal_stiffness(r_star, e_star), 2.11171e9, max_relative = 1e-5);
        assert_relative_eq!(tangential_stiffness(r_star, g_star), 2.75596e9, max_relative = 1e-5);
    }

    /// particle-verification.md §8 check 17 (table printed to 6 decimals, hence 2.5e-5).
    #[test]
    fn damping_ratio_matches_spec_table() {
        for (e, alpha) in [(1.0, 0.0), (0.97, 0.021679), (0.95, 0.036504), (0.82, 0.140969), (0.8, 0.158426), (0.5, 0.481769)] {
            assert_relative_eq!(damping_ratio(e), alpha, max_relative = 2.5e-5, epsilon = 1e-12);
        }
        assert_relative_eq!(damping_ratio(0.0), 5f64.sqrt());
        assert_relative_eq!(damping_ratio(f64::NAN), 5f64.sqrt());
        assert!((damping_ratio(1e-300) - 5f64.sqrt()).abs() < 1e-2);
    }

    #[test]
    fn coulomb_limit_caps_the_tangential_force() {
        let constants = PairConstants {
            normal_stiffness: 1e6,
            tangential_stiffness: 1e6,
            effective_mass: 1.0,
            damping_scale: 1e3,
            friction: 0.1,
            slip_test: SlipTest::Thesis,
        };
        let n = Vec3::new(0.0, 0.0, -1.0);
        let mut delta_t = Vec3::zeros();
        let f = hertz_mindlin_force(&constants, 0.0, n, 1e-4, Vec3::new(10.0, 0.0, 0.0), &mut delta_t, 1e-3);
        assert!(f.sliding);
        assert_relative_eq!(f.tangential.norm(), 0.1 * f.normal.norm(), max_relative = 1e-12);
        assert!(f.tangential.x < 0.0);
        assert_relative_eq!(1e6 * 1e-2 * delta_t.norm(), 0.1 * f.normal.norm(), max_relative = 1e-12);
    }
}
