//! Particle–particle contacts of one sub-step (fluid-dem-model.md §7.8): every listed pair is
//! evaluated in parallel into its own slot, then each particle sums its pairs in ascending
//! partner id, the order in which the reference adds them, so both give the same bits and the
//! result does not depend on the number of threads.

use rayon::prelude::*;

use spillage_model::closure::contact::hertz_mindlin_force;
use spillage_model::particles::first_touch::pair_record;
use spillage_model::particles::guards::{pair_fault, Fault, MAX_OVERLAP_RATIO};
use spillage_model::particles::materials::MaterialTable;
use spillage_model::particles::state::Vec3;

use super::arrays::ParticleArrays;
use super::neighbour_list::{NeighbourList, PairForce, PairSlot};

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

/// Evaluates every listed pair into its slot; true when some pair has a fault.
pub fn evaluate_pairs(list: &mut NeighbourList, arrays: &ParticleArrays, context: &PairContext) -> bool {
    (&mut list.slots, &mut list.forces)
        .into_par_iter()
        .with_min_len(512)
        .map(|(slot, out)| {
            evaluate(slot, out, arrays, context);
            slot.fault
        })
        .reduce(|| false, |x, y| x || y)
}

fn evaluate(slot: &mut PairSlot, out: &mut PairForce, arrays: &ParticleArrays, context: &PairContext) {
    let (a, b) = (slot.a as usize, slot.b as usize);
    let (ra, rb) = (arrays.radius[a], arrays.radius[b]);
    let offset = arrays.position[b] - arrays.position[a];
    let distance = offset.norm();
    slot.fault = false;
    if !(distance < ra + rb) {
        out.touching = false;
        slot.record = None;
        return;
    }
    let overlap = ra + rb - distance;
    let fed = arrays.id[a] >= context.fed_from || arrays.id[b] >= context.fed_from;
    if distance == 0.0 || overlap > MAX_OVERLAP_RATIO * ra.min(rb) {
        let fault = pair_fault(&arrays.particle(a), &arrays.particle(b), distance, overlap, fed);
        slot.fault = fault.is_some();
        if matches!(fault, Some(Fault::Coincident { .. })) {
            out.touching = false;
            slot.record = None;
            return;
        }
    }
    let normal = offset / distance;
    // §7.8 step 2: relative velocity of the contact point.
    let v_rel = arrays.velocity[a] + arrays.spin[a].cross(&(ra * normal)) - (arrays.velocity[b] + arrays.spin[b].cross(&(-rb * normal)));
    let new_contact = slot.record.is_none();
    let record = slot
        .record
        .get_or_insert_with(|| pair_record(context.materials, context.wet_fluid, &arrays.particle(a), &arrays.particle(b), normal, v_rel, context.time));
    let force = hertz_mindlin_force(&slot.constants, record.damping_ratio, normal, overlap, v_rel, &mut record.tangential_overlap, context.dt);
    record.normal = normal;
    // §7.8 steps 6–7.
    *out = PairForce {
        touching: true,
        force: force.normal + force.tangential,
        torque_a: (ra * normal).cross(&force.tangential),
        torque_b: (-rb * normal).cross(&(-force.tangential)),
    };
    slot.overlap = overlap;
    if context.energy {
        slot.elastic = 0.4 * force.normal.norm() * overlap;
        slot.placed = if new_contact && fed { slot.elastic } else { 0.0 };
    }
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

/// The first pair fault in the reference's order (ascending ids of a, then b).
pub fn first_fault(list: &NeighbourList, arrays: &ParticleArrays, fed_from: u64) -> Option<Fault> {
    let slot = list.slots.iter().filter(|s| s.fault).min_by_key(|s| (arrays.id[s.a as usize], arrays.id[s.b as usize]))?;
    let (a, b) = (arrays.particle(slot.a as usize), arrays.particle(slot.b as usize));
    let distance = (b.position - a.position).norm();
    pair_fault(&a, &b, distance, a.radius() + b.radius() - distance, a.id >= fed_from || b.id >= fed_from)
}
