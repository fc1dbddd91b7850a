//! Aggregation algebraic multigrid (unsmoothed, double pairwise aggregation, Notay 2010) used
//! as the preconditioner of flexible CG for the pressure: a K-cycle (Notay & Vassilevski 2008:
//! on every coarse level except the coarsest, the correction is two steps of flexible CG
//! preconditioned by the next coarser cycle, the second skipped when the first reduces the
//! coarse residual by 4), one multicolour Gauss–Seidel sweep forward before and backward after
//! the coarse correction ([`super::smoother`]), Galerkin coarse matrices Aᶜ = PᵀAP with
//! piecewise-constant P, dense Cholesky on the coarsest level. The K-cycle keeps the iteration
//! count nearly independent of the number of levels, where the V-cycle of unsmoothed aggregation
//! degrades with every level added (measured on the lid-driven cavity's pressure matrix, 256²:
//! 33 → 10 iterations to a normalised residual of 1e-7).
//!
//! This module holds the hierarchy and the cycle; [`coarsening`] builds the levels (pairwise
//! aggregation, Galerkin products, the coarsest level's Cholesky factor).
//!
//! The aggregation and the colourings are sequential and in index order (deterministic). When a
//! matrix has the sparsity pattern of the previous setup, they are kept and only the values are
//! recomputed (inverse diagonals and coarse matrices through a precomputed fine-entry →
//! coarse-entry map), which is cheap enough to do for every solve. Everything else runs on
//! rayon with thread-count-independent results (fixed-chunk reductions, multicolour sweeps).
//!
//! The hierarchy is stored in f32: an f32 copy of the fine matrix, and f32 coarse matrices and
//! coarse vectors; the kernels compute in f64 and level 0 reads and writes CG's f64 vectors. A
//! preconditioner only has to approximate A⁻¹, and the flexible CG around it keeps its own
//! residual in f64, so the solves still reach 1e-12 (the equivalence tests' setting) with the
//! same iteration counts, while the cycle moves about a third fewer bytes (lid-driven cavity
//! 384², 2 threads: 1.68 → 1.45 µs per cell-step).

use rayon::prelude::*;

use super::csr::{Csr, Real};
use super::reduce::{Reducer, CHUNK};
use super::smoother::{inverse_diagonal, sweep, sweep_from_zero, Colouring};
use super::{par_range, par_update, Out, Preconditioner};

mod coarsening;
use coarsening::{cholesky, coarse_pattern, coarse_values, galerkin, members, pairwise};

/// Coarsest level size solved by dense Cholesky.
const DENSE_MAX: usize = 64;
/// Largest coarsest level still factored densely (when coarsening stalls above DENSE_MAX).
const DENSE_LIMIT: usize = 4 * DENSE_MAX;
/// Strength threshold: j is a strong neighbour of i if −a_ij ≥ β max_k(−a_ik).
const STRENGTH: f64 = 0.25;
/// K-cycle: skip the second coarse Krylov step when ‖r̃‖ ≤ t ‖r‖ (Notay's t = 0.25).
const KCYCLE_SKIP: f64 = 0.25;
/// K-cycle only below a transfer that reduces the rows at least this many times (Notay's
/// AGMG applies the same guard): the work of level k is 2ᵏ visits × its rows.
const KCYCLE_MIN_RATIO: usize = 3;
/// K-cycle only on coarse levels of at least this many rows: below it a level's kernels cost
/// their fixed overheads more than their rows, and the 2ᵏ visits multiply those.
const KCYCLE_MIN_ROWS: usize = 2048;
/// Pairing: a candidate replaces the best so far only if it is stronger by more than this
/// factor. Couplings that are equal up to rounding (of the face geometry, and of the f32
/// storage: 6e-8) then pair in column order, which keeps the aggregates of a uniform block
/// regular (2 × 2 after two passes, so every coarse level stays a two-colour grid) instead of
/// following the rounding noise.
const TIE: f64 = 1.0 + 1e-5;
const NONE: u32 = u32::MAX;

