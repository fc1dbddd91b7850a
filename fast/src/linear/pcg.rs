//! Flexible preconditioned conjugate gradients (FCG(1), Notay 2000) for the symmetric positive
//! definite pressure equation: β = z_{k+1}·(r_{k+1} − r_k)/(z_k·r_k) (Polak–Ribière form), which
//! equals the classical β for a fixed SPD preconditioner and keeps CG convergent when the
//! preconditioner varies slightly between iterations (the K-cycle AMG of [`super::amg`] is a
//! nonlinear operator: its inner Krylov steps depend on the residual).

use super::csr::Csr;
use super::reduce::Reducer;
use super::{par_update, Out, Preconditioner, SolveStats, Tolerance};

/// Work vectors of CG (kept between solves: no allocation once sized).
#[derive(Clone, Debug, Default)]
pub struct Pcg {
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
    red: Reducer,
    /// Bytes streamed by the CG kernels (as [`super::amg::Amg::bytes_streamed`], excluding the
    /// preconditioner).
    bytes: f64,
}

/// OpenFOAM's normalisation factor Σ|Ax − Ax̄| + Σ|b − Ax̄| + 10⁻²⁰ (x̄ = mean of x), given
/// ax = A x; A x̄ = x̄ · (row sums of A).
pub fn normalisation(a: &Csr, b: &[f64], x: &[f64], ax: &[f64], red: &mut Reducer) -> f64 {
    let n = a.n;
    let mean = red.sum(n, |i| x[i]) / n as f64;
    red.sum(n, |i| {
        let a_mean = mean * a.row_sum(i);
        (ax[i] - a_mean).abs() + (b[i] - a_mean).abs()
    }) + 1e-20
}

impl Pcg {
    fn size(&mut self, n: usize) {
        for v in [&mut self.r, &mut self.z, &mut self.p, &mut self.q] {
            v.resize(n, 0.0);
        }
    }

    /// Bytes streamed by the CG iterations so far (the preconditioner counts its own).
    pub fn bytes_streamed(&self) -> f64 {
        self.bytes
    }

    /// Solves A x = b from the initial guess in `x`.
    pub fn solve(&mut self, a: &Csr, b: &[f64], x: &mut [f64], m: &mut impl Preconditioner, tol: Tolerance) -> SolveStats {
        let n = a.n;
        self.size(n);
        let Pcg { r, z, p, q, red, bytes } = self;
        let matrix = (12 * a.col.len() + 4 * (n + 1) + 8 * n) as f64;
        let nf = n as f64;
        a.multiply(x, q);
        let norm = normalisation(a, b, x, q, red);
        par_update(&mut r[..], |i, r| *r = b[i] - q[i]);
        let mut residual = red.sum(n, |i| r[i].abs()) / norm;
        let mut stats = SolveStats { iterations: 0, initial_residual: residual, final_residual: residual };
        if residual < tol.tolerance {
            return stats;
        }
        m.apply(a, r, z);
        p.copy_from_slice(z);
        let mut rz = red.sum(n, |i| r[i] * z[i]);
        while stats.iterations < tol.max_iterations {
            stats.iterations += 1;
            // product with p·q, fused update + |r| (x, r read and written, p, q read), r·z and
            // z·q, p update
            *bytes += matrix + 16.0 * nf + 48.0 * nf + 24.0 * nf + 24.0 * nf;
            let [pq, _] = a.multiply_sum2(p, q, red, |i, qi| [p[i] * qi, 0.0]);
            if pq == 0.0 || !pq.is_finite() {
                break;
            }
            let alpha = rz / pq;
            // update and residual norm in one pass (the reduction's fixed chunks visit every
            // entry exactly once, so the writes are disjoint)
            let (xo, ro) = (Out::of(x), Out::of(r));
            let (pr, qr) = (&*p, &*q);
            residual = red.sum(n, |i| unsafe {
                // SAFETY: entry i of x and r is written by this task only
                *xo.ptr(i) += alpha * pr[i];
                let ri = *ro.ptr(i) - alpha * qr[i];
                *ro.ptr(i) = ri;
                ri.abs()
            }) / norm;
            if residual < tol.tolerance {
                break;
            }
            m.apply(a, r, z);
            // r_{k+1} − r_k = −α q, so z_{k+1}·(r_{k+1} − r_k) = −α z_{k+1}·q
            let [rz_new, zq] = red.sum2(n, |i| [r[i] * z[i], z[i] * q[i]]);
            let beta = -alpha * zq / rz;
            rz = rz_new;
            par_update(&mut p[..], |i, p| *p = z[i] + beta * *p);
        }
        stats.final_residual = residual;
        stats
    }
}
