//! Convection interpolation: the owner weight λ of u_f = λ u_P + (1 − λ) u_N (spec §8.10).

use spillage_model::fluid::settings::ConvectionScheme;
use spillage_model::mesh::Vec3;

use super::geometry::Link;
use super::gradient::directional;

/// Owner weight of the face value for a face with relative flux `flux` (owner → neighbour).
/// `grad` are the cell gradients of the latest velocity iterate (used by the limiter only).
pub fn convection_weight(scheme: ConvectionScheme, linear_fraction: f64, link: &Link, flux: f64, u: &[Vec3], grad: &[[Vec3; 3]]) -> f64 {
    let upwind = if flux >= 0.0 { 1.0 } else { 0.0 };
    match scheme {
        ConvectionScheme::Linear => link.weight,
        ConvectionScheme::Upwind => upwind,
        ConvectionScheme::Blended => linear_fraction * link.weight + (1.0 - linear_fraction) * upwind,
        ConvectionScheme::LimitedLinear => {
            let limiter = limited_linear_v(link, flux, u, grad);
            limiter * link.weight + (1.0 - limiter) * upwind
        }
    }
}

/// OpenFOAM's `limitedLinearV 1` limiter (NVDVTVDV r-function with the limitedLinear limiter
/// ψ = max(min(2r, 1), 0)), one limiter per face for the whole vector, taken in the direction
/// of the face difference u_N − u_P.
fn limited_linear_v(link: &Link, flux: f64, u: &[Vec3], grad: &[[Vec3; 3]]) -> f64 {
    let gradf = u[link.neighbour] - u[link.owner];
    let upwind_cell = if flux >= 0.0 { link.owner } else { link.neighbour };
    let gradcf = gradf.dot(&directional(&grad[upwind_cell], &link.delta));
    let gradf2 = gradf.norm_squared();
    let r = if gradcf.abs() >= 1000.0 * gradf2 { 2.0 * 1000.0 * gradcf.signum() * gradf2.signum() - 1.0 } else { 2.0 * gradcf / gradf2 - 1.0 };
    (2.0 * r).clamp(0.0, 1.0)
}
