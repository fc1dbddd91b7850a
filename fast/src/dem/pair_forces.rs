//! Particle–particle contacts of one sub-step (fluid-dem-model.md §7.8): the threads take
//! consecutive segments of the listed pairs, evaluate them and add each to its two particles,
//! every particle receiving its pairs in ascending partner id, the order in which the reference
//! adds them, so both give the same bits and the result does not depend on the number of
//! threads.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use spillage_model::closure::contact::{hertz_mindlin_force, PairConstants};
use spillage_model::particles::first_touch::pair_record;
use spillage_model::particles::guards::{pair_fault, Fault, MAX_OVERLAP_RATIO};
use spillage_model::particles::materials::MaterialTable;
use spillage_model::particles::state::Vec3;
use spillage_model::particles::ContactRecord;

use super::arrays::ParticleArrays;
use super::neighbour_list::{NeighbourList, Pair, PairEnergy, PairForce, Touch};
use super::pair_lanes::{Lane, PairGroup};
use crate::team::{DisjointSlices, Team};

/// What the pair evaluation reads besides the particles.
pub struct PairContext<'a> {
    pub materials: &'a MaterialTable,
    pub wet_fluid: Option<(f64, f64)>,
    /// Time at the end of the sub-step [s] (stamps new contacts).
    pub time: f64,
    pub dt: f64,
    /// Particles with this id or above were fed in this step.
    pub fed_from: u64,
    /// Whether to measure the contacts' elastic energy (the guard needs it at the step's end,
    /// and while fed particles make their first contacts).
    pub energy: bool,
}

/// Every listed pair evaluated into its entries and added to its two particles' `force`,
/// `torque` and `count` as it goes (no second pass over the pairs' forces); true when some pair
/// has a fault (found by [`first_fault`]). The sums start from what they hold: zero, as the
/// pass that moved the particles left them ([`super::integrate::advance_particles`]).
///
/// The list is in ascending (id of a, id of b), so each particle receives its pairs in ascending
/// partner id, the reference's order of summation. The threads take consecutive segments of the
/// list ([`Segments`](super::neighbour_list::Segments)): a particle's first segment adds to it
/// directly, the later ones set their contributions aside, and these are added at the end in
/// segment order, so every sum is taken in list order whatever the number of threads: the same
/// bits on 1 or N.
pub fn evaluate_and_add(
    list: &mut NeighbourList,
    arrays: &ParticleArrays,
    context: &PairContext,
    force: &mut [Vec3],
    torque: &mut [Vec3],
    count: &mut [u32],
    team: &Team,
) -> bool {
    let planned = list.segments.bounds.last().copied().unwrap_or(0) == list.pairs.len() && list.segments.first.len() == arrays.len();
    if list.segments.threads != rayon::current_num_threads() || !planned {
        list.segments.plan(&list.pairs, &list.touch, arrays.len(), rayon::current_num_threads());
    }
    let NeighbourList { pairs, constants, touch, records, energy, forces, segments, set_aside, .. } = list;
    let n_segments = segments.count();
    segments.reserve_aside(set_aside);
    let sums = SharedSums::new(force, torque, count);
    let (touches, records, energy, kept, aside) =
        (DisjointSlices::new(touch), DisjointSlices::new(records), DisjointSlices::new(energy), DisjointSlices::new(forces), DisjointSlices::new(set_aside));
    let fault = AtomicBool::new(false);
    // each segment is one piece of the part, run once
    team.run(n_segments, &|s| {
        let started = Instant::now();
        let range = segments.bounds[s]..segments.bounds[s + 1];
        // SAFETY: segment s's own range of the pairs' entries, and its own buffer
        let (touch, records, energy, kept, aside) = unsafe {
            (touches.range(range.clone()), records.range(range.clone()), energy.range(range.clone()), kept.range(range.clone()), &mut aside.range(s..s + 1)[0])
        };
        let segment = Segment { index: s as u32, first: &segments.first, sums: &sums, aside };
        let entries = Entries { pairs: &pairs[range], constants, touch, records, energy, kept };
        if segment.evaluate(entries, arrays, context) {
            fault.store(true, Ordering::Relaxed);
        }
        segments.book(s, started);
    });
    let fault = fault.into_inner();
    for contribution in set_aside.iter().flatten() {
        // SAFETY: the segments are joined; nothing else holds the sums' memory now
        unsafe { sums.add(contribution.particle as usize, contribution.is_a, &contribution.force) };
    }
    // the next loop's cuts, from this one's times and contacts (no bit depends on them)
    if segments.rebalance(pairs, touch, arrays.len()) {
        segments.reserve_aside(set_aside);
    }
    fault
}

