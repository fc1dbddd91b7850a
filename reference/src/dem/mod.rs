//! The reference DEM: soft spheres with Hertz–Mindlin–Tsuji contacts, triangle-mesh walls and a
//! symplectic (velocity-Verlet) integrator with DEM sub-steps inside an outer step
//! (fluid-dem-model.md §5.7–§5.10, §7).
//!
//! Written to be read: arrays of structs, one loop per equation, a cell list for neighbours.

pub mod contacts;
pub mod neighbours;

use std::collections::BTreeMap;

use spillage_model::case::Case;
use spillage_model::closure::drag::FluidAtParticle;
use spillage_model::particles::dem_setup::{DemSetup, WallMeshes};
use spillage_model::particles::guards::EnergyBudget;
use spillage_model::particles::materials::MaterialTable;
use spillage_model::particles::non_contact::NonContactForces;
use spillage_model::particles::settings::ParticlesSection;
use spillage_model::particles::substeps::{substeps_for, worst_collision_time};
use spillage_model::particles::{ContactRecord, Particle, ParticleState, Partner};
use spillage_model::solver::{SolverError, StepReport};
use spillage_model::state::State;
use spillage_model::step::{ParticleLoad, ParticlePhase, RotorPose, StepContext};
use spillage_model::walls::state::WallState;

pub use contacts::ContactSample;

/// The fluid seen by particle `i` (index into the particle list) during a sub-step.
pub type FluidSampler<'a> = &'a dyn Fn(usize, &Particle) -> Option<FluidAtParticle>;

/// The reference DEM: a particle phase of the step driver ([`spillage_model::step::Coupled`]).
/// It holds the case's constants and the wall meshes; particles, walls and their contact history
/// live in the state it is handed.
pub struct ReferenceDem {
    section: ParticlesSection,
    materials: MaterialTable,
    /// Gravity, drag, the rotating frame's fictitious forces and the feedback to the fluid.
    forces: NonContactForces,
    wall_meshes: WallMeshes,
    /// Fluid density and viscosity for the wet restitution (T3.103), if wet.
    wet_fluid: Option<(f64, f64)>,
    /// Per wall: whether its contacts book sliding wear.
    sliding_walls: Vec<bool>,
    /// The load being summed over the sub-steps of a step (time integrals, divided by Δt at
    /// the end of the step).
    load: ParticleLoad,
    /// Contact history being worked on during a step, keyed by (particle id, partner); several
    /// records per key only for a particle touching one wall in several places (a concave
    /// corner). Rebuilt from the state at the start of every step.
    history: BTreeMap<(u64, Partner), Vec<ContactRecord>>,
    /// Contacts of the last sub-step (diagnostics).
    samples: Vec<ContactSample>,
    /// The guards' measurements of the last sub-step ([`contacts::Watch`]).
    watch: contacts::Watch,
    /// The step's energy budget ([`EnergyBudget`]).
    budget: EnergyBudget,
    /// The first id of the particles fed in the current step (the state's next id at the end
    /// of the last step, or when the phase was set up).
    fed_from: u64,
}

fn unsupported(what: impl Into<String>) -> SolverError {
    SolverError::Unsupported(what.into())
}

impl ReferenceDem {
    /// Sets up the DEM for `case`; missing particle or wall states in `state` are built from the
    /// case (walls with STL paths relative to the case file's folder).
    pub fn new(case: &Case, state: &mut State) -> Result<Self, SolverError> {
        let DemSetup { section, materials, forces, wet_fluid, sliding_walls } = DemSetup::new(case, state).map_err(unsupported)?;
        let walls = state.walls.as_ref().expect("the setup builds the walls");
        let wall_meshes = WallMeshes::new(walls).map_err(unsupported)?;
        Ok(Self {
            wall_meshes,
            wet_fluid,
            sliding_walls,
            forces,
            load: ParticleLoad::default(),
            history: BTreeMap::new(),
            samples: Vec::new(),
            watch: contacts::Watch::default(),
            budget: EnergyBudget::default(),
            fed_from: state.particles.as_ref().map_or(0, |p| p.next_id),
            materials,
            section,
        })
    }

