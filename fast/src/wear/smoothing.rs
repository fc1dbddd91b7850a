//! Step 2 of wear: the wear rate w on the wall surface (wear-model.md §7.2–7.3), the same
//! discretisation as the reference (P1 nodes, lumped mass M, cotangent stiffness L, implicit
//! Euler): (M/Δt + κL + λM) wⁿ⁺¹ = M wⁿ/Δt + λ b, b_j = Σ_i W_i φ_j(x_i)/Δt.
//!
//! Solved by Jacobi-preconditioned conjugate gradients (the matrix is symmetric positive
//! definite: M/Δt + λM is, and L is positive semi-definite) from the previous rate, to a
//! normalised residual of [`TOLERANCE`]. The operators are fixed on the unworn wall (§7.3, as
//! the reference), so the matrix structure is built once and its values only when Δt changes.
//!
//! Conservation: L's columns sum to zero, so summing the rows of the exact solution gives
//! Σ_j (M_j/Δt + λM_j) w_j = Σ_j rhs_j, which is the discrete identity
//! Σ Δt ∫wⁿ⁺¹ + ∫w^N/λ = Σ W_i of §7.3. A direct solve meets it to round-off; an iterative
//! one only to its residual. After the solve, w is therefore scaled by the one factor
//! Σ rhs / Σ (M/Δt + λM) w (1 ± 10⁻¹⁴ or so): the identity then holds to round-off, and no node
//! changes sign (a uniform shift would give far-away nodes of zero rate a tiny rate of either
//! sign).

use spillage_model::solver::SolverError;
use spillage_model::wear::surface::WearSurface;

use crate::linear::pcg::Pcg;
use crate::linear::reduce::Reducer;
use crate::linear::{par_update, Csr, Jacobi, Tolerance};

/// Normalised residual (OpenFOAM's, [`Tolerance`]) the solve stops at: the matrix is strongly
/// diagonal (M/Δt dominates κL unless the triangles are far smaller than √(κΔt)), so CG reaches
/// round-off level in a few tens of iterations, three orders below the 1e-10 relative bound of
/// the equivalence with the reference's direct solve.
pub const TOLERANCE: f64 = 1e-14;
/// A solve that ends above this normalised residual is an error (not a smoothing within the
/// equivalence bound).
pub const ACCEPTED: f64 = 1e-11;
const MAX_ITERATIONS: usize = 2000;

/// The smoothing matrix of one wall and its solver's work arrays.
pub struct Smoothing {
    kappa: f64,
    lambda: f64,
    a: Csr,
    /// Positions in `a.val` of (i, j) and (j, i) of each stiffness entry.
    positions: Vec<[u32; 2]>,
    /// Δt the values of `a` are for (NaN before the first step).
    dt: f64,
    rhs: Vec<f64>,
    pcg: Pcg,
    red: Reducer,
}

impl Smoothing {
    /// The structure of M/Δt + κL + λM on `surface` (values set on the first step).
    pub fn new(surface: &WearSurface, kappa: f64, lambda: f64) -> Self {
        let n = surface.n_nodes;
        let mut row_start = vec![0u32; n + 1];
        for &(i, j, _) in &surface.stiffness {
            row_start[i as usize + 1] += 1;
            row_start[j as usize + 1] += 1;
        }
        for r in 0..n {
            row_start[r + 1] += row_start[r];
        }
        let mut fill: Vec<u32> = row_start[..n].to_vec();
        let mut col = vec![0u32; 2 * surface.stiffness.len()];
        let mut positions = Vec::with_capacity(surface.stiffness.len());
        for &(i, j, _) in &surface.stiffness {
            let mut place = |row: u32, column: u32| {
                let slot = fill[row as usize];
                col[slot as usize] = column;
                fill[row as usize] += 1;
                slot
            };
            positions.push([place(i, j), place(j, i)]);
        }
        let a = Csr { n, row_start, val: vec![0.0; col.len()], col, diag: vec![0.0; n] };
        Smoothing { kappa, lambda, a, positions, dt: f64::NAN, rhs: vec![0.0; n], pcg: Pcg::default(), red: Reducer::default() }
    }

    /// The matrix values for step size `dt`, summed in the reference's order (diagonal: the mass
    /// terms, then −κL_ij of each edge in stiffness order), so the entries have its bits.
    fn set_dt(&mut self, surface: &WearSurface, dt: f64) {
        let (kappa, lambda) = (self.kappa, self.lambda);
        for (d, m) in self.a.diag.iter_mut().zip(&surface.node_area) {
            *d = m / dt + lambda * m;
        }
        for (&(i, j, l), &[ij, ji]) in surface.stiffness.iter().zip(&self.positions) {
            self.a.val[ij as usize] = kappa * l;
            self.a.val[ji as usize] = kappa * l;
            self.a.diag[i as usize] += -kappa * l;
            self.a.diag[j as usize] += -kappa * l;
        }
        self.dt = dt;
    }

