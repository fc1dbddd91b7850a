//! Right-preconditioned BiCGStab (van der Vorst 1992) with a diagonal (Jacobi) preconditioner,
//! for the non-symmetric momentum equation.

use super::csr::Csr;
use super::gang::{self, Crew, Slot};
use super::pace::{run_paced, Pace};
use super::pcg::initial_residual;
use super::{SolveStats, Tolerance};

/// Work vectors (kept between solves: no allocation once sized), shared by the members of the
/// gang that runs a solve ([`gang`]).
#[derive(Clone, Debug, Default)]
pub struct BiCgStab {
    r: Vec<Slot<f64>>,
    r0: Vec<Slot<f64>>,
    p: Vec<Slot<f64>>,
    v: Vec<Slot<f64>>,
    s: Vec<Slot<f64>>,
    t: Vec<Slot<f64>>,
    y: Vec<Slot<f64>>,
    zs: Vec<Slot<f64>>,
    partials: Vec<gang::PartialSum>,
    /// Gang or alone, by the speed each has had ([`super::pace`]).
    pace: Pace,
}

impl BiCgStab {
    /// Solves A x = b from the initial guess in `x`, preconditioned by the diagonal of A, on a
    /// gang of the current pool's threads or on the calling thread, whichever has been faster
    /// ([`super::pace`]).
    ///
    /// The Jacobi preconditioner is applied inside the vector updates, and every product and
    /// update carries the sums that follow it, so an iteration makes six passes over the
    /// vectors instead of thirteen. The arithmetic (and so the bits) is that of the textbook
    /// loop with `z = r / diag`.
    pub fn solve(&mut self, a: &Csr, b: &[f64], x: &mut [f64], tol: Tolerance) -> SolveStats {
        let n = a.n;
        for v in [&mut self.r, &mut self.r0, &mut self.p, &mut self.v, &mut self.s, &mut self.t, &mut self.y, &mut self.zs] {
            v.resize_with(n, Slot::default);
        }
        let BiCgStab { r, r0, p, v, s, t, y, zs, partials, pace } = self;
        let vectors = Vectors { r, r0, p, v, s, t, y, zs };
        let x = Slot::from_mut_slice(x);
        // before the first iteration: the initial residual (a product and five passes) against
        // an iteration's two products and five passes, about half an iteration
        // SAFETY: the vectors are this solve's alone (borrowed from `self` and the caller), and
        // every member runs `iterate` whole
        run_paced(pace, n, partials, |crew| unsafe { iterate(crew, a, b, x, &vectors, tol) }, |stats| stats.iterations, 0.5)
    }
}

/// The work vectors of one solve.
struct Vectors<'a> {
    r: &'a [Slot<f64>],
    r0: &'a [Slot<f64>],
    p: &'a [Slot<f64>],
    v: &'a [Slot<f64>],
    s: &'a [Slot<f64>],
    t: &'a [Slot<f64>],
    y: &'a [Slot<f64>],
    zs: &'a [Slot<f64>],
}

/// The BiCGStab iterations, run by every member of `crew`.
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
unsafe fn iterate(crew: &Crew, a: &Csr, b: &[f64], x: &[Slot<f64>], w: &Vectors, tol: Tolerance) -> SolveStats {
    let n = a.n;
    let Vectors { r, r0, p, v, s, t, y, zs } = *w;
    let at = |v: &[Slot<f64>], i: usize| unsafe { v[i].get() };
    let d = &a.diag;
    let (norm, mut residual) = unsafe { initial_residual(crew, a, b, x, t, r) };
    let mut stats = SolveStats { iterations: 0, initial_residual: residual, final_residual: residual };
    if residual < tol.tolerance {
        return stats;
    }
    crew.for_each(n, |i| unsafe {
        r0[i].set(at(r, i));
        p[i].set(0.0);
        v[i].set(0.0);
    });
    let (mut rho, mut alpha, mut omega) = (1.0f64, 1.0f64, 1.0f64);
    let mut rho_new = crew.sum(n, |i| at(r0, i) * at(r, i));
    while stats.iterations < tol.max_iterations {
        stats.iterations += 1;
        if rho_new == 0.0 || !rho_new.is_finite() {
            break;
        }
        let beta = (rho_new / rho) * (alpha / omega);
        rho = rho_new;
        // p = r + β(p − ω v) and y = p / diag
        crew.for_each(n, |i| unsafe {
            let pi = at(r, i) + beta * (at(p, i) - omega * at(v, i));
            p[i].set(pi);
            y[i].set(pi / d[i]);
        });
        let [r0v, _] = unsafe { a.multiply_sum2_shared(crew, y, v, |i, vi| [at(r0, i) * vi, 0.0]) };
        if r0v == 0.0 || !r0v.is_finite() {
            break;
        }
        alpha = rho / r0v;
        // s = r − α v, zs = s / diag, and |s|
        let s_res = crew.sum(n, |i| unsafe {
            let si = at(r, i) - alpha * at(v, i);
            s[i].set(si);
            zs[i].set(si / d[i]);
            si.abs()
        }) / norm;
        if s_res < tol.tolerance {
            crew.for_each(n, |i| unsafe { x[i].set(at(x, i) + alpha * at(y, i)) });
            residual = s_res;
            break;
        }
        let [ts, tt] = unsafe { a.multiply_sum2_shared(crew, zs, t, |i, ti| [ti * at(s, i), ti * ti]) };
        if tt == 0.0 || !tt.is_finite() {
            break;
        }
        omega = ts / tt;
        // x += α y + ω zs, r = s − ω t, and |r|, r0·r (the next iteration's ρ)
        let [abs_r, r0r] = crew.sum2(n, |i| unsafe {
            x[i].set(at(x, i) + (alpha * at(y, i) + omega * at(zs, i)));
            let ri = at(s, i) - omega * at(t, i);
            r[i].set(ri);
            [ri.abs(), at(r0, i) * ri]
        });
        residual = abs_r / norm;
        rho_new = r0r;
        if residual < tol.tolerance || omega == 0.0 {
            break;
        }
    }
    stats.final_residual = residual;
    stats
}