/// Map from one level to the next coarser one.
#[derive(Clone, Debug, Default)]
struct Transfer {
    /// Coarse row of each fine row.
    agg: Vec<u32>,
    /// Fine rows of coarse row I: `members[start[I]..start[I + 1]]` (ascending).
    start: Vec<u32>,
    members: Vec<u32>,
    /// Coarse off-diagonal entry of each fine off-diagonal entry (`NONE`: inside one aggregate,
    /// adds to the coarse diagonal).
    entry_map: Vec<u32>,
    /// The members whose residual is restricted: `residual_members[residual_start[I]..
    /// residual_start[I + 1]]`, the members of I not in the fine level's last colour. The
    /// pre-smoothing sweep solves the last colour's rows exactly from their updated neighbours,
    /// so their residual is zero up to rounding and is not recomputed.
    residual_start: Vec<u32>,
    residual_members: Vec<u32>,
}

impl Transfer {
    fn select_residual_members(&mut self, colouring: &Colouring) {
        let last = colouring.colours().saturating_sub(1);
        self.residual_start.clear();
        self.residual_start.push(0);
        self.residual_members.clear();
        for big_i in 0..self.start.len() - 1 {
            let rows = &self.members[self.start[big_i] as usize..self.start[big_i + 1] as usize];
            self.residual_members.extend(rows.iter().filter(|&&i| colouring.colours() == 1 || colouring.colour_of(i as usize) != last));
            self.residual_start.push(self.residual_members.len() as u32);
        }
    }
}

/// Smoother data of one level: its colouring and inverse diagonal.
#[derive(Clone, Debug, Default)]
struct Smoother {
    colouring: Colouring,
    inv_diag: Vec<f32>,
}

/// Work vectors of the coarse level of one transfer: right-hand side, correction and the K-cycle
/// vectors (two preconditioned directions, their images, the updated residual).
#[derive(Clone, Debug, Default)]
struct LevelWork {
    bc: Vec<f32>,
    xc: Vec<f32>,
    v1: Vec<f32>,
    v2: Vec<f32>,
    w1: Vec<f32>,
    w2: Vec<f32>,
    rt: Vec<f32>,
}

/// Dense Cholesky factor L (row-major, lower) of the coarsest matrix.
#[derive(Clone, Debug, Default)]
struct Dense {
    n: usize,
    l: Vec<f64>,
}

/// The hierarchy. [`Amg::setup`] must be called with the matrix later handed to `apply`.
#[derive(Clone, Debug, Default)]
pub struct Amg {
    transfers: Vec<Transfer>,
    /// Level 0: the f32 copy of the matrix of the last setup.
    fine: Csr<f32>,
    /// Matrices of levels 1..L.
    coarse: Vec<Csr<f32>>,
    /// Smoothers of levels 0..L−1 (the coarsest level has its own solve).
    smoothers: Vec<Smoother>,
    work: Vec<LevelWork>,
    dense: Option<Dense>,
    /// Smoother of the coarsest level when coarsening stalled before it was small.
    coarsest_smoother: Smoother,
    marker: Vec<usize>,
    pair_tmp: Csr<f32>,
    agg1: Vec<u32>,
    agg2: Vec<u32>,
    scratch_start: Vec<u32>,
    scratch_members: Vec<u32>,
    /// Sparsity pattern of the finest matrix of the last setup.
    pattern_rows: Vec<u32>,
    pattern_cols: Vec<u32>,
    ctx: Ctx,
}

impl Amg {
    /// Makes the next [`Amg::setup`] aggregate afresh even if the sparsity pattern is unchanged.
    pub fn forget_aggregation(&mut self) {
        self.pattern_rows.clear();
        self.pattern_cols.clear();
    }

