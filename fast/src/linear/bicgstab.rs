//! Right-preconditioned BiCGStab (van der Vorst 1992) for the non-symmetric momentum equation.


use super::csr::Csr;
use super::pcg::normalisation;
use super::reduce::Reducer;
use super::{par_update, Preconditioner, SolveStats, Tolerance};

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
    /// Solves A x = b from the initial guess in `x`.
    pub fn solve(&mut self, a: &Csr, b: &[f64], x: &mut [f64], m: &mut impl Preconditioner, tol: Tolerance) -> SolveStats {
        let n = a.n;
        for v in [&mut self.r, &mut self.r0, &mut self.p, &mut self.v, &mut self.s, &mut self.t, &mut self.y, &mut self.zs] {
            v.resize(n, 0.0);
        }
        let BiCgStab { r, r0, p, v, s, t, y, zs, red } = self;
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
        while stats.iterations < tol.max_iterations {
            stats.iterations += 1;
            let rho_new = red.sum(n, |i| r0[i] * r[i]);
            if rho_new == 0.0 || !rho_new.is_finite() {
                break;
            }
            let beta = (rho_new / rho) * (alpha / omega);
            rho = rho_new;
            par_update(&mut p[..], |i, p| *p = r[i] + beta * (*p - omega * v[i]));
            m.apply(a, p, y);
            a.multiply(y, v);
            let r0v = red.sum(n, |i| r0[i] * v[i]);
            if r0v == 0.0 || !r0v.is_finite() {
                break;
            }
            alpha = rho / r0v;
            par_update(&mut s[..], |i, s| *s = r[i] - alpha * v[i]);
            let s_res = red.sum(n, |i| s[i].abs()) / norm;
            if s_res < tol.tolerance {
                par_update(&mut x[..], |i, x| *x += alpha * y[i]);
                residual = s_res;
                break;
            }
            m.apply(a, s, zs);
            a.multiply(zs, t);
            let [ts, tt] = red.sum2(n, |i| [t[i] * s[i], t[i] * t[i]]);
            if tt == 0.0 || !tt.is_finite() {
                break;
            }
            omega = ts / tt;
            par_update(&mut x[..], |i, x| *x += alpha * y[i] + omega * zs[i]);
            par_update(&mut r[..], |i, r| *r = s[i] - omega * t[i]);
            residual = red.sum(n, |i| r[i].abs()) / norm;
            if residual < tol.tolerance || omega == 0.0 {
                break;
            }
        }
        stats.final_residual = residual;
        stats
    }
}
