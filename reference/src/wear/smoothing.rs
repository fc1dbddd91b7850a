//! Step 2 of wear: the wear rate w on the wall surface (wear-model.md §7.2–7.3).
//!
//! Eq. 4.1 is printed with the wrong signs (§13 row 7); the form consistent with its own
//! solution 4.2 is ∂w/∂t − ∇_s·(κ∇_s w) = −λw + λ Σ_i W_i δ(t − t_i) δ_s(x − x_i), discretised
//! with P1 nodes, lumped mass M and the cotangent stiffness L, implicit Euler (§7.3):
//! (M/Δt + κL + λM) wⁿ⁺¹ = M wⁿ/Δt + λ b, b_j = Σ_i W_i φ_j(x_i)/Δt.
//! L's rows and columns sum to zero (zero flux at the rim), so summing the rows gives the
//! conservation identity Σ Δt ∫wⁿ⁺¹ + ∫w^N/λ = Σ W_i exactly, up to the solve's round-off.

use spillage_model::solver::SolverError;
use spillage_model::wear::surface::WearSurface;

use crate::fluid::linear::SparseMatrix;

/// Solves for the new rate `rate` (in place, from the old one) and returns the depth each node
/// recedes by this step, Δt wⁿ⁺¹ [m].
pub fn smooth(surface: &WearSurface, kappa: f64, lambda: f64, dt: f64, node_volume: &[f64], rate: &mut [f64]) -> Result<Vec<f64>, SolverError> {
    let n = surface.n_nodes;
    let mut matrix = SparseMatrix::new(n);
    let mut rhs = vec![0.0; n];
    for j in 0..n {
        let m = surface.node_area[j];
        matrix.add_diagonal(j, m / dt + lambda * m);
        rhs[j] = m * rate[j] / dt + lambda * node_volume[j] / dt;
    }
    for &(i, j, l) in &surface.stiffness {
        let (i, j) = (i as usize, j as usize);
        matrix.add_off_diagonal(i, j, kappa * l);
        matrix.add_off_diagonal(j, i, kappa * l);
        matrix.add_diagonal(i, -kappa * l);
        matrix.add_diagonal(j, -kappa * l);
    }
    let solution = matrix.solve(&[rhs], "wear smoothing")?.remove(0);
    rate.copy_from_slice(&solution);
    Ok(solution.iter().map(|w| dt * w).collect())
}

/// Without smoothing each node recedes by its deposited volume over its area at once; the rate
/// reported is that depth over Δt.
pub fn direct(surface: &WearSurface, dt: f64, node_volume: &[f64], rate: &mut [f64]) -> Vec<f64> {
    let depth: Vec<f64> = node_volume.iter().zip(&surface.node_area).map(|(v, a)| if *a > 0.0 { v / a } else { 0.0 }).collect();
    for (r, d) in rate.iter_mut().zip(&depth) {
        *r = d / dt;
    }
    depth
}
