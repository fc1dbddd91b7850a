//! Square sparse matrix in compressed-row form with the diagonal kept apart (the PISO algorithm
//! reads A, the diagonal, on its own), stored in f64 (the equations) or f32 (the multigrid
//! preconditioner's copies, [`super::amg`]). Every kernel computes in f64 whatever the storage;
//! on f64 data the conversions are the identity, so the bits are those of plain f64 code.

use super::gang::{Crew, Slot};
use super::par_update;

/// Storage type of matrix and vector entries: f64, or f32 where half the bytes are worth more
/// than the digits (a preconditioner only has to approximate).
pub trait Real: Copy + Default + PartialEq + PartialOrd + Send + Sync + std::fmt::Debug + 'static {
    fn get(self) -> f64;
    fn put(x: f64) -> Self;
}

impl Real for f64 {
    #[inline(always)]
    fn get(self) -> f64 {
        self
    }
    #[inline(always)]
    fn put(x: f64) -> Self {
        x
    }
}

impl Real for f32 {
    #[inline(always)]
    fn get(self) -> f64 {
        self as f64
    }
    #[inline(always)]
    fn put(x: f64) -> Self {
        x as f32
    }
}

/// `step(… step(step(init, v₀ x_{c₀}), v₁ x_{c₁}) …)` over the entries (`cols`, `vals`) of a
/// row, in their order. A row of four entries (the interior rows of a 2-D hexahedral mesh's
/// 5-point stencil and of its coarse levels) is written out, without the loop's branch, whose
/// exit the short loop mispredicts; the operations and their order, so the bits, are those of
/// the loop. (`pressure_solve` on a 100² grid: about 10 % less time a CG iteration on one
/// thread and 15 % on two, minimum of 8–10 alternating runs; a second special case for six
/// entries, the 3-D stencil's, gained nothing on a 24³ grid and cost the 2-D case its gain.)
#[inline(always)]
pub(super) fn fold_row<T: Real>(cols: &[u32], vals: &[T], init: f64, x_at: impl Fn(usize) -> f64, step: impl Fn(f64, f64) -> f64) -> f64 {
    let term = |k: usize| vals[k].get() * x_at(cols[k] as usize);
    let mut s = init;
    if cols.len() == 4 && vals.len() == 4 {
        s = step(s, term(0));
        s = step(s, term(1));
        s = step(s, term(2));
        return step(s, term(3));
    }
    for (&c, &v) in cols.iter().zip(vals) {
        s = step(s, v.get() * x_at(c as usize));
    }
    s
}

#[derive(Clone, Debug, Default)]
pub struct Csr<T = f64> {
    pub n: usize,
    /// Row r holds off-diagonal entries `row_start[r]..row_start[r + 1]`.
    pub row_start: Vec<u32>,
    pub col: Vec<u32>,
    pub val: Vec<T>,
    pub diag: Vec<T>,
}

impl<T: Real> Csr<T> {
    /// Σ_j a_rj x_j over the off-diagonal entries of row r, x_j read by `x_at(j)`.
    #[inline(always)]
    fn row_off_diagonal_with(&self, r: usize, x_at: impl Fn(usize) -> f64) -> f64 {
        let (lo, hi) = (self.row_start[r] as usize, self.row_start[r + 1] as usize);
        fold_row(&self.col[lo..hi], &self.val[lo..hi], 0.0, x_at, |s, t| s + t)
    }

    /// Σ_j a_rj x_j over the off-diagonal entries of row r.
    #[inline(always)]
    pub fn row_off_diagonal<V: Real>(&self, r: usize, x: &[V]) -> f64 {
        self.row_off_diagonal_with(r, |c| x[c].get())
    }

    /// [`Csr::row_off_diagonal`] of a vector shared by a gang.
    ///
    /// # Safety
    /// No member writes the entries of `x` that row r reads (the gang's rule).
    #[inline(always)]
    pub unsafe fn row_off_diagonal_shared<V: Real>(&self, r: usize, x: &[Slot<V>]) -> f64 {
        self.row_off_diagonal_with(r, |c| unsafe { x[c].get() }.get())
    }

