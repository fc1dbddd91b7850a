//! Particle–particle contacts of one sub-step (fluid-dem-model.md §7.8): every listed pair is
//! evaluated in parallel into its own entries, then each particle sums its pairs in ascending
//! partner id, the order in which the reference adds them, so both give the same bits and the
//! result does not depend on the number of threads.

use rayon::prelude::*;

use spillage_model::closure::contact::{hertz_mindlin_force, PairConstants};
use spillage_model::particles::first_touch::pair_record;
use spillage_model::particles::guards::{pair_fault, Fault, MAX_OVERLAP_RATIO};
use spillage_model::particles::materials::MaterialTable;
use spillage_model::particles::state::Vec3;
use spillage_model::particles::ContactRecord;

use super::arrays::ParticleArrays;
use super::neighbour_list::{NeighbourList, Pair, PairEnergy, PairForce, Touch};
use super::pair_lanes::{four_pairs, FourPairs, Lane};

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

/// Evaluates every listed pair into its entries; true when some pair has a fault (found by
/// [`first_fault`]). Summed per particle by [`gather`].
pub fn evaluate_pairs(list: &mut NeighbourList, arrays: &ParticleArrays, context: &PairContext) -> bool {
    let constants = &list.constants;
    let groups =
        (list.pairs.par_chunks(4), list.touch.par_chunks_mut(4), list.records.par_chunks_mut(4), list.energy.par_chunks_mut(4), list.forces.par_chunks_mut(4));
    groups
        .into_par_iter()
        .with_min_len(128)
        .map(|(pairs, touch, records, energy, out)| evaluate_group(pairs, constants, touch, records, energy, out, arrays, context))
        .reduce(|| false, |x, y| x || y)
}

/// On one thread: every listed pair evaluated into its entries and added to its two particles'
/// `force`, `torque` and `count` at once (no second pass over the pairs' forces). The list is in
/// ascending (id of a, id of b), so each particle receives its pairs in ascending partner id,
/// as [`gather`] sums them: the same bits as [`evaluate_pairs`] and [`gather`].
pub fn evaluate_and_add(
    list: &mut NeighbourList,
    arrays: &ParticleArrays,
    context: &PairContext,
    force: &mut [Vec3],
    torque: &mut [Vec3],
    count: &mut [u32],
) -> bool {
    force.fill(Vec3::zeros());
    torque.fill(Vec3::zeros());
    count.fill(0);
    let constants = &list.constants;
    let groups =
        list.pairs.chunks(4).zip(list.touch.chunks_mut(4)).zip(list.records.chunks_mut(4)).zip(list.energy.chunks_mut(4)).zip(list.forces.chunks_mut(4));
    let mut fault = false;
    // the pairs' forces are read back at once; the list keeps them only when the totals need
    // their touching flags (the energy guard's sub-steps)
    let mut scratch = [PairForce::default(); 4];
    for ((((pairs, touch), records), energy), kept) in groups {
        let out = if context.energy { kept } else { &mut scratch[..pairs.len()] };
        fault |= evaluate_group(pairs, constants, touch, records, energy, out, arrays, context);
        for (pair, f) in pairs.iter().zip(out.iter()).filter(|(_, f)| f.touching) {
            let (a, b) = (pair.a as usize, pair.b as usize);
            force[a] += f.force;
            torque[a] += f.torque_a;
            count[a] += 1;
            force[b] -= f.force;
            torque[b] += f.torque_b;
            count[b] += 1;
        }
    }
    fault
}

/// Up to four consecutive pairs: through [`four_pairs`], and the lanes it leaves (or a last
/// group of fewer than four) through the scalar [`evaluate`]; true when one has a fault.
#[allow(clippy::too_many_arguments)]
#[inline]
fn evaluate_group(
    pairs: &[Pair],
    constants: &[PairConstants],
    touch: &mut [Touch],
    records: &mut [Option<ContactRecord>],
    energy: &mut [PairEnergy],
    out: &mut [PairForce],
    arrays: &ParticleArrays,
    context: &PairContext,
) -> bool {
    let lanes = if pairs.len() == 4 {
        let group = FourPairs { pairs, constants, touch: &mut *touch, energy: &mut *energy, out: &mut *out };
        four_pairs(group, arrays, context.dt, context.energy)
    } else {
        [Lane::Scalar; 4]
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
        if touch.active {
            touch.active = false;
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
            if touch.active {
                touch.active = false;
                *record = None;
            }
            return fault;
        }
    }
    let normal = offset / distance;
    // §7.8 step 2: relative velocity of the contact point.
    let v_rel = arrays.velocity[a] + arrays.spin[a].cross(&(ra * normal)) - (arrays.velocity[b] + arrays.spin[b].cross(&(-rb * normal)));
    let new_contact = !touch.active;
    if new_contact {
        let first = pair_record(context.materials, context.wet_fluid, &arrays.particle(a), &arrays.particle(b), normal, v_rel, context.time);
        *touch = Touch { active: true, tangential_overlap: first.tangential_overlap, damping_ratio: first.damping_ratio };
        *record = Some(first);
    }
    let force = hertz_mindlin_force(constants, touch.damping_ratio, normal, overlap, v_rel, &mut touch.tangential_overlap, context.dt);
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

/// Particle `k`'s sum over its touching pairs: (force, torque, count).
#[inline]
pub fn gather(list: &NeighbourList, k: usize) -> (Vec3, Vec3, u32) {
    let (mut force, mut torque, mut count) = (Vec3::zeros(), Vec3::zeros(), 0);
    for &(slot, is_a) in &list.adjacency[list.adjacency_start[k]..list.adjacency_start[k + 1]] {
        let s = &list.forces[slot as usize];
        if !s.touching {
            continue;
        }
        if is_a {
            force += s.force;
            torque += s.torque_a;
        } else {
            force -= s.force;
            torque += s.torque_b;
        }
        count += 1;
    }
    (force, torque, count)
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
