//! Whether a solver's next solve runs on a gang of the pool's threads or on the calling thread
//! alone, chosen by the speed each way has had on this machine in this run.
//!
//! Why: a gang's members meet at hundreds of barriers per iteration and read each other's
//! rows at their blocks' edges, so a gang is as fast as the cache line that carries them
//! between the cores. On the 2-core VM that line takes 26–45 ns in some periods and 180–260 ns
//! in others (a two-thread ping-pong, measured between runs on 2026-11-28; the two vCPUs
//! sharing a core or not). The default cutter head's first 0.15 revolution took 3.8–4.2 s on
//! 2 threads in the fast periods, 6.3–6.4 s in the slow ones, and 5.85–6.04 s on 1 thread in
//! either (runs alternating): in the slow periods the gangs made two threads slower than one.
//! A machine with several sockets has the same slow line between them.
//!
//! So every solver keeps the cost per unit of work (seconds per row and iteration) that each
//! way has had lately, runs its solves the cheaper way, and now and then two solves the other
//! way (a probe), to follow the machine when it changes. The way changes only who computes:
//! a gang's sums and loops give the bits of one thread whatever its size ([`super::gang`]), so
//! the results do not depend on the timings.

use std::time::{Duration, Instant};

use super::gang::{self, Crew, PartialSum};

/// The two ways of running a solve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Way {
    /// A gang of the pool's threads ([`super::gang::run`]).
    Gang,
    /// The calling thread alone ([`super::gang::run_alone`]).
    Alone,
}

/// Solves from one probe to the next: [`PROBE_FIRST`] after the choice changed, then about
/// twice as many each time a probe confirms it, up to [`PROBE_LAST`]. The machine's periods
/// last minutes and a solve milliseconds, so at the longest interval a way that became the
/// cheaper is found within a few hundred solves, and the probes cost 2/257 of the difference
/// between the ways (the chosen way's own solves show at once when it becomes the dearer).
/// Odd intervals, so that probes do not keep landing on the same corrector of a step.
const PROBE_FIRST: u64 = 9;
const PROBE_LAST: u64 = 257;

/// The first solve of a run is not recorded, nor the first of each probe: the other thread
/// may be napping (it naps after 2 ms without work, [`crate::team`]) and the solve's rows are
/// in the other core's cache.
const COLD: u64 = 1;

/// The chosen way is kept until the other is this much cheaper: two ways of nearly the same
/// cost would otherwise trade places at every probe.
const MARGIN: f64 = 0.95;

/// A way's cost is the least of its last this many measurements: interference (other
/// processes, the system) only ever slows a solve, so a lone slow solve does not move the
/// estimate, while a change of the machine shows after this many solves of the way.
const KEPT: usize = 3;

/// A solver's record of the two ways' costs.
#[derive(Clone, Debug, Default)]
pub(super) struct Pace {
    /// The last [`KEPT`] measurements (seconds per unit of work) of [`Way::Gang`] and
    /// [`Way::Alone`], the n-th of a way at n mod [`KEPT`].
    samples: [[f64; KEPT]; 2],
    /// Measurements taken of each way (all of them, not only those kept).
    taken: [u64; 2],
    /// The way of the solves that are not probes, once both ways are measured.
    chosen: Option<Way>,
    /// Solves so far (recorded or not).
    solves: u64,
    /// Solves from the last probe to the next ([`PROBE_FIRST`] … [`PROBE_LAST`]).
    interval: u64,
    /// The first of the two solves of the next (or current) probe.
    probe: Option<u64>,
}

impl Way {
    fn index(self) -> usize {
        match self {
            Way::Gang => 0,
            Way::Alone => 1,
        }
    }

    fn other(self) -> Way {
        match self {
            Way::Gang => Way::Alone,
            Way::Alone => Way::Gang,
        }
    }
}

impl Pace {
    /// The way the next solve takes: the chosen one (a gang before there is a choice), the
    /// other one during a probe.
    pub(super) fn next(&self) -> Way {
        let base = self.chosen.unwrap_or(Way::Gang);
        match self.probe {
            Some(p) if self.solves == p || self.solves == p + 1 => base.other(),
            _ => base,
        }
    }

