//! Standard wall functions (spec fluid-dem-model.md §3.2 "Wall treatment" leaves them open; the
//! thesis' OpenFOAM setup uses `nutkWallFunction` and `epsilonWallFunction`, which these follow):
//! the log law u⁺ = ln(E y⁺)/κ, with y⁺ from the turbulent kinetic energy of the wall cell.
//!
//! For a wall face at normal distance y from the centre of its cell, with k_P in that cell:
//!   y⁺ = C_μ^¼ √k_P y/ν,
//!   ν_t,w = ν (κ y⁺/ln(E y⁺) − 1) above the laminar switch y⁺_lam, 0 below (`nutkWallFunction`);
//!   ε_P = C_μ^¾ k_P^{3/2}/(κ y) and G_P = (ν + ν_t,w) |u_P − u_w|/y · C_μ^¼ √k_P/(κ y)
//!   (`epsilonWallFunction`, its default without the low-Re correction), averaged over the wall
//!   faces of a cell with several.
//! The wall shear stress of the momentum equation is then (ν + ν_t,w)(u_P − u_w)/y = u_τ² when
//! k_P = u_τ²/√C_μ (local equilibrium) and u_P follows the log law at y⁺.

use super::settings::RealizableConstants;

/// The y⁺ where the viscous sublayer u⁺ = y⁺ meets the log law: y⁺ = ln(E y⁺)/κ (11.53 for
/// κ = 0.41, E = 9.8), by the fixed-point iteration OpenFOAM uses (10 sweeps from 11).
pub fn y_plus_laminar(c: &RealizableConstants) -> f64 {
    let mut y = 11.0;
    for _ in 0..10 {
        y = (c.wall_e * y).max(1.0).ln() / c.kappa;
    }
    y
}

/// y⁺ of a wall face: C_μ^¼ √k_P y/ν.
pub fn y_plus(k: f64, y: f64, nu: f64, c: &RealizableConstants) -> f64 {
    c.c_mu.powf(0.25) * k.max(0.0).sqrt() * y / nu
}

/// ν_t,w of the wall face (`nutkWallFunction`): ν(κy⁺/ln(Ey⁺) − 1) for y⁺ > y⁺_lam, else 0.
pub fn wall_eddy_viscosity(y_plus: f64, nu: f64, y_plus_lam: f64, c: &RealizableConstants) -> f64 {
    if y_plus > y_plus_lam {
        nu * (c.kappa * y_plus / (c.wall_e * y_plus).ln() - 1.0)
    } else {
        0.0
    }
}

/// ε in a wall cell from one of its wall faces: C_μ^¾ k^{3/2}/(κ y).
pub fn wall_cell_dissipation(k: f64, y: f64, c: &RealizableConstants) -> f64 {
    c.c_mu.powf(0.75) * k.max(0.0).powf(1.5) / (c.kappa * y)
}

/// Production of k in a wall cell from one of its wall faces:
/// (ν + ν_t,w)|u_P − u_w|/y · C_μ^¼ √k/(κ y).
pub fn wall_cell_production(nu: f64, nu_t_wall: f64, slip_speed: f64, k: f64, y: f64, c: &RealizableConstants) -> f64 {
    (nu + nu_t_wall) * slip_speed / y * c.c_mu.powf(0.25) * k.max(0.0).sqrt() / (c.kappa * y)
}

/// The `y_plus_<patch>` diagnostic name of each wall condition (per condition index, from
/// `Conditions::wall_patch_names`). Report names are `&'static str`; these few live as long as
/// the program.
pub fn y_plus_names(wall_patches: Vec<Option<String>>) -> Vec<Option<&'static str>> {
    wall_patches.into_iter().map(|p| p.map(|name| &*Box::leak(format!("y_plus_{name}").into_boxed_str()))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn laminar_switch_solves_its_equation() {
        let c = RealizableConstants::default();
        let y = y_plus_laminar(&c);
        // the fixed point of y = ln(Ey)/κ; 10 sweeps converge to ~1e-6 (contraction 1/(κy) ≈ 0.2)
        assert!((y - (c.wall_e * y).ln() / c.kappa).abs() < 1e-5, "{y}");
        assert!((y - 11.53).abs() < 0.01, "{y}");
    }

    #[test]
    fn equilibrium_wall_shear_is_u_tau_squared() {
        // a wall cell in the log layer: k = u_τ²/√C_μ, u_P = u_τ ln(E y⁺)/κ
        let c = RealizableConstants::default();
        let (u_tau, nu, y) = (0.05, 1e-6, 2e-3);
        let k = u_tau * u_tau / c.c_mu.sqrt();
        let yp = y_plus(k, y, nu, &c);
        assert!((yp - u_tau * y / nu).abs() < 1e-9 * yp);
        let u_p = u_tau * (c.wall_e * yp).ln() / c.kappa;
        let nu_w = wall_eddy_viscosity(yp, nu, y_plus_laminar(&c), &c);
        let tau = (nu + nu_w) * u_p / y;
        assert!((tau - u_tau * u_tau).abs() < 1e-12, "{tau}");
        // and production = dissipation in that cell (local equilibrium): G = u_τ³/(κy) = ε
        let g = wall_cell_production(nu, nu_w, u_p, k, y, &c);
        let eps = wall_cell_dissipation(k, y, &c);
        assert!((g - eps).abs() < 1e-12 * eps, "{g} {eps}");
        assert!((eps - u_tau.powi(3) / (c.kappa * y)).abs() < 1e-12 * eps);
    }
}
