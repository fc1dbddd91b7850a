//! The neighbour list's pairs cut into one segment per thread, and the cuts moved while the
//! list lasts so that the segments keep taking the same time.
//!
//! Where the cuts fall changes no bit of any sum ([`Segments`]), so they may follow the clock.
//! A plan gives each segment its share of the pairs' weight ([`pair_weight`]: touching or
//! apart); the shares start equal. Every [`BALANCE_WINDOW`] pair loops the segments' measured
//! times give each segment's speed (weight per second), and when the slowest segment ran more
//! than [`BALANCE_TOLERANCE`] over the mean, the shares move halfway toward the speeds' and the
//! pairs are cut again by their present contacts.
//!
//! Why: a settling bed keeps one neighbour list for hundreds of sub-steps while its contacts
//! open and close, and one core of a virtual machine may run slower than the other for a while.
//! On the 10⁴ settling bed with two threads, cut once when the list was built, one segment took
//! twice the other's time for a hundred sub-steps at a stretch, and over the whole run the two
//! differed by 87 µs per sub-step on average (of 530 µs): the time the faster thread waited.
//! Following the clock, the 10⁵ bed's two-thread run took 0.959 of its time (median of 6
//! alternating pairs), the 10⁴ bed's 0.978–0.993 (three sets of 16).
//!
//! Only the shares move halfway: a window's times carry the noise of the machine (a window
//! of the 10⁴ bed is about 16 ms), and a re-cut costs a few passes over the pairs.

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use super::neighbour_list::{Pair, Touch};
use super::pair_lanes::WIDEST_GROUP;

/// The listed pairs cut into consecutive segments, one per thread, each evaluated and added to
/// its particles as it goes ([`super::pair_forces::evaluate_and_add`]). A particle's pair
/// forces must be summed in list order (ascending partner id, the reference's order), so only
/// the first segment a particle appears in adds to it directly; later segments set their
/// contributions aside, and these are added after all segments are done, segment by segment:
/// the same sums in the same order as one thread takes them, wherever the cuts fall.
#[derive(Default)]
pub struct Segments {
    /// Segment s holds pairs `bounds[s]..bounds[s + 1]`; every cut but the list's end is a
    /// multiple of [`WIDEST_GROUP`], so only the last segment's last group can fall short of a
    /// kernel's width. An empty list has no segment (`[0]`).
    pub bounds: Vec<usize>,
    /// Each particle's first segment (`u32::MAX`: in no pair).
    pub first: Vec<u32>,
    /// The thread count it was planned for.
    pub threads: usize,
    /// Per segment, the weight the plan gave it.
    weights: Vec<f64>,
    /// Per segment, the nanoseconds its evaluations took since the last look at the balance.
    nanos: Vec<AtomicU64>,
    /// Pair loops since the last look at the balance.
    loops: u32,
    /// Per segment, its speed in the last window (a buffer kept between windows).
    speeds: Vec<f64>,
    /// Per segment, the most contributions it can set aside (the capacity its buffer needs so
    /// that no sub-step allocates, [`Self::reserve_aside`]).
    aside: Vec<usize>,
    /// Plans made so far (list builds, thread counts and re-cuts).
    pub cuts: u64,
    /// Per segment, the share of the weight it is planned to take (equal at first; kept across
    /// plans of the same segment count, since a slow core stays slow when the list is rebuilt;
    /// equal again when the count changes, with the threads or for a short list). Never below
    /// [`SMALLEST_SHARE`] of an equal share.
    shares: Vec<f64>,
}

/// Fewest pairs worth a segment of their own (a thread's share below this costs more in
/// setting aside than it gains).
const MIN_SEGMENT_PAIRS: usize = 1024;

/// Pair loops whose segment times are summed before the balance is looked at: long enough that
/// the clock's resolution and a single interruption do not decide (32 sub-steps of the 10⁴ bed
/// on two threads are about 16 ms of pair loop), short enough to follow a settling bed.
pub const BALANCE_WINDOW: u32 = 32;

/// The slowest segment's time over the mean beyond which the segments are cut again: a re-cut
/// costs four passes over the pairs (weights, cuts, first segments, set-aside bounds), worth it
/// only for a gain of a few per cent; below this, a window's imbalance is mostly the machine's
/// noise.
pub const BALANCE_TOLERANCE: f64 = 1.04;

/// The smallest share of the weight a segment is given, as a fraction of an equal share: a
/// segment never shrinks to nothing (which would leave its thread idle for good, since a list
/// with fewer segments than threads is never re-balanced). A quarter of an equal share of at
/// least [`MIN_SEGMENT_PAIRS`] pairs, each weighing at least 1, outweighs a group of
/// [`WIDEST_GROUP`] pairs weighing at most 3 each, so every planned cut is made.
const SMALLEST_SHARE: f64 = 0.25;

