//! Building the levels of the aggregation multigrid (parent module doc): greedy pairwise
//! aggregation, the coarse sparsity pattern and values of Aᶜ = PᵀAP, and the dense Cholesky
//! factor of the coarsest matrix.

use rayon::prelude::*;

use super::super::reduce::CHUNK;
use super::super::Out;
use super::*;

/// Greedy pairwise aggregation in row order: each unaggregated row pairs with its strongest
/// unaggregated strong neighbour (or stays alone). Returns the number of aggregates.
pub(super) fn pairwise(a: &Csr<f32>, agg: &mut Vec<u32>) -> usize {
    agg.clear();
    agg.resize(a.n, NONE);
    let mut nc = 0u32;
    for i in 0..a.n {
        if agg[i] != NONE {
            continue;
        }
        let (lo, hi) = (a.row_start[i] as usize, a.row_start[i + 1] as usize);
        let max_neg = a.val[lo..hi].iter().fold(0.0f64, |m, &v| m.max(-(v as f64)));
        let mut best = NONE;
        let mut best_v = 0.0;
        for k in lo..hi {
            let j = a.col[k];
            let v = -(a.val[k] as f64);
            if j as usize != i && agg[j as usize] == NONE && v >= STRENGTH * max_neg && v > best_v * TIE {
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

pub(super) fn members(agg: &[u32], nc: usize, start: &mut Vec<u32>, members: &mut Vec<u32>) {
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
    // fill pointers kept in start[c] (shifted back afterwards): no scratch allocation
    for (i, &c) in agg.iter().enumerate() {
        members[start[c as usize] as usize] = i as u32;
        start[c as usize] += 1;
    }
    for c in (1..=nc).rev() {
        start[c] = start[c - 1];
    }
    start[0] = 0;
}

/// Sparsity of Aᶜ = PᵀAP and the fine-entry → coarse-entry map of `t` (coarse columns in
/// order of first appearance over the members' rows).
pub(super) fn coarse_pattern(a: &Csr<f32>, t: &mut Transfer, nc: usize, out: &mut Csr<f32>, marker: &mut Vec<usize>) {
    out.n = nc;
    out.row_start.clear();
    out.row_start.push(0);
    out.col.clear();
    t.entry_map.clear();
    t.entry_map.resize(a.col.len(), NONE);
    marker.clear();
    marker.resize(nc, usize::MAX);
    for big_i in 0..nc {
        let row_begin = out.col.len();
        for &i in &t.members[t.start[big_i] as usize..t.start[big_i + 1] as usize] {
            let i = i as usize;
            for k in a.row_start[i] as usize..a.row_start[i + 1] as usize {
                let big_j = t.agg[a.col[k] as usize] as usize;
                if big_j == big_i {
                    continue;
                }
                if marker[big_j] == usize::MAX || marker[big_j] < row_begin {
                    marker[big_j] = out.col.len();
                    out.col.push(big_j as u32);
                }
                t.entry_map[k] = marker[big_j] as u32;
            }
        }
        out.row_start.push(out.col.len() as u32);
    }
    out.val.clear();
    out.val.resize(out.col.len(), 0.0);
    out.diag.clear();
    out.diag.resize(nc, 0.0);
}

/// Values of Aᶜ = PᵀAP on the pattern of [`coarse_pattern`]; each coarse row sums its members'
/// entries in member and entry order (one task per coarse row: thread-count independent).
pub(super) fn coarse_values(a: &Csr<f32>, t: &Transfer, out: &mut Csr<f32>) {
    let (od, ov) = (Out::of(&mut out.diag), Out::of(&mut out.val));
    let (rs, nc) = (&out.row_start, out.n);
    (0..nc).into_par_iter().with_min_len(CHUNK / 4).for_each(|big_i| {
        let (lo, hi) = (rs[big_i] as usize, rs[big_i + 1] as usize);
        // SAFETY: coarse row big_i owns diag[big_i] and val[lo..hi]; no other task touches them
        let row = unsafe { std::slice::from_raw_parts_mut(ov.ptr(lo), hi - lo) };
        row.fill(0.0);
        let mut d = 0.0;
        for &i in &t.members[t.start[big_i] as usize..t.start[big_i + 1] as usize] {
            let i = i as usize;
            d += a.diag[i] as f64;
            for k in a.row_start[i] as usize..a.row_start[i + 1] as usize {
                match t.entry_map[k] {
                    NONE => d += a.val[k] as f64,
                    m => row[m as usize - lo] += a.val[k],
                }
            }
        }
        unsafe { od.set(big_i, d as f32) };
    });
}

/// Aᶜ = PᵀAP for the piecewise-constant prolongation of `agg`.
pub(super) fn galerkin(a: &Csr<f32>, agg: &[u32], nc: usize, out: &mut Csr<f32>, marker: &mut Vec<usize>, start: &mut Vec<u32>, mem: &mut Vec<u32>) {
    members(agg, nc, start, mem);
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
            d += a.diag[i] as f64;
            for k in a.row_start[i] as usize..a.row_start[i + 1] as usize {
                let big_j = agg[a.col[k] as usize] as usize;
                let v = a.val[k];
                if big_j == big_i {
                    d += v as f64;
                } else if marker[big_j] != usize::MAX && marker[big_j] >= row_begin {
                    out.val[marker[big_j]] += v;
                } else {
                    marker[big_j] = out.col.len();
                    out.col.push(big_j as u32);
                    out.val.push(v);
                }
            }
        }
        out.diag.push(d as f32);
        out.row_start.push(out.col.len() as u32);
    }
}

/// Dense Cholesky factor of a (small) SPD matrix; `None` if it is not positive definite.
pub(super) fn cholesky(a: &Csr<f32>) -> Option<Dense> {
    let n = a.n;
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        m[i * n + i] = a.diag[i] as f64;
        for k in a.row_start[i] as usize..a.row_start[i + 1] as usize {
            m[i * n + a.col[k] as usize] += a.val[k] as f64;
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
    pub(super) fn solve(&self, b: &[f64], x: &mut [f64]) {
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
