//! The limiter of the `limited_linear` convection scheme (spec fluid-dem-model.md §8.10),
//! OpenFOAM's `limitedLinearV 1`: one function for both fluid solvers and the rotor's torque
//! budget. When it is evaluated (every outer iteration or once per step) is
//! [`super::settings::LimiterUpdate`].

use crate::mesh::Vec3;

/// The limiter ψ ∈ [0, 1] of a face (1: linear, 0: upwind): the NVDVTVDV r-function with the
/// limitedLinear limiter ψ = max(min(2r, 1), 0), one limiter per face for the whole vector, taken
/// in the direction of the face difference `gradf` = u_N − u_P. `gradcf` is gradf·(d·∇u) with the
/// upwind cell's gradient ∇u along the owner-to-neighbour vector d.
#[inline]
pub fn limited_linear_v(gradf: &Vec3, gradcf: f64) -> f64 {
    let gradf2 = gradf.norm_squared();
    let r = if gradcf.abs() >= 1000.0 * gradf2 { 2.0 * 1000.0 * gradcf.signum() * gradf2.signum() - 1.0 } else { 2.0 * gradcf / gradf2 - 1.0 };
    (2.0 * r).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ψ = 2r clamped to [0, 1] with r = 2 gradcf/|gradf|² − 1: a linear profile (gradcf =
    /// |gradf|², r = 1) is linear, an extremum (gradcf ≤ ½|gradf|², r ≤ 0) upwind, and r = ¼
    /// half-way; a face without difference takes the sign of gradcf (OpenFOAM's r of 1999).
    #[test]
    fn limiter_values() {
        let d = Vec3::new(0.3, -0.4, 0.0); // |d|² = 0.25
        assert_eq!(limited_linear_v(&d, 0.25), 1.0);
        assert_eq!(limited_linear_v(&d, 0.125), 0.0);
        assert_eq!(limited_linear_v(&d, -0.1), 0.0);
        assert!((limited_linear_v(&d, 0.25 * 0.625) - 0.5).abs() < 1e-15);
        assert_eq!(limited_linear_v(&Vec3::zeros(), 1e-3), 1.0);
        assert_eq!(limited_linear_v(&Vec3::zeros(), -1e-3), 0.0);
    }
}
