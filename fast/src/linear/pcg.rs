//! Flexible preconditioned conjugate gradients (FCG(1), Notay 2000) for the symmetric positive
//! definite pressure equation: β = z_{k+1}·(r_{k+1} − r_k)/(z_k·r_k) (Polak–Ribière form), which
//! equals the classical β for a fixed SPD preconditioner and keeps CG convergent when the
//! preconditioner varies slightly between iterations (the K-cycle AMG of [`super::amg`] is a
//! nonlinear operator: its inner Krylov steps depend on the residual).

use super::csr::Csr;
use super::gang::{self, Crew, Slot};
use super::{Preconditioner, SolveStats, Tolerance};

/// Work vectors of CG (kept between solves: no allocation once sized), shared by the members of
/// the gang that runs a solve.
#[derive(Clone, Debug, Default)]
pub struct Pcg {
    r: Vec<Slot<f64>>,
    z: Vec<Slot<f64>>,
    p: Vec<Slot<f64>>,
    q: Vec<Slot<f64>>,
    partials: Vec<Slot<[f64; 2]>>,
    /// Bytes streamed by the CG kernels (as [`super::amg::Amg::bytes_streamed`], excluding the
    /// preconditioner).
    bytes: f64,
}

/// OpenFOAM's normalisation factor Σ|Ax − Ax̄| + Σ|b − Ax̄| + 10⁻²⁰ (x̄ = mean of x), given
/// ax = A x; A x̄ = x̄ · (row sums of A).
pub(super) fn normalisation(crew: &Crew, a: &Csr, b: &[f64], x: &[Slot<f64>], ax: &[Slot<f64>]) -> f64 {
    let n = a.n;
    // SAFETY: x and ax are not written during these sums
    let mean = crew.sum(n, |i| unsafe { x[i].get() }) / n as f64;
    crew.sum(n, |i| {
        let a_mean = mean * a.row_sum(i);
        (unsafe { ax[i].get() } - a_mean).abs() + (b[i] - a_mean).abs()
    }) + 1e-20
}

impl Pcg {
    fn size(&mut self, n: usize) {
        for v in [&mut self.r, &mut self.z, &mut self.p, &mut self.q] {
            v.resize_with(n, Slot::default);
        }
        self.partials.resize_with(gang::partials_for(n), Slot::default);
    }

    /// Bytes streamed by the CG iterations so far (the preconditioner counts its own).
    pub fn bytes_streamed(&self) -> f64 {
        self.bytes
    }

    /// Solves A x = b from the initial guess in `x`, on a gang of the current pool's threads.
    pub fn solve(&mut self, a: &Csr, b: &[f64], x: &mut [f64], m: &mut impl Preconditioner, tol: Tolerance) -> SolveStats {
        let n = a.n;
        self.size(n);
        let Pcg { r, z, p, q, partials, bytes } = self;
        let (r, z, p, q, x) = (&r[..], &z[..], &p[..], &q[..], Slot::from_mut_slice(x));
        let shared = &*m;
        let (stats, cg_bytes, m_bytes) = gang::run(n, partials, |crew| iterate(crew, a, b, x, [r, z, p, q], shared, tol));
        *bytes += cg_bytes;
        m.record_bytes(m_bytes);
        stats
    }
}

/// The CG iterations, run by every member of `crew`: (statistics, bytes of the CG kernels,
/// bytes of the preconditioner).
//
// SAFETY (every unsafe read and write below): a loop writes only its own entries (its block's,
// or its chunk's in a sum) of the vectors it writes, and reads the entries it writes or entries
// of vectors no member writes in that loop; the barrier that ends each loop orders its writes
// before the reads of the loops after it.
fn iterate(
    crew: &Crew,
    a: &Csr,
    b: &[f64],
    x: &[Slot<f64>],
    [r, z, p, q]: [&[Slot<f64>]; 4],
    m: &impl Preconditioner,
    tol: Tolerance,
) -> (SolveStats, f64, f64) {
    let n = a.n;
    let (mut bytes, mut m_bytes) = (0.0, 0.0);
    let at = |v: &[Slot<f64>], i: usize| unsafe { v[i].get() };
    let matrix = (12 * a.col.len() + 4 * (n + 1) + 8 * n) as f64;
    let nf = n as f64;
    a.multiply_shared(crew, x, q);
    let norm = normalisation(crew, a, b, x, q);
    crew.for_each(n, |i| unsafe { r[i].set(b[i] - at(q, i)) });
    let mut residual = crew.sum(n, |i| at(r, i).abs()) / norm;
    let mut stats = SolveStats { iterations: 0, initial_residual: residual, final_residual: residual };
    if residual < tol.tolerance {
        return (stats, bytes, m_bytes);
    }
    m.apply(crew, a, r, z, &mut m_bytes);
    crew.for_each(n, |i| unsafe { p[i].set(at(z, i)) });
    let mut rz = crew.sum(n, |i| at(r, i) * at(z, i));
    while stats.iterations < tol.max_iterations {
        stats.iterations += 1;
        // product with p·q, fused update + |r| (x, r read and written, p, q read), r·z and
        // z·q, p update
        bytes += matrix + 16.0 * nf + 48.0 * nf + 24.0 * nf + 24.0 * nf;
        let [pq, _] = a.multiply_sum2_shared(crew, p, q, |i, qi| [at(p, i) * qi, 0.0]);
        if pq == 0.0 || !pq.is_finite() {
            break;
        }
        let alpha = rz / pq;
        // update and residual norm in one pass
        residual = crew.sum(n, |i| unsafe {
            x[i].set(x[i].get() + alpha * at(p, i));
            let ri = r[i].get() - alpha * at(q, i);
            r[i].set(ri);
            ri.abs()
        }) / norm;
        if residual < tol.tolerance {
            break;
        }
        m.apply(crew, a, r, z, &mut m_bytes);
        // r_{k+1} − r_k = −α q, so z_{k+1}·(r_{k+1} − r_k) = −α z_{k+1}·q
        let [rz_new, zq] = crew.sum2(n, |i| [at(r, i) * at(z, i), at(z, i) * at(q, i)]);
        let beta = -alpha * zq / rz;
        rz = rz_new;
        crew.for_each(n, |i| unsafe { p[i].set(at(z, i) + beta * at(p, i)) });
    }
    stats.final_residual = residual;
    (stats, bytes, m_bytes)
}
