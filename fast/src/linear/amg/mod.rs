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
//! This module holds the hierarchy; [`coarsening`] builds the levels (pairwise aggregation,
//! Galerkin products, the coarsest level's Cholesky factor), [`cycle`] applies them.
//!
//! The aggregation and the colourings are sequential and in index order (deterministic). When a
//! matrix has the sparsity pattern of the previous setup, they are kept and only the values are
//! recomputed (inverse diagonals and coarse matrices through a precomputed fine-entry →
//! coarse-entry map), which is cheap enough to do for every solve. The setup's other loops run
//! on rayon; the cycle runs on the gang of threads of the solve that applies it
//! ([`super::gang`]), its results independent of the thread count (fixed-chunk reductions,
//! multicolour sweeps).
//!
//! The hierarchy is stored in f32: an f32 copy of the fine matrix, and f32 coarse matrices and
//! coarse vectors; the kernels compute in f64 and level 0 reads and writes CG's f64 vectors. A
//! preconditioner only has to approximate A⁻¹, and the flexible CG around it keeps its own
//! residual in f64, so the solves still reach 1e-12 (the equivalence tests' setting) with the
//! same iteration counts, while the cycle moves about a third fewer bytes (lid-driven cavity
//! 384², 2 threads: 1.68 → 1.45 µs per cell-step).

use super::csr::Csr;
use super::gang::{self, Crew, PartialSum, Slot};
use super::par_update;
use super::smoother::{inverse_diagonal, Colouring};
use super::Preconditioner;

mod coarsening;
mod cycle;
use coarsening::{cholesky, coarse_pattern, coarse_values, galerkin, members, pairwise};
use cycle::{cycle, Levels};

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
/// A coarse correction on a level of fewer rows than this runs on one member of the gang while
/// the others wait at one barrier: its loops (a colour of a few hundred rows) are shorter than
/// the barriers after them, some twenty a visit of such a level and the levels below it.
const SOLO_ROWS: usize = 1024;
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
    bc: Vec<Slot<f32>>,
    xc: Vec<Slot<f32>>,
    v1: Vec<Slot<f32>>,
    v2: Vec<Slot<f32>>,
    w1: Vec<Slot<f32>>,
    w2: Vec<Slot<f32>>,
    rt: Vec<Slot<f32>>,
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
    /// Chunk sums of the coarse corrections run by one member ([`SOLO_ROWS`]).
    solo_partials: Vec<PartialSum>,
    /// Bytes the executed kernels stream (see [`Amg::bytes_streamed`]).
    bytes: f64,
}

impl Amg {
    /// Makes the next [`Amg::setup`] aggregate afresh even if the sparsity pattern is unchanged.
    pub fn forget_aggregation(&mut self) {
        self.pattern_rows.clear();
        self.pattern_cols.clear();
    }

    /// Whether the hierarchy was set up for a matrix of `a`'s size (rows and entries).
    pub fn fits(&self, a: &Csr) -> bool {
        !self.smoothers.is_empty() && self.pattern_rows.len() == a.row_start.len() && self.pattern_cols.len() == a.col.len()
    }

    /// Whether the hierarchy was set up for a matrix of `a`'s sparsity pattern (a [`Amg::setup`]
    /// for `a` then keeps its aggregation).
    pub fn has_pattern_of(&self, a: &Csr) -> bool {
        !self.smoothers.is_empty() && self.pattern_rows == a.row_start && self.pattern_cols == a.col
    }

