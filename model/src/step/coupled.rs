//! [`Coupled`]: the only thing that advances time. One step is spec fluid-dem-model.md §8.7,
//! Algorithm 1, read top to bottom:
//!
//! 1. clock: Δt (fixed, or from the Courant number, [`super::time_step`]), the time
//!    coefficients and the rotor pose at tⁿ and tⁿ⁺¹ ([`StepContext`]); the fluid mesh's rotor
//!    zone is turned to tⁿ⁺¹ first, because particles are located in the new mesh position
//!    (spec §8.7 [R]);
//! 2. feed: particles owed by the feeds are placed ([`bookkeeping::feed`]);
//! 3. sample: the fluid each particle sees, held for the whole step (§5.10);
//! 4. DEM sub-steps: particles and walls to tⁿ⁺¹ ([`ParticlePhase::advance`]);
//! 5. exits: particles that left the domain or the mesh are removed and logged (with their
//!    entries of the particle load);
//! 6. PIMPLE with the particle load ([`FluidPhase::advance`]; one-way coupling passes none);
//! 7. clock: t, step, Δt and the rotor angle of the state move to tⁿ⁺¹.
//!
//! A step that returns an error leaves the run unusable (the particles may already have moved
//! while the fluid and the clock have not): the caller stops and reports, as `spillage run`
//! does, keeping what was written before.
//!
//! Fluid-only and particle-only runs are the same driver with one phase [`Absent`]. Because the
//! driver is generic, any fluid phase pairs with any particle phase (tests run the reference
//! fluid with either particle phase to localise a disagreement).

use super::context::StepContext;
use super::phases::{Absent, FluidPhase, ParticleLoad, ParticlePhase};
use super::rotor_pose::RotorPose;
use super::time_step::TimeStepControl;
use crate::case::Case;
use crate::closure::drag::FluidAtParticle;
use crate::fluid::settings::TimeScheme;
use crate::mesh::{Mesh, Vec3};
use crate::particles::bookkeeping::{self, ExitRoute};
use crate::particles::settings::ParticlesSection;
use crate::solver::{Solver, SolverError, StepReport};
use crate::state::State;

/// A fluid phase, a particle phase, or both, and the state they advance.
pub struct Coupled<F: FluidPhase = Absent, P: ParticlePhase = Absent> {
    fluid: Option<F>,
    particles: Option<P>,
    state: State,
    scheme: TimeScheme,
    time_step: TimeStepControl,
    rotor: Option<RotorPose>,
    particle_section: Option<ParticlesSection>,
    /// The still fluid of `[particles.ambient]` when it exerts forces (particle-only runs).
    ambient: Option<FluidAtParticle>,
    /// Fluid seen by each particle this step (reused).
    samples: Vec<Option<FluidAtParticle>>,
    label: &'static str,
}

/// A fluid-only run.
pub type FluidOnly<F> = Coupled<F, Absent>;
/// A particle-only run.
pub type ParticlesOnly<P> = Coupled<Absent, P>;

fn unsupported(what: impl Into<String>) -> SolverError {
    SolverError::Unsupported(what.into())
}

impl<F: FluidPhase, P: ParticlePhase> Coupled<F, P> {
    /// Sets up a run of `case` from `state` (the initial state or a checkpoint). The state must
    /// hold what each present phase advances (a fluid state for a fluid phase; particles and
    /// walls for a particle phase): the phases' constructors fill in what is missing.
    pub fn new(case: &Case, mut state: State, mut fluid: Option<F>, particles: Option<P>) -> Result<Self, SolverError> {
        if fluid.is_none() && particles.is_none() {
            return Err(unsupported("a run needs a fluid phase, a particle phase or both"));
        }
        if case.fluid.is_some() != fluid.is_some() || case.particles.is_some() != particles.is_some() {
            let has = |b: bool| if b { "has" } else { "has no" };
            return Err(unsupported(format!(
                "the case {} [fluid] and {} [particles], the run {} fluid phase and {} particle phase",
                has(case.fluid.is_some()),
                has(case.particles.is_some()),
                has(fluid.is_some()),
                has(particles.is_some())
            )));
        }
        // the phases match the case, so the state must match it too
        check_state_matches_case(case, &state)?;
        if particles.is_some() && state.walls.is_none() {
            return Err(unsupported("the state has particles but no walls"));
        }
        let time_step = TimeStepControl::from_case(case, fluid.is_some())?;
        let rotor = RotorPose::from_case(case, state.rotor_angle);
        if let Some(f) = fluid.as_mut() {
            f.place_rotor(rotor.as_ref())?;
        }
        if let Some(walls) = state.walls.as_mut() {
            walls.place(state.time, rotor.as_ref());
        }
        let particle_section = case.particles.clone();
        let ambient = particle_section
            .as_ref()
            .and_then(|s| s.ambient.as_ref())
            .filter(|a| a.forces && fluid.is_none())
            .map(|a| FluidAtParticle::still(a.density, a.kinematic_viscosity));
        if let (Some(section), Some(p)) = (&particle_section, &state.particles) {
            if p.feed_debt.len() != section.feed.len() || p.feed_random.len() != section.feed.len() {
                return Err(unsupported(format!("the state has {} feeds, the case {}", p.feed_debt.len(), section.feed.len())));
            }
        }
        let label = match (&fluid, &particles) {
            (Some(f), Some(p)) if f.name() != p.name() => match (f.name(), p.name()) {
                ("fast", "reference") => "fast fluid + reference particles",
                ("reference", "fast") => "reference fluid + fast particles",
                _ => "mixed",
            },
            (Some(f), _) => f.name(),
            (None, Some(p)) => p.name(),
            (None, None) => unreachable!("checked above"),
        };
        Ok(Coupled { fluid, particles, state, scheme: case.numerics.time_scheme, time_step, rotor, particle_section, ambient, samples: Vec::new(), label })
    }

