//! The step size: fixed (`[time] dt`) or adapted to a maximum Courant number
//! (`[time] max_courant`, spec fluid-dem-model.md §8.9; the thesis runs Co_max = 0.5 with
//! particles).
//!
//! The adaptive rule is OpenFOAM's `setDeltaT` [R: the spec gives only Co_max]: from the
//! Courant number Coⁿ of the last step, f = Co_max/Coⁿ, Δt ← min(min(f, 1 + 0.1 f), 1.2) Δtⁿ,
//! so the step shrinks at once when the flow speeds up and grows by at most 20 % per step
//! (variable-step BDF2 stays second order and stable for such ratios). It is capped by
//! `max_dt` and, with `end_time`, lands on it exactly: when less than 1.5 steps remain, the
//! remainder is taken in one step (≤ Δt) or two equal ones, so no sliver of a step is left.
//! A frozen-rotor start-up (t < 0, `crate::fluid::frozen_rotor`) lands on t = 0 the same way,
//! with a fixed Δt too.
//! The first step takes
//! min(Co_max / (Co per second of the start state), `max_dt`).
//!
//! A step whose fluid diverged and converged with a smaller Δt ([`super::coupled`]'s retry)
//! leaves a limit between the two, `State::dt_limit`, which grows by [`DT_LIMIT_GROWTH`] per
//! step: the Courant number alone does not see what made the step diverge (on the refined
//! rotor/stator of issue 15 the viscous diffusion number), and without the limit the rule grew
//! Δt back into divergence every few steps (rotor/stator with 32 radial cells, 5 s: 179 of 681
//! steps retried).

use crate::case::Case;
use crate::solver::SolverError;
use crate::state::State;

/// How the driver picks Δt.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TimeStepControl {
    Fixed { dt: f64, end_time: Option<f64> },
    Courant { max_courant: f64, max_dt: f64, end_time: Option<f64> },
}

/// Largest growth of Δt from one step to the next (OpenFOAM's `maxDeltaT` factor 1.2).
const MAX_GROWTH: f64 = 1.2;

/// Growth of `State::dt_limit` per step: slow enough that a limit found by a retry holds for
/// tens of steps (1.01³⁵ ≈ √2, the gap a retry leaves), so the flow may change what it allows.
pub const DT_LIMIT_GROWTH: f64 = 1.01;

impl TimeStepControl {
    pub fn from_case(case: &Case, has_fluid: bool) -> Result<TimeStepControl, SolverError> {
        let t = &case.time;
        match (t.dt, t.max_courant) {
            (Some(dt), _) => Ok(TimeStepControl::Fixed { dt, end_time: t.end_time }),
            (None, Some(max_courant)) if has_fluid => {
                Ok(TimeStepControl::Courant { max_courant, max_dt: t.max_dt.unwrap_or(f64::INFINITY), end_time: t.end_time })
            }
            (None, Some(_)) => {
                Err(SolverError::Unsupported("`[time] max_courant` needs a fluid; a particle-only run needs a fixed `[time] dt` for its outer step".into()))
            }
            (None, None) => Err(SolverError::Unsupported("`[time]` needs `dt` or `max_courant`".into())),
        }
    }

    /// Δt of the step after `state`; `courant_rate` is the Courant number per second of the
    /// state's flow (asked for only on the first adaptive step).
    pub fn next_dt(&self, state: &State, courant_rate: impl FnOnce() -> f64) -> Result<f64, SolverError> {
        let (dt, end_time) = match *self {
            TimeStepControl::Fixed { dt, end_time } => (dt, end_time),
            TimeStepControl::Courant { max_courant, max_dt, end_time } => {
                let dt = if state.step == 0 || state.dt <= 0.0 {
                    let rate = courant_rate();
                    if !rate.is_finite() {
                        return Err(SolverError::Diverged { step: 0, time: state.time, what: format!("the Courant number of the start state is {rate}") });
                    }
                    let dt = if rate > 0.0 { (max_courant / rate).min(max_dt) } else { max_dt };
                    if !dt.is_finite() {
                        return Err(SolverError::Unsupported(
                            "`[time] max_courant`: the start state does not move (Courant number 0), so the first step cannot be chosen from it; give `[time] max_dt`".into(),
                        ));
                    }
                    dt
                } else if !state.courant.is_finite() {
                    return Err(SolverError::Diverged { step: state.step, time: state.time, what: format!("Courant number {}", state.courant) });
                } else {
                    adapted_dt(state.dt, state.courant, max_courant).min(max_dt)
                };
                let dt = state.dt_limit.map_or(dt, |limit| dt.min(limit));
                (dt, end_time)
            }
        };
        // land on end_time exactly rather than overshoot it or leave a sliver (module doc); the
        // run loop ends within 1e-12 relative of end_time. A frozen-rotor start-up (t < 0) lands
        // on t = 0 the same way, with either control (crate::fluid::frozen_rotor).
        let start_up = state.time < 0.0;
        let (end_time, landing) = if start_up { (Some(0.0), true) } else { (end_time, matches!(self, TimeStepControl::Courant { .. })) };
        Ok(match end_time {
            Some(end) if landing && end - state.time < 1.5 * dt && end > state.time => {
                let remaining = end - state.time;
                if remaining <= dt {
                    remaining
                } else {
                    0.5 * remaining
                }
            }
            _ => dt,
        })
    }
}

