//! Right-preconditioned BiCGStab (van der Vorst 1992) with a diagonal (Jacobi) preconditioner,
//! for the non-symmetric momentum equation.

use super::csr::Csr;
use super::pcg::normalisation;
use super::reduce::Reducer;
use super::{par_update, Out, SolveStats, Tolerance};

#[derive(Clone, Debug, Default)]
pub struct BiCgStab {
    r: Vec<f64>,
    r0: Vec<f64>,
    p: Vec<f64>,
    v: Vec<f64>,
    s: Vec<f64>,
    t: Vec<f64>,
    y: Vec<f64>,
    zs: Vec<f64>,
    red: Reducer,
}

impl BiCgStab {
    /// Solves A x = b from the initial guess in `x`, preconditioned by the diagonal of A.
    ///
    /// The Jacobi preconditioner is applied inside the vector updates, and every product and
    /// update carries the sums that follow it, so an iteration makes six passes over the
    /// vectors instead of thirteen. The arithmetic (and so the bits) is that of the textbook
    /// loop with `z = r / diag`.
    pub fn solve(&mut self, a: &Csr, b: &[f64], x: &mut [f64], tol: Tolerance) -> SolveStats {
        let n = a.n;
        for v in [&mut self.r, &mut self.r0, &mut self.p, &mut self.v, &mut self.s, &mut self.t, &mut self.y, &mut self.zs] {
            v.resize(n, 0.0);
        }
        let BiCgStab { r, r0, p, v, s, t, y, zs, red } = self;
        let d = &a.diag;
        a.multiply(x, t);
        let norm = normalisation(a, b, x, t, red);
        par_update(&mut r[..], |i, r| *r = b[i] - t[i]);
        let mut residual = red.sum(n, |i| r[i].abs()) / norm;
        let mut stats = SolveStats { iterations: 0, initial_residual: residual, final_residual: residual };
        if residual < tol.tolerance {
            return stats;
        }
        r0.copy_from_slice(r);
        p.fill(0.0);
        v.fill(0.0);
        let (mut rho, mut alpha, mut omega) = (1.0f64, 1.0f64, 1.0f64);
        let mut rho_new = red.sum(n, |i| r0[i] * r[i]);
        while stats.iterations < tol.max_iterations {
            stats.iterations += 1;
            if rho_new == 0.0 || !rho_new.is_finite() {
                break;
            }
            let beta = (rho_new / rho) * (alpha / omega);
            rho = rho_new;
            // p = r + β(p − ω v) and y = p / diag
            let (ys, vr) = (Out::of(y), &*v);
            par_update(&mut p[..], |i, p| {
                *p = r[i] + beta * (*p - omega * vr[i]);
                // SAFETY: entry i of y is written by the task that owns entry i of p
                unsafe { ys.set(i, *p / d[i]) };
            });
            let [r0v, _] = a.multiply_sum2(y, v, red, |i, vi| [r0[i] * vi, 0.0]);
            if r0v == 0.0 || !r0v.is_finite() {
                break;
            }
            alpha = rho / r0v;
            // s = r − α v, zs = s / diag, and |s|
            let (ss, zo, vr) = (Out::of(s), Out::of(zs), &*v);
            let s_res = red.sum(n, |i| {
                let si = r[i] - alpha * vr[i];
                // SAFETY: the reduction's chunks visit every entry exactly once
                unsafe {
                    ss.set(i, si);
                    zo.set(i, si / d[i]);
                }
                si.abs()
            }) / norm;
            if s_res < tol.tolerance {
                par_update(&mut x[..], |i, x| *x += alpha * y[i]);
                residual = s_res;
                break;
            }
            let sr = &*s;
            let [ts, tt] = a.multiply_sum2(zs, t, red, |i, ti| [ti * sr[i], ti * ti]);
            if tt == 0.0 || !tt.is_finite() {
                break;
            }
            omega = ts / tt;
            // x += α y + ω zs, r = s − ω t, and |r|, r0·r (the next iteration's ρ)
            let (xs, ro) = (Out::of(x), Out::of(r));
            let (yr, zr, tr) = (&*y, &*zs, &*t);
            let [abs_r, r0r] = red.sum2(n, |i| {
                // SAFETY: the reduction's chunks visit every entry exactly once
                unsafe {
                    *xs.ptr(i) += alpha * yr[i] + omega * zr[i];
                    let ri = sr[i] - omega * tr[i];
                    ro.set(i, ri);
                    [ri.abs(), r0[i] * ri]
                }
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
}