    /// Builds the hierarchy for `a`: aggregation, colourings and values, or only the values
    /// when `a` has the sparsity pattern of the previous setup.
    pub fn setup(&mut self, a: &Csr) {
        if !self.smoothers.is_empty() && self.pattern_rows == a.row_start && self.pattern_cols == a.col {
            self.update_values(a);
            return;
        }
        self.pattern_rows.clone_from(&a.row_start);
        self.pattern_cols.clone_from(&a.col);
        self.fine.n = a.n;
        self.fine.row_start.clone_from(&a.row_start);
        self.fine.col.clone_from(&a.col);
        single_precision_values(a, &mut self.fine);
        // the previous levels' storage is reused (no allocation once it is large enough)
        let mut level = 0;
        loop {
            let (done, rest) = self.coarse.split_at_mut(level);
            let fine: &Csr<f32> = if level == 0 { &self.fine } else { &done[level - 1] };
            let n = fine.n;
            if n <= DENSE_MAX {
                break;
            }
            // double pairwise: pair on the fine matrix, then pair the pairs
            let n1 = pairwise(fine, &mut self.agg1);
            galerkin(fine, &self.agg1, n1, &mut self.pair_tmp, &mut self.marker, &mut self.scratch_start, &mut self.scratch_members);
            let n2 = pairwise(&self.pair_tmp, &mut self.agg2);
            if level == self.transfers.len() {
                self.transfers.push(Transfer::default());
            }
            let t = &mut self.transfers[level];
            t.agg.clear();
            t.agg.extend(self.agg1.iter().map(|&i| self.agg2[i as usize]));
            members(&t.agg, n2, &mut t.start, &mut t.members);
            let mut fresh = Csr::default();
            let c = match rest.first_mut() {
                Some(c) => c,
                None => &mut fresh,
            };
            coarse_pattern(fine, t, n2, c, &mut self.marker);
            coarse_values(fine, t, c);
            if rest.is_empty() {
                self.coarse.push(fresh);
            }
            let stalled = n2 * 10 > n * 9;
            level += 1;
            if stalled {
                break;
            }
        }
        self.transfers.truncate(level);
        self.coarse.truncate(level);
        self.smoothers.resize_with(level, Smoother::default);
        for k in 0..level {
            let m = if k == 0 { &self.fine } else { &self.coarse[k - 1] };
            self.smoothers[k].colouring.build(m);
            self.transfers[k].select_residual_members(&self.smoothers[k].colouring);
        }
        let last = self.coarse.last().unwrap_or(&self.fine);
        self.coarsest_smoother.colouring.build(last);
        self.work.resize_with(level, LevelWork::default);
        for k in 0..level {
            let nc = self.coarse[k].n;
            let w = &mut self.work[k];
            for v in [&mut w.bc, &mut w.xc, &mut w.v1, &mut w.v2, &mut w.w1, &mut w.w2, &mut w.rt] {
                v.resize(nc, 0.0);
            }
        }
        self.finish_values();
    }

    /// Coarse values of the kept aggregation for new fine values.
    fn update_values(&mut self, a: &Csr) {
        single_precision_values(a, &mut self.fine);
        for k in 0..self.transfers.len() {
            let (done, rest) = self.coarse.split_at_mut(k);
            let fine = if k == 0 { &self.fine } else { &done[k - 1] };
            coarse_values(fine, &self.transfers[k], &mut rest[0]);
        }
        self.finish_values();
    }

    /// Inverse diagonals and the coarsest factor.
    fn finish_values(&mut self) {
        for k in 0..self.smoothers.len() {
            let m = if k == 0 { &self.fine } else { &self.coarse[k - 1] };
            inverse_diagonal(m, &mut self.smoothers[k].inv_diag);
        }
        let last = self.coarse.last().unwrap_or(&self.fine);
        self.dense = if last.n <= DENSE_LIMIT { cholesky(last) } else { None };
        if self.dense.is_none() {
            inverse_diagonal(last, &mut self.coarsest_smoother.inv_diag);
        }
    }

    /// (rows, off-diagonal entries, colours) of every level but the coarsest.
    pub fn level_sizes(&self) -> Vec<(usize, usize, usize)> {
        self.smoothers
            .iter()
            .enumerate()
            .map(|(k, s)| {
                let (n, nnz) =
                    if k == 0 { (self.pattern_rows.len() - 1, self.pattern_cols.len()) } else { (self.coarse[k - 1].n, self.coarse[k - 1].col.len()) };
                (n, nnz, s.colouring.colours())
            })
            .collect()
    }

    /// Bytes streamed by all `apply` calls so far: every array a kernel touches counted once
    /// per pass (matrix rows 8 B per off-diagonal + 4 B row start + 4 B diagonal, 8 B per f64
    /// and 4 B per f32 vector entry read or written, 4 B per index; rows a kernel skips are not
    /// counted), i.e. the traffic with perfect reuse of the
    /// gathered x entries within a pass and none between passes — what a bandwidth-bound
    /// implementation must move.
    pub fn bytes_streamed(&self) -> f64 {
        self.ctx.bytes
    }

    pub fn levels(&self) -> usize {
        self.coarse.len() + 1
    }
}

impl Preconditioner for Amg {
    /// One cycle on the hierarchy of the last [`Amg::setup`], whose matrix `_a` must be.
    fn apply(&mut self, _a: &Csr, r: &[f64], z: &mut [f64]) {
        let Amg { transfers, fine, coarse, smoothers, work, dense, coarsest_smoother, ctx, .. } = self;
        let levels = Levels { transfers, coarse, smoothers, dense: dense.as_ref(), coarsest: coarsest_smoother };
        cycle(fine, r, z, &levels, 0, work, ctx);
    }
}

