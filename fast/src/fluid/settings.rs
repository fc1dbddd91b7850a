//! Controls and counters of the fast solver's linear solves: tolerances from the case
//! ([`FastSettings`]), what a step's solves cost ([`SolveCounts`]), and the check that turns an
//! unconverged solve into an error.

use spillage_model::fluid::settings::NumericsSection;

use spillage_model::mesh::Vec3;

use crate::linear::{Csr, SolveStats, Tolerance};

/// Linear-solver controls of the fast solver (the reference solves exactly). The defaults are
/// tight enough for the step-by-step equivalence with the reference (tests/fast_equivalence.rs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FastSettings {
    /// Pressure: AMG-preconditioned CG, normalised residual (OpenFOAM's definition).
    pub pressure: Tolerance,
    /// Momentum components: Jacobi-preconditioned BiCGStab.
    pub momentum: Tolerance,
}

impl Default for FastSettings {
    fn default() -> Self {
        FastSettings { pressure: Tolerance { tolerance: 1e-12, max_iterations: 2000 }, momentum: Tolerance { tolerance: 1e-12, max_iterations: 2000 } }
    }
}

impl FastSettings {
    /// The controls a case file sets (`[numerics] linear_tolerance`, `max_linear_iterations`).
    pub fn from_numerics(numerics: &NumericsSection) -> Self {
        let tolerance = Tolerance { tolerance: numerics.linear_tolerance, max_iterations: numerics.max_linear_iterations };
        FastSettings { pressure: tolerance, momentum: tolerance }
    }
}

/// Iteration counts of the last step (for benchmarks).
#[derive(Clone, Copy, Debug, Default)]
pub struct SolveCounts {
    pub pressure_solves: usize,
    pub pressure_iterations: usize,
    pub momentum_iterations: usize,
    /// Iterations of the first [`SolveCounts::PER_SOLVE`] pressure solves of the step, in order.
    pub pressure_per_solve: [u16; SolveCounts::PER_SOLVE],
    /// Wall-clock seconds of the step in the multigrid setup, the pressure solves and the
    /// momentum solves (for the benchmark's breakdown; never used by the algorithm).
    pub amg_setup_seconds: f64,
    pub pressure_seconds: f64,
    pub momentum_seconds: f64,
    pub step_seconds: f64,
}

impl SolveCounts {
    pub const PER_SOLVE: usize = 12;
}

/// Why a solve that used its whole iteration budget is not an answer (`None` when it
/// converged): a silently unconverged solve would pass off a wrong state as a result.
pub fn unconverged(stats: &SolveStats, tolerance: Tolerance) -> Option<String> {
    (stats.iterations >= tolerance.max_iterations && stats.final_residual > tolerance.tolerance).then(|| {
        // a residual that grew is a diverging system, not a slow one: more iterations would
        // not help (issue 15 item 1: a finer mesh at the same Δt got the advice to raise them)
        let advice = if stats.final_residual > stats.initial_residual {
            format!(
                "the residual grew from {:.3e}: the system diverges (a time step too large for the mesh? lower [time] dt or max_courant, and check the Courant number with `spillage check`)",
                stats.initial_residual
            )
        } else {
            "raise [numerics] max_linear_iterations or loosen linear_tolerance".to_string()
        };
        format!("did not converge in {} iterations (normalised residual {:.3e} > {:.1e}); {advice}", stats.iterations, stats.final_residual, tolerance.tolerance)
    })
}

/// Where a failed solve of A x = b is worst, for its error message: the first cell whose value
/// is not finite, else the cell of the largest residual |b − Ax|, with its centre. Runs only on
/// the error path (it allocates the residual).
pub fn worst_cell(matrix: &Csr, rhs: &[f64], x: &[f64], cell_centres: &[Vec3]) -> String {
    let cell = x.iter().position(|v| !v.is_finite()).unwrap_or_else(|| {
        let mut ax = vec![0.0; x.len()];
        matrix.multiply(x, &mut ax);
        (0..x.len()).max_by(|&a, &b| (rhs[a] - ax[a]).abs().total_cmp(&(rhs[b] - ax[b]).abs())).unwrap_or(0)
    });
    match cell_centres.get(cell) {
        Some(c) => format!("worst in cell {cell} at ({:.4e}, {:.4e}, {:.4e}) m", c.x, c.y, c.z),
        None => format!("worst in row {cell}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_growing_residual_is_reported_as_divergence_not_as_too_few_iterations() {
        let limit = Tolerance { tolerance: 1e-8, max_iterations: 2000 };
        let diverging = SolveStats { iterations: 2000, initial_residual: 1e-3, final_residual: 56.29 };
        let message = unconverged(&diverging, limit).unwrap();
        assert!(message.contains("diverges") && !message.contains("raise [numerics] max_linear_iterations"), "{message}");
        let slow = SolveStats { iterations: 2000, initial_residual: 1e-3, final_residual: 1e-6 };
        assert!(unconverged(&slow, limit).unwrap().contains("raise [numerics] max_linear_iterations"));
        let converged = SolveStats { iterations: 12, initial_residual: 1e-3, final_residual: 1e-9 };
        assert!(unconverged(&converged, limit).is_none());
    }

    #[test]
    fn the_worst_cell_is_the_first_non_finite_value_else_the_largest_residual() {
        // diag(1, 2, 4) x = (1, 1, 1)
        let m = Csr { n: 3, row_start: vec![0, 0, 0, 0], col: vec![], val: vec![], diag: vec![1.0, 2.0, 4.0] };
        let centres = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(2.0, 0.0, 0.0)];
        let rhs = [1.0, 1.0, 1.0];
        // residuals 0, 0.5, 1 → cell 2
        assert!(worst_cell(&m, &rhs, &[1.0, 0.25, 0.0], &centres).starts_with("worst in cell 2 at (2.0000e0"));
        assert!(worst_cell(&m, &rhs, &[1.0, f64::NAN, 0.0], &centres).starts_with("worst in cell 1 at (1.0000e0"));
    }
}
