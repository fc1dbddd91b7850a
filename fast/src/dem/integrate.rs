//! The two halves of a velocity-Verlet sub-step (fluid-dem-model.md §5.10), per particle in
//! parallel: the half-kick with the contact force and torque, half the non-contact update
//! ([`NonContactForces::update`]) and, in the first half, the drift. Between two sub-steps the
//! second half of one and the first half of the next are one pass ([`Pass::Between`]).

use rayon::prelude::*;

use spillage_model::closure::drag::FluidAtParticle;
use spillage_model::particles::non_contact::{LoadShare, NonContactForces};
use spillage_model::particles::state::Vec3;

use super::arrays::ParticleArrays;

/// Per-particle accumulators of a step, in internal order.
#[derive(Default)]
pub struct StepSums {
    /// The load shares summed over the step's updates.
    pub load: Vec<LoadShare>,
    /// Kinetic-energy change of the last non-contact update [J].
    pub work: Vec<f64>,
    /// The same for the second update of a pass between two sub-steps ([`Pass::Between`]).
    pub work_next: Vec<f64>,
}

impl StepSums {
    pub fn reset(&mut self, n: usize) {
        self.load.clear();
        self.load.resize(n, LoadShare::default());
        self.work.clear();
        self.work.resize(n, 0.0);
        self.work_next.clear();
        self.work_next.resize(n, 0.0);
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
    /// in internal order.
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
    let known = origins.len() == arrays.len();
    let ParticleArrays { state_index, diameter, density, mass, inertia, volume, position, velocity, spin, force, torque, .. } = arrays;
    let h = 0.5 * dt;
    // held particles (`[particles] motion`) take no kick and no drift
    let motion = forces.motion;
    // half the non-contact update of particle k, its work into `work` and its load into `load`
    let update = |k: usize, v: &mut Vec3, x: &Vec3, load: &mut LoadShare, work: &mut f64| {
        let before = v.norm_squared();
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
        *work = 0.5 * mass[k] * (v.norm_squared() - before);
    };
    let kick = |k: usize, v: &mut Vec3, w: &mut Vec3| {
        *v = motion.kick(*v, h * force[k] / mass[k]);
        *w = motion.kick(*w, h * torque[k] / inertia[k]);
    };
    let displacement = (velocity, spin, position, &mut sums.load, (&mut sums.work, &mut sums.work_next))
        .into_par_iter()
        .enumerate()
        .with_min_len(512)
        .map(|(k, (v, w, x, load, (work, work_next)))| {
            if pass != Pass::First {
                update(k, v, x, load, work);
                kick(k, v, w);
            }
            if pass == Pass::Second {
                return 0.0;
            }
            kick(k, v, w);
            update(k, v, x, load, if pass == Pass::Between { work_next } else { work });
            *x = motion.drift(*x, *v, dt);
            if known {
                (*x - origins[k]).norm_squared()
            } else {
                f64::NAN
            }
        })
        // the largest of exact values: the same whatever the threads (NaN wins)
        .reduce(|| 0.0, |x, y| if x.is_nan() || y.is_nan() { f64::NAN } else { x.max(y) });
    let total = |work: &[f64]| -> f64 { work.iter().sum() };
    match pass {
        Pass::First => PassSums { work_second: 0.0, work_first: total(&sums.work), max_displacement_sq: displacement },
        Pass::Between => PassSums { work_second: total(&sums.work), work_first: total(&sums.work_next), max_displacement_sq: displacement },
        Pass::Second => PassSums { work_second: total(&sums.work), work_first: 0.0, max_displacement_sq: displacement },
    }
}
