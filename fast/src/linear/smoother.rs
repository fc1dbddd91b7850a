//! Multicolour Gauss–Seidel: the rows are coloured greedily in index order so that no two rows
//! of one colour are coupled; a sweep updates the colours one after the other, each colour's
//! rows all at once from the latest values of the other colours. Rows of one colour do not read
//! each other, so they run in parallel and the result is the same on any number of threads
//! (and the same as the sequential sweep in colour order). On the hexahedral meshes the greedy
//! colouring of the 5/7-point stencil is the red–black chequerboard, whose Gauss–Seidel smooths
//! the Poisson equation at least as well as the lexicographic sweep; there is no sequential
//! dependency chain from row to row, and no division (the inverse diagonal is stored).

use super::csr::{fold_row, Csr, Real};
use super::gang::{Crew, Slot};
use super::par_update;

/// Rows grouped by colour: colour k holds rows `order[start[k]..start[k + 1]]` (ascending).
#[derive(Clone, Debug, Default)]
pub struct Colouring {
    pub order: Vec<u32>,
    pub start: Vec<u32>,
    colour: Vec<u32>,
    used: Vec<usize>,
}

impl Colouring {
    /// Greedy first-fit colouring of the graph of `a` in row order (deterministic).
    pub fn build<T: Real>(&mut self, a: &Csr<T>) {
        let n = a.n;
        self.colour.clear();
        self.colour.resize(n, u32::MAX);
        self.used.clear();
        let mut n_colours = 0usize;
        for r in 0..n {
            for k in a.row_start[r] as usize..a.row_start[r + 1] as usize {
                let c = self.colour[a.col[k] as usize];
                if c != u32::MAX {
                    self.used[c as usize] = r;
                }
            }
            let c = (0..n_colours).find(|&c| self.used[c] != r).unwrap_or(n_colours);
            if c == n_colours {
                n_colours += 1;
                self.used.push(usize::MAX);
            }
            self.colour[r] = c as u32;
        }
        self.start.clear();
        self.start.resize(n_colours + 1, 0);
        for &c in &self.colour {
            self.start[c as usize + 1] += 1;
        }
        for k in 0..n_colours {
            self.start[k + 1] += self.start[k];
        }
        self.order.clear();
        self.order.resize(n, 0);
        // counting sort by colour, rows ascending within a colour (`used` as fill pointers)
        self.used.clear();
        self.used.extend(self.start[..n_colours].iter().map(|&s| s as usize));
        for r in 0..n {
            let c = self.colour[r] as usize;
            self.order[self.used[c]] = r as u32;
            self.used[c] += 1;
        }
    }

    /// Colour of row r.
    pub fn colour_of(&self, r: usize) -> usize {
        self.colour[r] as usize
    }

    pub fn colours(&self) -> usize {
        self.start.len().saturating_sub(1)
    }
}

/// 1/diag of `a` into `inv`.
pub fn inverse_diagonal<T: Real>(a: &Csr<T>, inv: &mut Vec<T>) {
    inv.resize(a.n, T::default());
    par_update(&mut inv[..], |i, v| *v = T::put(1.0 / a.diag[i].get()));
}

/// One Gauss–Seidel sweep on A x = b in colour order (`forward`) or reverse colour order,
/// updating x in place, by the members of a gang.
///
/// # Safety
/// Every member of `crew` calls it with the same vectors, which no other gang uses, `b` is not
/// `x`, and `colouring` is [`Colouring::build`]'s for the pattern of `a` (every row once, no two
/// coupled rows of one colour: the rows of a colour are written side by side).
pub unsafe fn sweep<T: Real, V: Real>(crew: &Crew, a: &Csr<T>, inv_diag: &[T], colouring: &Colouring, b: &[Slot<V>], x: &[Slot<V>], forward: bool) {
    assert_eq!(x.len(), a.n, "sweep: x has the matrix size");
    let n_colours = colouring.colours();
    // SAFETY: the caller's promise
    unsafe {
        if forward {
            colour_passes(crew, a, inv_diag, colouring, b, x, 0..n_colours);
        } else {
            colour_passes(crew, a, inv_diag, colouring, b, x, (0..n_colours).rev());
        }
    }
}

/// The Gauss–Seidel update of the rows of each colour in `colours`, one colour after the other
/// (a barrier between two colours).
///
/// # Safety
/// As [`sweep`].
unsafe fn colour_passes<T: Real, V: Real>(
    crew: &Crew,
    a: &Csr<T>,
    inv_diag: &[T],
    colouring: &Colouring,
    b: &[Slot<V>],
    x: &[Slot<V>],
    colours: impl Iterator<Item = usize>,
) {
    for k in colours {
        let rows = &colouring.order[colouring.start[k] as usize..colouring.start[k + 1] as usize];
        crew.for_each(rows.len(), |i| {
            let r = rows[i] as usize;
            // SAFETY: rows of this colour are written by their block's member only and do not
            // read each other; rows of the other colours are not written during this pass
            let (lo, hi) = (a.row_start[r] as usize, a.row_start[r + 1] as usize);
            let s = fold_row(&a.col[lo..hi], &a.val[lo..hi], unsafe { b[r].get() }.get(), |c| unsafe { x[c].get() }.get(), |s, t| s - t);
            unsafe { x[r].set(V::put(s * inv_diag[r].get())) };
        });
    }
}

