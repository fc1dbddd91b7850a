//! Square sparse matrix in compressed-row form with the diagonal kept apart (the PISO algorithm
//! reads A, the diagonal, on its own).


use super::par_update;

#[derive(Clone, Debug, Default)]
pub struct Csr {
    pub n: usize,
    /// Row r holds off-diagonal entries `row_start[r]..row_start[r + 1]`.
    pub row_start: Vec<u32>,
    pub col: Vec<u32>,
    pub val: Vec<f64>,
    pub diag: Vec<f64>,
}

impl Csr {
    /// Σ_j a_rj x_j over the off-diagonal entries of row r.
    #[inline(always)]
    pub fn row_off_diagonal(&self, r: usize, x: &[f64]) -> f64 {
        let (lo, hi) = (self.row_start[r] as usize, self.row_start[r + 1] as usize);
        let mut s = 0.0;
        for (&c, &v) in self.col[lo..hi].iter().zip(&self.val[lo..hi]) {
            s += v * x[c as usize];
        }
        s
    }

    /// y = A x.
    pub fn multiply(&self, x: &[f64], y: &mut [f64]) {
        par_update(&mut y[..], |r, y| *y = self.diag[r] * x[r] + self.row_off_diagonal(r, x));
    }

    /// y = (A − D) x.
    pub fn multiply_off_diagonal(&self, x: &[f64], y: &mut [f64]) {
        par_update(&mut y[..], |r, y| *y = self.row_off_diagonal(r, x));
    }

    /// Row sums Σ_j a_rj (diagonal included): A·1.
    pub fn row_sum(&self, r: usize) -> f64 {
        let (lo, hi) = (self.row_start[r] as usize, self.row_start[r + 1] as usize);
        self.diag[r] + self.val[lo..hi].iter().sum::<f64>()
    }
}