    /// Solves for the new rate `rate` (in place, from the old one, which is the initial guess)
    /// and writes the depth each node recedes by this step, Δt wⁿ⁺¹ [m], into `depth`.
    pub fn smooth(&mut self, surface: &WearSurface, dt: f64, node_volume: &[f64], rate: &mut [f64], depth: &mut [f64], wall: &str) -> Result<(), SolverError> {
        if dt.to_bits() != self.dt.to_bits() {
            self.set_dt(surface, dt);
        }
        let lambda = self.lambda;
        let area = &surface.node_area;
        par_update(&mut self.rhs, |j, b| *b = area[j] * rate[j] / dt + lambda * node_volume[j] / dt);
        let stats = self.pcg.solve(&self.a, &self.rhs, rate, &mut Jacobi, Tolerance { tolerance: TOLERANCE, max_iterations: MAX_ITERATIONS });
        if let Some(row) = rate.iter().position(|v| !v.is_finite()) {
            return Err(SolverError::LinearSolve(format!(
                "wear smoothing of wall `{wall}`: the solution is not finite (singular matrix?); first in row {row}"
            )));
        }
        if !(stats.final_residual <= ACCEPTED) {
            return Err(SolverError::LinearSolve(format!(
                "wear smoothing of wall `{wall}`: normalised residual {:e} after {} iterations (accepted: {ACCEPTED:e})",
                stats.final_residual, stats.iterations
            )));
        }
        // restore the conservation identity (module documentation); both sums in a fixed
        // order, so the factor has the same bits on any number of threads
        let rhs = &self.rhs;
        let [target, _] = self.red.sum2(rhs.len(), |j| [rhs[j], 0.0]);
        let r = &*rate;
        let [held, _] = self.red.sum2(r.len(), |j| [(area[j] / dt + lambda * area[j]) * r[j], 0.0]);
        if held != 0.0 && held.is_finite() {
            let factor = target / held;
            par_update(rate, |_, w| *w *= factor);
        }
        let r = &*rate;
        par_update(depth, |j, d| *d = dt * r[j]);
        Ok(())
    }
}

/// Without smoothing each node recedes by its deposited volume over its area at once; the rate
/// reported is that depth over Δt (as the reference).
pub fn direct(surface: &WearSurface, dt: f64, node_volume: &[f64], rate: &mut [f64], depth: &mut [f64]) {
    let area = &surface.node_area;
    par_update(depth, |j, d| *d = if area[j] > 0.0 { node_volume[j] / area[j] } else { 0.0 });
    let depth = &*depth;
    par_update(rate, |j, r| *r = depth[j] / dt);
}

#[cfg(test)]
mod tests {
    use super::*;
    use spillage_model::walls::geometry::plane;
    use spillage_model::walls::state::Vec3;

    #[test]
    fn one_impact_decays_as_the_discrete_damping_and_conserves_its_volume() {
        // as the reference's test (A20/A21 in discrete form): after an impact of volume W at
        // step 1, ∫w dA = λW/(1 + λΔt)ⁿ at step n, and Σ Δt ∫wⁿ + ∫w^N/λ = W at every N
        let mesh = plane(Vec3::zeros(), Vec3::z(), [0.2, 0.02], [40, 1], Some(Vec3::x()));
        let surface = WearSurface::new(&mesh.vertices, &mesh.triangles);
        let (kappa, lambda, dt, volume) = (1e-3, 100.0, 1e-3, 2.5e-9);
        let mut smoothing = Smoothing::new(&surface, kappa, lambda);
        let n = surface.n_nodes;
        let (mut rate, mut depth) = (vec![0.0; n], vec![0.0; n]);
        let mut source = vec![0.0; n];
        source[7] = 0.3 * volume;
        source[8] = 0.7 * volume;
        let nothing = vec![0.0; n];
        let mut receded = 0.0;
        for step in 1..=200 {
            smoothing.smooth(&surface, dt, if step == 1 { &source } else { &nothing }, &mut rate, &mut depth, "strip").unwrap();
            let integral: f64 = rate.iter().zip(&surface.node_area).map(|(w, a)| w * a).sum();
            let expected = lambda * volume / (1.0 + lambda * dt).powi(step);
            // the conservation factor makes the row sum exact: round-off only, as the direct
            // solve (1e-12)
            assert!((integral - expected).abs() <= 1e-12 * expected, "step {step}: {integral:e} vs {expected:e}");
            receded += depth.iter().zip(&surface.node_area).map(|(d, a)| d * a).sum::<f64>();
            let identity = receded + integral / lambda;
            assert!((identity - volume).abs() <= 1e-13 * volume, "step {step}: {identity:e} vs {volume:e}");
        }
    }
}