/// A pair's contribution to one of its particles, set aside by a segment that is not the
/// particle's first.
#[derive(Clone, Copy, Debug)]
pub struct SetAside {
    particle: u32,
    is_a: bool,
    force: PairForce,
}

/// The particles' sums, written by the segments in parallel: each particle only by its first
/// segment ([`Segments::first`]), so no two threads write the same entry.
struct SharedSums {
    force: *mut Vec3,
    torque: *mut Vec3,
    count: *mut u32,
    len: usize,
}

// SAFETY: the segments write disjoint entries (each particle's first segment only), and the
// set-aside contributions are added after the segments are joined.
unsafe impl Sync for SharedSums {}

impl SharedSums {
    fn new(force: &mut [Vec3], torque: &mut [Vec3], count: &mut [u32]) -> Self {
        assert!(force.len() == torque.len() && force.len() == count.len());
        Self { force: force.as_mut_ptr(), torque: torque.as_mut_ptr(), count: count.as_mut_ptr(), len: force.len() }
    }

    /// Particle `k`'s sums, to add a run of its pairs as side a to.
    ///
    /// # Safety
    /// No other thread reads or writes particle `k`'s entries until the run is stored.
    #[inline]
    unsafe fn load_run(&self, k: usize) -> RunOfA {
        assert!(k < self.len);
        // SAFETY: k is in bounds; the caller holds particle k's entries alone.
        unsafe { RunOfA { k, force: *self.force.add(k), torque: *self.torque.add(k), count: *self.count.add(k) } }
    }

    /// Stores a run's sums back (nothing for no run).
    ///
    /// # Safety
    /// As [`Self::load_run`], for the run's particle.
    #[inline]
    unsafe fn store_run(&self, run: &RunOfA) {
        if run.k == usize::MAX {
            return;
        }
        assert!(run.k < self.len);
        // SAFETY: k is in bounds; the caller holds particle k's entries alone.
        unsafe { (*self.force.add(run.k), *self.torque.add(run.k), *self.count.add(run.k)) = (run.force, run.torque, run.count) };
    }

    /// Adds a pair's force to its particle `k` (side a: +force, torque on a; side b: −force,
    /// torque on b).
    ///
    /// # Safety
    /// No other thread reads or writes particle `k`'s entries meanwhile.
    #[inline]
    unsafe fn add(&self, k: usize, is_a: bool, f: &PairForce) {
        assert!(k < self.len);
        // SAFETY: k is in bounds; the caller holds particle k's entries alone.
        let (force, torque, count) = unsafe { (&mut *self.force.add(k), &mut *self.torque.add(k), &mut *self.count.add(k)) };
        if is_a {
            *force += f.force;
            *torque += f.torque_a;
        } else {
            *force -= f.force;
            *torque += f.torque_b;
        }
        *count += 1;
    }
}

/// One thread's segment of the list.
struct Segment<'a> {
    index: u32,
    first: &'a [u32],
    sums: &'a SharedSums,
    aside: &'a mut Vec<SetAside>,
}

/// A segment's pairs and their entries.
struct Entries<'a> {
    pairs: &'a [Pair],
    constants: &'a [PairConstants],
    touch: &'a mut [Touch],
    records: &'a mut [Option<ContactRecord>],
    energy: &'a mut [PairEnergy],
    kept: &'a mut [PairForce],
}