/// What a pair costs the pair loop, relative to one apart (an estimate: a touching pair takes
/// the contact law and is added to its particles, a group of pairs all apart returns early).
/// With segments of equal pair counts, the 10⁵ settling bed's first segment (the lower ids)
/// took a fifth longer than the second on two threads (28.7 % against 23.5 % of a profile's
/// samples in the pair kernel) while the other thread waited; cut by these weights, 26.5 %
/// against 25.6 %.
fn pair_weight(touch: &Touch) -> f64 {
    if touch.active() {
        3.0
    } else {
        1.0
    }
}

impl Segments {
    /// Plans the segments of `pairs` (their contact histories `touch`) among `n` particles for
    /// `threads` threads, each segment about the same work ([`pair_weight`]).
    pub fn plan(&mut self, pairs: &[Pair], touch: &[Touch], n: usize, threads: usize) {
        self.plan_with(pairs, n, threads, MIN_SEGMENT_PAIRS, |i| touch.get(i).map_or(1.0, pair_weight));
    }

    /// [`Self::plan`] with segments of at least `min_pairs` pairs (tests cut short lists) and
    /// pair `i` weighing `weight(i)`.
    pub fn plan_with(&mut self, pairs: &[Pair], n: usize, threads: usize, min_pairs: usize, weight: impl Fn(usize) -> f64) {
        let count = threads.clamp(1, (pairs.len() / min_pairs.max(1)).max(1));
        if self.shares.len() != count {
            self.shares = vec![1.0 / count as f64; count];
        }
        let total: f64 = (0..pairs.len()).map(&weight).sum();
        let mut until_cut = total * self.shares[0];
        self.bounds.clear();
        self.bounds.push(0);
        self.weights.clear();
        let mut sum = 0.0;
        let mut since_cut = 0.0;
        for (i, _) in pairs.iter().enumerate() {
            let cuts = self.bounds.len() - 1;
            // cut before the first whole group past the next share of the weight
            if cuts < count - 1 && i % WIDEST_GROUP == 0 && i > self.bounds[cuts] && sum >= until_cut {
                until_cut += total * self.shares[cuts + 1];
                self.bounds.push(i);
                self.weights.push(since_cut);
                since_cut = 0.0;
            }
            let w = weight(i);
            sum += w;
            since_cut += w;
        }
        if !pairs.is_empty() {
            self.bounds.push(pairs.len());
            self.weights.push(since_cut);
        }
        self.threads = threads;
        self.nanos.clear();
        self.nanos.resize_with(self.count(), AtomicU64::default);
        self.loops = 0;
        self.first.clear();
        self.first.resize(n, u32::MAX);
        for (s, bound) in self.bounds.windows(2).enumerate() {
            for pair in &pairs[bound[0]..bound[1]] {
                for p in [pair.a, pair.b] {
                    let first = &mut self.first[p as usize];
                    *first = (*first).min(s as u32);
                }
            }
        }
        // the most each segment can set aside: its pairs' sides whose particle an earlier
        // segment adds to
        self.aside.clear();
        for (s, bound) in self.bounds.windows(2).enumerate() {
            let sides = pairs[bound[0]..bound[1]].iter().flat_map(|pair| [pair.a, pair.b]);
            self.aside.push(sides.filter(|&p| self.first[p as usize] != s as u32).count());
        }
        self.cuts += 1;
    }

    /// Gives each segment's buffer of set-aside contributions (`set_aside`, one per segment)
    /// the capacity the plan can ask of it, so that the sub-steps between two plans allocate
    /// nothing (call after a plan; a no-op when the buffers are large enough).
    pub fn reserve_aside<T>(&self, set_aside: &mut Vec<Vec<T>>) {
        set_aside.resize_with(self.count(), Vec::new);
        for (buffer, &need) in set_aside.iter_mut().zip(&self.aside) {
            if buffer.capacity() < need {
                buffer.reserve(need - buffer.len());
            }
        }
    }

    /// How many segments there are.
    pub fn count(&self) -> usize {
        self.bounds.len().saturating_sub(1)
    }

    /// Books the time segment `s` took since `started` (segments book their own entries, from
    /// any thread).
    pub fn book(&self, s: usize, started: Instant) {
        let nanos = u64::try_from(started.elapsed().as_nanos()).unwrap_or(u64::MAX);
        self.nanos[s].fetch_add(nanos, Ordering::Relaxed);
    }

