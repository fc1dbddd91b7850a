//! A whole solve run by a gang of threads at once (SPMD, as an OpenMP parallel region): every
//! member runs the same code, each loop on its own block of the rows, the members meeting at a
//! spinning barrier after each loop; scalars (step lengths, residuals) every member computes
//! alike from the same sums.
//!
//! Why: a pressure solve on the meshes this solver runs (10–50 thousand cells) is thousands of
//! loops of a few microseconds each (a multicolour sweep of one colour of a coarse level is a
//! few hundred rows). Handed to rayon one by one, a loop cost 3–5 µs more on two threads than
//! its work (measured: a 3 000-entry update took 3.0 µs on one thread and 3.9 µs on two, with
//! the workers kept awake), so the loops of the coarse levels ran on one thread and the cutter
//! head's pressure solve was no faster on two threads than on one. A barrier of a gang costs a
//! fraction of a microsecond.
//!
//! Determinism: a sum is cut into fixed chunks of [`GANG_CHUNK`] entries whatever the gang's
//! size, each chunk summed in index order, the chunk sums added in chunk order by every member
//! (the bits of one thread); element-wise loops write
//! disjoint entries. A gang that gathers fewer members than the pool has threads (the others
//! busy) computes the same bits.
//!
//! Shared vectors are slices of [`Slot`]s: members read and write entries through them, with
//! the rule that makes this sound — between two barriers, an entry written by one member is
//! neither read nor written by another. The kernels that take a [`Crew`] are `unsafe`: their
//! callers promise that rule for the vectors they pass (no other gang uses them, an output is
//! not also an input the kernel reads at other rows) and that every member of the crew calls
//! the same kernels in the same order, as the collective operations of [`Crew`] require.

use std::any::Any;
use std::cell::{Cell, UnsafeCell};
use std::ops::Range;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use super::reduce::{chunk_sum, in_chunk_order, GANG_CHUNK};

/// An entry of a vector the members of a gang share.
#[repr(transparent)]
#[derive(Default)]
pub struct Slot<T>(UnsafeCell<T>);

// SAFETY: members access a slot only under the gang's rule (module doc): no two members touch
// an entry between two barriers when one of them writes it.
unsafe impl<T: Send> Sync for Slot<T> {}

impl<T: Copy> Slot<T> {
    /// # Safety
    /// No other thread writes this entry between the barriers around the read.
    #[inline(always)]
    pub unsafe fn get(&self) -> T {
        unsafe { *self.0.get() }
    }

    /// # Safety
    /// No other thread reads or writes this entry between the barriers around the write.
    #[inline(always)]
    pub unsafe fn set(&self, value: T) {
        unsafe { *self.0.get() = value }
    }

    /// The entries of a slice borrowed uniquely, as slots (as `Cell::from_mut`).
    pub fn from_mut_slice(values: &mut [T]) -> &[Slot<T>] {
        // SAFETY: `Slot<T>` is `repr(transparent)` over `UnsafeCell<T>`, itself over `T`; the
        // unique borrow is held for the slots' lifetime
        unsafe { &*(values as *mut [T] as *const [Slot<T>]) }
    }

    /// The entries as plain values, when no member runs.
    pub fn as_mut_slice(slots: &mut [Slot<T>]) -> &mut [T] {
        // SAFETY: as `from_mut_slice`; the unique borrow excludes every member
        unsafe { &mut *(slots as *mut [Slot<T>] as *mut [T]) }
    }
}

/// A slot's clone is a fresh default entry: slots hold the scratch vectors of a solve, whose
/// entries are written before they are read in every solve.
impl<T: Copy + Default> Clone for Slot<T> {
    fn clone(&self) -> Self {
        Slot::default()
    }
}

impl<T> std::fmt::Debug for Slot<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Slot")
    }
}

/// The two sums of one chunk, written by the member that owns the chunk and read by all after
/// a barrier. Atomic (relaxed: the barrier orders them), so that members calling the sums out
/// of step get wrong numbers rather than a data race.
#[derive(Default)]
pub struct PartialSum([AtomicU64; 2]);