    fn history_from_records(records: &[ContactRecord]) -> BTreeMap<(u64, Partner), Vec<ContactRecord>> {
        let mut history: BTreeMap<(u64, Partner), Vec<ContactRecord>> = BTreeMap::new();
        for r in records {
            history.entry((r.particle, r.partner)).or_default().push(r.clone());
        }
        history
    }

    /// Starts working on the contact history stored in `particles` (call before sub-stepping
    /// outside [`ParticlePhase::advance`]).
    pub fn load_history(&mut self, particles: &ParticleState) {
        self.history = Self::history_from_records(&particles.contacts);
    }

    /// Writes the working contact history into `particles` (sorted, for checkpoints).
    pub fn store_history(&self, particles: &mut ParticleState) {
        particles.contacts = self.history.values().flatten().cloned().collect();
    }

    /// The contacts evaluated at the last sub-step.
    pub fn contact_samples(&self) -> &[ContactSample] {
        &self.samples
    }

    /// Overrides the fluid used by the wet restitution law.
    pub fn set_wet_fluid(&mut self, fluid: Option<(f64, f64)>) {
        self.wet_fluid = fluid;
    }

    /// Worst-case collision time (§7.6, [`worst_collision_time`]).
    pub fn collision_time(&self, particles: &[Particle], walls: &WallState) -> f64 {
        worst_collision_time(&self.section, &self.materials, particles, walls)
    }

    /// Number of sub-steps for an outer step `dt` (T3.106, or the fixed `particles.substep`).
    pub fn substeps_for(&self, dt: f64, particles: &[Particle], walls: &WallState) -> u64 {
        substeps_for(&self.section, &self.materials, dt, particles, walls)
    }

    /// One DEM sub-step of `dt` ending at `end_time` (velocity Verlet, §5.10): half-kick with the
    /// stored contact force and torque, half the fluid-force update, move (walls to their pose at
    /// `end_time`, the rotor walls at `rotor_end`), new contact forces, the other half of the fluid update,
    /// second half-kick. The fluid update is split symmetrically so the step stays second
    /// order and symplectic for conservative forces (gravity).
    pub fn substep(
        &mut self,
        particles: &mut ParticleState,
        walls: &mut WallState,
        dt: f64,
        end_time: f64,
        rotor_end: Option<&RotorPose>,
        fluid: FluidSampler<'_>,
    ) {
        // held particles (`[particles] motion`) take no kick and no drift
        let motion = self.forces.motion;
        for (i, p) in particles.particles.iter_mut().enumerate() {
            p.velocity = motion.kick(p.velocity, 0.5 * dt * p.contact_force / p.mass());
            p.spin = motion.kick(p.spin, 0.5 * dt * p.contact_torque / p.moment_of_inertia());
            let f = fluid(i, p);
            self.fluid_forces(i, p, f.as_ref(), 0.5 * dt);
            p.position = motion.drift(p.position, p.velocity, dt);
        }
        walls.place(end_time, rotor_end);
        self.evaluate_contacts(particles, walls, end_time, dt);
        for (i, p) in particles.particles.iter_mut().enumerate() {
            let f = fluid(i, p);
            self.fluid_forces(i, p, f.as_ref(), 0.5 * dt);
            p.velocity = motion.kick(p.velocity, 0.5 * dt * p.contact_force / p.mass());
            p.spin = motion.kick(p.spin, 0.5 * dt * p.contact_torque / p.moment_of_inertia());
        }
    }

    /// The non-contact update of particle `i` over `dt` ([`NonContactForces::update`]), its
    /// share of the step's load when two-way coupled, and its work in the energy budget.
    fn fluid_forces(&mut self, i: usize, p: &mut Particle, fluid: Option<&FluidAtParticle>, dt: f64) {
        let before = p.velocity.norm_squared();
        let (velocity, share) = self.forces.update(p.velocity, p.position, p.diameter, p.density, p.volume(), fluid, dt);
        p.velocity = velocity;
        if let Some(share) = share {
            self.load.accumulate(i, &share);
        }
        self.budget.external += 0.5 * p.mass() * (p.velocity.norm_squared() - before);
    }

    /// Rebuilds the collision mesh of every wall that moved its vertices since (a receding wall,
    /// wear-model.md §7.4), so contacts see its worn shape.
    pub fn refresh_wall_meshes(&mut self, walls: &WallState) -> Result<(), SolverError> {
        self.wall_meshes.refresh(walls).map_err(unsupported)
    }

