//! The two halves of a velocity-Verlet sub-step (fluid-dem-model.md §5.10), per particle in
//! parallel: the half-kick with the contact force and torque, half the non-contact update
//! ([`NonContactForces::update`]) and, in the first half, the drift. Between two sub-steps the
//! second half of one and the first half of the next are one pass ([`Pass::Between`]).

use rayon::prelude::*;

use spillage_model::closure::drag::FluidAtParticle;
use spillage_model::particles::non_contact::{LoadShare, NonContactForces};
use spillage_model::particles::settings::Motion;
use spillage_model::particles::state::Vec3;

use super::arrays::ParticleArrays;

/// Particles per block of a pass: the pass sums its work block by block, each block in internal
/// order, then the blocks in order, so the sums do not depend on the number of threads.
const BLOCK: usize = 1024;

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

/// One pass of length `dt` sub-steps over every particle; `fluid` is indexed by the state's
/// order (empty: no particle sees a fluid), `origins` are the neighbour list's build positions.
pub fn advance_particles(
    pass: Pass,
    arrays: &mut ParticleArrays,
    sums: &mut StepSums,
    forces: &NonContactForces,
    fluid: &[Option<FluidAtParticle>],
    dt: f64,
    origins: &[Vec3],
) -> PassSums {
    let ParticleArrays { state_index, diameter, density, mass, inertia, volume, position, velocity, spin, force, torque, .. } = arrays;
    let h = 0.5 * dt;
    let kernel = PassKernel { pass, h, dt, motion: forces.motion, mass, inertia, force, torque, origins: (origins.len() == mass.len()).then_some(origins) };
    sums.blocks.resize(mass.len().div_ceil(BLOCK), BlockSums::default());
    let blocks = (
        velocity.par_chunks_mut(BLOCK),
        spin.par_chunks_mut(BLOCK),
        position.par_chunks_mut(BLOCK),
        sums.load.par_chunks_mut(BLOCK),
        sums.blocks.par_iter_mut(),
    );
    if fluid.is_empty() && forces.rotating_frame.is_none() {
        // without a fluid or a rotating frame the non-contact update is gravity alone,
        // `v + h g`: [`NonContactForces::update`]'s dry branch, the same operations, inline
        let (gravity, motion) = (forces.gravity, forces.motion);
        blocks.into_par_iter().enumerate().for_each(|(b, (v, w, x, _, out))| {
            *out = kernel.block(b * BLOCK, v, w, x, |_, v, _| *v = motion.kick(*v, h * gravity));
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
                load.implicit_drag += share.implicit_drag;
                load.explicit_force += share.explicit_force;
                load.drag += share.drag;
                load.slip_reynolds = share.slip_reynolds;
            }
        };
        blocks.into_par_iter().enumerate().for_each(|(b, (v, w, x, load, out))| {
            let start = b * BLOCK;
            *out = kernel.block(start, v, w, x, |k, v, x| update(k, v, x, &mut load[k - start]));
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
    mass: &'a [f64],
    inertia: &'a [f64],
    force: &'a [Vec3],
    torque: &'a [Vec3],
    origins: Option<&'a [Vec3]>,
}

impl PassKernel<'_> {
    /// The pass over the block of particles from `start` (`v`, `w`, `x`: their velocities,
    /// spins and positions); `update(k, v, x)` takes half the non-contact update of particle k.
    #[inline]
    fn block(
        &self,
        start: usize,
        velocity: &mut [Vec3],
        spin: &mut [Vec3],
        position: &mut [Vec3],
        mut update: impl FnMut(usize, &mut Vec3, &Vec3),
    ) -> BlockSums {
        let Self { pass, h, dt, motion, .. } = *self;
        let mut sums = BlockSums::default();
        for (j, ((v, w), x)) in velocity.iter_mut().zip(spin.iter_mut()).zip(position.iter_mut()).enumerate() {
            let k = start + j;
            let m = self.mass[k];
            // a pass between two sub-steps kicks twice with the same contact force: its velocity
            // changes are divided out once
            let (dv, dw) = (h * self.force[k] / m, h * self.torque[k] / self.inertia[k]);
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
            let displacement = match self.origins {
                Some(origins) => (*x - origins[k]).norm_squared(),
                None => f64::NAN,
            };
            sums.max_displacement_sq =
                if displacement.is_nan() || sums.max_displacement_sq.is_nan() { f64::NAN } else { sums.max_displacement_sq.max(displacement) };
        }
        sums
    }
}
