//! Square sparse matrix in compressed-row form with the diagonal kept apart (the PISO algorithm
//! reads A, the diagonal, on its own).


use super::reduce::Reducer;
use super::{par_update, Out};

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

    /// y = A x and, in the same pass, the two sums Σᵢ f(i, yᵢ) (fixed-chunk reduction: the same
    /// bits on any number of threads).
    pub fn multiply_sum2(&self, x: &[f64], y: &mut [f64], red: &mut Reducer, f: impl Fn(usize, f64) -> [f64; 2] + Sync) -> [f64; 2] {
        assert_eq!(y.len(), self.n, "multiply: y has the matrix size");
        let ys = Out::of(y);
        red.sum2(self.n, |r| {
            let yr = self.diag[r] * x[r] + self.row_off_diagonal(r, x);
            // SAFETY: r < n; the reduction's chunks visit every row exactly once
            unsafe { ys.set(r, yr) };
            f(r, yr)
        })
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
