//! Whether a solver's next solve runs on a gang of the pool's threads or on the calling thread
//! alone, chosen by the speed each way has had on this machine in this run.
//!
//! Why: a gang's members meet at hundreds of barriers per iteration and read each other's
//! rows at their blocks' edges, so a gang is as fast as the cache line that carries them
//! between the cores. On the 2-core VM that line takes 26–45 ns in some periods and 180–260 ns
//! in others (a two-thread ping-pong, measured between runs on 2026-11-28; the two vCPUs
//! sharing a core or not). The default cutter head's first 0.15 revolution took 3.83–3.94 s on
//! 2 threads in the fast periods, 6.31–6.33 s in the slow ones, and 5.85–6.04 s on 1 thread in
//! either (runs alternating): in the slow periods the gangs made two threads slower than one.
//! A machine with several sockets has the same slow line between them.
//!
//! So every solver keeps the cost per unit of work (seconds per row and iteration) that each
//! way has had lately, runs its solves the cheaper way, and now and then one solve the other
//! way (a probe), to follow the machine when it changes. The way changes only who computes:
//! a gang's sums and loops give the bits of one thread whatever its size ([`super::gang`]), so
//! the results do not depend on the timings.

use std::time::{Duration, Instant};

use super::gang::{self, Crew, PartialSum};

/// The two ways of running a solve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Way {
    /// A gang of the pool's threads ([`super::gang::run`]).
    Gang,
    /// The calling thread alone ([`super::gang::run_alone`]).
    Alone,
}

/// A solve that runs the way not chosen, to measure it again (a probe), comes this many
/// solves after the last one while the choice keeps being confirmed, doubling from
/// [`PROBE_FIRST`] up to [`PROBE_LAST`] solves; after the choice changes, again after
/// [`PROBE_FIRST`]. The machine's periods last minutes, a solve milliseconds: at the longest
/// interval a change is found within a second or two of a run, and the probes cost 1/256 of
/// the difference between the ways.
const PROBE_FIRST: u64 = 8;
const PROBE_LAST: u64 = 256;

/// The first solve of a run is not recorded: it faults in the memory of its vectors.
const COLD: u64 = 1;

/// A way's cost is the least of its last this many measurements: interference (other
/// processes, the system) only ever slows a solve, so a lone slow solve does not move the
/// estimate, while a change of the machine shows after this many solves of the way.
const KEPT: usize = 3;

/// A solver's record of the two ways' costs.
#[derive(Clone, Debug, Default)]
pub struct Pace {
    /// The last [`KEPT`] measurements (seconds per unit of work) of [`Way::Gang`] and
    /// [`Way::Alone`], the n-th of a way at n mod [`KEPT`].
    samples: [[f64; KEPT]; 2],
    /// Measurements taken of each way (all of them, not only those kept).
    taken: [u64; 2],
    /// Solves recorded, and the cold ones before them.
    solves: u64,
    /// Solves from one probe to the next, and the solve of the next probe.
    interval: u64,
    next_probe: u64,
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
    /// The way the next solve takes.
    pub fn next(&self) -> Way {
        match self.cheaper() {
            // a gang first, then a solve alone, before either is chosen
            None if self.cost(Way::Gang).is_none() => Way::Gang,
            None => Way::Alone,
            Some(cheaper) if self.solves >= self.next_probe => cheaper.other(),
            Some(cheaper) => cheaper,
        }
    }

    /// The way measured cheaper, once both are measured.
    fn cheaper(&self) -> Option<Way> {
        Some(if self.cost(Way::Alone)? < self.cost(Way::Gang)? { Way::Alone } else { Way::Gang })
    }

    /// Records a solve that took `way`, `elapsed`, for `work` units (rows × iterations; none
    /// recorded for no work).
    pub fn record(&mut self, way: Way, elapsed: Duration, work: f64) {
        if work <= 0.0 {
            return;
        }
        if self.solves < COLD {
            self.solves += 1;
            return;
        }
        let before = self.cheaper();
        let k = way.index();
        self.samples[k][(self.taken[k] % KEPT as u64) as usize] = elapsed.as_secs_f64() / work;
        self.taken[k] += 1;
        let after = self.cheaper();
        self.interval = match (before, after) {
            // both ways just measured for the first time
            (None, Some(_)) => PROBE_FIRST,
            // the choice changed, by a probe or by the chosen way's own solves
            (Some(before), Some(after)) if before != after => PROBE_FIRST,
            // a probe confirmed the choice
            (Some(before), _) if before != way => (2 * self.interval).min(PROBE_LAST),
            _ => self.interval,
        };
        if before != after || before.is_some_and(|before| before != way) {
            self.next_probe = self.solves + self.interval;
        }
        self.solves += 1;
    }

