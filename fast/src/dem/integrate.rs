//! The two halves of a velocity-Verlet sub-step (fluid-dem-model.md §5.10), per particle in
//! parallel: the half-kick with the contact force and torque, half the non-contact update
//! ([`NonContactForces::update`]) and, in the first half, the drift. Between two sub-steps the
//! second half of one and the first half of the next are one pass ([`Pass::Between`]).
//!
//! The pass also finishes each particle's contact force just before it moves it (its wall
//! contacts, [`BeforeMove`]) and clears the sums for the next sub-step's pairs after: one
//! parallel region and one sweep over the particles' memory where there were three.

use spillage_model::closure::drag::{DragLaw, FluidAtParticle};
use spillage_model::coupling::Feedback;
use spillage_model::particles::non_contact::{LoadShare, NonContactForces};
use spillage_model::particles::settings::Motion;
use spillage_model::particles::state::Vec3;

use super::arrays::{ParticleArrays, ParticleProperties};
use super::drag_lanes::{lane_kernel, takes_lanes, LaneInputs, LaneKernel, LaneResults, LANES};
use crate::team::{DisjointSlices, Team};

/// Particles per block of a pass: the pass sums its work block by block, each block in internal
/// order, then the blocks in order, so the sums do not depend on the number of threads. Each
/// block's [`BeforeMove`] holds the slices of its particles' state cut at this length.
///
/// The blocks are the pieces the team shares out, so they must be many for a coupled cloud,
/// whose pass carries the drag law of every particle: P3 fine's 1 683 particles made two blocks
/// of 1 024 and 659, and on two threads one waited a third of every pass. At 256, P3 fine took
/// 0.907 of its time per step (median of 5 alternating pairs on 2 threads); the 10⁴ settling
/// bed 0.978 (2 threads) and 0.983 (1 thread). The work sums feed only the energy guard (its
/// test and, when it fails, its message): the block length changes their last bits, not the
/// particles' (the same bits on any thread count, as before).
pub const BLOCK: usize = 256;

/// Per-particle accumulators of a step, in internal order, and the pass's block sums.
#[derive(Default)]
pub struct StepSums {
    /// The load shares summed over the step's updates.
    pub load: Vec<LoadShare>,
    blocks: Vec<BlockSums>,
}

/// What one block of particles adds up in a pass.
#[derive(Clone, Copy, Default)]
struct BlockSums {
    work_second: f64,
    work_first: f64,
    max_displacement_sq: f64,
}

impl StepSums {
    pub fn reset(&mut self, n: usize) {
        self.load.clear();
        self.load.resize(n, LoadShare::default());
    }
}

/// Which part of the sub-steps one pass over the particles takes.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Pass {
    /// The first half of the step's first sub-step: half-kick, half the non-contact update,
    /// drift.
    First,
    /// The second half of a sub-step (half the non-contact update, half-kick) and the first
    /// half of the next, at once: one pass over the particles' memory instead of two, each
    /// particle taking the same operations in the same order.
    Between,
    /// The second half of the step's last sub-step.
    Second,
}

/// What a pass adds up.
pub struct PassSums {
    /// Work of the non-contact forces in the second half of a sub-step [J] (0 for
    /// [`Pass::First`]), then in the first half of the next (0 for [`Pass::Second`]), each summed
    /// over blocks of `BLOCK` particles in internal order, then over the blocks in order (the
    /// energy guard's budget: any fixed order would do, this one keeps the threads apart).
    pub work_second: f64,
    pub work_first: f64,
    /// After a drift: the largest squared displacement from the neighbour list's build
    /// positions (NaN when they are not these particles').
    pub max_displacement_sq: f64,
}

/// What a pass does to a particle just before it moves it: adds the rest of its contact force,
/// torque and count (the walls'; the pairs' are added before the pass). `j` is its place in
/// the pass's block, `k` its internal index; position, velocity and spin are the ones its
/// contacts are evaluated at. Each block of the pass has its own (its block's state).
///
/// It may read only particle `k`'s own state and must be called in the block's order: the pass
/// in lanes ([`PassKernel::block_in_lanes`]) calls it for a group of particles before it moves
/// any of them, which changes nothing only under these two conditions.
pub trait BeforeMove: Send {
    #[allow(clippy::too_many_arguments)]
    fn before_move(
        &mut self,
        j: usize,
        k: usize,
        properties: &ParticleProperties,
        position: &Vec3,
        velocity: &Vec3,
        spin: &Vec3,
        force: &mut Vec3,
        torque: &mut Vec3,
        count: &mut u32,
    );

