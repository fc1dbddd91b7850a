//! The fluid-force update of [`LANES`] particles at once (fluid-dem-model.md §5.10, §8.4): the
//! model's own [`fluid_force_step`] and [`LoadShare::of_update`], inlined into a loop over
//! lanes that the compiler turns into SIMD, with AVX-512 or AVX2 where the CPU has them.
//!
//! The drag law is the particles' hottest formula: in a dense coupled cloud (P3 fine) it ran
//! twice per particle per DEM sub-step, one particle at a time, and took about a third of the
//! fast solver's time. Its `exp` and `ln` are the model's own ([`spillage_model::closure::elementary`]),
//! which use only correctly rounded operations and no fused multiply-add, so a lane computes
//! the bits the reference computes for the same particle, at any width (tested below against
//! the scalar model code on every path this CPU has).

use spillage_model::closure::drag::{fluid_force_step, DragLaw, FluidAtParticle};
use spillage_model::coupling::Feedback;
use spillage_model::particles::non_contact::LoadShare;
use spillage_model::particles::settings::{FluidForces, Motion};
use spillage_model::particles::state::Vec3;

/// Particles per call: one AVX-512 register of doubles.
pub const LANES: usize = 8;

type Lane = [f64; LANES];

/// What the update reads, one array per component so that each is one SIMD load.
#[derive(Clone, Copy, Default)]
pub struct LaneInputs {
    pub velocity: [Lane; 3],
    pub fluid_velocity: [Lane; 3],
    pub fluid_acceleration: [Lane; 3],
    pub fluid_fraction: Lane,
    pub fluid_density: Lane,
    pub kinematic_viscosity: Lane,
    pub diameter: Lane,
    pub density: Lane,
    pub volume: Lane,
    pub mass: Lane,
}

impl LaneInputs {
    /// Lane `j`'s particle velocity.
    #[inline(always)]
    pub fn velocity(&self, j: usize) -> Vec3 {
        Vec3::new(self.velocity[0][j], self.velocity[1][j], self.velocity[2][j])
    }

    /// What lane `j`'s particle sees of the fluid.
    #[inline(always)]
    pub fn fluid(&self, j: usize) -> FluidAtParticle {
        let three = |a: &[Lane; 3]| Vec3::new(a[0][j], a[1][j], a[2][j]);
        FluidAtParticle {
            density: self.fluid_density[j],
            kinematic_viscosity: self.kinematic_viscosity[j],
            velocity: three(&self.fluid_velocity),
            material_acceleration: three(&self.fluid_acceleration),
            fluid_fraction: self.fluid_fraction[j],
        }
    }

    /// Puts particle (`velocity`, `diameter`, `density`, `volume`, `mass`) in `fluid` into `lane`.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn set(&mut self, lane: usize, velocity: &Vec3, fluid: &FluidAtParticle, diameter: f64, density: f64, volume: f64, mass: f64) {
        for c in 0..3 {
            self.velocity[c][lane] = velocity[c];
            self.fluid_velocity[c][lane] = fluid.velocity[c];
            self.fluid_acceleration[c][lane] = fluid.material_acceleration[c];
        }
        self.fluid_fraction[lane] = fluid.fluid_fraction;
        self.fluid_density[lane] = fluid.density;
        self.kinematic_viscosity[lane] = fluid.kinematic_viscosity;
        self.diameter[lane] = diameter;
        self.density[lane] = density;
        self.volume[lane] = volume;
        self.mass[lane] = mass;
    }
}

/// What the update gives, per lane: the new velocity, the load share (when the fluid receives
/// one) and the work of the update, ½ m (|u'|² − |u|²).
#[derive(Clone, Copy, Default)]
pub struct LaneResults {
    pub velocity: [Lane; 3],
    pub implicit_drag: Lane,
    pub explicit_force: [Lane; 3],
    pub drag: [Lane; 3],
    pub slip_reynolds: Lane,
    pub work: Lane,
}

impl LaneResults {
    pub fn velocity(&self, lane: usize) -> Vec3 {
        Vec3::new(self.velocity[0][lane], self.velocity[1][lane], self.velocity[2][lane])
    }

    pub fn share(&self, lane: usize) -> LoadShare {
        let v = |a: &[Lane; 3]| Vec3::new(a[0][lane], a[1][lane], a[2][lane]);
        LoadShare {
            implicit_drag: self.implicit_drag[lane],
            explicit_force: v(&self.explicit_force),
            drag: v(&self.drag),
            slip_reynolds: self.slip_reynolds[lane],
        }
    }
}

/// The free particles' fluid-force update over `dt` of every lane (`law`, `feedback` and
/// `gravity` as [`spillage_model::particles::non_contact::NonContactForces`] holds them, without
/// a rotating frame, with the full set of fluid forces).
pub type LaneKernel = fn(DragLaw, Option<Feedback>, Vec3, f64, &LaneInputs, &mut LaneResults);

