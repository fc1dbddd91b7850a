//! The pool's threads kept awake from one parallel loop to the next.
//!
//! A DEM sub-step has two parallel parts (the pair segments, then the pass over the particles),
//! each a fraction of a millisecond in a 10⁴ bed; a pressure solve is hundreds of loops of tens
//! of microseconds. Handed to rayon one by one, each waited for a sleeping worker to wake:
//! measured on the 2-core VM, the second pair segment started 60–230 µs after the first, per
//! part and sub-step, which held two threads to 1.2–1.5× one.
//!
//! A [`Team`] instead keeps the pool's other workers spinning on a shared ticket, and each part
//! is split into pieces that any member claims (the caller too), so a piece starts within a
//! spin of being posted. While spinning, the members also take the pool's other work (rayon's
//! parallel iterators, [`crate::linear::par_update`], the gangs of the linear solves,
//! [`crate::linear::gang`]) as soon as it is queued: [`keep_awake`] holds a team for a whole run
//! for that alone.
//!
//! Each member has a home share of every part's pieces, the same share of consecutive pieces
//! in every part of the team (the caller the first, the helpers the next ones in the order they
//! join): it runs its own from the front, then takes what is left of the others' from the back.
//! A sub-step's parts cut the particles the same way every time, so a thread keeps meeting the
//! same particles and finds them in its own cache. Pieces handed out
//! first come, first served went to whichever thread came first, so a block's particles changed
//! cores from one sub-step to the next (measured on 2 threads, medians of interleaved runs: the
//! 10⁵ settling bed 13.18 → 12.78 s, the 10⁴ bed 1.167 → 1.149 s).
//!
//! Which thread runs which piece does not matter for the results: the pieces write disjoint
//! memory and their sums are combined in piece order, so the bits are those of one thread.
//! A member that never joins (the pool's workers busy elsewhere) leaves its pieces to the
//! others; with one thread the caller runs every piece in order.

use std::any::Any;
use std::marker::PhantomData;
use std::ops::Range;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

/// A part of a sub-step, run piece by piece: `piece(i)` for every i below the piece count.
pub type Part<'a> = dyn Fn(usize) + Sync + 'a;

/// The posted part: its number and the part itself with its lifetime
/// erased (sound because [`Team::run`] returns only once every claimed piece has finished, and
/// a piece is claimed only while its part is posted).
#[derive(Clone, Copy)]
struct Posted {
    part: u64,
    run: *const Part<'static>,
}

// SAFETY: the pointer is dereferenced only by a member holding a claimed piece of the posted
// part, which `Team::run` outlives (see `Posted`); the part itself is `Sync`.
unsafe impl Send for Posted {}

/// Iterations of a member's spin between two looks for the pool's other work (rayon's
/// parallel iterators queued by the caller) and, finding none, a yield of the core to the
/// system.
const SPINS_PER_LOOK: u32 = 64;

/// How long a member without work spins before it naps: far longer than the gaps between two
/// loops of a step (microseconds), far shorter than a run's serial stretches (writing frames).
const SPIN_BEFORE_NAPS: Duration = Duration::from_millis(2);

/// A napping member's sleep between two looks at the pool's work (a part posted to the team
/// wakes it at once).
const NAP: Duration = Duration::from_micros(200);

/// What a team holds before its first part.
fn no_part(_: usize) {}

/// Threads running the parts of a step together ([`with_team`]).
pub struct Team {
    posted: Mutex<Posted>,
    /// The posted part's number in the upper 32 bits (its publication: the homes are set first).
    ticket: AtomicU64,
    /// Per member, the pieces of its home share not yet claimed: the part's number in the upper
    /// [`PART_BITS`], the first unclaimed piece in the next [`PIECE_BITS`], the end of the share
    /// in the lower [`PIECE_BITS`].
    homes: Vec<Share>,
    /// Pieces of the posted part finished.
    finished: AtomicUsize,
    /// A piece panicked: its payload, re-raised by [`Team::run`] on the caller.
    panic: Mutex<Option<Box<dyn Any + Send>>>,
    stop: AtomicBool,
    /// The caller's count of parts posted.
    parts: AtomicU64,
    /// The members helping (woken when a part is posted).
    members: Mutex<Vec<std::thread::Thread>>,
    /// A part is being run ([`Team::run`] is not re-entrant).
    posting: AtomicBool,
    /// The thread that owns the team (runs `with_team`'s closure): it never helps its own team
    /// (were it to pick a helper job from its own queue while the closure waits, it would spin
    /// until a stop only the closure can give).
    owner: OnceLock<std::thread::ThreadId>,
}