    /// Called once the pass has moved every particle of the block (its state still near in
    /// the cache): nothing by default.
    #[inline]
    fn after_block(&mut self) {}
}

/// Nothing to add: the first pass of a step, or no walls.
#[derive(Clone, Copy)]
pub struct NothingToAdd;

impl BeforeMove for NothingToAdd {
    #[inline]
    fn before_move(&mut self, _: usize, _: usize, _: &ParticleProperties, _: &Vec3, _: &Vec3, _: &Vec3, _: &mut Vec3, _: &mut Vec3, _: &mut u32) {}
}

/// The number of blocks a pass cuts `n` particles into (each takes one [`BeforeMove`]).
fn blocks_of(n: usize) -> usize {
    n.div_ceil(BLOCK)
}

/// One pass of length `dt` sub-steps over every particle, by the `team`; `fluid` is indexed
/// by the state's order (empty: no particle sees a fluid), `origins` are the neighbour list's
/// build positions. `before(b)` makes what block `b` (of [`BLOCK`] particles) does to a particle
/// before moving it; it is called exactly once per block and pass, so it may hand block `b`
/// the block's own ranges of per-particle state ([`DisjointSlices`]). Unless the pass is the step's last
/// ([`Pass::Second`], whose contact forces the state keeps), it leaves the contact forces,
/// torques and counts at zero, ready for the next sub-step's sums.
#[allow(clippy::too_many_arguments)]
pub fn advance_particles<B: BeforeMove>(
    pass: Pass,
    arrays: &mut ParticleArrays,
    sums: &mut StepSums,
    forces: &NonContactForces,
    fluid: &[Option<FluidAtParticle>],
    dt: f64,
    origins: &[Vec3],
    team: &Team,
    before: impl Fn(usize) -> B + Sync,
) -> PassSums {
    advance(pass, arrays, sums, forces, fluid, dt, origins, team, before, true)
}