/// Whether a pass updates its particles in lanes (given a fluid sample for them): free
/// particles under the full set of fluid forces, without a rotating frame. The lanes inline
/// [`fluid_force_step`] only; the held particles', the wear model's drag-and-buoyancy and the
/// rotating frame's updates stay particle by particle.
pub fn takes_lanes(motion: Motion, rotating_frame: bool, fluid_forces: FluidForces) -> bool {
    motion == Motion::Free && !rotating_frame && fluid_forces == FluidForces::Full
}

/// The SIMD a [`LaneKernel`] can use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LaneWidth {
    Avx512,
    Avx2,
    Portable,
}

impl LaneWidth {
    /// The widest this CPU has.
    pub fn detect() -> Self {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                return LaneWidth::Avx512;
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                return LaneWidth::Avx2;
            }
        }
        LaneWidth::Portable
    }

    /// As a run's summary names it (`dem_drag_kernel`): a coupled run's speed depends on it,
    /// its bits do not.
    pub fn describe(self) -> &'static str {
        match self {
            LaneWidth::Avx512 => "AVX-512, eight particles a call",
            LaneWidth::Avx2 => "AVX2, eight particles a call",
            LaneWidth::Portable => "portable lanes, eight particles a call",
        }
    }
}

/// The [`LaneKernel`] on the widest SIMD this CPU has ([`LaneWidth::detect`]).
pub fn lane_kernel() -> LaneKernel {
    match LaneWidth::detect() {
        #[cfg(target_arch = "x86_64")]
        LaneWidth::Avx512 => |law, feedback, gravity, dt, inputs, results| {
            // SAFETY: chosen only on a CPU with AVX-512 F (`LaneWidth::detect`)
            unsafe { update_lanes_avx512(law, feedback, gravity, dt, inputs, results) }
        },
        #[cfg(target_arch = "x86_64")]
        LaneWidth::Avx2 => |law, feedback, gravity, dt, inputs, results| {
            // SAFETY: chosen only on a CPU with AVX2 (`LaneWidth::detect`)
            unsafe { update_lanes_avx2(law, feedback, gravity, dt, inputs, results) }
        },
        _ => update_lanes_baseline,
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn update_lanes_avx512(law: DragLaw, feedback: Option<Feedback>, gravity: Vec3, dt: f64, inputs: &LaneInputs, results: &mut LaneResults) {
    by_law(law, feedback, gravity, dt, inputs, results)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn update_lanes_avx2(law: DragLaw, feedback: Option<Feedback>, gravity: Vec3, dt: f64, inputs: &LaneInputs, results: &mut LaneResults) {
    by_law(law, feedback, gravity, dt, inputs, results)
}

fn update_lanes_baseline(law: DragLaw, feedback: Option<Feedback>, gravity: Vec3, dt: f64, inputs: &LaneInputs, results: &mut LaneResults) {
    by_law(law, feedback, gravity, dt, inputs, results)
}

/// One loop per law and feedback, each with its choice as a constant, so that no lane
/// branches on them.
#[inline(always)]
fn by_law(law: DragLaw, feedback: Option<Feedback>, gravity: Vec3, dt: f64, inputs: &LaneInputs, results: &mut LaneResults) {
    match law {
        DragLaw::BrownLawler => by_feedback(DragLaw::BrownLawler, feedback, gravity, dt, inputs, results),
        DragLaw::SchillerNaumann => by_feedback(DragLaw::SchillerNaumann, feedback, gravity, dt, inputs, results),
        DragLaw::Stokes => by_feedback(DragLaw::Stokes, feedback, gravity, dt, inputs, results),
    }
}

#[inline(always)]
fn by_feedback(law: DragLaw, feedback: Option<Feedback>, gravity: Vec3, dt: f64, inputs: &LaneInputs, results: &mut LaneResults) {
    match feedback {
        None => lanes(law, None, gravity, dt, inputs, results),
        Some(Feedback::DragAndFluidAcceleration) => lanes(law, Some(Feedback::DragAndFluidAcceleration), gravity, dt, inputs, results),
        Some(Feedback::Literal) => lanes(law, Some(Feedback::Literal), gravity, dt, inputs, results),
    }
}

#[inline(always)]
fn lanes(law: DragLaw, feedback: Option<Feedback>, gravity: Vec3, dt: f64, x: &LaneInputs, out: &mut LaneResults) {
    for j in 0..LANES {
        let (velocity, fluid) = (x.velocity(j), x.fluid(j));
        // the operations of `NonContactForces::update` and of the pass's work, in their order
        let before = velocity.norm_squared();
        let step = fluid_force_step(law, velocity, x.diameter[j], x.density[j], &fluid, gravity, dt);
        out.work[j] = 0.5 * x.mass[j] * (step.velocity.norm_squared() - before);
        for c in 0..3 {
            out.velocity[c][j] = step.velocity[c];
        }
        if let Some(feedback) = feedback {
            let share = LoadShare::of_update(feedback, &step, x.volume[j], x.density[j], fluid.density, gravity, dt);
            out.implicit_drag[j] = share.implicit_drag;
            for c in 0..3 {
                out.explicit_force[c][j] = share.explicit_force[c];
                out.drag[c][j] = share.drag[c];
            }
            out.slip_reynolds[j] = share.slip_reynolds;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use spillage_model::particles::non_contact::NonContactForces;

    /// Lanes spread over zero, creeping and turbulent slip, dense to lone (α_c = 1 exactly, and
    /// just above 1), still and moving fluid, two diameters and densities.
    fn inputs(seed: u64) -> LaneInputs {
        let mut state = seed;
        let mut next = |low: f64, high: f64| {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            low + (high - low) * ((state >> 11) as f64 / (1u64 << 53) as f64)
        };
        let mut x = LaneInputs::default();
        for j in 0..LANES {
            let speed = [0.0, 1e-7, 1e-4, 0.01, 0.1, 0.5, 1.0, 3.0][j];
            let velocity = Vec3::new(next(-1.0, 1.0), next(-1.0, 1.0), next(-1.0, 1.0)) * speed;
            let fluid_velocity = Vec3::new(next(-0.2, 0.2), next(-0.2, 0.2), 0.0);
            let fluid = FluidAtParticle {
                density: 998.2,
                kinematic_viscosity: 1.0034e-6,
                // lane 0 at zero slip (ln 0 = −∞ in the drag law)
                velocity: if j == 0 { velocity } else { fluid_velocity },
                material_acceleration: Vec3::new(next(-2.0, 2.0), next(-2.0, 2.0), next(-2.0, 2.0)),
                // lone (α = 1 exactly) and a mapping's round-off above 1
                fluid_fraction: match j {
                    3 => 1.0,
                    5 => 1.0 + 1e-12,
                    _ => next(0.55, 1.0),
                },
            };
            let (d, rho): (f64, f64) = if j % 2 == 0 { (0.01, 2650.0) } else { (0.02, 1800.0) };
            let volume = std::f64::consts::PI * d.powi(3) / 6.0;
            x.set(j, &velocity, &fluid, d, rho, volume, volume * rho);
        }
        x
    }

    /// What the scalar model code gives for lane j: `NonContactForces::update` and the work.
    fn scalar(forces: &NonContactForces, x: &LaneInputs, dt: f64, j: usize) -> (Vec3, Option<LoadShare>, f64) {
        let (v, fluid) = (x.velocity(j), x.fluid(j));
        let (after, share) = forces.update(v, Vec3::zeros(), x.diameter[j], x.density[j], x.volume[j], Some(&fluid), dt);
        (after, share, 0.5 * x.mass[j] * (after.norm_squared() - v.norm_squared()))
    }

    /// Every lane, on every SIMD path this CPU has, equals the scalar model code bit for bit,
    /// for each law and feedback.
    #[test]
    fn lanes_compute_the_scalar_bits() {
        type Path = fn(DragLaw, Option<Feedback>, Vec3, f64, &LaneInputs, &mut LaneResults);
        let mut paths: Vec<(&str, Path)> = vec![("baseline", update_lanes_baseline), ("chosen", lane_kernel())];
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: only called on a CPU with AVX2 (checked just above)
                paths.push(("avx2", |l, f, g, d, x, r| unsafe { update_lanes_avx2(l, f, g, d, x, r) }));
            }
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY: only called on a CPU with AVX-512 F (checked just above)
                paths.push(("avx512", |l, f, g, d, x, r| unsafe { update_lanes_avx512(l, f, g, d, x, r) }));
            }
        }
        let gravity = Vec3::new(0.0, -9.81, 0.0);
        let dt = 1.6e-5;
        for law in [DragLaw::BrownLawler, DragLaw::SchillerNaumann, DragLaw::Stokes] {
            for feedback in [None, Some(Feedback::DragAndFluidAcceleration), Some(Feedback::Literal)] {
                let forces = NonContactForces { drag_law: law, gravity, rotating_frame: None, feedback, motion: Motion::Free, fluid_forces: FluidForces::Full };
                for seed in 1..20 {
                    let x = inputs(seed);
                    for (name, path) in &paths {
                        let mut out = LaneResults::default();
                        path(law, feedback, gravity, dt, &x, &mut out);
                        for j in 0..LANES {
                            let (velocity, share, work) = scalar(&forces, &x, dt, j);
                            let bits = |v: Vec3| v.map(f64::to_bits);
                            assert_eq!(bits(out.velocity(j)), bits(velocity), "{name} {law:?} {feedback:?} lane {j}");
                            assert_eq!(out.work[j].to_bits(), work.to_bits(), "{name} lane {j}");
                            if let Some(share) = share {
                                let lane = out.share(j);
                                assert_eq!(
                                    (lane.implicit_drag.to_bits(), bits(lane.explicit_force), bits(lane.drag), lane.slip_reynolds.to_bits()),
                                    (share.implicit_drag.to_bits(), bits(share.explicit_force), bits(share.drag), share.slip_reynolds.to_bits()),
                                    "{name} {law:?} {feedback:?} lane {j}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}
