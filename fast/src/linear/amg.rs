//! Aggregation algebraic multigrid (unsmoothed, double pairwise aggregation after Notay 2010) used
//! as a symmetric V-cycle preconditioner for CG: block Gauss–Seidel forward before and backward
//! after the coarse correction (so the cycle is a symmetric operator), Galerkin coarse matrices
//! Aᶜ = PᵀAP with piecewise-constant P, dense Cholesky on the coarsest level.
//!
//! The aggregation is sequential and in index order (deterministic); everything else runs on
//! rayon with thread-count-independent results.

use rayon::prelude::*;

use super::csr::Csr;
use super::reduce::CHUNK;
use super::smoother::{block_gauss_seidel, block_gauss_seidel_from_zero};
use super::Preconditioner;

/// Coarsest level size solved by dense Cholesky.
const DENSE_MAX: usize = 64;
/// Strength threshold: j is a strong neighbour of i if −a_ij ≥ β max_k(−a_ik).
const STRENGTH: f64 = 0.25;
const NONE: u32 = u32::MAX;

/// Map from one level to the next coarser one.
#[derive(Clone, Debug, Default)]
struct Transfer {
    /// Coarse row of each fine row.
    agg: Vec<u32>,
    /// Fine rows of coarse row I: `members[start[I]..start[I + 1]]` (ascending).
    start: Vec<u32>,
    members: Vec<u32>,
}

/// Work vectors of one level: the fine residual and scratch, and the coarse right-hand side and
/// correction of the next level.
#[derive(Clone, Debug, Default)]
struct LevelWork {
    r: Vec<f64>,
    tmp: Vec<f64>,
    bc: Vec<f64>,
    xc: Vec<f64>,
}

/// Dense Cholesky factor L (row-major, lower) of the coarsest matrix.
#[derive(Clone, Debug, Default)]
struct Dense {
    n: usize,
    l: Vec<f64>,
}

#[derive(Clone, Debug, Default)]
pub struct Amg {
    transfers: Vec<Transfer>,
    /// Matrices of levels 1..L (level 0 is the matrix handed to `apply`).
    coarse: Vec<Csr>,
    work: Vec<LevelWork>,
    dense: Option<Dense>,
    marker: Vec<usize>,
    pair_tmp: Csr,
    agg1: Vec<u32>,
    agg2: Vec<u32>,
}

impl Amg {
    /// Builds the hierarchy for `a` (aggregation and coarse matrices).
    pub fn setup(&mut self, a: &Csr) {
        self.transfers.clear();
        self.coarse.clear();
        let mut level = 0;
        loop {
            let fine: &Csr = if level == 0 { a } else { &self.coarse[level - 1] };
            let n = fine.n;
            if n <= DENSE_MAX {
                break;
            }
            // double pairwise: pair on the fine matrix, then pair the pairs
            let n1 = pairwise(fine, &mut self.agg1);
            galerkin(fine, &self.agg1, n1, &mut self.pair_tmp, &mut self.marker);
            let n2 = pairwise(&self.pair_tmp, &mut self.agg2);
            let mut t = Transfer::default();
            t.agg.extend(self.agg1.iter().map(|&i| self.agg2[i as usize]));
            members(&t.agg, n2, &mut t.start, &mut t.members);
            let mut c = Csr::default();
            galerkin(&self.pair_tmp, &self.agg2, n2, &mut c, &mut self.marker);
            let stalled = n2 * 10 > n * 9;
            self.transfers.push(t);
            self.coarse.push(c);
            level += 1;
            if stalled {
                break;
            }
        }
        let last = if level == 0 { a } else { &self.coarse[level - 1] };
        self.dense = if last.n <= 4 * DENSE_MAX { cholesky(last) } else { None };
        self.work.resize_with(level + 1, LevelWork::default);
        for k in 0..=level {
            let n = if k == 0 { a.n } else { self.coarse[k - 1].n };
            let nc = if k < level { self.coarse[k].n } else { 0 };
            let w = &mut self.work[k];
            w.r.resize(n, 0.0);
            w.tmp.resize(n, 0.0);
            w.bc.resize(nc, 0.0);
            w.xc.resize(nc, 0.0);
        }
    }

    pub fn levels(&self) -> usize {
        self.coarse.len() + 1
    }
}

impl Preconditioner for Amg {
    fn apply(&mut self, a: &Csr, r: &[f64], z: &mut [f64]) {
        cycle(a, r, z, &self.transfers, &self.coarse, &mut self.work, self.dense.as_ref());
    }
}