impl PartialSum {
    fn set(&self, sums: [f64; 2]) {
        self.0[0].store(sums[0].to_bits(), Ordering::Relaxed);
        self.0[1].store(sums[1].to_bits(), Ordering::Relaxed);
    }

    fn get(&self) -> [f64; 2] {
        [f64::from_bits(self.0[0].load(Ordering::Relaxed)), f64::from_bits(self.0[1].load(Ordering::Relaxed))]
    }
}

/// Chunk sums are scratch: a clone starts afresh.
impl Clone for PartialSum {
    fn clone(&self) -> Self {
        PartialSum::default()
    }
}

impl std::fmt::Debug for PartialSum {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("PartialSum")
    }
}

/// Element-wise loops give a member at least this many entries (a few hundred nanoseconds of
/// work, the cost of the barrier after them); shorter loops run on fewer members.
const MIN_BLOCK: usize = 64;

/// Block boundaries are multiples of this many entries (a cache line of f32), so two members do
/// not write one line of a vector they write in index order (loops over rows in colour order
/// or through an index list can still share lines at their blocks' edges).
const ALIGN: usize = 16;

/// Spins of a waiting member between two offers of its core to the system (a member
/// descheduled by an oversubscribed machine gets it back).
const SPINS_PER_YIELD: u32 = 4096;

/// How long the first member waits for the others to join before it starts with those that
/// have: the pool's threads kept awake join within microseconds, a sleeping pool's within tens.
#[cfg(not(test))]
const GATHER: Duration = Duration::from_micros(300);
/// In the tests, which run side by side on few cores, long enough for a worker the system has
/// not scheduled yet: they check what a gang of several members computes, not how fast it forms.
#[cfg(test)]
const GATHER: Duration = Duration::from_millis(50);

/// Solves shorter than this many rows run on the calling thread alone (their loops are shorter
/// than the gathering of a gang).
pub const GANG_MIN_ROWS: usize = 4096;

/// The gate bit set once the gang's membership is closed (the lower bits count the members).
const CLOSED: usize = 1 << (usize::BITS - 1);

/// State the members of one gang share.
struct Gang {
    /// Members joined, and [`CLOSED`] once no more may join.
    gate: AtomicUsize,
    /// Members arrived at the current barrier.
    waiting: AtomicUsize,
    /// Barriers passed: on a cache line of its own, as the waiting members poll it while the
    /// others arrive.
    generation: OwnLine,
    poisoned: AtomicBool,
    payload: Mutex<Option<Box<dyn Any + Send>>>,
}

#[repr(align(128))]
struct OwnLine(AtomicUsize);

/// The panic of a member that found another member's panic (not reported: the first one is).
struct Poisoned;

impl Gang {
    fn new() -> Self {
        Gang {
            gate: AtomicUsize::new(1),
            waiting: AtomicUsize::new(0),
            generation: OwnLine(AtomicUsize::new(0)),
            poisoned: AtomicBool::new(false),
            payload: Mutex::new(None),
        }
    }
}

/// One member of a running gang: its number, the gang's size, and the shared partial sums.
/// Its collective operations ([`Crew::barrier`], [`Crew::for_each`], [`Crew::sum`],
/// [`Crew::sum2`], [`Crew::alone`]) must be called by every member, in the same order.
pub struct Crew<'g> {
    id: usize,
    size: usize,
    gang: &'g Gang,
    /// Two buffers of chunk sums, used in turn (a member may write the next sum's chunks while
    /// another still reads this one's).
    partials: &'g [PartialSum],
    flip: Cell<usize>,
}

