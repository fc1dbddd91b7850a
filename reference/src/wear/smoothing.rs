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

#[cfg(test)]
mod tests {
    use super::*;
    use spillage_model::walls::geometry::plane;
    use spillage_model::walls::state::Vec3;

    /// A strip along x, `cells` quads long, one quad across.
    fn strip(length: f64, width: f64, cells: u32) -> (WearSurface, Vec<Vec3>) {
        let mesh = plane(Vec3::zeros(), Vec3::z(), [length, width], [cells, 1], Some(Vec3::x()));
        let surface = WearSurface::new(&mesh.vertices, &mesh.triangles);
        let nodes = surface.nodes(&mesh.vertices);
        (surface, nodes)
    }

    #[test]
    fn one_impact_decays_as_the_discrete_damping_and_conserves_its_volume() {
        // A20/A21 in discrete form: after an impact of volume W at step 1, ∫w dA =
        // λW/(1 + λΔt)ⁿ at step n (implicit Euler of dS/dt = −λS + λWδ), and
        // Σ Δt ∫wⁿ + ∫w^N/λ = W at every N (§7.3 identity)
        let (surface, _) = strip(0.2, 0.02, 40);
        let (kappa, lambda, dt, volume) = (1e-3, 100.0, 1e-3, 2.5e-9);
        let mut rate = vec![0.0; surface.n_nodes];
        let mut source = vec![0.0; surface.n_nodes];
        source[7] = 0.3 * volume;
        source[8] = 0.7 * volume;
        let nothing = vec![0.0; surface.n_nodes];
        let mut receded = 0.0;
        for n in 1..=200 {
            let depth = smooth(&surface, kappa, lambda, dt, if n == 1 { &source } else { &nothing }, &mut rate).unwrap();
            let integral: f64 = rate.iter().zip(&surface.node_area).map(|(w, a)| w * a).sum();
            let expected = lambda * volume / (1.0 + lambda * dt).powi(n);
            // direct LU solve: round-off only
            assert!((integral - expected).abs() <= 1e-12 * expected, "step {n}: {integral:e} vs {expected:e}");
            receded += depth.iter().zip(&surface.node_area).map(|(d, a)| d * a).sum::<f64>();
            let identity = receded + integral / lambda;
            assert!((identity - volume).abs() <= 1e-13 * volume, "step {n}: {identity:e} vs {volume:e}");
        }
    }

    /// Largest relative error of the steady profile of a line source across a strip against
    /// A23, w(x) = q/(2ℓ) e^(−|x|/ℓ), over |x| ≤ 3ℓ, with `per_length` cells per ℓ.
    fn steady_profile_error(per_length: u32) -> f64 {
        let (kappa, lambda) = (1e-3_f64, 100.0_f64);
        let ell = (kappa / lambda).sqrt();
        let (length, width) = (20.0 * ell, 0.01);
        let (surface, nodes) = strip(length, width, 20 * per_length);
        // q [m²/s] per unit width at x = 0, split between the two nodes there; one implicit
        // step of 10⁹/λ is the steady state to 1e-9
        let (q, dt) = (1e-6, 1e9 / lambda);
        let mut source = vec![0.0; surface.n_nodes];
        let at_zero: Vec<usize> = (0..surface.n_nodes).filter(|&j| nodes[j].x.abs() < 1e-12).collect();
        assert_eq!(at_zero.len(), 2);
        for &j in &at_zero {
            source[j] = 0.5 * q * width * dt;
        }
        let mut rate = vec![0.0; surface.n_nodes];
        smooth(&surface, kappa, lambda, dt, &source, &mut rate).unwrap();
        (0..surface.n_nodes)
            .filter(|&j| nodes[j].x.abs() <= 3.0 * ell + 1e-12)
            .map(|j| {
                let exact = q / (2.0 * ell) * (-nodes[j].x.abs() / ell).exp();
                (rate[j] - exact).abs() / exact
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn a_line_source_spreads_into_the_steady_exponential_profile_at_second_order() {
        let errors: Vec<f64> = [4, 8, 16].map(steady_profile_error).to_vec();
        eprintln!("steady profile, largest relative error at 4, 8, 16 cells per ℓ: {errors:?}");
        // A23 gives 1e-2 for a mesh-dependent comparison; 8 cells per spreading length reach it
        assert!(errors[1] < 1e-2, "{errors:?}");
        for k in 1..errors.len() {
            let order = (errors[k - 1] / errors[k]).log2();
            // P1 elements: second order in the node values
            assert!(order > 1.8, "observed order {order} from {errors:?}");
        }
    }
}