/// [`advance_particles`], with the free particles in a fluid in [`LANES`] when `lanes_allowed`
/// (the tests hold the two ways to the same bits).
#[allow(clippy::too_many_arguments)]
fn advance<B: BeforeMove>(
    pass: Pass,
    arrays: &mut ParticleArrays,
    sums: &mut StepSums,
    forces: &NonContactForces,
    fluid: &[Option<FluidAtParticle>],
    dt: f64,
    origins: &[Vec3],
    team: &Team,
    before: impl Fn(usize) -> B + Sync,
    lanes_allowed: bool,
) -> PassSums {
    let ParticleArrays { state_index, id, material, diameter, density, radius, mass, inertia, volume, position, velocity, spin, force, torque, contacts } =
        arrays;
    let properties = ParticleProperties { id, material, diameter: &diameter[..], density: &density[..], radius, mass };
    let n = mass.len();
    let h = 0.5 * dt;
    let kernel = PassKernel { pass, h, dt, motion: forces.motion, properties, inertia, origins: (origins.len() == n).then_some(origins) };
    sums.blocks.resize(blocks_of(n), BlockSums::default());
    let moving = (DisjointSlices::new(velocity), DisjointSlices::new(spin), DisjointSlices::new(position));
    let contact = (DisjointSlices::new(force), DisjointSlices::new(torque), DisjointSlices::new(contacts));
    let (loads, block_sums) = (DisjointSlices::new(&mut sums.load), DisjointSlices::new(&mut sums.blocks));
    // block b's share of the particles' state: the blocks' ranges are disjoint, and each block
    // is one piece of the part, run once
    let block = |b: usize| {
        let range = b * BLOCK..n.min((b + 1) * BLOCK);
        // SAFETY: block b's own range of each array (see above)
        unsafe {
            let moving = (moving.0.range(range.clone()), moving.1.range(range.clone()), moving.2.range(range.clone()));
            let contact = (contact.0.range(range.clone()), contact.1.range(range.clone()), contact.2.range(range.clone()));
            let load = loads.range(range.clone());
            (range.start, moving, contact, load, &mut block_sums.range(b..b + 1)[0])
        }
    };
    if fluid.is_empty() && forces.rotating_frame.is_none() {
        // without a fluid or a rotating frame the non-contact update is gravity alone,
        // `v + h g`: [`NonContactForces::update`]'s dry branch, the same operations, inline
        let gravity = forces.gravity;
        team.run(blocks_of(n), &|b| {
            let (start, moving, contact, _, out) = block(b);
            *out = match forces.motion {
                Motion::Free => kernel.block::<true>(start, moving, contact, &mut before(b), |_, v, _| *v = Motion::Free.kick(*v, h * gravity)),
                Motion::Held => kernel.block::<false>(start, moving, contact, &mut before(b), |_, v, _| *v = Motion::Held.kick(*v, h * gravity)),
            };
        });
    } else {
        // half the non-contact update of particle k, its load share into `load`
        let update = |k: usize, v: &mut Vec3, x: &Vec3, load: &mut LoadShare| {
            // without a fluid the update reads neither the particle's size nor its density
            let at = if fluid.is_empty() { None } else { fluid.get(state_index[k]).and_then(|f| f.as_ref()) };
            let (after, share) = match at {
                Some(at) => forces.update(*v, *x, diameter[k], density[k], volume[k], Some(at), h),
                None => forces.update(*v, *x, 0.0, 0.0, 0.0, None, h),
            };
            *v = after;
            if let Some(share) = share {
                load.add(&share);
            }
        };
        // free particles in a fluid, without a rotating frame: their drag laws in SIMD lanes
        let in_lanes = lanes_allowed && !fluid.is_empty() && takes_lanes(forces.motion, forces.rotating_frame.is_some(), forces.fluid_forces);
        let lanes = in_lanes.then(|| FluidLanes {
            fluid,
            state_index: &state_index[..],
            diameter: &diameter[..],
            density: &density[..],
            volume: &volume[..],
            mass: kernel.properties.mass,
            law: forces.drag_law,
            feedback: forces.feedback,
            gravity: forces.gravity,
            kernel: lane_kernel(),
        });
        team.run(blocks_of(n), &|b| {
            let (start, moving, contact, load, out) = block(b);
            *out = match (&lanes, forces.motion) {
                (Some(lanes), _) => kernel.block_in_lanes(start, moving, contact, &mut before(b), lanes, load, &update),
                (None, Motion::Free) => kernel.block::<true>(start, moving, contact, &mut before(b), |k, v, x| update(k, v, x, &mut load[k - start])),
                (None, Motion::Held) => kernel.block::<false>(start, moving, contact, &mut before(b), |k, v, x| update(k, v, x, &mut load[k - start])),
            };
        });
    }
    let mut total = PassSums { work_second: 0.0, work_first: 0.0, max_displacement_sq: 0.0 };
    for block in &sums.blocks {
        total.work_second += block.work_second;
        total.work_first += block.work_first;
        // the largest of exact values (NaN wins)
        let (x, y) = (total.max_displacement_sq, block.max_displacement_sq);
        total.max_displacement_sq = if x.is_nan() || y.is_nan() { f64::NAN } else { x.max(y) };
    }
    total
}

/// What a pass reads besides the moving particles' own arrays.
struct PassKernel<'a> {
    pass: Pass,
    h: f64,
    dt: f64,
    motion: Motion,
    properties: ParticleProperties<'a>,
    inertia: &'a [f64],
    origins: Option<&'a [Vec3]>,
}

/// A block's velocities, spins and positions.
type Moving<'a> = (&'a mut [Vec3], &'a mut [Vec3], &'a mut [Vec3]);
/// A block's contact forces, torques and counts.
type Contact<'a> = (&'a mut [Vec3], &'a mut [Vec3], &'a mut [u32]);