    /// Builds the hierarchy for `a`: aggregation, colourings and values, or only the values
    /// when `a` has the sparsity pattern of the previous setup.
    pub fn setup(&mut self, a: &Csr) {
        if self.has_pattern_of(a) {
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
        if self.solo_partials.is_empty() {
            self.solo_partials = gang::solo_partials(SOLO_ROWS);
        }
        for k in 0..level {
            let nc = self.coarse[k].n;
            let w = &mut self.work[k];
            for v in [&mut w.bc, &mut w.xc, &mut w.v1, &mut w.v2, &mut w.w1, &mut w.w2, &mut w.rt] {
                v.resize_with(nc, Slot::default);
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
        self.bytes
    }

    pub fn levels(&self) -> usize {
        self.coarse.len() + 1
    }
}

impl Preconditioner for Amg {
    /// One cycle on the hierarchy of the last [`Amg::setup`], whose matrix `_a` must be.
    unsafe fn apply(&self, crew: &Crew, _a: &Csr, r: &[Slot<f64>], z: &[Slot<f64>], bytes: &mut f64) {
        let Amg { transfers, fine, coarse, smoothers, work, dense, coarsest_smoother, solo_partials, .. } = self;
        let levels = Levels { transfers, coarse, smoothers, dense: dense.as_ref(), coarsest: coarsest_smoother, solo_partials };
        // SAFETY: the caller's promise; the work vectors are this solve's (one at a time)
        unsafe { cycle(crew, fine, r, z, &levels, 0, work, bytes) };
    }

    fn record_bytes(&mut self, bytes: f64) {
        self.bytes += bytes;
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

    /// The whole K-cycle CG (sweeps, restrictions, products with sums, the coarse K-cycle
    /// steps, the coarse corrections one member runs alone, the dense coarsest solve) on a gang
    /// of two threads gives the bits of one thread.
    #[test]
    fn a_gang_of_two_threads_solves_with_the_bits_of_one() {
        let a = laplacian(96, 64);
        assert!(a.n >= crate::linear::gang::GANG_MIN_ROWS);
        let b: Vec<f64> = (0..a.n).map(|i| ((i * 31) % 17) as f64 - 8.0 + 1e-3 * i as f64).collect();
        let tol = Tolerance { tolerance: 1e-12, max_iterations: 500 };
        let solve = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                crate::team::keep_awake(|| {
                    let mut amg = Amg::default();
                    amg.setup(&a);
                    let sizes = amg.level_sizes();
                    assert!(sizes.iter().any(|&(rows, _, _)| rows < SOLO_ROWS) && sizes[1].0 >= SOLO_ROWS, "levels shared and alone: {sizes:?}");
                    let mut x = vec![0.0; a.n];
                    let gangs = || crate::linear::gang::GANGS_OF_SEVERAL.with(|c| c.get());
                    let before = gangs();
                    let stats = Pcg::default().solve(&a, &b, &mut x, &mut amg, tol);
                    (x, stats, gangs() - before)
                })
            })
        };
        let (x_one, stats_one, _) = solve(1);
        assert!(stats_one.final_residual < 1e-12, "{stats_one:?}");
        let (x_two, stats_two) =
            (0..50).map(|_| solve(2)).find(|(_, _, gangs)| *gangs > 0).map(|(x, s, _)| (x, s)).expect("a gang of two threads formed in 50 tries");
        assert_eq!(stats_one, stats_two);
        assert!(x_one.iter().zip(&x_two).all(|(p, q)| p.to_bits() == q.to_bits()), "the bits of one thread");
    }

    /// With the aggregation made on a matrix of the mesh alone, a solve does not depend on the
    /// matrices set up before it: a hierarchy that kept its aggregation from an earlier matrix
    /// solves with the bits of one set up for this matrix alone (a restarted run).
    #[test]
    fn a_hierarchy_aggregated_on_a_fixed_matrix_solves_as_one_set_up_afresh() {
        let geometric = laplacian(80, 60);
        // coefficients varying by 2× over the grid, and differently from one step to the next
        let step_matrix = |step: f64| {
            let mut a = geometric.clone();
            for (k, v) in a.val.iter_mut().enumerate() {
                *v *= 1.0 + 0.5 * ((k as f64 * 0.013 + step).sin() + 1.0);
            }
            for r in 0..a.n {
                a.diag[r] = -a.val[a.row_start[r] as usize..a.row_start[r + 1] as usize].iter().sum::<f64>() + 1e-3;
            }
            a
        };
        let (first, second) = (step_matrix(0.0), step_matrix(1.7));
        let b: Vec<f64> = (0..second.n).map(|i| ((i * 31) % 17) as f64 - 8.0).collect();
        let tol = Tolerance { tolerance: 1e-12, max_iterations: 500 };
        let solve = |amg: &mut Amg| {
            let mut x = vec![0.0; second.n];
            let stats = Pcg::default().solve(&second, &b, &mut x, amg, tol);
            (x.iter().map(|v| v.to_bits()).collect::<Vec<_>>(), stats)
        };
        // aggregated on `geometric`, each later setup keeps the aggregation (the same pattern)
        let mut kept = Amg::default();
        for a in [&geometric, &first, &second] {
            kept.setup(a);
        }
        let mut afresh = Amg::default();
        for a in [&geometric, &second] {
            afresh.setup(a);
        }
        let (x_kept, stats_kept) = solve(&mut kept);
        assert!(stats_kept.final_residual < 1e-12, "{stats_kept:?}");
        assert_eq!((x_kept, stats_kept), solve(&mut afresh));
        // aggregated on the step's own matrix instead, the hierarchy is another one
        let mut own = Amg::default();
        own.setup(&second);
        assert_ne!(solve(&mut own).0, solve(&mut afresh).0, "the aggregation matrix matters (else the test shows nothing)");
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
