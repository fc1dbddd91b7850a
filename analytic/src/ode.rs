//! Small ODE integrators for the semi-analytic references: classical RK4 with event location and
//! adaptive Dormand–Prince RK5(4).
//!
//! States are fixed-size arrays `[f64; N]`; the right-hand side is `f(t, y) -> dy/dt`.

use crate::error::{AnalyticError, Result};

fn axpy<const N: usize>(y: &[f64; N], h: f64, k: &[f64; N]) -> [f64; N] {
    let mut out = *y;
    for i in 0..N {
        out[i] += h * k[i];
    }
    out
}

/// One classical fourth-order Runge–Kutta step of size `h`.
pub fn rk4_step<const N: usize, F: Fn(f64, &[f64; N]) -> [f64; N]>(f: &F, t: f64, y: &[f64; N], h: f64) -> [f64; N] {
    let k1 = f(t, y);
    let k2 = f(t + 0.5 * h, &axpy(y, 0.5 * h, &k1));
    let k3 = f(t + 0.5 * h, &axpy(y, 0.5 * h, &k2));
    let k4 = f(t + h, &axpy(y, h, &k3));
    let mut out = *y;
    for i in 0..N {
        out[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    }
    out
}

/// Result of [`rk4_until_event`]: time and state at the event, plus the extreme of `watch`.
#[derive(Debug, Clone, Copy)]
pub struct EventHit<const N: usize> {
    pub time: f64,
    pub state: [f64; N],
    /// Largest value of the watched quantity seen at any step (including the event state).
    pub watch_max: f64,
}

/// Integrates with fixed RK4 steps `h` from `(t0, y0)` until `event(y)` changes sign from
/// positive to ≤ 0, then locates the crossing by bisection on the length of the last step
/// (each trial redoes one RK4 step from the last accepted state, so the event time has the
/// integrator's own accuracy). Fails if no event occurs before `t_max`.
pub fn rk4_until_event<const N: usize, F, E, W>(f: &F, t0: f64, y0: [f64; N], h: f64, t_max: f64, event: E, watch: W) -> Result<EventHit<N>>
where
    F: Fn(f64, &[f64; N]) -> [f64; N],
    E: Fn(&[f64; N]) -> f64,
    W: Fn(&[f64; N]) -> f64,
{
    let mut t = t0;
    let mut y = y0;
    let mut watch_max = watch(&y);
    let max_steps = ((t_max - t0) / h).ceil() as usize + 1;
    for _ in 0..max_steps {
        let next = rk4_step(f, t, &y, h);
        if event(&next) <= 0.0 {
            let (mut lo, mut hi) = (0.0, h);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if event(&rk4_step(f, t, &y, mid)) > 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
                if hi - lo <= 1e-15 * (t.abs() + h) {
                    break;
                }
            }
            let step = 0.5 * (lo + hi);
            let state = rk4_step(f, t, &y, step);
            watch_max = watch_max.max(watch(&state));
            return Ok(EventHit { time: t + step, state, watch_max });
        }
        y = next;
        t += h;
        watch_max = watch_max.max(watch(&y));
    }
    Err(AnalyticError::NoConvergence { what: "RK4 event search (event not reached before t_max)", iterations: max_steps, residual: event(&y) })
}

// Dormand–Prince 5(4) tableau.
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
// Error coefficients: 5th-order minus embedded 4th-order weights.
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;

/// Tolerances of [`dopri_at_times`].
#[derive(Debug, Clone, Copy)]
pub struct Tolerance {
    pub relative: f64,
    pub absolute: f64,
}