    /// Contact forces and torques at the current positions (fluid-dem-model.md §7.8).
    fn evaluate_contacts(&mut self, particles: &mut ParticleState, walls: &WallState, time: f64, dt: f64) {
        let mut impacts = Vec::new();
        let context = contacts::Context {
            materials: &self.materials,
            walls: &walls.walls,
            meshes: &self.wall_meshes.meshes,
            wet_fluid: self.wet_fluid,
            sliding_walls: &self.sliding_walls,
            time,
            dt,
            fed_from: self.fed_from,
        };
        self.samples = contacts::evaluate(&context, &mut particles.particles, &mut self.history, &mut impacts, &mut self.watch);
        self.budget.walls += dt * self.watch.wall_power;
        self.budget.placed += self.watch.new_contact_energy;
        particles.counts.impacts += impacts.iter().filter(|i| !i.sliding).count() as u64;
        particles.impacts.extend(impacts);
    }
}

impl ParticlePhase for ReferenceDem {
    fn name(&self) -> &'static str {
        "reference"
    }

    /// The contact history is rebuilt from the state every step; only the first fed id is kept.
    fn rewind(&mut self, particles: &ParticleState) {
        self.fed_from = particles.next_id;
    }

    /// One outer step in DEM sub-steps of equal length; the rotor walls follow the step's rotor
    /// pose at every sub-step.
    fn advance(
        &mut self,
        ctx: &StepContext,
        particles: &mut ParticleState,
        walls: &mut WallState,
        fluid: &[Option<FluidAtParticle>],
        report: &mut StepReport,
    ) -> Result<Option<ParticleLoad>, SolverError> {
        self.refresh_wall_meshes(walls)?;
        // no contact in the history: nothing stored (a restart's contacts hold energy the phase
        // has not measured yet)
        let elastic_start = particles.contacts.is_empty().then_some(0.0);
        self.load_history(particles);
        let n = self.substeps_for(ctx.dt, &particles.particles, walls);
        let dt_s = ctx.dt / n as f64;
        if fluid.len() != particles.particles.len() {
            return Err(unsupported(format!("the fluid was sampled for {} particles, but there are {}", fluid.len(), particles.particles.len())));
        }
        let sampler = |i: usize, _: &Particle| fluid[i];
        self.load = ParticleLoad::zeros(if self.forces.feedback.is_some() { particles.particles.len() } else { 0 });
        self.budget.start_step(&particles.particles);
        self.watch.fault = None;
        for k in 0..n {
            let elapsed = (k + 1) as f64 * dt_s;
            // the last sub-step ends exactly where the step does (tⁿ⁺¹, the step's rotor pose), so
            // the walls are where a restart from tⁿ⁺¹ places them
            let (end_time, rotor_end) = if k + 1 == n { (ctx.time_end(), ctx.rotor) } else { (ctx.time + elapsed, ctx.rotor_after(elapsed)) };
            self.substep(particles, walls, dt_s, end_time, rotor_end.as_ref(), &sampler);
            if let Some(fault) = self.watch.fault.take() {
                return Err(SolverError::Diverged {
                    step: ctx.step,
                    time: end_time,
                    what: format!("{} (DEM sub-step {} of {n})", fault.describe(&walls.walls), k + 1),
                });
            }
        }
        self.budget.check(ctx, &particles.particles, self.watch.elastic_energy, elastic_start, self.section.collision_speed)?;
        self.fed_from = particles.next_id;
        self.store_history(particles);
        let max_overlap_ratio = self.samples.iter().map(|s| s.overlap / s.radius).fold(0.0, f64::max);
        report.values.extend([
            ("substeps", n as f64),
            ("contacts", self.samples.len() as f64),
            ("particle_kinetic_energy", particles.particles.iter().map(|p| p.kinetic_energy()).sum()),
            ("max_overlap_ratio", max_overlap_ratio),
        ]);
        if self.forces.feedback.is_none() {
            return Ok(None);
        }
        let mut load = std::mem::take(&mut self.load);
        load.time_average(&particles.particles, ctx.dt);
        Ok(Some(load))
    }
}