/// The f32 values of `a` into `out` (same pattern).
fn single_precision_values(a: &Csr, out: &mut Csr<f32>) {
    out.val.resize(a.val.len(), 0.0);
    out.diag.resize(a.n, 0.0);
    let (val, diag) = (&a.val, &a.diag);
    par_update(&mut out.val[..], |k, v| *v = val[k] as f32);
    par_update(&mut out.diag[..], |i, d| *d = diag[i] as f32);
}

/// Mutable state threaded through the cycle: the reduction buffer and the byte tally.
#[derive(Clone, Debug, Default)]
struct Ctx {
    red: Reducer,
    /// Bytes the executed kernels stream (each array a kernel touches counted once per pass:
    /// the compulsory traffic, see [`Amg::bytes_streamed`]).
    bytes: f64,
}

/// Bytes of one entry of `T`.
fn size<T>() -> f64 {
    std::mem::size_of::<T>() as f64
}

/// Bytes of a matrix pass: row starts, columns, values and diagonal.
fn matrix_bytes<T: Real>(a: &Csr<T>) -> f64 {
    (4.0 + size::<T>()) * a.col.len() as f64 + 4.0 * (a.n + 1) as f64 + size::<T>() * a.n as f64
}

/// A multicolour sweep on vectors of `V`: the matrix without its diagonal, the colour order,
/// b, 1/diag and x read and written.
fn sweep_bytes<T: Real, V: Real>(a: &Csr<T>) -> f64 {
    matrix_bytes(a) + (4.0 + 3.0 * size::<V>()) * a.n as f64
}

/// Read-only parts of the hierarchy.
struct Levels<'a> {
    transfers: &'a [Transfer],
    coarse: &'a [Csr<f32>],
    smoothers: &'a [Smoother],
    dense: Option<&'a Dense>,
    coarsest: &'a Smoother,
}

/// Exact (dense) or approximate (two symmetric sweeps, when coarsening stalled) coarsest solve.
fn coarsest<V: Real>(a: &Csr<f32>, b: &[V], x: &mut [V], levels: &Levels, ctx: &mut Ctx) {
    match levels.dense {
        Some(d) => {
            ctx.bytes += 8.0 * (d.n * d.n) as f64 + 2.0 * size::<V>() * d.n as f64;
            let mut bd = [0.0; DENSE_LIMIT];
            let mut xd = [0.0; DENSE_LIMIT];
            for (bd, b) in bd.iter_mut().zip(b) {
                *bd = b.get();
            }
            d.solve(&bd[..d.n], &mut xd[..d.n]);
            for (x, xd) in x.iter_mut().zip(&xd) {
                *x = V::put(*xd);
            }
        }
        None => {
            let s = levels.coarsest;
            ctx.bytes += 4.0 * sweep_bytes::<f32, V>(a);
            sweep_from_zero(a, &s.inv_diag, &s.colouring, b, x);
            for forward in [false, true, false] {
                sweep(a, &s.inv_diag, &s.colouring, b, x, forward);
            }
        }
    }
}