    /// Records a solve that took `way` and `elapsed` for `work` units (rows × iterations,
    /// with the work before the first iteration counted in: a solve that needed no iteration
    /// says nothing of the ways and is not measured).
    pub(super) fn record(&mut self, way: Way, elapsed: Duration, work: f64) {
        let solve = self.solves;
        self.solves += 1;
        let probe_end = self.probe == Some(solve.wrapping_sub(1));
        if solve >= COLD && self.probe != Some(solve) && work > 0.0 {
            let k = way.index();
            self.samples[k][(self.taken[k] % KEPT as u64) as usize] = elapsed.as_secs_f64() / work;
            self.taken[k] += 1;
        }
        let (Some(gang), Some(alone)) = (self.cost(Way::Gang), self.cost(Way::Alone)) else {
            // the gang measured: the first probe, alone, at once (again if it measured nothing)
            if self.cost(Way::Gang).is_some() && self.probe.is_none_or(|p| p + 1 < self.solves) {
                self.probe = Some(self.solves);
            }
            return;
        };
        let Some(chosen) = self.chosen else {
            self.choose(if alone < gang { Way::Alone } else { Way::Gang });
            return;
        };
        let (mine, other) = (self.cost(chosen).unwrap_or(f64::INFINITY), self.cost(chosen.other()).unwrap_or(f64::INFINITY));
        if other < MARGIN * mine {
            self.choose(chosen.other());
        } else if probe_end {
            self.interval = (2 * self.interval - 1).min(PROBE_LAST);
            self.probe = Some(self.solves + self.interval);
        }
    }

    /// `way` chosen anew: probed again after [`PROBE_FIRST`] solves.
    fn choose(&mut self, way: Way) {
        self.chosen = Some(way);
        self.interval = PROBE_FIRST;
        self.probe = Some(self.solves + self.interval);
    }

    /// The seconds per unit of work of `way`: the least of its last [`KEPT`] measurements,
    /// once measured.
    fn cost(&self, way: Way) -> Option<f64> {
        let k = way.index();
        let kept = (self.taken[k] as usize).min(KEPT);
        self.samples[k][..kept].iter().copied().reduce(f64::min)
    }
}

