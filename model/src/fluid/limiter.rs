//! The limiter of the `limited_linear` convection scheme (spec fluid-dem-model.md §8.10),
//! OpenFOAM's `limitedLinearV 1`: one function for both fluid solvers and the rotor's torque
//! budget. When it is evaluated (every outer iteration or once per step) is
//! [`super::settings::LimiterUpdate`].

use crate::mesh::Vec3;

/// A face whose velocity difference is at most this fraction of its larger velocity is linear
/// ([`limited_linear_v`]).
pub const UNIFORM_FACE: f64 = 1e-6;

/// The limiter ψ ∈ [0, 1] of a face between cells P and N (1: linear, 0: upwind): the NVDVTVDV
/// r-function with the limitedLinear limiter ψ = max(min(2r, 1), 0), one limiter per face for the
/// whole vector, taken in the direction of the face difference u_N − u_P. `upwind_along_d` is
/// d·∇u of the upwind cell's gradient along the owner-to-neighbour vector d.
///
/// A face whose difference is below [`UNIFORM_FACE`] of the larger of |u_P|, |u_N| is linear
/// (ψ = 1) whatever r says. There r is a ratio of differences the solvers' round-off moves, and
/// with it the face's share of its cells' diagonal coefficients, ±½ of the flux, which the
/// pressure equation divides by; the face value itself differs between linear and upwind by less
/// than 5e-7 of the velocity. Measured in the Coriolis arm (water alone, limiter once per step,
/// tests/rotating_frame.rs): without the cut the two solvers drifted apart to 1.2e-6 of the
/// fields in 30 steps, with faces below 1e-7 cut to 2.5e-7, below 1e-6 to 1.6e-11.
#[inline]
pub fn limited_linear_v(u_p: &Vec3, u_n: &Vec3, upwind_along_d: &Vec3) -> f64 {
    let gradf = u_n - u_p;
    let gradcf = gradf.dot(upwind_along_d);
    let gradf2 = gradf.norm_squared();
    if gradf2 <= UNIFORM_FACE * UNIFORM_FACE * u_p.norm_squared().max(u_n.norm_squared()) {
        return 1.0;
    }
    let r = if gradcf.abs() >= 1000.0 * gradf2 { 2.0 * 1000.0 * gradcf.signum() * gradf2.signum() - 1.0 } else { 2.0 * gradcf / gradf2 - 1.0 };
    (2.0 * r).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ψ = 2r clamped to [0, 1] with r = 2 gradcf/|gradf|² − 1: a linear profile (gradcf =
    /// |gradf|², r = 1) is linear, an extremum (gradcf ≤ ½|gradf|², r ≤ 0) upwind, and r = ¼
    /// half-way; a face whose difference is below UNIFORM_FACE of its velocity is linear, even
    /// where r would make it upwind, and one just above it is limited.
    #[test]
    fn limiter_values() {
        // u_P = 0, |u_N| = 1: gradf = u_N, |gradf|² = 1, gradcf = u_N·g
        let (zero, u_n) = (Vec3::zeros(), Vec3::new(0.6, -0.8, 0.0));
        let along = |gradcf: f64| u_n * gradcf;
        assert_eq!(limited_linear_v(&zero, &u_n, &along(1.0)), 1.0);
        assert_eq!(limited_linear_v(&zero, &u_n, &along(0.5)), 0.0);
        assert_eq!(limited_linear_v(&zero, &u_n, &along(-0.4)), 0.0);
        assert!((limited_linear_v(&zero, &u_n, &along(0.625)) - 0.5).abs() < 1e-15);
        assert_eq!(limited_linear_v(&zero, &zero, &along(-1e-3)), 1.0);
        // u_P = u_N + a difference 0.9 (1.1) × UNIFORM_FACE of |u_P| ≈ 1 in the direction that
        // makes r < 0
        let small = u_n + u_n * (0.9 * UNIFORM_FACE);
        assert_eq!(limited_linear_v(&small, &u_n, &u_n), 1.0);
        let above = u_n + u_n * (1.1 * UNIFORM_FACE);
        assert_eq!(limited_linear_v(&above, &u_n, &u_n), 0.0);
    }
}
