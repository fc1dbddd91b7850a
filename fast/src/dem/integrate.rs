//! The two halves of a velocity-Verlet sub-step (fluid-dem-model.md §5.10), per particle in
//! parallel: the half-kick with the contact force and torque, half the non-contact update
//! ([`NonContactForces::update`]) and, in the first half, the drift.

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
}

impl StepSums {
    pub fn reset(&mut self, n: usize) {
        self.load.clear();
        self.load.resize(n, LoadShare::default());
        self.work.clear();
        self.work.resize(n, 0.0);
    }
}

/// Which half of the sub-step.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Half {
    /// Half-kick, half the non-contact update, drift.
    First,
    /// Half the non-contact update, half-kick.
    Second,
}

/// One half of a sub-step of length `dt` for every particle; `fluid` is indexed by the
/// state's order (empty: no particle sees a fluid). Returns the work of the non-contact forces [J] (summed in internal order)
/// and, after the drift, the largest squared displacement from `origins` (the neighbour list's
/// build positions; NaN when they are not these particles').
pub fn half_step(
    half: Half,
    arrays: &mut ParticleArrays,
    sums: &mut StepSums,
    forces: &NonContactForces,
    fluid: &[Option<FluidAtParticle>],
    dt: f64,
    origins: &[Vec3],
) -> (f64, f64) {
    let known = origins.len() == arrays.len();
    let ParticleArrays { state_index, diameter, density, mass, inertia, volume, position, velocity, spin, force, torque, .. } = arrays;
    let h = 0.5 * dt;
    // held particles (`[particles] motion`) take no kick and no drift
    let motion = forces.motion;
    let displacement = (velocity, spin, position, &mut sums.load, &mut sums.work)
        .into_par_iter()
        .enumerate()
        .with_min_len(512)
        .map(|(k, (v, w, x, load, work))| {
            if half == Half::First {
                *v = motion.kick(*v, h * force[k] / mass[k]);
                *w = motion.kick(*w, h * torque[k] / inertia[k]);
            }
            let before = v.norm_squared();
            let (after, share) = forces.update(*v, *x, diameter[k], density[k], volume[k], fluid.get(state_index[k]).and_then(|f| f.as_ref()), h);
            *v = after;
            if let Some(share) = share {
                load.implicit_drag += share.implicit_drag;
                load.explicit_force += share.explicit_force;
                load.drag += share.drag;
                load.slip_reynolds = share.slip_reynolds;
            }
            *work = 0.5 * mass[k] * (v.norm_squared() - before);
            match half {
                Half::First => {
                    *x = motion.drift(*x, *v, dt);
                    if known {
                        (*x - origins[k]).norm_squared()
                    } else {
                        f64::NAN
                    }
                }
                Half::Second => {
                    *v = motion.kick(*v, h * force[k] / mass[k]);
                    *w = motion.kick(*w, h * torque[k] / inertia[k]);
                    0.0
                }
            }
        })
        // the largest of exact values: the same whatever the threads (NaN wins)
        .reduce(|| 0.0, |x, y| if x.is_nan() || y.is_nan() { f64::NAN } else { x.max(y) });
    (sums.work.iter().sum(), displacement)
}