impl Crew<'_> {
    pub fn id(&self) -> usize {
        self.id
    }

    pub fn size(&self) -> usize {
        self.size
    }

    /// Waits until every member has arrived.
    pub fn barrier(&self) {
        if self.size == 1 {
            return;
        }
        let gang = self.gang;
        let generation = gang.generation.0.load(Ordering::Acquire);
        if gang.waiting.fetch_add(1, Ordering::AcqRel) + 1 == self.size {
            gang.waiting.store(0, Ordering::Relaxed);
            gang.generation.0.store(generation + 1, Ordering::Release);
            return;
        }
        let mut spins = 0u32;
        while gang.generation.0.load(Ordering::Acquire) == generation {
            spins += 1;
            if spins.is_multiple_of(SPINS_PER_YIELD) {
                // looked at now and then only: the flag shares a cache line with the arrivals
                if gang.poisoned.load(Ordering::Acquire) {
                    std::panic::resume_unwind(Box::new(Poisoned));
                }
                std::thread::yield_now();
            } else {
                std::hint::spin_loop();
            }
        }
    }

    /// This member's block of a loop over `0..n`.
    pub fn block(&self, n: usize) -> Range<usize> {
        let parts = (n / MIN_BLOCK).clamp(1, self.size);
        if self.id >= parts {
            return n..n;
        }
        let edge = |m: usize| if m == parts { n } else { (m * n / parts).next_multiple_of(ALIGN).min(n) };
        edge(self.id)..edge(self.id + 1)
    }

    /// f(i) for every i < n, each member its block, then a barrier.
    #[inline]
    pub fn for_each(&self, n: usize, f: impl Fn(usize)) {
        for i in self.block(n) {
            f(i);
        }
        self.barrier();
    }

    /// Σ_{i<n} f(i), every member returning the same bits.
    pub fn sum(&self, n: usize, f: impl Fn(usize) -> f64) -> f64 {
        self.sum2(n, |i| [f(i), 0.0])[0]
    }

    /// Two sums in one pass: each member sums its chunks of [`GANG_CHUNK`] entries in index order,
    /// and after a barrier every member adds all chunk sums in chunk order.
    pub fn sum2(&self, n: usize, f: impl Fn(usize) -> [f64; 2]) -> [f64; 2] {
        let chunks = n.div_ceil(GANG_CHUNK);
        let buffer = self.flip.get();
        self.flip.set(1 - buffer);
        let half = self.partials.len() / 2;
        assert!(chunks <= half, "gang: {chunks} chunk sums for a buffer of {half}");
        let partial = &self.partials[buffer * half..buffer * half + chunks];
        let (first, end) = (self.id * chunks / self.size, (self.id + 1) * chunks / self.size);
        for (k, slot) in partial.iter().enumerate().take(end).skip(first) {
            // the closure, not `&f`: passed by reference the summand was not inlined (5 % more
            // instructions in a pressure solve, counted by cachegrind)
            #[allow(clippy::redundant_closure)]
            let sums = chunk_sum(k, GANG_CHUNK, n, |i| f(i));
            // chunk k is this member's; the others read it after the barrier, and it is
            // rewritten only two sums later, after the next sum's barrier, which every member
            // reaches after reading it
            slot.set(sums);
        }
        self.barrier();
        in_chunk_order(partial.iter().map(PartialSum::get))
    }

    /// f on the first member alone, then a barrier.
    pub fn alone(&self, f: impl FnOnce()) {
        if self.id == 0 {
            f();
        }
        self.barrier();
    }
}

/// The chunk sums of a gang whose sums run over up to `rows` entries.
fn sized(rows: usize, partials: &mut Vec<PartialSum>) -> &[PartialSum] {
    partials.resize_with(2 * rows.div_ceil(GANG_CHUNK).max(1), PartialSum::default);
    partials
}

/// [`run`] on the calling thread alone (a gang of one): for solves run side by side, one a
/// thread, where a gang would wait for threads busy with the others' solves.
pub fn run_alone<R>(rows: usize, partials: &mut Vec<PartialSum>, body: impl FnOnce(&Crew) -> R) -> R {
    solo(sized(rows, partials), body)
}

