//! [`Coupled`]: the only thing that advances time. One step is spec fluid-dem-model.md §8.7,
//! Algorithm 1, read top to bottom:
//!
//! 1. clock: Δt (fixed, or from the Courant number, [`super::time_step`]), the time
//!    coefficients and the rotor pose at tⁿ and tⁿ⁺¹ ([`StepContext`]); the fluid mesh's rotor
//!    zone is turned to tⁿ⁺¹ first, because particles are located in the new mesh position
//!    (spec §8.7 [R]); the steps of a frozen-rotor start-up (t < 0) keep the pose
//!    ([`crate::fluid::frozen_rotor`]);
//! 2. feed: particles owed by the feeds are placed ([`bookkeeping::feed`]);
//!    with `[particles.solids_pressure]` the particles' velocities then take the step's KTGF
//!    solids-pressure correction ([`SolidsPressure::correct`]);
//! 3. sample: the fluid each particle sees, held for the whole step (§5.10);
//! 4. DEM sub-steps: particles and walls to tⁿ⁺¹ ([`ParticlePhase::advance`]);
//! 5. exits: particles that left the domain or the mesh are removed and logged (with their
//!    entries of the particle load);
//! 6. map: with `[coupling]`, the particles' volume and load go to the cells
//!    ([`ParticleMeshMap::deposit`]) and α_c = 1 − α_p becomes the fluid's fraction of this step
//!    (T3.90; ∂α_c/∂t then follows from the stored time levels, T3.92);
//! 7. PIMPLE with the cell load ([`FluidPhase::advance`]; one-way coupling passes none);
//! 8. wear: the step's particle–wall impacts become removed volume and the eroding walls recede
//!    ([`WearPhase::advance`], `[wear]`); the impact log is emptied every step;
//! 9. clock: t, step, Δt and the rotor angle of the state move to tⁿ⁺¹.
//!
//! A step that returns an error from [`Coupled::advance_by`] leaves the run unusable (the
//! particles may already have moved while the fluid and the clock have not): the caller stops
//! and reports, as `spillage run` does, keeping what was written before. [`Coupled::advance`]
//! keeps the state of the step's start instead, and takes a step whose fluid diverged again
//! with a smaller Δt ([`retry`]).
//!
//! Fluid-only and particle-only runs are the same driver with one phase [`Absent`]. Because the
//! driver is generic, any fluid phase pairs with any particle phase (tests run the reference
//! fluid with either particle phase to localise a disagreement).

use super::context::StepContext;
use super::phases::{Absent, FluidPhase, ParticleLoad, ParticlePhase, WearPhase};
use super::rotor_pose::RotorPose;
use super::time_step::TimeStepControl;
use crate::case::Case;
use crate::closure::drag::FluidAtParticle;
use crate::coupling::{CellLoad, ParticleMeshMap, StencilCache};
use crate::cutter_head::fluxes::HeadFluxes;
use crate::cutter_head::spillage::{self, SpillageCounts};
use crate::cutter_head::torque::{ControlVolume, TorqueBudget};
use crate::cutter_head::CutterHead;
use crate::fluid::frozen_rotor::StartUp;
use crate::fluid::sampling::sample_containing_cell;
use crate::fluid::settings::TimeScheme;
use crate::mesh::{Mesh, Vec3};
use crate::particles::batch::{self, LaterBatch};
use crate::particles::bookkeeping;
use crate::particles::settings::ParticlesSection;
use crate::particles::solids_pressure::SolidsPressure;
use crate::solver::{CouplingOutput, Solver, SolverError, StepReport};
use crate::state::State;

mod exit_route;
mod later_batch;
pub mod median;
mod particle_stage;
mod retry;

use median::median;

use exit_route::exit_route;

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
    /// Fluid seen by each particle this step, in particle order after the exits (reused).
    samples: Vec<Option<FluidAtParticle>>,
    /// The particle ↔ mesh mapping of a two-way coupled run (`[coupling]`).
    mapping: Option<ParticleMeshMap>,
    /// The stencils of the last deposit, for the next step's sample ([`StencilCache`]).
    stencils: StencilCache,
    /// The particle load of the last step, per particle and mapped to the cells (output).
    particle_load: Option<ParticleLoad>,
    cell_load: Option<CellLoad>,
    /// Unit vector along gravity (settling velocities), if there is gravity.
    down: Option<Vec3>,
    /// A cutter head's geometry and hulls (spillage bookkeeping, hull fluxes).
    head: Option<(CutterHead, HeadFluxes)>,
    /// The rotor's angular-momentum budget of a fluid with a rotor (issue 16 check 3).
    torque: Option<TorqueBudget>,
    /// The wear phase (`[wear]`, set by [`Coupled::with_wear`]) and whether the case asks for one.
    wear: Option<Box<dyn WearPhase + Send>>,
    wear_in_case: bool,
    /// Per fluid mesh patch: a wall or symmetry plane, which particles do not leave through
    /// ([`exit_route`]).
    closed_patches: Vec<bool>,
    /// Whether the failure of the last step came from the fluid phase ([`retry`]).
    failed_in_fluid: bool,
    /// A frozen-rotor start-up (`[fluid] initial`, [`crate::fluid::frozen_rotor`]).
    start_up: Option<StartUp>,
    /// Head batches placed once the water has turned ([`batch`]).
    later_batches: Vec<LaterBatch>,
    /// The KTGF solids pressure between the particles (`[particles.solids_pressure]`).
    solids_pressure: Option<SolidsPressure>,
    label: &'static str,
}

