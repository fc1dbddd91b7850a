//! Sparse matrices assembled coefficient by coefficient and solved by direct LU factorisation
//! (faer): exact solves, so the reference solver's answers carry no iterative-solver tolerance.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;
use spillage_model::mesh::Vec3;
use spillage_model::solver::SolverError;

/// A square sparse matrix as a list of (row, column, value) entries; repeated entries add up.
#[derive(Clone, Debug)]
pub struct SparseMatrix {
    pub n: usize,
    pub entries: Vec<Triplet<usize, usize, f64>>,
    /// Diagonal, kept separately because the algorithm reads it (A of spec §8.5).
    pub diagonal: Vec<f64>,
}

impl SparseMatrix {
    pub fn new(n: usize) -> Self {
        SparseMatrix { n, entries: Vec::new(), diagonal: vec![0.0; n] }
    }

    pub fn add_diagonal(&mut self, row: usize, value: f64) {
        self.diagonal[row] += value;
    }

    pub fn add_off_diagonal(&mut self, row: usize, col: usize, value: f64) {
        debug_assert_ne!(row, col);
        self.entries.push(Triplet::new(row, col, value));
    }

    /// y = M x.
    pub fn multiply(&self, x: &[f64]) -> Vec<f64> {
        let mut y: Vec<f64> = self.diagonal.iter().zip(x).map(|(d, v)| d * v).collect();
        for e in &self.entries {
            y[e.row] += e.val * x[e.col];
        }
        y
    }

    /// Σ_N a_PN x_N (the off-diagonal part only).
    pub fn multiply_off_diagonal(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n];
        for e in &self.entries {
            y[e.row] += e.val * x[e.col];
        }
        y
    }

    /// Factorises once and solves for every right-hand side. `what` names the equation in
    /// error messages.
    pub fn solve(&self, rhs: &[Vec<f64>], what: &str) -> Result<Vec<Vec<f64>>, SolverError> {
        self.solve_located(rhs, what, None)
    }

    /// [`SparseMatrix::solve`] for an equation with one row per cell: a non-finite solution is
    /// reported with the first cell where it is not finite and that cell's centre.
    pub fn solve_on_cells(&self, rhs: &[Vec<f64>], what: &str, cell_centres: &[Vec3]) -> Result<Vec<Vec<f64>>, SolverError> {
        self.solve_located(rhs, what, Some(cell_centres))
    }

    fn solve_located(&self, rhs: &[Vec<f64>], what: &str, cell_centres: Option<&[Vec3]>) -> Result<Vec<Vec<f64>>, SolverError> {
        let mut all = self.entries.clone();
        for (i, d) in self.diagonal.iter().enumerate() {
            all.push(Triplet::new(i, i, *d));
        }
        let matrix = SparseColMat::<usize, f64>::try_new_from_triplets(self.n, self.n, &all)
            .map_err(|e| SolverError::LinearSolve(format!("{what}: cannot build the matrix: {e:?}")))?;
        let lu = matrix.sp_lu().map_err(|e| SolverError::LinearSolve(format!("{what}: LU factorisation failed: {e:?}")))?;
        let mut b = Mat::<f64>::zeros(self.n, rhs.len());
        for (j, column) in rhs.iter().enumerate() {
            for i in 0..self.n {
                b[(i, j)] = column[i];
            }
        }
        lu.solve_in_place(b.as_mut());
        let mut out = Vec::with_capacity(rhs.len());
        for j in 0..rhs.len() {
            let column: Vec<f64> = (0..self.n).map(|i| b[(i, j)]).collect();
            if let Some(row) = column.iter().position(|v| !v.is_finite()) {
                let place = match cell_centres.and_then(|c| c.get(row)) {
                    Some(x) => format!("; first in cell {row} at ({:.4e}, {:.4e}, {:.4e}) m", x.x, x.y, x.z),
                    None => format!("; first in row {row}"),
                };
                return Err(SolverError::LinearSolve(format!("{what}: the solution is not finite (singular matrix?){place}")));
            }
            out.push(column);
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_small_system_exactly_and_sums_repeated_entries() {
        // [2 -1 0; -1 2 -1; 0 -1 2] x = [1 0 1] → x = [1 1 1]
        let mut m = SparseMatrix::new(3);
        for i in 0..3 {
            m.add_diagonal(i, 1.0);
            m.add_diagonal(i, 1.0);
        }
        m.add_off_diagonal(0, 1, -0.5);
        m.add_off_diagonal(0, 1, -0.5);
        m.add_off_diagonal(1, 0, -1.0);
        m.add_off_diagonal(1, 2, -1.0);
        m.add_off_diagonal(2, 1, -1.0);
        let x = m.solve(&[vec![1.0, 0.0, 1.0]], "test").unwrap();
        for v in &x[0] {
            assert!((v - 1.0).abs() < 1e-14);
        }
        assert_eq!(m.multiply(&x[0]).iter().map(|v| (v * 1e12).round()).collect::<Vec<_>>(), vec![1e12, 0.0, 1e12]);
    }
}