/// `body` on the calling thread as a gang of one, its sums' chunks kept in `partials` (at least
/// two buffers of [`solo_partials`]`(rows)`): a solve alone, or a member of a running gang
/// working alone between two of its barriers (the coarse levels of a multigrid cycle, whose
/// loops are shorter than a barrier). A gang of one computes the bits of any gang.
pub fn solo<R>(partials: &[PartialSum], body: impl FnOnce(&Crew) -> R) -> R {
    let gang = Gang::new();
    body(&Crew { id: 0, size: 1, gang: &gang, partials, flip: Cell::new(0) })
}

/// Chunk sums enough for the sums of a gang over up to `rows` entries.
pub fn solo_partials(rows: usize) -> Vec<PartialSum> {
    let mut partials = Vec::new();
    sized(rows, &mut partials);
    partials
}

/// Whether [`run`] would gather a gang for `rows` rows (a pool of more than one thread, and at
/// least [`GANG_MIN_ROWS`] rows).
pub fn can_form(rows: usize) -> bool {
    rayon::current_num_threads() > 1 && rows >= GANG_MIN_ROWS
}

/// Runs `body` on a gang of the current rayon pool's threads (as many as join within
/// [`GATHER`]; the caller alone for fewer than [`GANG_MIN_ROWS`] rows or a pool of one) and
/// returns the first member's result. Its sums may run over up to `rows` entries; `partials`
/// holds their chunk sums (resized here: no allocation once large enough).
pub fn run<R: Send>(rows: usize, partials: &mut Vec<PartialSum>, body: impl Fn(&Crew) -> R + Sync) -> R {
    if !can_form(rows) {
        return run_alone(rows, partials, body);
    }
    let threads = rayon::current_num_threads();
    let partials = sized(rows, partials);
    let gang = Gang::new();
    let crew = |id: usize, size: usize| Crew { id, size, gang: &gang, partials, flip: Cell::new(0) };
    let member = |id: usize, size: usize| -> Option<R> {
        match catch_unwind(AssertUnwindSafe(|| body(&crew(id, size)))) {
            Ok(r) => Some(r),
            Err(payload) => {
                // the first panic's payload is kept before the others learn of it
                if !payload.is::<Poisoned>() {
                    gang.payload.lock().unwrap_or_else(|e| e.into_inner()).get_or_insert(payload);
                }
                gang.poisoned.store(true, Ordering::Release);
                None
            }
        }
    };
    let result = rayon::scope(|scope| {
        for _ in 1..threads {
            scope.spawn(|_| {
                // join unless the gang has closed
                let mut gate = gang.gate.load(Ordering::Acquire);
                let id = loop {
                    if gate & CLOSED != 0 {
                        return;
                    }
                    match gang.gate.compare_exchange_weak(gate, gate + 1, Ordering::AcqRel, Ordering::Acquire) {
                        Ok(_) => break gate,
                        Err(now) => gate = now,
                    }
                };
                let mut spins = 0u32;
                while gang.gate.load(Ordering::Acquire) & CLOSED == 0 {
                    spins += 1;
                    if spins.is_multiple_of(SPINS_PER_YIELD) {
                        std::thread::yield_now();
                    } else {
                        std::hint::spin_loop();
                    }
                }
                let size = gang.gate.load(Ordering::Acquire) & !CLOSED;
                member(id, size);
            });
        }
        let start = Instant::now();
        while gang.gate.load(Ordering::Acquire) < threads && start.elapsed() < GATHER {
            std::hint::spin_loop();
        }
        let size = gang.gate.fetch_or(CLOSED, Ordering::AcqRel);
        #[cfg(test)]
        if size > 1 {
            GANGS_OF_SEVERAL.with(|count| count.set(count.get() + 1));
        }
        member(0, size)
    });
    if let Some(payload) = gang.payload.lock().unwrap_or_else(|e| e.into_inner()).take() {
        std::panic::resume_unwind(payload);
    }
    result.expect("the first member returns or its panic is re-raised")
}

