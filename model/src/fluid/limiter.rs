//! The limiter of the `limited_linear` convection scheme (spec fluid-dem-model.md §8.10),
//! OpenFOAM's `limitedLinearV 1`: one function for both fluid solvers and the rotor's torque
//! budget. When it is evaluated (every outer iteration or once per step) is
//! [`super::settings::LimiterUpdate`].

use crate::mesh::Vec3;

/// A face whose velocity difference is at most this fraction of its larger velocity is linear
/// ([`limited_linear_v`]).
pub const UNIFORM_FACE: f64 = 1e-6;

/// The limiter ψ ∈ [0, 1] of a face (1: linear, 0: upwind): the NVDVTVDV r-function with the
/// limitedLinear limiter ψ = max(min(2r, 1), 0), one limiter per face for the whole vector, taken
/// in the direction of the face difference `gradf` = u_N − u_P. `gradcf` is gradf·(d·∇u) with the
/// upwind cell's gradient ∇u along the owner-to-neighbour vector d; `scale2` is the larger
/// |u|² of the face's two cells.
///
/// A face whose difference is below [`UNIFORM_FACE`] of that scale is linear (ψ = 1) whatever r
/// says. There r is a ratio of differences the solvers' round-off moves, and with it the
/// face's share of its cells' diagonal coefficients, ±½ of the flux, which the pressure
/// equation divides by; the face value itself differs between linear and upwind by less than
/// 5e-7 of the velocity. Measured in the Coriolis arm (water alone, limiter once per step,
/// tests/rotating_frame.rs): without the cut the two solvers drifted apart to 1.2e-6 of the
/// fields in 30 steps, with faces below 1e-7 cut to 2.5e-7, below 1e-6 to 1.6e-11.
#[inline]
pub fn limited_linear_v(gradf: &Vec3, gradcf: f64, scale2: f64) -> f64 {
    let gradf2 = gradf.norm_squared();
    if gradf2 <= UNIFORM_FACE * UNIFORM_FACE * scale2 {
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
        let d = Vec3::new(0.3, -0.4, 0.0); // |d|² = 0.25
        assert_eq!(limited_linear_v(&d, 0.25, 1.0), 1.0);
        assert_eq!(limited_linear_v(&d, 0.125, 1.0), 0.0);
        assert_eq!(limited_linear_v(&d, -0.1, 1.0), 0.0);
        assert!((limited_linear_v(&d, 0.25 * 0.625, 1.0) - 0.5).abs() < 1e-15);
        assert_eq!(limited_linear_v(&Vec3::zeros(), -1e-3, 0.0), 1.0);
        let small = d * (0.9 * UNIFORM_FACE / 0.5); // |small| = 0.9 UNIFORM_FACE
        assert_eq!(limited_linear_v(&small, -1.0, 1.0), 1.0);
        let above = d * (1.1 * UNIFORM_FACE / 0.5);
        assert_eq!(limited_linear_v(&above, -1.0, 1.0), 0.0);
    }
}