    pub fn fluid_phase(&self) -> Option<&F> {
        self.fluid.as_ref()
    }

    pub fn particle_phase(&self) -> Option<&P> {
        self.particles.as_ref()
    }

    /// The phases and the state at once, for verification rigs that drive a phase below the
    /// step (single DEM sub-steps); they advance no clock.
    pub fn parts_mut(&mut self) -> (Option<&mut F>, Option<&mut P>, &mut State) {
        (self.fluid.as_mut(), self.particles.as_mut(), &mut self.state)
    }

    /// The rotor at the current time.
    pub fn rotor(&self) -> Option<RotorPose> {
        self.rotor.map(|r| RotorPose { angle: self.state.rotor_angle, ..r })
    }

    /// The step size the next step will take.
    pub fn next_dt(&self) -> Result<f64, SolverError> {
        let courant_rate = || self.fluid.as_ref().map_or(0.0, |f| f.courant_rate(self.state.fluid.as_ref().expect("checked in new")));
        self.time_step.next_dt(&self.state, courant_rate)
    }

    /// One step of the size the case asks for.
    pub fn advance(&mut self, report: &mut StepReport) -> Result<(), SolverError> {
        let dt = self.next_dt()?;
        self.advance_by(dt, report)
    }

    /// One step of `dt` (tests impose step sequences with it).
    pub fn advance_by(&mut self, dt: f64, report: &mut StepReport) -> Result<(), SolverError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(unsupported(format!("time step {dt} s: expected a finite step > 0")));
        }
        report.values.clear();
        // 1. clock and rotor pose
        let ctx = StepContext::new(self.state.step + 1, self.state.time, dt, self.state.dt, self.scheme, self.rotor());
        let diverged = |what: String| SolverError::Diverged { step: ctx.step, time: ctx.time_end(), what };
        if ctx.time_end() <= ctx.time {
            return Err(diverged(format!("the time step {dt:e} s no longer advances the clock from t = {} s", ctx.time)));
        }
        if let Some(fluid) = self.fluid.as_mut() {
            fluid.place_rotor(ctx.rotor.as_ref())?;
        }

        // 2–5. particles: feed, sample, DEM sub-steps, exits
        let mut load: Option<ParticleLoad> = None;
        if let Some(phase) = self.particles.as_mut() {
            let section = self.particle_section.as_ref().expect("a particle phase has a [particles] section");
            let particles = self.state.particles.as_mut().expect("checked in new");
            bookkeeping::feed(section, particles, ctx.time, dt);
            self.samples.clear();
            match (&self.fluid, &self.state.fluid) {
                (Some(fluid), Some(fluid_state)) => fluid.sample(fluid_state, &particles.particles, &mut self.samples),
                _ => self.samples.resize(particles.particles.len(), self.ambient),
            }
            let walls = self.state.walls.as_mut().expect("checked in new");
            load = phase.advance(&ctx, particles, walls, &self.samples, report)?;
            if let Some(l) = &load {
                if [l.volume.len(), l.implicit_drag.len(), l.explicit_force.len()].iter().any(|&n| n != particles.particles.len()) {
                    return Err(unsupported(format!(
                        "the particle phase returned a load for {} particles, but there are {}",
                        l.volume.len(),
                        particles.particles.len()
                    )));
                }
            }
            if let Some(p) = particles.particles.iter().find(|p| !(p.position.iter().chain(p.velocity.iter()).all(|v| v.is_finite()))) {
                return Err(diverged(format!("particle {} has a non-finite position or velocity", p.id)));
            }
            let mesh = self.fluid.as_ref().map(|f| f.mesh());
            let domain = section.domain.clone();
            bookkeeping::remove_exited(particles, load.as_mut(), ctx.time_end(), |p| exit_route(domain.as_ref(), mesh, &p.position));
            report.values.push(("particles", particles.particles.len() as f64));
            report.values.push(("escaped", particles.escaped() as f64));
            report.values.push(("impacts", particles.impacts.len() as f64));
        }

        // 6. the fluid, with the particle load of this step
        if let Some(phase) = self.fluid.as_mut() {
            let fluid = self.state.fluid.as_mut().expect("checked in new");
            let outcome = phase.advance(&ctx, fluid, load.as_ref(), report)?;
            if !outcome.courant_max.is_finite() {
                return Err(diverged(format!("Courant number {}", outcome.courant_max)));
            }
            self.state.courant = outcome.courant_max;
        }

        // 7. the clock
        self.state.time = ctx.time_end();
        self.state.step = ctx.step;
        self.state.dt = dt;
        if let Some(r) = ctx.rotor {
            self.state.rotor_angle = r.angle;
            report.values.push(("rotor_angle", r.angle));
        }
        Ok(())
    }
}