/// Whether an adaptive run at `time` has reached `end_time`: its last step lands on the end
/// time, and the sum of the steps may miss it only by round-off.
pub fn reached_end_time(time: f64, end_time: f64) -> bool {
    time >= end_time - 1e-12 * end_time.abs()
}

/// OpenFOAM's `setDeltaT`: Δt after a step of `dt_old` that reached Courant number `courant`.
pub fn adapted_dt(dt_old: f64, courant: f64, max_courant: f64) -> f64 {
    let factor = max_courant / (courant + f64::MIN_POSITIVE);
    dt_old * factor.min(1.0 + 0.1 * factor).min(MAX_GROWTH)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_shrinks_at_once_and_grows_by_at_most_20_percent() {
        // twice the allowed Courant number: halve at once (f = 0.5 < 1 + 0.1 f)
        assert_eq!(adapted_dt(1.0, 1.0, 0.5), 0.5);
        // a still flow: grow by 1.2 only
        assert_eq!(adapted_dt(1.0, 1e-9, 0.5), MAX_GROWTH);
        // at the target: f = 1, min(1, 1.1, 1.2) = 1
        assert_eq!(adapted_dt(0.3, 0.5, 0.5), 0.3);
    }

    #[test]
    fn the_last_step_lands_on_the_end_time() {
        let control = TimeStepControl::Courant { max_courant: 0.5, max_dt: 0.1, end_time: Some(1.0) };
        let state = State { time: 0.95, step: 3, dt: 0.1, courant: 0.5, ..State::default() };
        assert_eq!(control.next_dt(&state, || 0.0).unwrap(), 1.0 - 0.95);
        // 1.3 steps left (0.13 s): two steps of 0.065 s rather than one full and a sliver
        let state = State { time: 0.87, step: 3, dt: 0.1, courant: 0.5, ..State::default() };
        let dt = control.next_dt(&state, || 0.0).unwrap();
        assert!((dt - 0.5 * (1.0 - 0.87)).abs() < 1e-15);
        // and the second of the two lands on the end time
        let state = State { time: 0.87 + dt, step: 4, dt, courant: 0.5, ..State::default() };
        let last = control.next_dt(&state, || 0.0).unwrap();
        assert!((state.time + last - 1.0).abs() < 1e-15, "{}", state.time + last);
    }

    #[test]
    fn a_frozen_rotor_start_up_lands_on_zero_with_either_control() {
        for control in
            [TimeStepControl::Fixed { dt: 0.3, end_time: Some(5.0) }, TimeStepControl::Courant { max_courant: 0.5, max_dt: 0.3, end_time: Some(5.0) }]
        {
            let mut state = State { time: -1.0, step: 0, dt: 0.0, courant: 0.5, ..State::default() };
            let mut steps = 0;
            while state.time < 0.0 {
                let dt = control.next_dt(&state, || 0.5 / 0.3).unwrap();
                assert!(dt >= 0.15 - 1e-15 && dt <= 0.3, "{dt}: no sliver, no step longer than asked");
                state = State { time: state.time + dt, step: state.step + 1, dt, ..state };
                steps += 1;
            }
            // 1 s in steps of at most 0.3 s: 0.3, 0.3, then 0.4 s left in two of 0.2 s
            assert_eq!((state.time, steps), (0.0, 4), "{control:?}");
        }
    }

    #[test]
    fn a_non_finite_courant_number_is_an_error() {
        let control = TimeStepControl::Courant { max_courant: 0.5, max_dt: 0.1, end_time: Some(1.0) };
        let state = State { time: 0.5, step: 3, dt: 0.1, courant: f64::NAN, ..State::default() };
        assert!(control.next_dt(&state, || 0.0).is_err());
        assert!(control.next_dt(&State::default(), || f64::NAN).is_err());
    }

    #[test]
    fn a_still_start_without_max_dt_is_an_error_that_says_what_to_give() {
        let control = TimeStepControl::Courant { max_courant: 0.5, max_dt: f64::INFINITY, end_time: Some(1.0) };
        let e = control.next_dt(&State::default(), || 0.0).unwrap_err().to_string();
        assert!(e.contains("max_dt"), "{e}");
    }
}