/// Forward sweep from x = 0. The first colour's neighbours are all still zero, so its rows are
/// x = b / diag without reading the matrix (the same bits as the full sweep: b − Σ a·0 = b), and
/// only the rows of the third and later colours need zeroing before the later colours read them.
///
/// # Safety
/// As [`sweep`].
pub unsafe fn sweep_from_zero<T: Real, V: Real>(crew: &Crew, a: &Csr<T>, inv_diag: &[T], colouring: &Colouring, b: &[Slot<V>], x: &[Slot<V>]) {
    assert_eq!(x.len(), a.n, "sweep: x has the matrix size");
    let n_colours = colouring.colours();
    let rows_from = |k: usize| &colouring.order[colouring.start[k.min(n_colours)] as usize..];
    let later = rows_from(2);
    // SAFETY (both loops): every row index is < n and appears once in the colour order, so
    // each is written by one member; the two loops touch different rows (no barrier between)
    for i in crew.block(later.len()) {
        unsafe { x[later[i] as usize].set(V::default()) };
    }
    let first = &colouring.order[..colouring.start[1.min(n_colours)] as usize];
    crew.for_each(first.len(), |i| {
        let r = first[i] as usize;
        unsafe { x[r].set(V::put(b[r].get().get() * inv_diag[r].get())) };
    });
    // SAFETY: the caller's promise
    unsafe { colour_passes(crew, a, inv_diag, colouring, b, x, 1..n_colours) };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_colouring_is_a_chequerboard_and_the_sweep_matches_sequential_gauss_seidel() {
        let (nx, ny) = (7, 5);
        let n = nx * ny;
        let mut a = Csr { n, row_start: vec![0], ..Default::default() };
        for j in 0..ny {
            for i in 0..nx {
                for (di, dj) in [(0i64, -1i64), (-1, 0), (1, 0), (0, 1)] {
                    let (ii, jj) = (i as i64 + di, j as i64 + dj);
                    if ii >= 0 && jj >= 0 && (ii as usize) < nx && (jj as usize) < ny {
                        a.col.push((jj as usize * nx + ii as usize) as u32);
                        a.val.push(-1.0);
                    }
                }
                a.diag.push(4.5);
                a.row_start.push(a.col.len() as u32);
            }
        }
        let mut colouring = Colouring::default();
        colouring.build(&a);
        assert_eq!(colouring.colours(), 2);
        for k in 0..2 {
            for &r in &colouring.order[colouring.start[k] as usize..colouring.start[k + 1] as usize] {
                let (i, j) = (r as usize % nx, r as usize / nx);
                assert_eq!((i + j) % 2, k, "row {r}");
            }
        }
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
        let mut inv = Vec::new();
        inverse_diagonal(&a, &mut inv);
        let mut x = vec![0.0; n];
        let mut b_shared = b.clone();
        let (bs, xs) = (Slot::from_mut_slice(&mut b_shared), Slot::from_mut_slice(&mut x));
        // SAFETY: b and x are this gang's alone, b is not x, and the one member runs both
        crate::linear::gang::run(n, &mut Vec::new(), |crew| unsafe {
            sweep_from_zero(crew, &a, &inv, &colouring, bs, xs);
            sweep(crew, &a, &inv, &colouring, bs, xs, false);
        });
        // sequential Gauss–Seidel visiting the rows in colour order, then in reverse
        let mut y = vec![0.0; n];
        let mut visit: Vec<usize> = colouring.order.iter().map(|&r| r as usize).collect();
        for pass in 0..2 {
            for &r in &visit {
                let mut s = b[r];
                for k in a.row_start[r] as usize..a.row_start[r + 1] as usize {
                    s -= a.val[k] * y[a.col[k] as usize];
                }
                y[r] = s * (1.0 / a.diag[r]);
            }
            if pass == 0 {
                // reverse colour order, rows of a colour in any order (they are uncoupled)
                visit = (0..2)
                    .rev()
                    .flat_map(|k| colouring.order[colouring.start[k] as usize..colouring.start[k + 1] as usize].iter().map(|&r| r as usize))
                    .collect();
            }
        }
        for i in 0..n {
            assert_eq!(x[i].to_bits(), y[i].to_bits(), "row {i}");
        }
    }
}