/// The contributions of the pairs of one particle as side a, which are consecutive in the
/// list (it is sorted by a's id, and a particle's pairs as side b, lower ids' pairs, all come
/// before): summed in registers from the particle's sums, loaded before the first and stored
/// after the last. These are the additions of adding each pair to memory, in the same order,
/// with one load and store per particle instead of per pair.
struct RunOfA {
    /// The particle (`usize::MAX`: none).
    k: usize,
    force: Vec3,
    torque: Vec3,
    count: u32,
}

impl Segment<'_> {
    /// The segment through the kernel the processor runs best ([`PairKernel::detect`]),
    /// called from a loop compiled for its instructions (the processor is asked once per
    /// segment, not per group).
    fn evaluate(self, entries: Entries, arrays: &ParticleArrays, context: &PairContext) -> bool {
        match PairKernel::detect() {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: detect() found AVX-512 F on this processor.
            PairKernel::Avx512 => unsafe { self.evaluate_avx512(entries, arrays, context) },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: detect() found AVX on this processor.
            PairKernel::Avx => unsafe { self.evaluate_avx(entries, arrays, context) },
            _ => self.evaluate_with(super::pair_lanes::in_lanes, entries, arrays, context),
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f")]
    fn evaluate_avx512(self, entries: Entries, arrays: &ParticleArrays, context: &PairContext) -> bool {
        // the closure inherits the function's AVX-512, so it may call the AVX-512 kernel
        self.evaluate_with(|group, arrays, dt, energy| super::pair_lanes_avx512::eight_pairs_avx512(group, arrays, dt, energy), entries, arrays, context)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    fn evaluate_avx(self, entries: Entries, arrays: &ParticleArrays, context: &PairContext) -> bool {
        // the closure inherits the function's AVX, so it may call the AVX kernel
        self.evaluate_with(|group, arrays, dt, energy| super::pair_lanes_avx::four_pairs_avx(group, arrays, dt, energy), entries, arrays, context)
    }

    /// Evaluates the segment's pairs, `N` at a time through `kernel`, and adds each touching
    /// pair to its particles (to the sums of those whose first segment this is, else aside).
    #[inline(always)]
    fn evaluate_with<const N: usize, K>(self, kernel: K, entries: Entries, arrays: &ParticleArrays, context: &PairContext) -> bool
    where
        K: Fn(PairGroup, &ParticleArrays, f64, bool) -> [Lane; N],
    {
        let Entries { pairs, constants, touch, records, energy, kept } = entries;
        self.aside.clear();
        let groups = pairs.chunks(N).zip(touch.chunks_mut(N)).zip(records.chunks_mut(N)).zip(energy.chunks_mut(N)).zip(kept.chunks_mut(N));
        let mut fault = false;
        // the pairs' forces are read back at once; the list keeps them only when the totals
        // need their touching flags (the energy guard's sub-steps)
        let mut scratch = [PairForce::default(); N];
        let mut run = RunOfA { k: usize::MAX, force: Vec3::zeros(), torque: Vec3::zeros(), count: 0 };
        for ((((pairs, touch), records), energy), kept) in groups {
            let out = if context.energy { kept } else { &mut scratch[..pairs.len()] };
            fault |= evaluate_group(&kernel, pairs, constants, touch, records, energy, out, arrays, context);
            for (pair, f) in pairs.iter().zip(out.iter()).filter(|(_, f)| f.touching) {
                let (a, b) = (pair.a as usize, pair.b as usize);
                if self.first[a] == self.index {
                    if run.k != a {
                        // SAFETY: this segment is both particles' first: no other thread
                        // writes them
                        unsafe {
                            self.sums.store_run(&run);
                            run = self.sums.load_run(a);
                        }
                    }
                    run.force += f.force;
                    run.torque += f.torque_a;
                    run.count += 1;
                } else {
                    self.aside.push(SetAside { particle: pair.a, is_a: true, force: *f });
                }
                if self.first[b] == self.index {
                    // SAFETY: this segment is the particle's first: no other thread writes it
                    // (and it is not the open run's particle, which is only ever side a)
                    unsafe { self.sums.add(b, false, f) };
                } else {
                    self.aside.push(SetAside { particle: pair.b, is_a: false, force: *f });
                }
            }
        }
        // SAFETY: as above
        unsafe { self.sums.store_run(&run) };
        fault
    }
}

/// Up to `N` consecutive pairs: through `kernel`, and the lanes it leaves (or a last group of
/// fewer than `N`) through the scalar [`evaluate`]; true when one has a fault.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn evaluate_group<const N: usize, K>(
    kernel: &K,
    pairs: &[Pair],
    constants: &[PairConstants],
    touch: &mut [Touch],
    records: &mut [Option<ContactRecord>],
    energy: &mut [PairEnergy],
    out: &mut [PairForce],
    arrays: &ParticleArrays,
    context: &PairContext,
) -> bool
where
    K: Fn(PairGroup, &ParticleArrays, f64, bool) -> [Lane; N],
{
    let lanes = if pairs.len() == N {
        let group = PairGroup { pairs, constants, touch: &mut *touch, energy: &mut *energy, out: &mut *out };
        kernel(group, arrays, context.dt, context.energy)
    } else {
        [Lane::Scalar; N]
    };
    let mut fault = false;
    for (l, pair) in pairs.iter().enumerate().filter(|&(l, _)| lanes[l] == Lane::Scalar) {
        fault |= evaluate(pair, &constants[pair.constants as usize], &mut touch[l], &mut records[l], &mut energy[l], &mut out[l], arrays, context);
    }
    fault
}

/// One pair; returns whether it has a fault. The record (cold memory) is touched only when a
/// contact begins or ends.
#[allow(clippy::too_many_arguments)]
#[inline]
fn evaluate(
    pair: &Pair,
    constants: &PairConstants,
    touch: &mut Touch,
    record: &mut Option<ContactRecord>,
    energy: &mut PairEnergy,
    out: &mut PairForce,
    arrays: &ParticleArrays,
    context: &PairContext,
) -> bool {
    let (a, b) = (pair.a as usize, pair.b as usize);
    let (ra, rb) = (arrays.radius[a], arrays.radius[b]);
    let offset = arrays.position[b] - arrays.position[a];
    let distance = offset.norm();
    if !(distance < ra + rb) {
        out.touching = false;
        if touch.active() {
            *touch = Touch::default();
            *record = None;
        }
        return false;
    }
    let overlap = ra + rb - distance;
    let fed = arrays.id[a] >= context.fed_from || arrays.id[b] >= context.fed_from;
    let mut fault = false;
    if distance == 0.0 || overlap > MAX_OVERLAP_RATIO * ra.min(rb) {
        let found = pair_fault(&arrays.particle(a), &arrays.particle(b), distance, overlap, fed);
        fault = found.is_some();
        if matches!(found, Some(Fault::Coincident { .. })) {
            out.touching = false;
            if touch.active() {
                *touch = Touch::default();
                *record = None;
            }
            return fault;
        }
    }
    let normal = offset / distance;
    // §7.8 step 2: relative velocity of the contact point.
    let v_rel = arrays.velocity[a] + arrays.spin[a].cross(&(ra * normal)) - (arrays.velocity[b] + arrays.spin[b].cross(&(-rb * normal)));
    let new_contact = !touch.active();
    if new_contact {
        let first = pair_record(context.materials, context.wet_fluid, &arrays.particle(a), &arrays.particle(b), normal, v_rel, context.time);
        *touch = Touch::touching(first.tangential_overlap, first.damping_ratio);
        *record = Some(first);
    }
    let force = hertz_mindlin_force(constants, touch.damping_ratio(), normal, overlap, v_rel, &mut touch.tangential_overlap, context.dt);
    // §7.8 steps 6–7.
    *out = PairForce {
        touching: true,
        force: force.normal + force.tangential,
        torque_a: (ra * normal).cross(&force.tangential),
        torque_b: (-rb * normal).cross(&(-force.tangential)),
    };
    if context.energy {
        energy.overlap = overlap;
        energy.elastic = 0.4 * force.normal.norm() * overlap;
        energy.placed = if new_contact && fed { energy.elastic } else { 0.0 };
    }
    fault
}

/// The first pair fault in the reference's order (ascending ids of a, then b), found again at
/// the positions the pairs were evaluated at (faults are rare: they are not stored).
pub fn first_fault(list: &NeighbourList, arrays: &ParticleArrays, fed_from: u64) -> Option<Fault> {
    list.pairs
        .iter()
        .filter_map(|pair| {
            let (a, b) = (arrays.particle(pair.a as usize), arrays.particle(pair.b as usize));
            let distance = (b.position - a.position).norm();
            let overlap = a.radius() + b.radius() - distance;
            if !(distance < a.radius() + b.radius()) || !(distance == 0.0 || overlap > MAX_OVERLAP_RATIO * a.radius().min(b.radius())) {
                return None;
            }
            let fault = pair_fault(&a, &b, distance, overlap, a.id >= fed_from || b.id >= fed_from)?;
            Some(((a.id, b.id), fault))
        })
        .min_by_key(|(ids, _)| *ids)
        .map(|(_, fault)| fault)
}

/// The pair kernel a run takes: the widest lanes this processor has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PairKernel {
    /// Eight pairs a group in AVX-512 registers (`pair_lanes_avx512`).
    Avx512,
    /// Four pairs a group in AVX registers (`pair_lanes_avx`).
    Avx,
    /// Four pairs a group in portable lanes (`pair_lanes::in_lanes`).
    Portable,
}