/// A member's home share, on a cache line of its own: the members claim their own shares at
/// the same time, and shares on one line would pass it between the cores at every claim.
#[repr(align(128))]
struct Share(AtomicU64);

/// Bits of a home share's bounds: a part has fewer than 2²⁰ pieces (a pass's blocks of 256
/// particles: 268 million particles).
const PIECE_BITS: u32 = 20;
const PIECE_MASK: u64 = (1 << PIECE_BITS) - 1;
/// Bits of the part's number in a share: a team posts fewer than 2²⁴ parts (two a DEM sub-step,
/// a team lasting one outer step).
const PART_BITS: u32 = 64 - 2 * PIECE_BITS;
const PART_SHIFT: u32 = 2 * PIECE_BITS;

impl Team {
    /// A team of `members` threads (the caller and its helpers).
    fn new(members: usize) -> Self {
        Self {
            posted: Mutex::new(Posted { part: 0, run: &no_part as &Part<'static> as *const Part<'static> }),
            ticket: AtomicU64::new(0),
            homes: (0..members.max(1)).map(|_| Share(AtomicU64::new(0))).collect(),
            finished: AtomicUsize::new(0),
            panic: Mutex::new(None),
            stop: AtomicBool::new(false),
            parts: AtomicU64::new(0),
            // room for every helper: one joining late (a busy machine) allocates nothing in a sub-step
            members: Mutex::new(Vec::with_capacity(members)),
            posting: AtomicBool::new(false),
            owner: OnceLock::new(),
        }
    }

    /// Runs `part(i)` for every piece `i < pieces`, spread over the members, and returns once
    /// all have finished. One part at a time: posting another while one runs (from a piece, or
    /// from another thread) panics.
    pub fn run(&self, pieces: usize, part: &Part) {
        if pieces == 0 {
            return;
        }
        assert!(!self.posting.swap(true, Ordering::Acquire), "a team runs one part at a time");
        let number = self.parts.fetch_add(1, Ordering::Relaxed) + 1;
        assert!(number < 1 << PART_BITS && pieces < 1 << PIECE_BITS, "a team posts fewer than 2²⁴ parts of fewer than 2²⁰ pieces");
        // SAFETY: only the lifetime is erased; see `Posted`.
        let run = unsafe { std::mem::transmute::<*const Part<'_>, *const Part<'static>>(part as *const Part) };
        *self.posted.lock().unwrap_or_else(|e| e.into_inner()) = Posted { part: number, run };
        self.finished.store(0, Ordering::Relaxed);
        let homes = self.homes.len();
        for (m, home) in self.homes.iter().enumerate() {
            let (start, end) = (m * pieces / homes, (m + 1) * pieces / homes);
            home.0.store(number << PART_SHIFT | (start as u64) << PIECE_BITS | end as u64, Ordering::Relaxed);
        }
        // publishes the part (Release: a member that sees the ticket sees the posted part and
        // its home shares)
        self.ticket.store(number << 32, Ordering::Release);
        for member in self.members.lock().unwrap_or_else(|e| e.into_inner()).iter() {
            member.unpark();
        }
        // SAFETY: `part` is borrowed for this whole call
        unsafe { self.claim_pieces(number, run, 0) };
        let mut spins = 0u32;
        while self.finished.load(Ordering::Acquire) < pieces {
            spins += 1;
            // a member descheduled in the middle of a piece (more threads than cores) gets
            // the core back
            if spins.is_multiple_of(1024) {
                std::thread::yield_now();
            } else {
                std::hint::spin_loop();
            }
        }
        self.posting.store(false, Ordering::Release);
        if let Some(payload) = self.panic.lock().unwrap_or_else(|e| e.into_inner()).take() {
            std::panic::resume_unwind(payload);
        }
    }

