//! Convection interpolation: the owner weight λ of u_f = λ u_P + (1 − λ) u_N (spec §8.10).

use spillage_model::fluid::limiter;
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

/// The face's limiter ([`spillage_model::fluid::limiter::limited_linear_v`]) from the upwind
/// cell's gradient.
fn limited_linear_v(link: &Link, flux: f64, u: &[Vec3], grad: &[[Vec3; 3]]) -> f64 {
    let upwind_cell = if flux >= 0.0 { link.owner } else { link.neighbour };
    limiter::limited_linear_v(&u[link.owner], &u[link.neighbour], &directional(&grad[upwind_cell], &link.delta))
}