/// Integrates `dy/dt = f(t, y)` from `(t0, y0)` with adaptive Dormand–Prince 5(4) steps and
/// returns the state at each of `times` (which must be ≥ t0 and ascending). Steps are clipped so
/// that every output time is hit exactly (no interpolation error).
pub fn dopri_at_times<const N: usize, F: Fn(f64, &[f64; N]) -> [f64; N]>(
    f: &F,
    t0: f64,
    y0: [f64; N],
    times: &[f64],
    tolerance: Tolerance,
) -> Result<Vec<[f64; N]>> {
    const MAX_STEPS: usize = 1_000_000;
    let mut out = Vec::with_capacity(times.len());
    let mut t = t0;
    let mut y = y0;
    let span = times.last().map_or(0.0, |last| last - t0).abs();
    let mut h = if span > 0.0 { span * 1e-4 } else { 1e-6 };
    let mut steps = 0usize;
    let mut previous = t0;
    for &target in times {
        if !(target >= previous) {
            return Err(AnalyticError::Invalid { what: "output times", reason: format!("times must be ascending and >= t0; got {target} after {previous}") });
        }
        previous = target;
        while t < target {
            steps += 1;
            if steps > MAX_STEPS {
                return Err(AnalyticError::NoConvergence { what: "Dormand–Prince integration", iterations: MAX_STEPS, residual: target - t });
            }
            let step = h.min(target - t);
            let k1 = f(t, &y);
            let mut s = [0.0; N];
            for i in 0..N {
                s[i] = y[i] + step * A21 * k1[i];
            }
            let k2 = f(t + C2 * step, &s);
            for i in 0..N {
                s[i] = y[i] + step * (A31 * k1[i] + A32 * k2[i]);
            }
            let k3 = f(t + C3 * step, &s);
            for i in 0..N {
                s[i] = y[i] + step * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]);
            }
            let k4 = f(t + C4 * step, &s);
            for i in 0..N {
                s[i] = y[i] + step * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]);
            }
            let k5 = f(t + C5 * step, &s);
            for i in 0..N {
                s[i] = y[i] + step * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]);
            }
            let k6 = f(t + step, &s);
            let mut y_new = [0.0; N];
            for i in 0..N {
                y_new[i] = y[i] + step * (B1 * k1[i] + B3 * k3[i] + B4 * k4[i] + B5 * k5[i] + B6 * k6[i]);
            }
            let k7 = f(t + step, &y_new);
            let mut error_norm = 0.0f64;
            for i in 0..N {
                let err = step * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
                let scale = tolerance.absolute + tolerance.relative * y[i].abs().max(y_new[i].abs());
                error_norm = error_norm.max((err / scale).abs());
            }
            if !error_norm.is_finite() {
                h = 0.1 * step;
                continue;
            }
            if error_norm <= 1.0 {
                t += step;
                y = y_new;
            }
            let factor = if error_norm == 0.0 { 5.0 } else { 0.9 * error_norm.powf(-0.2) };
            h = step * factor.clamp(0.2, 5.0);
        }
        out.push(y);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rk4_is_fourth_order_on_exponential_decay() {
        let f = |_t: f64, y: &[f64; 1]| [-y[0]];
        let error_at = |n: usize| {
            let h = 1.0 / n as f64;
            let mut y = [1.0];
            for i in 0..n {
                y = rk4_step(&f, i as f64 * h, &y, h);
            }
            (y[0] - (-1.0f64).exp()).abs()
        };
        let order = (error_at(20) / error_at(40)).log2();
        // Fourth order: halving h divides the error by 2^4; allow 0.1 for higher-order terms.
        assert!((order - 4.0).abs() < 0.1, "observed order {order}");
    }

    #[test]
    fn dopri_hits_output_times_of_harmonic_oscillator() {
        let f = |_t: f64, y: &[f64; 2]| [y[1], -y[0]];
        let times = [0.5, 1.0, 10.0];
        let tol = Tolerance { relative: 1e-12, absolute: 1e-14 };
        let states = dopri_at_times(&f, 0.0, [1.0, 0.0], &times, tol).unwrap();
        for (t, y) in times.iter().zip(states.iter()) {
            // Global error accumulates over ~10 periods of steps at 1e-12 local tolerance.
            assert!((y[0] - t.cos()).abs() < 1e-10, "t={t}: {} vs {}", y[0], t.cos());
            assert!((y[1] + t.sin()).abs() < 1e-10);
        }
    }

    #[test]
    fn event_is_located_to_integrator_accuracy() {
        // Projectile y'' = -1 from y=0, v=1: returns to y=0 at t=2 with max height 1/2.
        let f = |_t: f64, y: &[f64; 2]| [y[1], -1.0];
        let hit = rk4_until_event(&f, 0.0, [1e-300, 1.0], 0.013, 10.0, |y| y[0], |y| y[0]).unwrap();
        assert!((hit.time - 2.0).abs() < 1e-12);
        assert!((hit.state[1] + 1.0).abs() < 1e-12);
        assert!(hit.watch_max <= 0.5 && hit.watch_max > 0.5 - 1e-3);
    }

    #[test]
    fn dopri_rejects_descending_times() {
        let f = |_t: f64, y: &[f64; 1]| [-y[0]];
        let tol = Tolerance { relative: 1e-8, absolute: 1e-10 };
        assert!(dopri_at_times(&f, 0.0, [1.0], &[1.0, 0.5], tol).is_err());
    }
}
