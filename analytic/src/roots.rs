//! Scalar root finding: Brent's method on a bracket, and an upward bracket search.
//!
//! Used by the terminal-velocity, hindered-settling and spillage-model solutions. The methods are
//! textbook (Brent 1973, "Algorithms for Minimization without Derivatives", ch. 4).

use crate::error::{AnalyticError, Result};

/// Finds a root of `f` in `[lower, upper]` with Brent's method (bisection + secant + inverse
/// quadratic interpolation). `f(lower)` and `f(upper)` must differ in sign (or one be zero).
/// Converges when the bracket is narrower than `x_tolerance` (absolute) or `f` is exactly zero.
pub fn brent<F: FnMut(f64) -> f64>(what: &'static str, mut f: F, lower: f64, upper: f64, x_tolerance: f64) -> Result<f64> {
    const MAX_ITERATIONS: usize = 200;
    let (mut a, mut b) = (lower, upper);
    let (mut fa, mut fb) = (f(a), f(b));
    if !(fa.is_finite() && fb.is_finite()) {
        return Err(AnalyticError::Invalid { what, reason: format!("function is not finite at the bracket ends ({fa}, {fb})") });
    }
    if fa == 0.0 {
        return Ok(a);
    }
    if fb == 0.0 {
        return Ok(b);
    }
    if fa.signum() == fb.signum() {
        return Err(AnalyticError::NoBracket { what, lower, upper });
    }
    let (mut c, mut fc) = (a, fa);
    let mut d = b - a;
    let mut e = d;
    for _ in 0..MAX_ITERATIONS {
        if fb.signum() == fc.signum() {
            c = a;
            fc = fa;
            d = b - a;
            e = d;
        }
        if fc.abs() < fb.abs() {
            a = b;
            b = c;
            c = a;
            fa = fb;
            fb = fc;
            fc = fa;
        }
        let tol = 2.0 * f64::EPSILON * b.abs() + 0.5 * x_tolerance;
        let m = 0.5 * (c - b);
        if m.abs() <= tol || fb == 0.0 {
            return Ok(b);
        }
        if e.abs() >= tol && fa.abs() > fb.abs() {
            // Interpolation step (secant or inverse quadratic).
            let s = fb / fa;
            let (mut p, mut q);
            if a == c {
                p = 2.0 * m * s;
                q = 1.0 - s;
            } else {
                let qa = fa / fc;
                let r = fb / fc;
                p = s * (2.0 * m * qa * (qa - r) - (b - a) * (r - 1.0));
                q = (qa - 1.0) * (r - 1.0) * (s - 1.0);
            }
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * m * q - (tol * q).abs()).min((e * q).abs()) {
                e = d;
                d = p / q;
            } else {
                d = m;
                e = m;
            }
        } else {
            d = m;
            e = m;
        }
        a = b;
        fa = fb;
        b += if d.abs() > tol { d } else { tol * m.signum() };
        fb = f(b);
        if !fb.is_finite() {
            return Err(AnalyticError::Invalid { what, reason: format!("function is not finite at x = {b}") });
        }
    }
    Err(AnalyticError::NoConvergence { what, iterations: MAX_ITERATIONS, residual: fb })
}

/// Starting from `[lower, upper]`, multiplies `upper` by `factor` until `f` changes sign between
/// `lower` and `upper` (at most `max_expansions` times). Returns the bracket.
pub fn expand_upper<F: FnMut(f64) -> f64>(what: &'static str, mut f: F, lower: f64, mut upper: f64, factor: f64, max_expansions: usize) -> Result<(f64, f64)> {
    let f_lower = f(lower);
    for _ in 0..=max_expansions {
        let f_upper = f(upper);
        if f_upper.is_finite() && f_lower.is_finite() && f_upper.signum() != f_lower.signum() {
            return Ok((lower, upper));
        }
        upper *= factor;
    }
    Err(AnalyticError::NoBracket { what, lower, upper })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brent_finds_known_roots() {
        let root = brent("cos x - x", |x| x.cos() - x, 0.0, 1.0, 1e-15).unwrap();
        // Dottie number, known to 15 digits.
        assert!((root - 0.739_085_133_215_160_6).abs() < 1e-14);
        let cube = brent("x^3 - 2", |x| x * x * x - 2.0, 0.0, 5.0, 1e-14).unwrap();
        assert!((cube - 2f64.cbrt()).abs() < 1e-13);
    }

    #[test]
    fn brent_rejects_bracket_without_sign_change() {
        let err = brent("x^2 + 1", |x| x * x + 1.0, -1.0, 1.0, 1e-12).unwrap_err();
        assert!(matches!(err, AnalyticError::NoBracket { .. }));
    }

    #[test]
    fn expansion_finds_far_root() {
        let (lo, hi) = expand_upper("x - 1000", |x| x - 1000.0, 0.0, 1.0, 2.0, 20).unwrap();
        assert!(lo == 0.0 && hi >= 1000.0);
        let root = brent("x - 1000", |x| x - 1000.0, lo, hi, 1e-12).unwrap();
        assert!((root - 1000.0).abs() < 1e-9);
    }
}