impl PassKernel<'_> {
    /// The pass over the block of particles from `start` (`moving`: their velocities, spins and
    /// positions; `contact`: their contact forces, torques and counts, which `before`
    /// completes particle by particle); `update(k, v, x)` takes half the non-contact update of
    /// particle k. `FREE` is the pass's [`Motion`] (free, else held) as a constant, so the
    /// kicks and drifts take no branch per particle.
    #[inline]
    fn block<const FREE: bool>(
        &self,
        start: usize,
        moving: Moving,
        contact: Contact,
        before: &mut impl BeforeMove,
        mut update: impl FnMut(usize, &mut Vec3, &Vec3),
    ) -> BlockSums {
        let Self { pass, h, dt, .. } = *self;
        debug_assert_eq!(self.motion, if FREE { Motion::Free } else { Motion::Held });
        let motion = if FREE { Motion::Free } else { Motion::Held };
        let (velocity, spin, position) = moving;
        let (force, torque, count) = contact;
        let mut sums = BlockSums::default();
        let mut not_a_number = false;
        for (j, ((v, w), x)) in velocity.iter_mut().zip(spin.iter_mut()).zip(position.iter_mut()).enumerate() {
            let k = start + j;
            before.before_move(j, k, &self.properties, x, v, w, &mut force[j], &mut torque[j], &mut count[j]);
            let m = self.properties.mass[k];
            // a pass between two sub-steps kicks twice with the same contact force: its velocity
            // changes are divided out once
            let (dv, dw) = (h * force[j] / m, h * torque[j] / self.inertia[k]);
            if pass != Pass::Second {
                // the next sub-step's pairs add to zero
                (force[j], torque[j], count[j]) = (Vec3::zeros(), Vec3::zeros(), 0);
            }
            // the non-contact update's work (its kinetic-energy change)
            let mut updated = |v: &mut Vec3| {
                let before = v.norm_squared();
                update(k, v, x);
                0.5 * m * (v.norm_squared() - before)
            };
            if pass != Pass::First {
                sums.work_second += updated(v);
                *v = motion.kick(*v, dv);
                *w = motion.kick(*w, dw);
            }
            if pass == Pass::Second {
                continue;
            }
            *v = motion.kick(*v, dv);
            *w = motion.kick(*w, dw);
            sums.work_first += updated(v);
            *x = motion.drift(*x, *v, dt);
            self.record_displacement(x, k, &mut sums, &mut not_a_number);
        }
        finish_block(before, sums, not_a_number)
    }

    /// Adds particle `k`'s squared displacement from the neighbour list's build position, at
    /// `x` after its drift, to the block's largest (`not_a_number`: whether one was NaN): the
    /// list is rebuilt once a particle has moved half its skin, and a NaN must force that.
    #[inline]
    fn record_displacement(&self, x: &Vec3, k: usize, sums: &mut BlockSums, not_a_number: &mut bool) {
        let displacement = match self.origins {
            Some(origins) => (*x - origins[k]).norm_squared(),
            None => f64::NAN,
        };
        *not_a_number |= displacement.is_nan();
        sums.max_displacement_sq = sums.max_displacement_sq.max(displacement);
    }

    /// [`Self::block`] for free particles with [`FluidLanes`]: the same operations on each
    /// particle in the same order, grouped by [`LANES`] particles so that their non-contact
    /// updates run side by side. Grouping them moves a particle's contacts and kicks relative
    /// to its neighbours' in time, which changes nothing: each reads only its own particle's
    /// state, and the work sums are still added particle by particle in internal order. A
    /// group with a particle outside the fluid (no sample) takes `update` one by one.
    #[allow(clippy::too_many_arguments)]
    fn block_in_lanes(
        &self,
        start: usize,
        moving: Moving,
        contact: Contact,
        before: &mut impl BeforeMove,
        lanes: &FluidLanes,
        load: &mut [LoadShare],
        update: &impl Fn(usize, &mut Vec3, &Vec3, &mut LoadShare),
    ) -> BlockSums {
        let Self { pass, h, dt, .. } = *self;
        let (velocity, spin, position) = moving;
        let (force, torque, count) = contact;
        let mut sums = BlockSums::default();
        let mut not_a_number = false;
        let (mut inputs, mut results) = (LaneInputs::default(), LaneResults::default());
        let (mut dv, mut dw) = ([Vec3::zeros(); LANES], [Vec3::zeros(); LANES]);
        for group in (0..velocity.len()).step_by(LANES) {
            let len = LANES.min(velocity.len() - group);
            for i in 0..len {
                let (j, k) = (group + i, start + group + i);
                before.before_move(j, k, &self.properties, &position[j], &velocity[j], &spin[j], &mut force[j], &mut torque[j], &mut count[j]);
                let m = self.properties.mass[k];
                (dv[i], dw[i]) = (h * force[j] / m, h * torque[j] / self.inertia[k]);
                if pass != Pass::Second {
                    (force[j], torque[j], count[j]) = (Vec3::zeros(), Vec3::zeros(), 0);
                }
            }
            let range = group..group + len;
            let in_fluid = lanes.all_in_fluid(start + group, len);
            let mut half_update = |velocity: &mut [Vec3], load: &mut [LoadShare], work: &mut f64| {
                if in_fluid {
                    lanes.update(start + group, velocity, load, h, work, &mut inputs, &mut results);
                } else {
                    for (i, (v, load)) in velocity.iter_mut().zip(load).enumerate() {
                        let k = start + group + i;
                        let before = v.norm_squared();
                        update(k, v, &position[group + i], load);
                        *work += 0.5 * self.properties.mass[k] * (v.norm_squared() - before);
                    }
                }
            };
            if pass != Pass::First {
                half_update(&mut velocity[range.clone()], &mut load[range.clone()], &mut sums.work_second);
                for i in 0..len {
                    velocity[group + i] += dv[i];
                    spin[group + i] += dw[i];
                }
            }
            if pass == Pass::Second {
                continue;
            }
            for i in 0..len {
                velocity[group + i] += dv[i];
                spin[group + i] += dw[i];
            }
            half_update(&mut velocity[range.clone()], &mut load[range.clone()], &mut sums.work_first);
            for j in range {
                position[j] = Motion::Free.drift(position[j], velocity[j], dt);
                self.record_displacement(&position[j], start + j, &mut sums, &mut not_a_number);
            }
        }
        finish_block(before, sums, not_a_number)
    }
}