    /// After a pair loop over `pairs` (their histories `touch`, as the loop left them): every
    /// [`BALANCE_WINDOW`] loops, when the slowest segment took more than [`BALANCE_TOLERANCE`]
    /// of the mean, moves each segment's share of the weight halfway toward its share of the
    /// segments' speeds and cuts again. Returns whether it cut.
    pub fn rebalance(&mut self, pairs: &[Pair], touch: &[Touch], n: usize) -> bool {
        self.loops += 1;
        let count = self.count();
        if self.loops < BALANCE_WINDOW || count < 2 || self.shares.len() != count {
            return false;
        }
        self.loops = 0;
        // each segment's speed in weight per second (into a kept buffer: sub-steps allocate
        // nothing)
        self.speeds.clear();
        let mut total_seconds = 0.0;
        let mut slowest: f64 = 0.0;
        for (nanos, weight) in self.nanos.iter().zip(&self.weights) {
            let seconds = nanos.swap(0, Ordering::Relaxed) as f64 * 1e-9;
            (total_seconds, slowest) = (total_seconds + seconds, slowest.max(seconds));
            self.speeds.push(weight / seconds);
        }
        if !(slowest > BALANCE_TOLERANCE * total_seconds / count as f64) {
            return false;
        }
        // equal times need shares of the weight in proportion to the speeds (a segment that
        // took no measurable time, or weighs nothing, gives no speed: the shares stay)
        let total_speed: f64 = self.speeds.iter().sum();
        if !total_speed.is_finite() || self.speeds.iter().any(|v| !(*v > 0.0)) {
            return false;
        }
        let floor = SMALLEST_SHARE / count as f64;
        for (share, v) in self.shares.iter_mut().zip(&self.speeds) {
            *share = (0.5 * *share + 0.5 * v / total_speed).max(floor);
        }
        // what the floor added is taken from the shares above it, in proportion to their room
        // above it (there is enough: the floors sum to a quarter)
        let excess = self.shares.iter().sum::<f64>() - 1.0;
        let room: f64 = self.shares.iter().map(|share| share - floor).sum();
        if excess > 0.0 && room > 0.0 {
            self.shares.iter_mut().for_each(|share| *share -= excess * (*share - floor) / room);
        }
        self.plan(pairs, touch, n, self.threads);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chain(n: usize) -> Vec<Pair> {
        (0..n as u32).map(|k| Pair { a: k, b: k + 1, constants: 0 }).collect()
    }

    /// A segment that ran at a third of the other's speed gets, at the re-cut, half its old share
    /// and half its share of the speeds (½ · ½ + ½ · ¼ = ⅜ of the pairs); a balance within the
    /// tolerance keeps the cuts; nothing is looked at before a window is full; a new list keeps
    /// the shares.
    #[test]
    fn the_slower_segment_gets_fewer_pairs() {
        let pairs = chain(8192);
        let touch = vec![Touch::default(); pairs.len()];
        let mut segments = Segments::default();
        segments.plan(&pairs, &touch, pairs.len() + 1, 2);
        assert_eq!(segments.bounds, vec![0, 4096, 8192]);
        let book = |segments: &Segments, first: u64, second: u64| {
            segments.nanos[0].fetch_add(first, Ordering::Relaxed);
            segments.nanos[1].fetch_add(second, Ordering::Relaxed);
        };
        for _ in 0..BALANCE_WINDOW - 1 {
            book(&segments, 3000, 1000);
            assert!(!segments.rebalance(&pairs, &touch, pairs.len() + 1));
        }
        assert!(segments.rebalance(&pairs, &touch, pairs.len() + 1));
        assert_eq!(segments.bounds, vec![0, 3072, 8192]);
        assert!(segments.first[3071] == 0 && segments.first[3072] == 0 && segments.first[3073] == 1);
        for _ in 0..BALANCE_WINDOW {
            book(&segments, 1010, 1000);
            segments.rebalance(&pairs, &touch, pairs.len() + 1);
        }
        assert_eq!(segments.bounds, vec![0, 3072, 8192], "1 % apart is within the tolerance");
        segments.plan(&pairs, &touch, pairs.len() + 1, 2);
        assert_eq!(segments.bounds, vec![0, 3072, 8192], "a new plan keeps the shares");
        segments.plan(&pairs, &touch, pairs.len() + 1, 1);
        segments.plan(&pairs, &touch, pairs.len() + 1, 2);
        assert_eq!(segments.bounds, vec![0, 4096, 8192], "another thread count starts equal");
        // a chain's second segment sets aside one side: its first pair's a, whose first
        // segment is the first
        assert_eq!(segments.aside, vec![0, 1]);
        let mut set_aside: Vec<Vec<u8>> = Vec::new();
        segments.reserve_aside(&mut set_aside);
        assert!(set_aside.len() == 2 && set_aside[1].capacity() >= 1);
    }

    /// However slow a segment's thread, its share stays at least a quarter of an equal one, so
    /// every cut is made and both threads keep a segment (a segment whose share shrank to
    /// nothing would have left its thread idle for good).
    #[test]
    fn a_very_slow_segment_keeps_a_floor_share() {
        let pairs = chain(2048);
        let touch = vec![Touch::default(); pairs.len()];
        let mut segments = Segments::default();
        segments.plan(&pairs, &touch, pairs.len() + 1, 2);
        for _ in 0..20 * BALANCE_WINDOW {
            segments.nanos[0].fetch_add(1_000_000, Ordering::Relaxed);
            segments.nanos[1].fetch_add(1, Ordering::Relaxed);
            segments.rebalance(&pairs, &touch, pairs.len() + 1);
            assert_eq!(segments.count(), 2, "bounds {:?}, shares {:?}", segments.bounds, segments.shares);
        }
        let floor = SMALLEST_SHARE / 2.0;
        assert!((segments.shares[0] - floor).abs() < 1e-12 && (segments.shares.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{:?}", segments.shares);
        assert_eq!(segments.bounds, vec![0, 256, 2048]);
    }
}
