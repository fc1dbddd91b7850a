//! Block Gauss–Seidel: the rows are cut into fixed blocks of [`BLOCK`] rows (independent of the
//! thread count); inside a block the sweep is sequential Gauss–Seidel, across blocks it uses the
//! values from before the sweep (block Jacobi), so the blocks run in parallel and the result
//! does not depend on how many threads run them.

use rayon::prelude::*;

use super::csr::Csr;

/// Rows per smoother block.
pub const BLOCK: usize = 1024;

/// One forward (`forward = true`) or backward block Gauss–Seidel sweep on A x = b, reading the
/// previous iterate from `x_old` and writing the new one to `x`.
pub fn block_gauss_seidel(a: &Csr, b: &[f64], x_old: &[f64], x: &mut [f64], forward: bool) {
    x.par_chunks_mut(BLOCK).enumerate().for_each(|(k, xb)| {
        let lo = k * BLOCK;
        let hi = lo + xb.len();
        xb.copy_from_slice(&x_old[lo..hi]);
        let mut sweep = |r: usize| {
            let (s, e) = (a.row_start[r] as usize, a.row_start[r + 1] as usize);
            let mut sum = b[r];
            for q in s..e {
                let c = a.col[q] as usize;
                let xc = if c >= lo && c < hi { xb[c - lo] } else { x_old[c] };
                sum -= a.val[q] * xc;
            }
            xb[r - lo] = sum / a.diag[r];
        };
        if forward {
            for r in lo..hi {
                sweep(r);
            }
        } else {
            for r in (lo..hi).rev() {
                sweep(r);
            }
        }
    });
}

/// Same sweep starting from x = 0 (no old iterate to read).
pub fn block_gauss_seidel_from_zero(a: &Csr, b: &[f64], x: &mut [f64], forward: bool) {
    x.par_chunks_mut(BLOCK).enumerate().for_each(|(k, xb)| {
        let lo = k * BLOCK;
        let hi = lo + xb.len();
        xb.fill(0.0);
        let mut sweep = |r: usize| {
            let (s, e) = (a.row_start[r] as usize, a.row_start[r + 1] as usize);
            let mut sum = b[r];
            for q in s..e {
                let c = a.col[q] as usize;
                if c >= lo && c < hi {
                    sum -= a.val[q] * xb[c - lo];
                }
            }
            xb[r - lo] = sum / a.diag[r];
        };
        if forward {
            for r in lo..hi {
                sweep(r);
            }
        } else {
            for r in (lo..hi).rev() {
                sweep(r);
            }
        }
    });
}