impl<F: FluidPhase> Coupled<F, Absent> {
    /// A fluid-only run.
    pub fn fluid_only(case: &Case, state: State, fluid: F) -> Result<Self, SolverError> {
        Coupled::new(case, state, Some(fluid), None)
    }
}

impl<P: ParticlePhase> Coupled<Absent, P> {
    /// A particle-only run.
    pub fn particles_only(case: &Case, state: State, particles: P) -> Result<Self, SolverError> {
        Coupled::new(case, state, None, Some(particles))
    }
}

/// Refuses a state whose parts do not match the case. Called on a restart state before the
/// phases' constructors (which would fill a missing part from its initial state, silently
/// restarting it) and by [`Coupled::new`].
pub fn check_state_matches_case(case: &Case, state: &State) -> Result<(), SolverError> {
    let has = |b: bool| if b { "has" } else { "has no" };
    if case.fluid.is_some() != state.fluid.is_some() || case.particles.is_some() != state.particles.is_some() {
        return Err(unsupported(format!(
            "the state {} fluid and {} particles, but the case {} [fluid] and {} [particles] (a checkpoint of another case?)",
            has(state.fluid.is_some()),
            has(state.particles.is_some()),
            has(case.fluid.is_some()),
            has(case.particles.is_some())
        )));
    }
    Ok(())
}

/// Where a particle at `position` has left to, if anywhere: outside `[particles] domain`, or
/// outside the fluid mesh (through the patch of the nearest boundary face). A point outside
/// every cell whose nearest boundary face is on a sliding interface is in the sliver between
/// the rotor's and the stator's polygonal rings (up to r(1 − cos π/n_θ) wide), inside the
/// domain: not an exit.
fn exit_route(domain: Option<&crate::particles::settings::BoxRegion>, mesh: Option<&Mesh>, position: &Vec3) -> Option<ExitRoute> {
    if let Some(d) = domain {
        if !d.contains([position.x, position.y, position.z]) {
            return Some(ExitRoute::Domain);
        }
    }
    let mesh = mesh?;
    if mesh.locate(position).is_some() {
        return None;
    }
    let nearest = (mesh.n_internal_faces..mesh.n_faces())
        .min_by(|&a, &b| (mesh.face_centres[a] - position).norm_squared().total_cmp(&(mesh.face_centres[b] - position).norm_squared()))?;
    let patch = mesh.patches.iter().find(|p| p.faces().contains(&nearest))?;
    if matches!(patch.kind, crate::mesh::PatchKind::Interface { .. }) {
        return None;
    }
    Some(ExitRoute::Patch(patch.name.clone()))
}

impl<F: FluidPhase, P: ParticlePhase> Solver for Coupled<F, P> {
    fn name(&self) -> &'static str {
        self.label
    }

    fn step_into(&mut self, report: &mut StepReport) -> Result<(), SolverError> {
        self.advance(report)
    }

    fn state(&self) -> &State {
        &self.state
    }

    fn mesh(&self) -> Option<&Mesh> {
        self.fluid.as_ref().map(|f| f.mesh())
    }
}