/// `body` run by a gang of the pool's threads or by the calling thread alone, as `pace`
/// chooses, and the time recorded against `rows × (iterations + before)` units of work, with
/// `iterations` read from the result and `before` the work of a solve before its first
/// iteration, in iterations. Where no gang can form (a pool of one thread, or fewer rows than
/// [`gang::GANG_MIN_ROWS`]) it runs alone and records nothing.
pub(super) fn run_paced<R: Send>(
    pace: &mut Pace,
    rows: usize,
    partials: &mut Vec<PartialSum>,
    body: impl Fn(&Crew) -> R + Sync,
    iterations: impl FnOnce(&R) -> usize,
    before: f64,
) -> R {
    if !gang::can_form(rows) {
        return gang::run_alone(rows, partials, body);
    }
    let way = pace.next();
    let start = Instant::now();
    let result = match way {
        Way::Gang => gang::run(rows, partials, body),
        Way::Alone => gang::run_alone(rows, partials, body),
    };
    let iterations = iterations(&result);
    let work = if iterations == 0 { 0.0 } else { rows as f64 * (iterations as f64 + before) };
    pace.record(way, start.elapsed(), work);
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs `solves` solves whose cost per unit of work is `cost(way, solve)` and returns the
    /// ways taken.
    fn run(pace: &mut Pace, solves: u64, cost: impl Fn(Way, u64) -> f64) -> Vec<Way> {
        (0..solves)
            .map(|k| {
                let way = pace.next();
                pace.record(way, Duration::from_secs_f64(cost(way, k) * 1e3), 1e3);
                way
            })
            .collect()
    }

    /// The solves (counted from 0) that took `way`.
    fn taking(ways: &[Way], way: Way) -> Vec<usize> {
        ways.iter().enumerate().filter(|(_, w)| **w == way).map(|(k, _)| k).collect()
    }

    #[test]
    fn a_run_starts_as_a_gang_probes_alone_and_keeps_the_cheaper_way() {
        let mut pace = Pace::default();
        // the gang twice as fast, its first (cold) solve 100× slower: two solves alone at
        // once (the second measured), then a gang but for the probes, each two solves alone,
        // 9, 17, 33, 65, 129, 257, 257 solves apart
        let ways = run(&mut pace, 600, |way, k| match way {
            Way::Gang if k == 0 => 1e-7,
            Way::Gang => 1e-9,
            Way::Alone => 2e-9,
        });
        assert_eq!(taking(&ways, Way::Alone), vec![2, 3, 13, 14, 32, 33, 67, 68, 134, 135, 265, 266, 524, 525]);
        // the gang's cost is that of its warm solves, to the division of whole nanoseconds
        let gang = pace.cost(Way::Gang).expect("measured");
        assert!((gang - 1e-9).abs() < 1e-24, "{gang}");
    }

    #[test]
    fn a_lone_slow_solve_does_not_change_the_way() {
        let mut pace = Pace::default();
        // the gang's 12th solve is held up 5× (the system took its core)
        let ways = run(&mut pace, 40, |way, k| match way {
            Way::Gang if k == 12 => 5e-9,
            Way::Gang => 1e-9,
            Way::Alone => 2e-9,
        });
        assert_eq!(taking(&ways, Way::Alone), vec![2, 3, 13, 14, 32, 33]);
    }

    #[test]
    fn the_way_follows_the_machine_when_the_gang_becomes_the_slower() {
        let mut pace = Pace::default();
        // the machine changes at solve 40: the gang 2× slower than one thread from then on;
        // after three gang solves at the new cost (40–42), alone but for the probes of the
        // gang, 9, 17, 33, … solves apart again
        let ways = run(&mut pace, 200, |way, k| match (way, k < 40) {
            (Way::Gang, true) => 1e-9,
            (Way::Gang, false) => 3e-9,
            (Way::Alone, _) => 1.5e-9,
        });
        assert_eq!(taking(&ways[..40], Way::Alone), vec![2, 3, 13, 14, 32, 33]);
        let gang: Vec<usize> = taking(&ways[40..], Way::Gang).iter().map(|k| k + 40).collect();
        assert_eq!(gang, vec![40, 41, 42, 52, 53, 71, 72, 106, 107, 173, 174]);
    }

    #[test]
    fn the_way_comes_back_when_the_gang_is_fast_again() {
        let mut pace = Pace::default();
        // the gang slow over solves 30–99, fast before and after: alone from solve 35 (after
        // three slow gang solves, 30, 31 and 34, around a probe), the gang probed at 44, 63,
        // 98, 165; the probe ending at 166 finds it fast again, and from then on only the
        // probes are alone
        let ways = run(&mut pace, 300, |way, k| match way {
            Way::Gang if (30..100).contains(&k) => 3e-9,
            Way::Gang => 1e-9,
            Way::Alone => 1.5e-9,
        });
        let gang: Vec<usize> = taking(&ways[35..167], Way::Gang).iter().map(|k| k + 35).collect();
        assert_eq!(gang, vec![44, 45, 63, 64, 98, 99, 165, 166]);
        let alone: Vec<usize> = taking(&ways[167..], Way::Alone).iter().map(|k| k + 167).collect();
        assert_eq!(alone, vec![176, 177, 195, 196, 230, 231, 297, 298]);
    }

    #[test]
    fn ways_of_nearly_the_same_cost_do_not_trade_places() {
        let mut pace = Pace::default();
        // one thread 1 % cheaper at first, 1 % dearer from solve 50: within the margin, so
        // alone stays chosen and the gang runs only its probes
        let ways = run(&mut pace, 200, |way, k| match way {
            Way::Gang => 1e-9,
            Way::Alone if k < 50 => 0.99e-9,
            Way::Alone => 1.01e-9,
        });
        let gang: Vec<usize> = taking(&ways[4..], Way::Gang).iter().map(|k| k + 4).collect();
        assert_eq!(gang, vec![13, 14, 32, 33, 67, 68, 134, 135]);
    }

    #[test]
    fn solves_without_work_are_not_recorded() {
        let mut pace = Pace::default();
        run(&mut pace, 10, |way, _| if way == Way::Gang { 1e-9 } else { 2e-9 });
        let before = (pace.cost(Way::Gang), pace.cost(Way::Alone), pace.taken);
        // a solve that needed no iteration, however long it took (its cost, 1 s / 0, would not
        // move a least-of-three: the count of measurements shows whether it was taken)
        pace.record(Way::Gang, Duration::from_secs(1), 0.0);
        assert_eq!((pace.cost(Way::Gang), pace.cost(Way::Alone), pace.taken), before);
        assert_eq!(pace.next(), Way::Gang);
    }
}