/// x = B b, one cycle from x = 0 on level `k` (matrix `a`). Level 0 works on the f64 vectors of
/// CG (`V` = f64) with the f32 matrix copy; the coarse levels on f32 vectors. Every kernel
/// computes in f64.
fn cycle<V: Real>(a: &Csr<f32>, b: &[V], x: &mut [V], levels: &Levels, k: usize, work: &mut [LevelWork], ctx: &mut Ctx) {
    if k == levels.transfers.len() {
        coarsest(a, b, x, levels, ctx);
        return;
    }
    let t = &levels.transfers[k];
    let s = &levels.smoothers[k];
    let ac = &levels.coarse[k];
    ctx.bytes += cycle_bytes::<V>(a, t, s, ac.n);
    let (w, rest) = work.split_first_mut().expect("one work set per transfer");
    sweep_from_zero(a, &s.inv_diag, &s.colouring, b, x);
    // restricted residual bc = Pᵀ(b − A x), fused (no fine residual vector)
    {
        let x = &*x;
        par_update(&mut w.bc[..], |c, bc| {
            let mut sum = 0.0;
            for &i in &t.residual_members[t.residual_start[c] as usize..t.residual_start[c + 1] as usize] {
                let i = i as usize;
                sum += b[i].get() - a.diag[i].get() * x[i].get() - a.row_off_diagonal(i, x);
            }
            *bc = sum as f32;
        });
    }
    if k + 1 == levels.transfers.len() {
        coarsest(ac, &w.bc, &mut w.xc, levels, ctx);
    } else if ac.n * KCYCLE_MIN_RATIO <= a.n && ac.n >= KCYCLE_MIN_ROWS {
        k_cycle_correction(ac, w, levels, k + 1, rest, ctx);
    } else {
        // poor coarsening (weakly coupled rows near the bottom of the hierarchy): one visit, or
        // the K-cycle's two visits per level would multiply without the work shrinking
        cycle(ac, &w.bc, &mut w.xc, levels, k + 1, rest, ctx);
    }
    // prolongation; the backward sweep starts with the last colour and overwrites those rows
    // from their (corrected) neighbours alone, so they are not corrected here
    let xc = &w.xc;
    let corrected = &s.colouring.order[..s.colouring.start[s.colouring.colours().saturating_sub(1)] as usize];
    let xs = Out::of(x);
    // SAFETY: every row appears once in the colour order
    par_range(corrected.len(), |m| unsafe {
        let i = corrected[m] as usize;
        let p = xs.ptr(i);
        *p = V::put((*p).get() + xc[t.agg[i] as usize] as f64);
    });
    sweep(a, &s.inv_diag, &s.colouring, b, x, false);
}

/// Bytes one visit of [`cycle`] streams on a level of `a.n` rows above one of `nc`: the
/// zero-start sweep (the first colour without the matrix), the restriction of the residuals
/// that are not zero, the prolongation to the rows the backward sweep does not overwrite, and
/// the backward sweep.
fn cycle_bytes<V: Real>(a: &Csr<f32>, t: &Transfer, s: &Smoother, nc: usize) -> f64 {
    let n = a.n as f64;
    let first = s.colouring.start.get(1).copied().unwrap_or(0) as f64;
    let last = s.colouring.start.len().checked_sub(2).map_or(0, |k| s.colouring.start[k]) as f64;
    let row_share = |rows: f64| if n > 0.0 { rows / n } else { 0.0 };
    let zero_start = sweep_bytes::<f32, V>(a) * row_share(n - first) + (4.0 + 2.0 * size::<V>() + 4.0) * first;
    let restricted = t.residual_members.len() as f64;
    let restriction = matrix_bytes(a) * row_share(restricted) + (4.0 + 2.0 * size::<V>()) * restricted + 12.0 * nc as f64;
    let prolongation = (12.0 + 2.0 * size::<V>()) * last;
    zero_start + restriction + prolongation + sweep_bytes::<f32, V>(a)
}

/// Coarse correction xc ≈ Aᶜ⁻¹ bc on level `k` by at most two flexible-CG steps preconditioned
/// with the next cycle (Notay & Vassilevski 2008, Algorithm 3.1 with t = [`KCYCLE_SKIP`]).
fn k_cycle_correction(ac: &Csr<f32>, w: &mut LevelWork, levels: &Levels, k: usize, rest: &mut [LevelWork], ctx: &mut Ctx) {
    let n = ac.n;
    let LevelWork { bc, xc, v1, v2, w1, w2, rt } = w;
    cycle(ac, bc, v1, levels, k, rest, ctx);
    let red = &mut ctx.red;
    let nf = n as f64;
    // product with two sums, two sums, residual update (f32 vectors)
    ctx.bytes += matrix_bytes(ac) + 12.0 * nf + 8.0 * nf + 12.0 * nf;
    let [rho1, alpha1] = ac.multiply_sum2(v1, w1, red, |i, w| [v1[i] as f64 * w, v1[i] as f64 * bc[i] as f64]);
    if rho1 <= 0.0 || !rho1.is_finite() {
        xc.fill(0.0);
        return;
    }
    let a1 = alpha1 / rho1;
    par_update(&mut rt[..], |i, r| *r = (bc[i] as f64 - a1 * w1[i] as f64) as f32);
    let [rt2, bc2] = red.sum2(n, |i| [rt[i] as f64 * rt[i] as f64, bc[i] as f64 * bc[i] as f64]);
    if rt2 <= KCYCLE_SKIP * KCYCLE_SKIP * bc2 {
        ctx.bytes += 8.0 * nf;
        par_update(&mut xc[..], |i, x| *x = (a1 * v1[i] as f64) as f32);
        return;
    }
    cycle(ac, rt, v2, levels, k, rest, ctx);
    let red = &mut ctx.red;
    // product with two sums, a sum, combination
    ctx.bytes += matrix_bytes(ac) + 12.0 * nf + 8.0 * nf + 12.0 * nf;
    let [gamma, beta] = ac.multiply_sum2(v2, w2, red, |i, w| [v2[i] as f64 * w1[i] as f64, v2[i] as f64 * w]);
    let alpha2 = red.sum(n, |i| v2[i] as f64 * rt[i] as f64);
    let rho2 = beta - gamma * gamma / rho1;
    if rho2 <= 0.0 || !rho2.is_finite() {
        par_update(&mut xc[..], |i, x| *x = (a1 * v1[i] as f64) as f32);
        return;
    }
    let (c1, c2) = (a1 - gamma * alpha2 / (rho1 * rho2), alpha2 / rho2);
    par_update(&mut xc[..], |i, x| *x = (c1 * v1[i] as f64 + c2 * v2[i] as f64) as f32);
}

