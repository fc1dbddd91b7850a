//! Flexible preconditioned conjugate gradients (FCG(1), Notay 2000) for the symmetric positive
//! definite pressure equation: β = z_{k+1}·(r_{k+1} − r_k)/(z_k·r_k) (Polak–Ribière form), which
//! equals the classical β for a fixed SPD preconditioner and keeps CG convergent when the
//! preconditioner varies slightly between iterations (the K-cycle AMG of [`super::amg`] is a
//! nonlinear operator: its inner Krylov steps depend on the residual).

use super::csr::Csr;
use super::gang::{self, Crew, Slot};
use super::pace::{run_paced, Pace};
use super::{Preconditioner, SolveStats, Tolerance};

/// Work vectors of CG (kept between solves: no allocation once sized), shared by the members of
/// the gang that runs a solve.
#[derive(Clone, Debug, Default)]
pub struct Pcg {
    r: Vec<Slot<f64>>,
    z: Vec<Slot<f64>>,
    p: Vec<Slot<f64>>,
    q: Vec<Slot<f64>>,
    partials: Vec<gang::PartialSum>,
    /// Solve on the calling thread alone ([`Pcg::on_the_calling_thread`]).
    alone: bool,
    /// Gang or alone, by the speed each has had ([`super::pace`]).
    pace: Pace,
    /// Bytes streamed by the CG kernels (as [`super::amg::Amg::bytes_streamed`], excluding the
    /// preconditioner).
    bytes: f64,
}

/// OpenFOAM's normalisation factor Σ|Ax − Ax̄| + Σ|b − Ax̄| + 10⁻²⁰ (x̄ = mean of x), given
/// ax = A x; A x̄ = x̄ · (row sums of A).
fn normalisation(crew: &Crew, a: &Csr, b: &[f64], x: &[Slot<f64>], ax: &[Slot<f64>]) -> f64 {
    let n = a.n;
    // SAFETY: x and ax are not written during these sums
    let mean = crew.sum(n, |i| unsafe { x[i].get() }) / n as f64;
    crew.sum(n, |i| {
        let a_mean = mean * a.row_sum(i);
        (unsafe { ax[i].get() } - a_mean).abs() + (b[i] - a_mean).abs()
    }) + 1e-20
}

/// r = b − A x, and (the normalisation, the normalised residual |r|₁ / normalisation), with `ax`
/// as the work vector of A x, by the members of a gang.
///
/// # Safety
/// Every member of `crew` calls it with the same vectors, which no other gang uses, `x`, `ax`
/// and `r` distinct.
pub(super) unsafe fn initial_residual(crew: &Crew, a: &Csr, b: &[f64], x: &[Slot<f64>], ax: &[Slot<f64>], r: &[Slot<f64>]) -> (f64, f64) {
    let n = a.n;
    // SAFETY: the caller's promise (ax is not x); each loop writes its own rows of one vector
    // it does not read at other rows
    unsafe { a.multiply_shared(crew, x, ax) };
    let norm = normalisation(crew, a, b, x, ax);
    crew.for_each(n, |i| unsafe { r[i].set(b[i] - ax[i].get()) });
    (norm, crew.sum(n, |i| unsafe { r[i].get() }.abs()) / norm)
}

impl Pcg {
    fn size(&mut self, n: usize) {
        for v in [&mut self.r, &mut self.z, &mut self.p, &mut self.q] {
            v.resize_with(n, Slot::default);
        }
    }

    /// Solves on the calling thread alone instead of a gang of the pool's threads: for solves
    /// run side by side, one a thread (each gang would wait for threads busy with the others).
    pub fn on_the_calling_thread(mut self) -> Self {
        self.alone = true;
        self
    }

    /// Bytes streamed by the CG iterations so far (the preconditioner counts its own).
    pub fn bytes_streamed(&self) -> f64 {
        self.bytes
    }

    /// Solves A x = b from the initial guess in `x`, on a gang of the current pool's threads
    /// or on the calling thread, whichever has been faster ([`super::pace`]); always on the
    /// calling thread with [`Pcg::on_the_calling_thread`], and for short solves.
    pub fn solve(&mut self, a: &Csr, b: &[f64], x: &mut [f64], m: &mut impl Preconditioner, tol: Tolerance) -> SolveStats {
        let n = a.n;
        self.size(n);
        let Pcg { r, z, p, q, partials, alone, pace, bytes } = self;
        let (r, z, p, q, x) = (&r[..], &z[..], &p[..], &q[..], Slot::from_mut_slice(x));
        let shared = &*m;
        // SAFETY: the vectors are this solve's alone (borrowed from `self` and the caller), and
        // every member runs `iterate` whole
        let body = |crew: &Crew| unsafe { iterate(crew, a, b, x, [r, z, p, q], shared, tol) };
        // before the first iteration: the initial residual's product and sums, about a fifth of
        // an iteration (the first multigrid cycle comes before the loop, and the last
        // iteration skips its own)
        let (stats, cg_bytes, m_bytes) =
            if *alone { gang::run_alone(n, partials, body) } else { run_paced(pace, n, partials, body, |(stats, _, _)| stats.iterations, 0.2) };
        *bytes += cg_bytes;
        m.record_bytes(m_bytes);
        stats
    }
}

/// The CG iterations, run by every member of `crew`: (statistics, bytes of the CG kernels,
/// bytes of the preconditioner).
///
/// # Safety
/// Every member of `crew` runs it whole, with distinct vectors no other gang uses.
//
// SAFETY (every unsafe block below): a loop writes only its own entries (its block's, or its
// chunk's in a sum) of the vectors it writes, and reads the entries it writes or entries of
// vectors no member writes in that loop; the barrier that ends each loop orders its writes
// before the reads of the loops after it. The kernels called (products, preconditioner, the
// initial residual) get distinct vectors of this solve, and every member calls them in step:
// every branch follows sums that all members compute alike.
unsafe fn iterate(
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
    let (norm, mut residual) = unsafe { initial_residual(crew, a, b, x, q, r) };
    let mut stats = SolveStats { iterations: 0, initial_residual: residual, final_residual: residual };
    if residual < tol.tolerance {
        return (stats, bytes, m_bytes);
    }
    unsafe { m.apply(crew, a, r, z, &mut m_bytes) };
    crew.for_each(n, |i| unsafe { p[i].set(at(z, i)) });
    let mut rz = crew.sum(n, |i| at(r, i) * at(z, i));
    while stats.iterations < tol.max_iterations {
        stats.iterations += 1;
        // product with p·q, fused update + |r| (x, r read and written, p, q read), r·z and
        // z·q, p update
        bytes += matrix + 16.0 * nf + 48.0 * nf + 24.0 * nf + 24.0 * nf;
        let [pq, _] = unsafe { a.multiply_sum2_shared(crew, p, q, |i, qi| [at(p, i) * qi, 0.0]) };
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
        unsafe { m.apply(crew, a, r, z, &mut m_bytes) };
        // r_{k+1} − r_k = −α q, so z_{k+1}·(r_{k+1} − r_k) = −α z_{k+1}·q
        let [rz_new, zq] = crew.sum2(n, |i| [at(r, i) * at(z, i), at(z, i) * at(q, i)]);
        let beta = -alpha * zq / rz;
        rz = rz_new;
        crew.for_each(n, |i| unsafe { p[i].set(at(z, i) + beta * at(p, i)) });
    }
    stats.final_residual = residual;
    (stats, bytes, m_bytes)
}