    /// The seconds per unit of work of `way`: the least of its last [`KEPT`] measurements,
    /// once measured.
    pub fn cost(&self, way: Way) -> Option<f64> {
        let k = way.index();
        let kept = (self.taken[k] as usize).min(KEPT);
        self.samples[k][..kept].iter().copied().reduce(f64::min)
    }
}

/// `body` run by a gang of the pool's threads or by the calling thread alone, as `pace`
/// chooses, and the time recorded against `rows × (iterations + 1)` units of work, with
/// `iterations` read from the result. Where no gang can form (a pool of one thread, or fewer
/// rows than [`gang::GANG_MIN_ROWS`]) it runs alone and records nothing.
pub fn run_paced<R: Send>(
    pace: &mut Pace,
    rows: usize,
    partials: &mut Vec<PartialSum>,
    body: impl Fn(&Crew) -> R + Sync,
    iterations: impl FnOnce(&R) -> usize,
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
    pace.record(way, start.elapsed(), (rows * (iterations(&result) + 1)) as f64);
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
    fn a_run_starts_as_a_gang_measures_alone_once_and_keeps_the_cheaper_way() {
        let mut pace = Pace::default();
        // the gang twice as fast, its first (cold) solve 100× slower: after the first solve
        // alone (2), a gang but for the probes, 8, 16, 32, … 256 solves apart
        let ways = run(&mut pace, 600, |way, k| match way {
            Way::Gang if k == 0 => 1e-7,
            Way::Gang => 1e-9,
            Way::Alone => 2e-9,
        });
        assert_eq!(taking(&ways, Way::Alone), vec![2, 10, 26, 58, 122, 250, 506]);
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
        assert_eq!(taking(&ways, Way::Alone), vec![2, 10, 26]);
    }

    #[test]
    fn the_way_follows_the_machine_when_the_gang_becomes_the_slower() {
        let mut pace = Pace::default();
        // the machine changes at solve 40: the gang 2× slower than one thread from then on;
        // after three gang solves at the new cost (40–42), alone but for the probes of the
        // gang, 8, 16, 32, … solves apart again
        let ways = run(&mut pace, 200, |way, k| match (way, k < 40) {
            (Way::Gang, true) => 1e-9,
            (Way::Gang, false) => 3e-9,
            (Way::Alone, _) => 1.5e-9,
        });
        assert_eq!(taking(&ways[..40], Way::Alone), vec![2, 10, 26]);
        assert_eq!(taking(&ways[40..], Way::Gang).iter().map(|k| k + 40).collect::<Vec<_>>(), vec![40, 41, 42, 50, 66, 98, 162]);
    }

    #[test]
    fn the_way_comes_back_when_the_gang_is_fast_again() {
        let mut pace = Pace::default();
        // the gang slow over solves 30–99, fast before and after: alone from solve 33, the
        // gang probed at 40, 56, 88, 152 (the intervals doubling); the probe at 152 finds it
        // fast again, and from then on only the probes are alone
        let ways = run(&mut pace, 300, |way, k| match way {
            Way::Gang if (30..100).contains(&k) => 3e-9,
            Way::Gang => 1e-9,
            Way::Alone => 1.5e-9,
        });
        let gang: Vec<usize> = taking(&ways[33..153], Way::Gang).iter().map(|k| k + 33).collect();
        assert_eq!(gang, vec![40, 56, 88, 152]);
        let alone: Vec<usize> = taking(&ways[153..], Way::Alone).iter().map(|k| k + 153).collect();
        assert_eq!(alone, vec![160, 176, 208, 272]);
    }

    #[test]
    fn solves_without_work_are_not_recorded() {
        let mut pace = Pace::default();
        pace.record(Way::Gang, Duration::from_millis(3), 0.0);
        assert_eq!(pace.cost(Way::Gang), None);
        assert_eq!(pace.next(), Way::Gang);
    }
}