/// A block's sums once it has moved every particle: its largest displacement NaN if one was
/// (no build positions, or a particle gone wrong), and `before` told the block is done.
fn finish_block(before: &mut impl BeforeMove, mut sums: BlockSums, not_a_number: bool) -> BlockSums {
    if not_a_number {
        sums.max_displacement_sq = f64::NAN;
    }
    before.after_block();
    sums
}

/// What the non-contact update of free particles in a fluid reads, for [`lane_kernel`].
struct FluidLanes<'a> {
    /// Indexed by the state's order (`state_index`); the rest by internal index.
    fluid: &'a [Option<FluidAtParticle>],
    state_index: &'a [usize],
    diameter: &'a [f64],
    density: &'a [f64],
    volume: &'a [f64],
    mass: &'a [f64],
    law: DragLaw,
    feedback: Option<Feedback>,
    gravity: Vec3,
    /// The widest SIMD this CPU has, chosen once per pass.
    kernel: LaneKernel,
}

impl FluidLanes<'_> {
    fn sample(&self, k: usize) -> Option<&FluidAtParticle> {
        self.fluid.get(self.state_index[k]).and_then(Option::as_ref)
    }

    fn all_in_fluid(&self, first: usize, len: usize) -> bool {
        (first..first + len).all(|k| self.sample(k).is_some())
    }

    /// Half the non-contact update (length `h`) of the particles from internal index `first`
    /// (`velocity`, `load`: theirs), every one with a fluid sample; their work added to `work`
    /// in their order. Lanes beyond the particles repeat the first one and are not read.
    #[allow(clippy::too_many_arguments)]
    fn update(&self, first: usize, velocity: &mut [Vec3], load: &mut [LoadShare], h: f64, work: &mut f64, inputs: &mut LaneInputs, results: &mut LaneResults) {
        for lane in 0..LANES {
            let i = if lane < velocity.len() { lane } else { 0 };
            let k = first + i;
            let fluid = self.sample(k).expect("the group was checked to be in the fluid");
            inputs.set(lane, &velocity[i], fluid, self.diameter[k], self.density[k], self.volume[k], self.mass[k]);
        }
        (self.kernel)(self.law, self.feedback, self.gravity, h, inputs, results);
        for (i, (v, load)) in velocity.iter_mut().zip(load).enumerate() {
            *work += results.work[i];
            *v = results.velocity(i);
            if self.feedback.is_some() {
                load.add(&results.share(i));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::counting_allocator::{count_during, mark_this_thread};
    use crate::team::with_team;
    use spillage_model::particles::settings::FluidForces;
    use spillage_model::particles::state::Particle;

    /// 300 particles (a block of 256 and one of 44: five full groups and one of four), two
    /// sizes and densities, with contact forces to kick with, in a moving fluid; particle 270
    /// has no fluid sample (its group takes the scalar update).
    fn particles_in_a_fluid() -> (ParticleArrays, Vec<Option<FluidAtParticle>>, Vec<Vec3>) {
        let mut state = 0x853c_49e6_748f_ea9bu64;
        let mut next = |low: f64, high: f64| {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            low + (high - low) * ((state >> 11) as f64 / (1u64 << 53) as f64)
        };
        let mut v = |scale: f64| Vec3::new(next(-scale, scale), next(-scale, scale), next(-scale, scale));
        let particles: Vec<Particle> = (0..300)
            .map(|i| {
                let (diameter, density) = if i % 3 == 0 { (0.02, 1800.0) } else { (0.01, 2650.0) };
                Particle {
                    id: i as u64,
                    material: 0,
                    diameter,
                    density,
                    position: v(0.5),
                    velocity: v(0.3),
                    spin: v(5.0),
                    contact_force: v(1e-2),
                    contact_torque: v(1e-6),
                    contacts: (i % 4) as u32,
                }
            })
            .collect();
        let fluid = (0..300)
            .map(|i| {
                (i != 270).then(|| FluidAtParticle {
                    density: 998.2,
                    kinematic_viscosity: 1.0034e-6,
                    velocity: v(0.2),
                    material_acceleration: v(1.0),
                    fluid_fraction: 0.6 + 0.4 * (i % 7) as f64 / 6.0,
                })
            })
            .collect();
        let mut arrays = ParticleArrays::default();
        arrays.load(&particles, 0.05);
        let origins = arrays.position.iter().map(|x| x + Vec3::new(1e-4, 0.0, 0.0)).collect();
        (arrays, fluid, origins)
    }

    /// The passes in lanes give the bits of the particle-by-particle passes: positions,
    /// velocities, spins, the contact sums left for the next sub-step, the load shares and the
    /// pass sums, for each kind of pass; and a pass in lanes allocates nothing.
    #[test]
    fn passes_in_lanes_have_the_bits_of_the_scalar_passes() {
        let forces = NonContactForces {
            drag_law: DragLaw::BrownLawler,
            gravity: Vec3::new(0.0, -9.81, 0.0),
            rotating_frame: None,
            feedback: Some(Feedback::DragAndFluidAcceleration),
            motion: Motion::Free,
            fluid_forces: FluidForces::Full,
        };
        let (arrays, fluid, origins) = particles_in_a_fluid();
        let n = arrays.len();
        let pool = rayon::ThreadPoolBuilder::new().num_threads(1).start_handler(|_| mark_this_thread()).build().expect("pool");
        pool.install(|| {
            with_team(|team| {
                let ((mut scalar, _, _), mut lanes) = (particles_in_a_fluid(), arrays);
                let (mut scalar_sums, mut lane_sums) = (StepSums::default(), StepSums::default());
                scalar_sums.reset(n);
                lane_sums.reset(n);
                for (i, pass) in [Pass::First, Pass::Between, Pass::Between, Pass::Second].into_iter().enumerate() {
                    let a = advance(pass, &mut scalar, &mut scalar_sums, &forces, &fluid, 3e-5, &origins, team, |_| NothingToAdd, false);
                    let (b, allocations) =
                        count_during(|| advance(pass, &mut lanes, &mut lane_sums, &forces, &fluid, 3e-5, &origins, team, |_| NothingToAdd, true));
                    // the first pass sizes the block sums
                    assert!(i == 0 || allocations == 0, "a pass in lanes allocated {allocations} times");
                    let bits = |v: &[Vec3]| v.iter().map(|x| x.map(f64::to_bits)).collect::<Vec<_>>();
                    for (name, x, y) in [
                        ("position", &scalar.position, &lanes.position),
                        ("velocity", &scalar.velocity, &lanes.velocity),
                        ("spin", &scalar.spin, &lanes.spin),
                        ("force", &scalar.force, &lanes.force),
                        ("torque", &scalar.torque, &lanes.torque),
                    ] {
                        assert_eq!(bits(x), bits(y), "{name} after {:?}", pass as u8);
                    }
                    assert_eq!(scalar.contacts, lanes.contacts);
                    for (s, l) in scalar_sums.load.iter().zip(&lane_sums.load) {
                        assert_eq!(s.implicit_drag.to_bits(), l.implicit_drag.to_bits());
                        assert_eq!(
                            (s.explicit_force.map(f64::to_bits), s.drag.map(f64::to_bits)),
                            (l.explicit_force.map(f64::to_bits), l.drag.map(f64::to_bits))
                        );
                        assert_eq!(s.slip_reynolds.to_bits(), l.slip_reynolds.to_bits());
                    }
                    assert_eq!(
                        (a.work_second.to_bits(), a.work_first.to_bits(), a.max_displacement_sq.to_bits()),
                        (b.work_second.to_bits(), b.work_first.to_bits(), b.max_displacement_sq.to_bits())
                    );
                }
                // the passes did something: the particle without a sample fell freely, the
                // others were dragged
                assert!(scalar_sums.load.iter().filter(|l| l.implicit_drag > 0.0).count() == 299);
            })
        });
    }
}