#[cfg(test)]
thread_local! {
    /// Gangs of more than one member this thread has led (tests check that a gang formed).
    pub(crate) static GANGS_OF_SEVERAL: Cell<usize> = const { Cell::new(0) };
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs `body` on a gang of `threads` until one forms with more than one member (a pool's
    /// worker can miss the gathering on a loaded machine, as when the tests run side by side),
    /// and returns its result. The pool's workers are kept awake, as `spillage run` keeps them.
    fn on_a_real_gang<R: Send>(threads: usize, rows: usize, body: impl Fn(&Crew) -> R + Sync) -> R {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let mut partials = Vec::new();
        for _ in 0..500 {
            let (size, result) = pool.install(|| crate::team::keep_awake(|| run(rows, &mut partials, |crew| (crew.size(), body(crew)))));
            if size > 1 {
                return result;
            }
        }
        panic!("no gang of more than one member formed in 500 tries");
    }

    #[test]
    fn sums_and_loops_of_a_gang_match_one_thread_bit_for_bit() {
        let n = 50_000;
        let v: Vec<f64> = (0..n).map(|i| ((i * 7919) % 1000) as f64 * 1e-3 + if i % 97 == 0 { 1e8 } else { 0.0 }).collect();
        let rounds = |crew: &Crew, out: &[Slot<f64>]| {
            let mut sums = Vec::new();
            for round in 0..200 {
                // SAFETY: entry i written by its block's member only, read after the barrier
                crew.for_each(n, |i| unsafe { out[i].set(v[i] * round as f64) });
                sums.push(crew.sum(n, |i| unsafe { out[i].get() }).to_bits());
            }
            sums
        };
        let mut out_one = vec![0.0; n];
        let one = {
            let out = Slot::from_mut_slice(&mut out_one);
            let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
            pool.install(|| {
                run(n, &mut Vec::new(), |crew| {
                    assert_eq!(crew.size(), 1, "a pool of one thread");
                    rounds(crew, out)
                })
            })
        };
        let mut out_gang = vec![0.0; n];
        let gang = {
            let out = Slot::from_mut_slice(&mut out_gang);
            on_a_real_gang(3, n, |crew| rounds(crew, out))
        };
        assert_eq!(one, gang);
        assert_eq!(out_one, out_gang);
        // the order of a fixed-chunk sum (`reduce.rs`), written out: chunks in index order,
        // their sums in chunk order
        let chunked: f64 =
            (0..n).step_by(GANG_CHUNK).map(|start| (start..(start + GANG_CHUNK).min(n)).fold(0.0, |s, i| s + v[i] * 199.0)).fold(0.0, |s, c| s + c);
        assert_eq!(*one.last().unwrap(), chunked.to_bits(), "the bits of a fixed-chunk sum");
    }

    #[test]
    fn blocks_cover_the_range_once_and_short_loops_use_fewer_members() {
        let gang = Gang::new();
        for size in 1..5 {
            for n in [0, 1, 63, 64, 200, 1000, 4097] {
                let mut covered = vec![0; n];
                for id in 0..size {
                    let crew = Crew { id, size, gang: &gang, partials: &[], flip: Cell::new(0) };
                    let block = crew.block(n);
                    if n < MIN_BLOCK * 2 && id > 0 {
                        assert!(block.is_empty(), "n {n}: member {id} has {block:?}");
                    }
                    for i in block {
                        covered[i] += 1;
                    }
                }
                assert!(covered.iter().all(|&c| c == 1), "size {size}, n {n}");
            }
        }
    }

    #[test]
    fn a_panicking_member_panics_the_solve_with_its_own_message_instead_of_hanging_it() {
        let result = catch_unwind(AssertUnwindSafe(|| {
            on_a_real_gang(2, 10_000, |crew| {
                for _ in 0..1000 {
                    crew.barrier();
                    assert!(crew.id() != crew.size() - 1 || crew.size() == 1, "the last member fails");
                }
            })
        }));
        let payload = result.expect_err("the gang of two panics");
        let message = payload.downcast_ref::<String>().map(String::as_str).or(payload.downcast_ref::<&str>().copied());
        assert_eq!(message, Some("the last member fails"));
    }
}