fn cycle(a: &Csr, b: &[f64], x: &mut [f64], transfers: &[Transfer], coarse: &[Csr], work: &mut [LevelWork], dense: Option<&Dense>) {
    let (w, rest) = work.split_first_mut().expect("one work set per level");
    if transfers.is_empty() {
        match dense {
            Some(d) => d.solve(b, x),
            None => {
                // coarsening stalled on a large level: symmetric sweeps instead of an exact solve
                block_gauss_seidel_from_zero(a, b, x, true);
                for forward in [false, true, false] {
                    w.tmp.copy_from_slice(x);
                    block_gauss_seidel(a, b, &w.tmp, x, forward);
                }
            }
        }
        return;
    }
    let t = &transfers[0];
    block_gauss_seidel_from_zero(a, b, x, true);
    w.r.par_iter_mut().with_min_len(CHUNK).enumerate().for_each(|(i, r)| *r = b[i] - a.diag[i] * x[i] - a.row_off_diagonal(i, x));
    let r = &w.r;
    w.bc.par_iter_mut().with_min_len(CHUNK).enumerate().for_each(|(c, bc)| {
        let mut s = 0.0;
        for &i in &t.members[t.start[c] as usize..t.start[c + 1] as usize] {
            s += r[i as usize];
        }
        *bc = s;
    });
    cycle(&coarse[0], &w.bc, &mut w.xc, &transfers[1..], &coarse[1..], rest, dense);
    let xc = &w.xc;
    x.par_iter_mut().with_min_len(CHUNK).enumerate().for_each(|(i, x)| *x += xc[t.agg[i] as usize]);
    w.tmp.copy_from_slice(x);
    block_gauss_seidel(a, b, &w.tmp, x, false);
}

/// Greedy pairwise aggregation in row order: each unaggregated row pairs with its strongest
/// unaggregated strong neighbour (or stays alone). Returns the number of aggregates.
fn pairwise(a: &Csr, agg: &mut Vec<u32>) -> usize {
    agg.clear();
    agg.resize(a.n, NONE);
    let mut nc = 0u32;
    for i in 0..a.n {
        if agg[i] != NONE {
            continue;
        }
        let (lo, hi) = (a.row_start[i] as usize, a.row_start[i + 1] as usize);
        let max_neg = a.val[lo..hi].iter().fold(0.0f64, |m, v| m.max(-v));
        let mut best = NONE;
        let mut best_v = 0.0;
        for k in lo..hi {
            let j = a.col[k];
            let v = -a.val[k];
            if j as usize != i && agg[j as usize] == NONE && v >= STRENGTH * max_neg && v > best_v {
                best = j;
                best_v = v;
            }
        }
        agg[i] = nc;
        if best != NONE {
            agg[best as usize] = nc;
        }
        nc += 1;
    }
    nc as usize
}

fn members(agg: &[u32], nc: usize, start: &mut Vec<u32>, members: &mut Vec<u32>) {
    start.clear();
    start.resize(nc + 1, 0);
    for &c in agg {
        start[c as usize + 1] += 1;
    }
    for c in 0..nc {
        start[c + 1] += start[c];
    }
    members.clear();
    members.resize(agg.len(), 0);
    let mut fill: Vec<u32> = start[..nc].to_vec();
    for (i, &c) in agg.iter().enumerate() {
        members[fill[c as usize] as usize] = i as u32;
        fill[c as usize] += 1;
    }
}

/// Aᶜ = PᵀAP for the piecewise-constant prolongation of `agg`.
fn galerkin(a: &Csr, agg: &[u32], nc: usize, out: &mut Csr, marker: &mut Vec<usize>) {
    let (mut start, mut mem) = (Vec::new(), Vec::new());
    members(agg, nc, &mut start, &mut mem);
    out.n = nc;
    out.row_start.clear();
    out.row_start.push(0);
    out.col.clear();
    out.val.clear();
    out.diag.clear();
    marker.clear();
    marker.resize(nc, usize::MAX);
    for big_i in 0..nc {
        let row_begin = out.col.len();
        let mut d = 0.0;
        for &i in &mem[start[big_i] as usize..start[big_i + 1] as usize] {
            let i = i as usize;
            d += a.diag[i];
            for k in a.row_start[i] as usize..a.row_start[i + 1] as usize {
                let big_j = agg[a.col[k] as usize] as usize;
                let v = a.val[k];
                if big_j == big_i {
                    d += v;
                } else if marker[big_j] != usize::MAX && marker[big_j] >= row_begin {
                    out.val[marker[big_j]] += v;
                } else {
                    marker[big_j] = out.col.len();
                    out.col.push(big_j as u32);
                    out.val.push(v);
                }
            }
        }
        out.diag.push(d);
        out.row_start.push(out.col.len() as u32);
    }
}

/// Dense Cholesky factor of a (small) SPD matrix; `None` if it is not positive definite.
fn cholesky(a: &Csr) -> Option<Dense> {
    let n = a.n;
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        m[i * n + i] = a.diag[i];
        for k in a.row_start[i] as usize..a.row_start[i + 1] as usize {
            m[i * n + a.col[k] as usize] += a.val[k];
        }
    }
    for j in 0..n {
        let mut d = m[j * n + j];
        for k in 0..j {
            d -= m[j * n + k] * m[j * n + k];
        }
        if d <= 0.0 || !d.is_finite() {
            return None;
        }
        let d = d.sqrt();
        m[j * n + j] = d;
        for i in j + 1..n {
            let mut s = m[i * n + j];
            for k in 0..j {
                s -= m[i * n + k] * m[j * n + k];
            }
            m[i * n + j] = s / d;
        }
    }
    Some(Dense { n, l: m })
}

impl Dense {
    fn solve(&self, b: &[f64], x: &mut [f64]) {
        let n = self.n;
        for i in 0..n {
            let mut s = b[i];
            for k in 0..i {
                s -= self.l[i * n + k] * x[k];
            }
            x[i] = s / self.l[i * n + i];
        }
        for i in (0..n).rev() {
            let mut s = x[i];
            for k in i + 1..n {
                s -= self.l[k * n + i] * x[k];
            }
            x[i] = s / self.l[i * n + i];
        }
    }
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