    /// (A x)_r of a vector shared by a gang.
    ///
    /// # Safety
    /// As [`Csr::row_off_diagonal_shared`], and for x_r.
    #[inline(always)]
    unsafe fn row_product_shared<V: Real>(&self, r: usize, x: &[Slot<V>]) -> V {
        V::put(self.diag[r].get() * unsafe { x[r].get() }.get() + unsafe { self.row_off_diagonal_shared(r, x) })
    }

    /// y = A x, by the members of a gang.
    ///
    /// # Safety
    /// Every member of `crew` calls it with the same vectors, which no other gang uses, and
    /// `y` is not `x`.
    pub unsafe fn multiply_shared<V: Real>(&self, crew: &Crew, x: &[Slot<V>], y: &[Slot<V>]) {
        assert_eq!(y.len(), self.n, "multiply: y has the matrix size");
        debug_assert!(!std::ptr::eq(x.as_ptr(), y.as_ptr()), "multiply: y is not x");
        // SAFETY: row r of y is written by its block's member only; x is not written
        crew.for_each(self.n, |r| unsafe { y[r].set(self.row_product_shared(r, x)) });
    }

    /// y = A x and, in the same pass, the two sums Σᵢ f(i, yᵢ), by the members of a gang
    /// (fixed-chunk sums: the same bits on any number of threads).
    ///
    /// # Safety
    /// As [`Csr::multiply_shared`]; `f` writes nothing and reads no entry of `y` but its own.
    pub unsafe fn multiply_sum2_shared<V: Real>(&self, crew: &Crew, x: &[Slot<V>], y: &[Slot<V>], f: impl Fn(usize, f64) -> [f64; 2]) -> [f64; 2] {
        assert_eq!(y.len(), self.n, "multiply: y has the matrix size");
        debug_assert!(!std::ptr::eq(x.as_ptr(), y.as_ptr()), "multiply: y is not x");
        crew.sum2(self.n, |r| {
            // SAFETY: row r of y is written by the member summing its chunk only; x is not
            // written
            let yr = unsafe { self.row_product_shared(r, x) };
            unsafe { y[r].set(yr) };
            f(r, yr.get())
        })
    }

    /// y = A x.
    pub fn multiply<V: Real>(&self, x: &[V], y: &mut [V]) {
        par_update(y, |r, y| *y = V::put(self.diag[r].get() * x[r].get() + self.row_off_diagonal(r, x)));
    }

    /// y = (A − D) x.
    pub fn multiply_off_diagonal<V: Real>(&self, x: &[V], y: &mut [V]) {
        par_update(y, |r, y| *y = V::put(self.row_off_diagonal(r, x)));
    }

    /// Row sums Σ_j a_rj (diagonal included): A·1.
    pub fn row_sum(&self, r: usize) -> f64 {
        let (lo, hi) = (self.row_start[r] as usize, self.row_start[r + 1] as usize);
        self.diag[r].get() + self.val[lo..hi].iter().map(|v| v.get()).sum::<f64>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The written-out row of four entries gives the loop's bits, for sums and for the
    /// sweep's differences, in f64 and f32 storage; other lengths take the loop.
    #[test]
    fn a_row_written_out_gives_the_bits_of_the_loop() {
        let x: Vec<f64> = (0..16).map(|i| (i as f64 * 0.37).sin() * 10f64.powi(i % 7 - 3)).collect();
        for len in 0..9 {
            let cols: Vec<u32> = (0..len).map(|k| ((k * 5 + 3) % 16) as u32).collect();
            let vals: Vec<f64> = (0..len).map(|k| -1.0 / (k as f64 + 1.3)).collect();
            let vals32: Vec<f32> = vals.iter().map(|&v| v as f32).collect();
            for (init, step) in [(0.0, (|s, t| s + t) as fn(f64, f64) -> f64), (0.731, |s, t| s - t)] {
                let looped = cols.iter().zip(&vals).fold(init, |s, (&c, &v)| step(s, v * x[c as usize]));
                let looped32 = cols.iter().zip(&vals32).fold(init, |s, (&c, &v)| step(s, v.get() * x[c as usize]));
                assert_eq!(fold_row(&cols, &vals, init, |c| x[c], step).to_bits(), looped.to_bits(), "{len} entries, f64");
                assert_eq!(fold_row(&cols, &vals32, init, |c| x[c], step).to_bits(), looped32.to_bits(), "{len} entries, f32");
            }
        }
    }
}