#[cfg(test)]
mod tests {
    use super::super::pcg::Pcg;
    use super::super::{Jacobi, Tolerance};
    use super::*;

    /// 5-point Laplacian on an nx × ny grid with Dirichlet walls (SPD).
    pub fn laplacian(nx: usize, ny: usize) -> Csr {
        let n = nx * ny;
        let mut a = Csr { n, row_start: vec![0], ..Default::default() };
        for j in 0..ny {
            for i in 0..nx {
                let mut d = 0.0;
                for (di, dj) in [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)] {
                    let (ii, jj) = (i as i64 + di, j as i64 + dj);
                    d += 1.0;
                    if ii >= 0 && jj >= 0 && (ii as usize) < nx && (jj as usize) < ny {
                        a.col.push((jj as usize * nx + ii as usize) as u32);
                        a.val.push(-1.0);
                    }
                }
                a.diag.push(d);
                a.row_start.push(a.col.len() as u32);
            }
        }
        a
    }

    #[test]
    fn rounding_noise_in_the_coefficients_does_not_break_the_regular_coarsening_of_a_uniform_grid() {
        // the face geometry of a uniform mesh gives couplings equal only up to rounding; with
        // the strongest-neighbour choice following that noise, the lid-driven cavity's coarse
        // levels had 5–6 colours and its solves took 62 instead of 34 CG iterations per step
        let mut a = laplacian(64, 48);
        for (k, v) in a.val.iter_mut().enumerate() {
            *v *= 1.0 + 1e-15 * (((k * 7919) % 13) as f64 - 6.0);
        }
        let mut amg = Amg::default();
        amg.setup(&a);
        let sizes = amg.level_sizes();
        assert!(sizes.len() >= 3, "{sizes:?}");
        for (k, &(rows, _, colours)) in sizes.iter().enumerate() {
            assert_eq!(rows, 64 * 48 >> (2 * k), "level {k}: 2 × 2 aggregates ({sizes:?})");
            assert_eq!(colours, 2, "level {k}: a chequerboard ({sizes:?})");
        }
    }

    #[test]
    fn amg_cg_solves_a_poisson_problem_in_far_fewer_iterations_than_jacobi_cg() {
        let a = laplacian(200, 150);
        let b: Vec<f64> = (0..a.n).map(|i| ((i * 31) % 17) as f64 - 8.0).collect();
        let tol = Tolerance { tolerance: 1e-12, max_iterations: 5000 };
        let mut amg = Amg::default();
        amg.setup(&a);
        let mut x = vec![0.0; a.n];
        let s_amg = Pcg::default().solve(&a, &b, &mut x, &mut amg, tol);
        let mut ax = vec![0.0; a.n];
        a.multiply(&x, &mut ax);
        let err = ax.iter().zip(&b).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max);
        // normalised residual 1e-12 of a right-hand side of size ~8 per row
        assert!(err < 1e-8, "max |Ax - b| = {err}");
        let mut y = vec![0.0; a.n];
        let s_jac = Pcg::default().solve(&a, &b, &mut y, &mut Jacobi, tol);
        eprintln!("levels {} AMG-CG {} iterations, Jacobi-CG {}", amg.levels(), s_amg.iterations, s_jac.iterations);
        assert!(s_amg.final_residual < 1e-12 && s_jac.final_residual < 1e-12);
        assert!(s_amg.iterations * 5 < s_jac.iterations, "{s_amg:?} vs {s_jac:?}");
    }
}