    /// Claims and runs pieces of part `number` until none is left (or another part is posted):
    /// those of its `home` share from the front, then the others' from the back.
    ///
    /// # Safety
    /// `part` is the part posted as `number` (or the caller's own, still borrowed).
    unsafe fn claim_pieces(&self, number: u64, part: *const Part<'static>, home: usize) {
        let homes = self.homes.len();
        for k in 0..homes {
            let share = &self.homes[(home + k) % homes].0;
            let own = k == 0;
            let mut cursor = share.load(Ordering::Acquire);
            loop {
                let (first, end) = ((cursor >> PIECE_BITS) & PIECE_MASK, cursor & PIECE_MASK);
                if cursor >> PART_SHIFT != number {
                    // a later part is posted: this one's pieces are all claimed
                    return;
                }
                if first >= end {
                    break;
                }
                let (piece, rest) = if own { (first, cursor + (1 << PIECE_BITS)) } else { (end - 1, cursor - 1) };
                match share.compare_exchange_weak(cursor, rest, Ordering::AcqRel, Ordering::Acquire) {
                    Ok(_) => {
                        // SAFETY: a piece of part `number` is claimed, so `run(number)` is
                        // waiting for it and the part it posted is alive
                        let part = unsafe { &*part };
                        if let Err(payload) = catch_unwind(AssertUnwindSafe(|| part(piece as usize))) {
                            *self.panic.lock().unwrap_or_else(|e| e.into_inner()) = Some(payload);
                        }
                        self.finished.fetch_add(1, Ordering::Release);
                        cursor = share.load(Ordering::Acquire);
                    }
                    Err(now) => cursor = now,
                }
            }
        }
    }

    /// A member's loop: spin on the ticket, help with the posted part and the pool's other
    /// work, until stopped; idle for longer than [`SPIN_BEFORE_NAPS`], it naps between looks.
    fn help(&self) {
        if self.owner.get() == Some(&std::thread::current().id()) {
            return;
        }
        // numbered as the helpers join: the caller, which never helps its own team, holds the
        // first share
        let home = {
            let mut members = self.members.lock().unwrap_or_else(|e| e.into_inner());
            members.push(std::thread::current());
            members.len()
        };
        let mut done_with = 0;
        let mut spins = 0u32;
        let mut idle_since = Instant::now();
        while !self.stop.load(Ordering::Acquire) {
            let ticket = self.ticket.load(Ordering::Acquire);
            let number = ticket >> 32;
            if number != done_with {
                let posted = *self.posted.lock().unwrap_or_else(|e| e.into_inner());
                if posted.part == number {
                    // SAFETY: `posted.run` is part `number`'s, dereferenced only once a piece of
                    // it is claimed (while `run` waits for that piece)
                    unsafe { self.claim_pieces(number, posted.run, home) };
                    done_with = number;
                    idle_since = Instant::now();
                }
                continue;
            }
            spins += 1;
            if spins < SPINS_PER_LOOK {
                std::hint::spin_loop();
                continue;
            }
            spins = 0;
            // the pool's other work (a neighbour-list build, the fluid's loops and solves) is taken as it
            // comes; with none, the core is offered to the system (a pool with more threads than
            // cores must not starve the thread that posts the parts)
            if rayon::yield_now() == Some(rayon::Yield::Executed) {
                idle_since = Instant::now();
            } else if idle_since.elapsed() > SPIN_BEFORE_NAPS {
                // a serial stretch of the run (output): `run` wakes the member when it posts
                std::thread::park_timeout(NAP);
            } else {
                std::thread::yield_now();
            }
        }
    }
}

/// Runs `f` with a team of the current rayon pool's threads: the pool's other workers spin on
/// the team until `f` returns. With one thread, `f`'s parts run on the caller alone.
pub fn with_team<R: Send>(f: impl FnOnce(&Team) -> R + Send) -> R {
    let members = rayon::current_num_threads();
    let team = Team::new(members);
    if members <= 1 {
        return f(&team);
    }
    rayon::scope(|scope| {
        // the closure runs here (on a worker of the pool, even when called from outside it)
        let _ = team.owner.set(std::thread::current().id());
        for _ in 1..members {
            scope.spawn(|_| team.help());
        }
        let result = catch_unwind(AssertUnwindSafe(|| f(&team)));
        team.stop.store(true, Ordering::Release);
        result.unwrap_or_else(|payload| std::panic::resume_unwind(payload))
    })
}

/// A slice the pieces of a part share, each piece taking its own range of it (as
/// `par_chunks_mut` hands out chunks, but to pieces claimed by whichever member comes).
pub struct DisjointSlices<'a, T> {
    start: *mut T,
    len: usize,
    slice: PhantomData<&'a mut [T]>,
}

// SAFETY: the pieces take disjoint ranges (the contract of `range`), as `par_chunks_mut` would
// hand them out.
unsafe impl<T: Send> Sync for DisjointSlices<'_, T> {}

impl<'a, T> DisjointSlices<'a, T> {
    pub fn new(slice: &'a mut [T]) -> Self {
        Self { start: slice.as_mut_ptr(), len: slice.len(), slice: PhantomData }
    }