/// A fluid-only run.
pub type FluidOnly<F> = Coupled<F, Absent>;
/// A particle-only run.
pub type ParticlesOnly<P> = Coupled<Absent, P>;

fn unsupported(what: impl Into<String>) -> SolverError {
    SolverError::Unsupported(what.into())
}

/// The error of a step that diverged, at the step's end time.
fn diverged(ctx: &StepContext, what: String) -> SolverError {
    SolverError::Diverged { step: ctx.step, time: ctx.time_end(), what }
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
        let start_up = StartUp::of_case(case);
        if let Some(s) = start_up.filter(|_| state.step == 0 && state.time == 0.0) {
            // a fresh run of a frozen-rotor start begins with the start-up, before t = 0
            state.time = s.start_time();
        }
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
        let mapping = case.coupling.as_ref().filter(|_| fluid.is_some() && particles.is_some()).map(|section| ParticleMeshMap::of_case(section, case));
        let solids_pressure = match particle_section.as_ref().and_then(|s| s.solids_pressure) {
            Some(_) if fluid.is_none() => return Err(unsupported("[particles.solids_pressure] needs a [fluid] section: its cells are the fluid mesh's")),
            Some(section) => Some(SolidsPressure::new(section)),
            None => None,
        };
        let g = Vec3::from(case.physics.gravity);
        let down = (g.norm() > 0.0).then(|| g.normalize());
        let head = match (&case.cutter_head, &fluid) {
            (Some(section), Some(f)) => Some(HeadFluxes::with_head(case, CutterHead::new(section), f.mesh()).map_err(unsupported)?),
            _ => None,
        };
        let torque = match &fluid {
            Some(f) => {
                let control = head.as_ref().map(|(h, fluxes)| ControlVolume::new(spillage::inside_cells(h, f.mesh()), &fluxes.faces));
                TorqueBudget::new(case, f.mesh(), control).map_err(unsupported)?
            }
            None => None,
        };
        let closed_patches = fluid.as_ref().map_or(Vec::new(), |f| {
            use crate::fluid::settings::BoundaryCondition;
            f.mesh().patches.iter().map(|p| matches!(case.boundary.get(&p.name), Some(BoundaryCondition::Wall { .. } | BoundaryCondition::Symmetry))).collect()
        });
        let mut run = Coupled {
            closed_patches,
            fluid,
            particles,
            state,
            scheme: case.numerics.time_scheme,
            time_step,
            rotor,
            particle_section,
            ambient,
            samples: Vec::new(),
            mapping,
            stencils: StencilCache::default(),
            particle_load: None,
            cell_load: None,
            down,
            head,
            torque,
            wear: None,
            wear_in_case: case.wear.is_some(),
            failed_in_fluid: false,
            start_up,
            later_batches: batch::later_batches(case).map_err(|e| field_error("", e))?,
            solids_pressure,
            label,
        };
        run.map_initial_fraction();
        Ok(run)
    }

    /// Maps a fresh run's initial particles to α_c, at every time level, so the first ∂α_c/∂t
    /// sees only what the particles do in that step. A restarted run keeps its checkpointed α_c.
    fn map_initial_fraction(&mut self) {
        if self.state.step != 0 {
            return;
        }
        if let (Some(map), Some(f), Some(fluid_state), Some(p)) = (&self.mapping, &self.fluid, self.state.fluid.as_mut(), &self.state.particles) {
            let mut cells = CellLoad::default();
            let volumes = ParticleLoad { volume: p.particles.iter().map(|p| p.volume()).collect(), ..ParticleLoad::zeros(p.particles.len()) };
            map.deposit_with(&mut self.stencils, f.mesh(), &p.particles, &volumes, &mut cells);
            map.fluid_fraction(&cells, &mut fluid_state.alpha);
            fluid_state.alpha_old.clone_from(&fluid_state.alpha);
            fluid_state.alpha_old_old.clone_from(&fluid_state.alpha);
        }
    }

    /// Builds the mapping's stencils and smooths its diffusion fields with `solvers` (the fast
    /// solver's parallel ones; the default is [`crate::coupling::MappingSolvers::IN_ORDER`]). A
    /// fresh run's initial α_c is mapped again with them, so every α_c of the run comes from the
    /// same solvers.
    pub fn with_mapping_solvers(mut self, solvers: crate::coupling::MappingSolvers) -> Self {
        if let Some(map) = self.mapping.as_mut() {
            map.solvers = solvers;
            self.map_initial_fraction();
        }
        self
    }

    /// Adds the wear phase of a `[wear]` case (the state must hold the wear state it advances,
    /// which the phase's constructor sets up).
    pub fn with_wear(mut self, wear: Box<dyn WearPhase + Send>) -> Result<Self, SolverError> {
        if !self.wear_in_case {
            return Err(unsupported("a wear phase was given, but the case has no [wear] section"));
        }
        if self.state.wear.is_none() {
            return Err(unsupported("a wear phase was given, but the state holds no wear state"));
        }
        self.wear = Some(wear);
        Ok(self)
    }

    /// The particle load of the last step, per particle (two-way coupled runs).
    pub fn particle_load(&self) -> Option<&ParticleLoad> {
        self.particle_load.as_ref()
    }

    /// The particle load of the last step mapped to the cells (two-way coupled runs).
    pub fn cell_load(&self) -> Option<&CellLoad> {
        self.cell_load.as_ref()
    }

    /// The fluid each particle saw in the last step (held for the whole step), in particle order.
    pub fn fluid_at_particles(&self) -> &[Option<FluidAtParticle>] {
        &self.samples
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

    /// A cutter head's geometry and hull fluxes, if the case has a head and a fluid.
    pub fn cutter_head(&self) -> Option<&(CutterHead, HeadFluxes)> {
        self.head.as_ref()
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

    /// One step of `dt` (tests impose step sequences with it). A diverging step is an error,
    /// not retried ([`Coupled::advance`] retries); `in_fluid` then says whether it was the
    /// fluid that failed, which a smaller step may cure.
    pub fn advance_by(&mut self, dt: f64, report: &mut StepReport) -> Result<(), SolverError> {
        self.failed_in_fluid = false;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(unsupported(format!("time step {dt} s: expected a finite step > 0")));
        }
        report.values.clear();
        // 1. clock and rotor pose
        let ctx = StepContext::new(self.state.step + 1, self.state.time, dt, self.state.dt, self.scheme, self.rotor());
        let ctx = self.start_up.map_or(ctx, |s| s.step(ctx, self.scheme));
        let diverged = |what: String| diverged(&ctx, what);
        if ctx.time_end() <= ctx.time {
            return Err(diverged(format!("the time step {dt:e} s no longer advances the clock from t = {} s", ctx.time)));
        }
        if let Some(fluid) = self.fluid.as_mut() {
            fluid.place_rotor(ctx.rotor.as_ref())?;
            // a mesh that follows a receding wall takes the wall's shape at tⁿ
            if let (Some(walls), Some(state)) = (&self.state.walls, &self.state.fluid) {
                fluid.follow_walls(&ctx, walls, state)?;
            }
        }

        // 2–5. particles: batches, feed, sample, DEM sub-steps, exits
        self.place_due_batches(&ctx)?;
        let load = self.advance_particles(&ctx, report)?;

        // 6. map the particle load to the cells; α_c of this step
        if let (Some(map), Some(phase)) = (&self.mapping, &self.fluid) {
            let load = load.as_ref().ok_or_else(|| unsupported("a two-way coupled case, but the particle phase returned no particle load"))?;
            let particles = self.state.particles.as_ref().expect("checked in new");
            let fluid = self.state.fluid.as_mut().expect("checked in new");
            let cells = self.cell_load.get_or_insert_with(CellLoad::default);
            map.deposit_with(&mut self.stencils, phase.mesh(), &particles.particles, load, cells);
            let clamped = map.fluid_fraction(cells, &mut fluid.alpha);
            let mesh = phase.mesh();
            let alpha_p_max = cells.particle_fraction.iter().fold(0.0, |a: f64, b| a.max(*b));
            let mapped_volume: f64 = cells.particle_fraction.iter().zip(&mesh.cell_volumes).map(|(a, v)| a * v).sum();
            report.values.extend([("alpha_p_max", alpha_p_max), ("alpha_c_clamped", clamped as f64), ("particle_volume", mapped_volume)]);
        }
        self.particle_load = load;

        // 7. the fluid, with the particle load of this step
        if let Some(phase) = self.fluid.as_mut() {
            let fluid = self.state.fluid.as_mut().expect("checked in new");
            if let Some(what) = non_finite_fluid(phase.mesh(), fluid) {
                return Err(diverged(format!("{what}, before the fluid step")));
            }
            let cells = self.mapping.as_ref().and(self.cell_load.as_ref());
            self.failed_in_fluid = true;
            let before = self.torque.as_ref().map(|t| t.before(phase.mesh(), fluid, &ctx));
            // a failed solve says where in the run it failed
            let outcome = phase.advance(&ctx, fluid, cells, report).map_err(|e| match e {
                SolverError::LinearSolve(what) => SolverError::LinearSolve(format!("step {}, t = {:e} s: {what}", ctx.step, ctx.time_end())),
                other => other,
            })?;
            if !outcome.courant_max.is_finite() {
                return Err(diverged(format!("Courant number {}", outcome.courant_max)));
            }
            if let Some(what) = non_finite_fluid(phase.mesh(), fluid) {
                return Err(diverged(what));
            }
            if let Some(what) = outcome.outer_loop_failure() {
                return Err(diverged(what));
            }
            self.failed_in_fluid = false;
            // issue 15: a step whose outer loop stopped at its cap unconverged, per step
            report.values.push(("outer_capped", if outcome.outer_capped { 1.0 } else { 0.0 }));
            self.state.courant = outcome.courant_max;
            if let Some((head, fluxes)) = &self.head {
                fluxes.report(head, phase.mesh(), fluid, ctx.rotor.as_ref(), report);
            }
            if let (Some(budget), Some(before)) = (&self.torque, before) {
                budget.after(phase.mesh(), fluid, &ctx, &before).report(ctx.rotor.map_or(0.0, |r| r.omega), report);
            }
        }

        // 8. wear, from the impacts of this step
        if let Some(particles) = self.state.particles.as_mut() {
            let mut impacts = std::mem::take(&mut particles.impacts);
            match (self.wear.as_mut(), self.wear_in_case) {
                (Some(phase), _) => {
                    let wear = self.state.wear.as_mut().expect("checked in with_wear");
                    let walls = self.state.walls.as_mut().expect("checked in new");
                    phase.advance(&ctx, &impacts, wear, walls, report)?;
                }
                (None, true) => return Err(unsupported("the case has a [wear] section, but the run has no wear phase")),
                (None, false) => {}
            }
            impacts.clear();
            particles.impacts = impacts;
        }

        // 9. the clock
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

/// A case key's error found by the driver, after `context`.
fn field_error(context: &str, e: crate::case::FieldError) -> SolverError {
    unsupported(format!("{context}key `{}` = {}: expected {}", e.key, e.value, e.allowed))
}

/// The first non-finite value of the fluid's fields, naming the field and the cell (or face)
/// with its centre; one pass over the fields, no allocation.
fn non_finite_fluid(mesh: &Mesh, fluid: &crate::fluid::state::FluidState) -> Option<String> {
    let cell = |field: &str, i: usize, value: String| {
        let c = mesh.cell_centres.get(i).map_or(String::new(), |c| format!(" at [{:e}, {:e}, {:e}] m", c.x, c.y, c.z));
        format!("the fluid {field} of cell {i}{c} is {value}")
    };
    if let Some(i) = fluid.velocity.iter().position(|v| !v.iter().all(|x| x.is_finite())) {
        return Some(cell("velocity", i, format!("{:?}", fluid.velocity[i])));
    }
    for (field, values) in [("pressure", &fluid.pressure), ("volume fraction", &fluid.alpha)] {
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Some(cell(field, i, values[i].to_string()));
        }
    }
    if let Some(t) = &fluid.turbulence {
        for (field, values) in [("turbulent kinetic energy k", &t.k), ("dissipation rate ε", &t.epsilon), ("turbulent viscosity ν_t", &t.nu_t)] {
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Some(cell(field, i, values[i].to_string()));
            }
        }
    }
    let i = fluid.flux.iter().position(|v| !v.is_finite())?;
    let c = mesh.face_centres.get(i).map_or(String::new(), |c| format!(" at [{:e}, {:e}, {:e}] m", c.x, c.y, c.z));
    Some(format!("the fluid flux of face {i}{c} is {}", fluid.flux[i]))
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

    fn coupling_output(&self) -> Option<CouplingOutput<'_>> {
        self.mapping.as_ref()?;
        Some(CouplingOutput { cells: self.cell_load.as_ref()?, particles: self.particle_load.as_ref()?, fluid_at_particles: &self.samples })
    }
}