impl PairKernel {
    /// The kernel for this processor (its features are looked up once and cached by std).
    #[inline]
    pub fn detect() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            let widest = widest_allowed();
            if std::arch::is_x86_feature_detected!("avx512f") && widest == PairKernel::Avx512 {
                return PairKernel::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx") && widest != PairKernel::Portable {
                return PairKernel::Avx;
            }
        }
        PairKernel::Portable
    }

    /// As a run's summary names it.
    pub fn describe(self) -> &'static str {
        match self {
            PairKernel::Avx512 => "AVX-512, eight pairs a group",
            PairKernel::Avx => "AVX, four pairs a group",
            PairKernel::Portable => "portable lanes, four pairs a group",
        }
    }
}

/// The widest kernel the pair loop may take where the processor has it: any, but for the test
/// that runs the loop through the narrower ones too.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn widest_allowed() -> PairKernel {
    #[cfg(test)]
    return match tests::WIDEST_KERNEL.load(Ordering::Relaxed) {
        0 => PairKernel::Avx512,
        1 => PairKernel::Avx,
        _ => PairKernel::Portable,
    };
    #[cfg(not(test))]
    PairKernel::Avx512
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The widest kernel the pair loop may take (0: AVX-512, 1: AVX, 2: portable lanes): the
    /// sums must not depend on it, so setting it never changes another test's result.
    pub static WIDEST_KERNEL: std::sync::atomic::AtomicU8 = std::sync::atomic::AtomicU8::new(0);
    use crate::dem::neighbour_list::History;
    use crate::team::with_team;
    use spillage_model::closure::contact::SlipTest;
    use spillage_model::particles::random::SplitMix64;
    use spillage_model::particles::settings::MaterialSection;
    use spillage_model::particles::Particle;

    /// A jumbled, compressed heap of spheres of three sizes, moving and spinning at random:
    /// most listed pairs touch, and ids are unrelated to position (so many particles appear in
    /// several segments and have contributions set aside).
    fn heap(n: usize) -> (ParticleArrays, MaterialTable) {
        let mut random = SplitMix64::new(5);
        let particles: Vec<Particle> = (0..n as u64)
            .map(|id| Particle {
                id: (id * 7919) % n as u64,
                material: 0,
                diameter: [0.01, 0.014, 0.02][(id % 3) as usize],
                density: 2650.0,
                position: Vec3::new(random.uniform(0.0, 0.12), random.uniform(0.0, 0.12), random.uniform(0.0, 0.12)),
                velocity: Vec3::new(random.uniform(-0.1, 0.1), random.uniform(-0.1, 0.1), random.uniform(-0.1, 0.1)),
                spin: Vec3::new(random.uniform(-5.0, 5.0), random.uniform(-5.0, 5.0), random.uniform(-5.0, 5.0)),
                contact_force: Vec3::zeros(),
                contact_torque: Vec3::zeros(),
                contacts: 0,
            })
            .collect();
        let mut arrays = ParticleArrays::default();
        arrays.load(&particles, 0.022);
        let m =
            MaterialSection { name: "rock".into(), density: 2650.0, youngs_modulus: 1e7, poisson_ratio: 0.3, softening: 1.0, restitution: 0.5, friction: 0.3 };
        (arrays, MaterialTable::new(&[m], SlipTest::Thesis))
    }

    /// Three sub-steps' pair sums with the list cut into many segments on several threads have
    /// the bits of one segment on one thread, new and continuing contacts alike, wherever the
    /// cuts fall and whichever width of lanes the kernel takes.
    #[test]
    fn segments_on_several_threads_sum_in_the_order_of_one() {
        let (arrays, materials) = heap(1500);
        let context = PairContext { materials: &materials, wet_fluid: None, time: 0.0, dt: 1e-5, fed_from: u64::MAX, energy: false };
        // `skewed`: the first third of the pairs weighs five times the rest, so the cuts fall
        // unevenly (the pair loop balances segments by weight)
        let sums = |threads: usize, segments: usize, skewed: bool| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut list = NeighbourList::default();
                list.skin = 0.001;
                with_team(|team| list.build(&arrays, &materials, History::Records(&[]), team));
                let third = list.pairs.len() / 3;
                list.segments.plan_with(&list.pairs, arrays.len(), segments, 4, |i| if skewed && i < third { 5.0 } else { 1.0 });
                if skewed {
                    let lengths: Vec<usize> = list.segments.bounds.windows(2).map(|w| w[1] - w[0]).collect();
                    assert!(lengths.len() == segments && lengths[0] * 3 < lengths[segments - 1], "uneven cuts: {lengths:?}");
                }
                // planned for these threads: evaluate_and_add keeps the cut
                list.segments.threads = threads;
                let n = arrays.len();
                let (mut force, mut torque, mut count) = (vec![Vec3::zeros(); n], vec![Vec3::zeros(); n], vec![0; n]);
                let mut all = Vec::new();
                for _ in 0..3 {
                    (force.fill(Vec3::zeros()), torque.fill(Vec3::zeros()), count.fill(0));
                    with_team(|team| evaluate_and_add(&mut list, &arrays, &context, &mut force, &mut torque, &mut count, team));
                    all.push((force.clone(), torque.clone(), count.clone()));
                }
                let aside = list.set_aside.iter().map(Vec::len).sum::<usize>();
                (all, list.pairs.len(), aside)
            })
        };
        let (one, pairs, _) = sums(1, 1, false);
        let touching = one[0].2.iter().map(|&c| c as usize).sum::<usize>() / 2;
        assert!(pairs > 2000 && touching > pairs / 2, "{pairs} pairs, {touching} touching: the test needs a dense heap");
        // and the narrower kernels (four AVX lanes, four portable ones: what a processor without
        // AVX-512 or without AVX runs) give the same bits too
        let cases = [(2, 2, 0, false), (3, 7, 0, false), (3, 7, 0, true), (1, 1, 1, false), (3, 7, 1, false), (1, 1, 2, false), (3, 7, 2, true)];
        for (threads, segments, widest, skewed) in cases {
            WIDEST_KERNEL.store(widest, Ordering::Relaxed);
            let (many, _, aside) = sums(threads, segments, skewed);
            WIDEST_KERNEL.store(0, Ordering::Relaxed);
            assert!(segments == 1 || aside > 200, "{segments} segments set aside only {aside} contributions");
            for (sub, (a, b)) in one.iter().zip(&many).enumerate() {
                // the first particle whose sum differs in any bit
                let differs = |x: &[Vec3], y: &[Vec3]| x.iter().zip(y).position(|(x, y)| (0..3).any(|i| x[i].to_bits() != y[i].to_bits()));
                assert_eq!(differs(&a.0, &b.0), None, "forces at sub-step {sub}, {segments} segments");
                assert_eq!(differs(&a.1, &b.1), None, "torques at sub-step {sub}, {segments} segments");
                assert!(a.2 == b.2, "contact counts at sub-step {sub}, {segments} segments");
            }
        }
    }
}