    /// The elements in `range`.
    ///
    /// # Safety
    /// No other range taken from this slice and still in use overlaps `range`.
    #[allow(clippy::mut_from_ref)]
    pub unsafe fn range(&self, range: Range<usize>) -> &'a mut [T] {
        assert!(range.start <= range.end && range.end <= self.len, "range {range:?} of a slice of {}", self.len);
        // SAFETY: in bounds (above); exclusive by the caller's contract.
        unsafe { std::slice::from_raw_parts_mut(self.start.add(range.start), range.end - range.start) }
    }
}

/// Runs `f` with the current pool's other workers spinning (and taking the pool's work as
/// soon as it is queued) until it returns: [`with_team`] without posting parts.
pub fn keep_awake<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    with_team(|_| f())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every piece of every part runs exactly once, on whichever member claims it, and a part's
    /// writes are all visible when `run` returns; a team of one runs them in order.
    #[test]
    fn every_piece_runs_once_per_part() {
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let counts: Vec<AtomicUsize> = (0..97).map(|_| AtomicUsize::new(0)).collect();
            let order = Mutex::new(Vec::new());
            pool.install(|| {
                with_team(|team| {
                    for round in 0..500 {
                        let pieces = 1 + round % 97;
                        team.run(pieces, &|i| {
                            counts[i].fetch_add(1, Ordering::Relaxed);
                            if threads == 1 && round == 40 {
                                order.lock().unwrap().push(i);
                            }
                        });
                        // everything the part did is done
                        let total: usize = counts.iter().map(|c| c.load(Ordering::Relaxed)).sum();
                        let expected: usize = (0..=round).map(|r| 1 + r % 97).sum();
                        assert_eq!(total, expected, "{threads} threads, round {round}");
                    }
                })
            });
            if threads == 1 {
                assert_eq!(*order.lock().unwrap(), (0..41).collect::<Vec<_>>());
            }
        }
    }

    /// Members that napped through a serial stretch longer than [`SPIN_BEFORE_NAPS`] still run
    /// the next part, and the pool's own parallel loops run inside [`keep_awake`].
    #[test]
    fn napping_members_and_the_pools_loops() {
        use rayon::prelude::*;
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let counts: Vec<AtomicUsize> = (0..16).map(|_| AtomicUsize::new(0)).collect();
        let sum = pool.install(|| {
            keep_awake(|| {
                let mut sum = 0u64;
                for _ in 0..3 {
                    std::thread::sleep(SPIN_BEFORE_NAPS * 3);
                    sum += (0..100_000u64).into_par_iter().sum::<u64>();
                    with_team(|team| {
                        std::thread::sleep(SPIN_BEFORE_NAPS * 3);
                        team.run(16, &|i| {
                            counts[i].fetch_add(1, Ordering::Relaxed);
                        });
                    });
                }
                sum
            })
        });
        assert_eq!(sum, 3 * 99_999 * 100_000 / 2);
        assert!(counts.iter().all(|c| c.load(Ordering::Relaxed) == 3));
    }

    /// A caller whose helpers never join runs every share: its own from the front, then the
    /// others' from the back, each piece once.
    #[test]
    fn the_caller_takes_the_shares_of_members_that_never_join() {
        let team = Team::new(3);
        let order = Mutex::new(Vec::new());
        for _ in 0..2 {
            order.lock().unwrap().clear();
            team.run(10, &|i| order.lock().unwrap().push(i));
            assert_eq!(*order.lock().unwrap(), [0, 1, 2, 5, 4, 3, 9, 8, 7, 6]);
        }
    }

    /// A part posted from inside a piece is refused (it would reset the count the outer part
    /// waits on).
    #[test]
    fn one_part_at_a_time() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
        let caught = pool.install(|| catch_unwind(AssertUnwindSafe(|| with_team(|team| team.run(2, &|_| team.run(1, &|_| {}))))));
        let payload = caught.expect_err("the nested part is refused");
        assert_eq!(payload.downcast_ref::<&str>(), Some(&"a team runs one part at a time"));
    }

    /// A panicking piece reaches the caller of `run` instead of hanging the team.
    #[test]
    fn a_panicking_piece_reaches_the_caller() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let caught = pool.install(|| {
            catch_unwind(AssertUnwindSafe(|| {
                with_team(|team| {
                    team.run(8, &|i| {
                        if i == 5 {
                            panic!("piece 5");
                        }
                    })
                })
            }))
        });
        let payload = caught.expect_err("the panic reaches the caller");
        assert_eq!(payload.downcast_ref::<&str>(), Some(&"piece 5"));
    }
}
