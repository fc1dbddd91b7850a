//! The reference DEM: soft spheres with Hertz–Mindlin–Tsuji contacts, triangle-mesh walls and a
//! symplectic (velocity-Verlet) integrator with DEM sub-steps inside an outer step
//! (fluid-dem-model.md §5.7–§5.10, §7).
//!
//! Written to be read: arrays of structs, one loop per equation, a cell list for neighbours.

pub mod contacts;
pub mod materials;
pub mod neighbours;

use std::collections::BTreeMap;

use spillage_model::case::Case;
use spillage_model::closure::collision_time::{collision_time, substeps};
use spillage_model::closure::drag::{fluid_force_step, DragLaw, FluidAtParticle};
use spillage_model::closure::rotating_frame::{dry_particle_update, fluid_force_step_in_rotating_frame, RotatingFrame};
use spillage_model::coupling::Feedback;
use spillage_model::particles::settings::ParticlesSection;
use spillage_model::particles::state::Vec3;
use spillage_model::particles::{initial_state, ContactRecord, Particle, ParticleState, Partner};
use spillage_model::solver::{SolverError, StepReport};
use spillage_model::state::State;
use spillage_model::step::{ParticleLoad, ParticlePhase, RotorPose, StepContext};
use spillage_model::walls::geometry::WallMesh;
use spillage_model::walls::state::WallState;

pub use contacts::ContactSample;
use materials::MaterialTable;

/// The fluid seen by particle `i` (index into the particle list) during a sub-step.
pub type FluidSampler<'a> = &'a dyn Fn(usize, &Particle) -> Option<FluidAtParticle>;

/// The reference DEM: a particle phase of the step driver ([`spillage_model::step::Coupled`]).
/// It holds the case's constants and the wall meshes; particles, walls and their contact history
/// live in the state it is handed.
pub struct ReferenceDem {
    section: ParticlesSection,
    materials: MaterialTable,
    gravity: Vec3,
    /// The case's rotating frame (wear-model.md §2.6), if any: its fictitious forces join the
    /// fluid-force update ([`Self::fluid_forces`]).
    rotating_frame: Option<RotatingFrame>,
    wall_meshes: Vec<WallMesh>,
    /// The wall revision each mesh was built from (a receding wall is rebuilt when it moves).
    mesh_revisions: Vec<u64>,
    /// Fluid density and viscosity for the wet restitution (T3.103), if wet.
    wet_fluid: Option<(f64, f64)>,
    drag_law: DragLaw,
    /// With `[coupling]`: which forces the fluid receives; the step then returns its load.
    feedback: Option<Feedback>,
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

/// A step's energy balance (issue 14 item 4: a sphere started on a wall went from 6.6e-4 J to
/// 2 111 J and the run ended `completed`). Contacts only store and return energy (Hertz springs)
/// or dissipate it (damping, friction); everything else that changes the kinetic energy is
/// measured where it acts: gravity, the fluid and the rotating frame in the fluid-force update,
/// the moving walls as Σ F·v_wall dt. So kinetic plus stored elastic energy may grow by at
/// most what those supplied.
#[derive(Default)]
struct EnergyBudget {
    /// Work of the non-contact forces in this step [J] (kinetic-energy change of their updates).
    external: f64,
    /// Work of the moving walls in this step [J].
    walls: f64,
    /// Elastic energy of the first touches of particles fed in this step [J]
    /// ([`contacts::Watch::new_contact_energy`]): where the feed put them, not what a contact
    /// made.
    placed: f64,
    /// Elastic energy stored at the end of the last step [J]; `None` before the first step of
    /// this phase (a restart's contacts are unknown until their first evaluation).
    elastic_end: Option<f64>,
    /// Kinetic energy of each particle at the start of the step (reused).
    start: Vec<f64>,
}

/// Energy a step may create beyond what gravity, the fluid and the moving walls supplied, as a
/// fraction of the step's energy scale (kinetic and elastic energy at its ends, the work
/// supplied, and every particle at the case's collision speed). Measured over the shipped DEM,
/// coupled and wear cases: at most 1.3e-5 (a disc dragging a sphere), 3.6e-4 in 150 steps of
/// the cutter head fed with rock (cutter_head_feed.toml); the elastic energy
/// estimated through the damped force errs by at most its damping part. A blow-up multiplies
/// the energy many times over (6.6e-4 J → 2 111 J).
const ENERGY_GAIN_MAX: f64 = 0.1;

fn unsupported(what: impl Into<String>) -> SolverError {
    SolverError::Unsupported(what.into())
}

impl ReferenceDem {
    /// Sets up the DEM for `case`; missing particle or wall states in `state` are built from the
    /// case (walls with STL paths relative to the case file's folder).
    pub fn new(case: &Case, state: &mut State) -> Result<Self, SolverError> {
        let section = case.particles.clone().ok_or_else(|| unsupported("the reference DEM needs a [particles] section"))?;
        if state.particles.is_none() {
            let initial = initial_state(case).map_err(|e| unsupported(format!("initial particles: key `{}` = {}: expected {}", e.key, e.value, e.allowed)))?;
            state.particles = Some(initial);
        }
        if state.walls.is_none() {
            let dir = case.path.parent().map(|p| p.to_path_buf()).unwrap_or_default();
            state.walls = Some(spillage_model::walls::build(case, &dir).map_err(|e| unsupported(format!("walls: {e}")))?);
        }
        let walls = state.walls.as_ref().expect("walls were just set");
        let mut wall_meshes = Vec::new();
        for w in &walls.walls {
            wall_meshes.push(WallMesh::new(&w.vertices, &w.triangles).map_err(|m| unsupported(format!("wall `{}`: {m}", w.name)))?);
        }
        let mesh_revisions = walls.walls.iter().map(|w| w.revision).collect();
        let materials = MaterialTable::new(&section.materials, section.slip_test);
        let wet_fluid = match (&case.fluid, &section.ambient) {
            (Some(f), _) => Some((f.density, f.kinematic_viscosity)),
            (None, Some(a)) if a.wet_restitution => Some((a.density, a.kinematic_viscosity)),
            _ => None,
        };
        let drag_law = match (&case.coupling, &section.ambient) {
            (Some(c), _) => c.drag,
            (None, Some(a)) => a.drag,
            (None, None) => DragLaw::default(),
        };
        let feedback = case.coupling.as_ref().map(|c| c.feedback);
        Ok(Self {
            gravity: Vec3::from(case.physics.gravity),
            rotating_frame: RotatingFrame::of_physics(&case.physics).map_err(|e| unsupported(format!("`{}` = {}: expected {}", e.key, e.value, e.allowed)))?,
            wall_meshes,
            mesh_revisions,
            wet_fluid,
            drag_law,
            feedback,
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

    /// Worst-case collision time (T3.105 as OpenFOAM evaluates it, §7.6): smallest radius,
    /// largest density, stiffest pair, largest speed |u| + |ω| r (plus the fastest wall
    /// surface), never below `collision_speed`; for pairs R = d_min/4 and the speed doubled.
    pub fn collision_time(&self, particles: &[Particle], walls: &WallState) -> f64 {
        if particles.is_empty() {
            return f64::INFINITY;
        }
        let d_min = particles.iter().map(|p| p.diameter).fold(f64::INFINITY, f64::min);
        let rho_max = particles.iter().map(|p| p.density).fold(0.0, f64::max);
        let speed_max = particles.iter().map(|p| p.velocity.norm() + p.spin.norm() * p.radius()).fold(0.0, f64::max);
        let wall_speed = walls.walls.iter().flat_map(|w| w.vertices.iter().map(move |v| w.surface_velocity(w.to_world(*v)).norm())).fold(0.0, f64::max);
        let e_star = self.materials.stiffest();
        let wall_contact = collision_time(rho_max, e_star, 0.5 * d_min, (speed_max + wall_speed).max(self.section.collision_speed));
        let pair_contact = collision_time(rho_max, e_star, 0.25 * d_min, (2.0 * speed_max).max(self.section.collision_speed));
        wall_contact.min(pair_contact)
    }

    /// Number of sub-steps for an outer step `dt` (T3.106, or the fixed `particles.substep`).
    pub fn substeps_for(&self, dt: f64, particles: &[Particle], walls: &WallState) -> u64 {
        match self.section.substep {
            Some(fixed) => substeps(dt, fixed, 1.0),
            None => substeps(dt, self.collision_time(particles, walls), self.section.steps_per_collision),
        }
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
        for (i, p) in particles.particles.iter_mut().enumerate() {
            p.velocity += 0.5 * dt * p.contact_force / p.mass();
            p.spin += 0.5 * dt * p.contact_torque / p.moment_of_inertia();
            let f = fluid(i, p);
            self.fluid_forces(i, p, f.as_ref(), 0.5 * dt);
            p.position += dt * p.velocity;
        }
        walls.place(end_time, rotor_end);
        self.evaluate_contacts(particles, walls, end_time, dt);
        for (i, p) in particles.particles.iter_mut().enumerate() {
            let f = fluid(i, p);
            self.fluid_forces(i, p, f.as_ref(), 0.5 * dt);
            p.velocity += 0.5 * dt * p.contact_force / p.mass();
            p.spin += 0.5 * dt * p.contact_torque / p.moment_of_inertia();
        }
    }

    /// The implicit fluid-force update of particle `i` over `dt` (§5.10), and, two-way coupled,
    /// its contribution to the step's load: ∫K dt and ∫(K u_p − F_AM − F_pg) dt (§8.4), with
    /// −∫V_p(ρ_p − ρ_c) g dt more for the literal feedback (§2.6).
    ///
    /// In a rotating frame (wear-model.md §2.6 [R]) the update adds −2Ω×u_p − Ω×(Ω×r) per unit
    /// particle mass. With a fluid (coupled, or the still `[particles.ambient]` fluid, at rest in
    /// the frame) the particle equation carries the pressure-gradient force, taken on the fluid's
    /// acceleration relative to an inertial frame, which supplies the centrifugal buoyancy
    /// ([`fluid_force_step_in_rotating_frame`]). Without any fluid (particle-only, no ambient)
    /// nothing supplies buoyancy and the full per-unit-mass form applies
    /// ([`dry_particle_update`]). Either way the Coriolis part is trapezoidal in u_p, which keeps
    /// the sub-step symmetric (and second order without drag).
    fn fluid_forces(&mut self, i: usize, p: &mut Particle, fluid: Option<&FluidAtParticle>, dt: f64) {
        let before = p.velocity.norm_squared();
        self.fluid_forces_update(i, p, fluid, dt);
        self.budget.external += 0.5 * p.mass() * (p.velocity.norm_squared() - before);
    }

    fn fluid_forces_update(&mut self, i: usize, p: &mut Particle, fluid: Option<&FluidAtParticle>, dt: f64) {
        let Some(fluid) = fluid else {
            match &self.rotating_frame {
                None => p.velocity += dt * self.gravity,
                Some(frame) => p.velocity = dry_particle_update(frame, p.velocity, p.position, self.gravity, dt),
            }
            return;
        };
        let step = match &self.rotating_frame {
            None => fluid_force_step(self.drag_law, p.velocity, p.diameter, p.density, fluid, self.gravity, dt),
            Some(frame) => fluid_force_step_in_rotating_frame(frame, self.drag_law, p.velocity, p.position, p.diameter, p.density, fluid, self.gravity, dt),
        };
        p.velocity = step.velocity;
        let Some(feedback) = self.feedback else { return };
        let load = &mut self.load;
        if i >= load.volume.len() {
            return;
        }
        let mut explicit = step.explicit_feedback();
        if feedback == Feedback::Literal {
            explicit -= p.volume() * (p.density - fluid.density) * self.gravity;
        }
        load.implicit_drag[i] += step.drag_factor * dt;
        for k in 0..3 {
            load.explicit_force[i][k] += explicit[k] * dt;
            load.drag[i][k] += step.drag[k] * dt;
        }
        load.slip_reynolds[i] = step.slip_reynolds;
    }

    /// Rebuilds the collision mesh of every wall that moved its vertices since (a receding wall,
    /// wear-model.md §7.4), so contacts see its worn shape.
    pub fn refresh_wall_meshes(&mut self, walls: &WallState) -> Result<(), SolverError> {
        for (i, w) in walls.walls.iter().enumerate() {
            if self.mesh_revisions[i] != w.revision {
                self.wall_meshes[i] = WallMesh::new(&w.vertices, &w.triangles).map_err(|m| unsupported(format!("worn wall `{}`: {m}", w.name)))?;
                self.mesh_revisions[i] = w.revision;
            }
        }
        Ok(())
    }

    /// Contact forces and torques at the current positions (fluid-dem-model.md §7.8).
    fn evaluate_contacts(&mut self, particles: &mut ParticleState, walls: &WallState, time: f64, dt: f64) {
        let mut impacts = Vec::new();
        let context = contacts::Context {
            materials: &self.materials,
            walls: &walls.walls,
            meshes: &self.wall_meshes,
            wet_fluid: self.wet_fluid,
            time,
            dt,
            fed_from: self.fed_from,
        };
        self.samples = contacts::evaluate(&context, &mut particles.particles, &mut self.history, &mut impacts, &mut self.watch);
        self.budget.walls += dt * self.watch.wall_power;
        self.budget.placed += self.watch.new_contact_energy;
        particles.counts.impacts += impacts.len() as u64;
        particles.impacts.extend(impacts);
    }
}

impl ReferenceDem {
    /// The step's energy balance ([`EnergyBudget`]): an error naming the particle whose kinetic
    /// energy grew most when the step created energy.
    /// `elastic_start`: the stored energy at the step's start when known without the last step
    /// (0 when no contact is in the history).
    fn check_energy(&mut self, ctx: &StepContext, particles: &[Particle], elastic_start: Option<f64>) -> Result<(), SolverError> {
        let budget = &mut self.budget;
        let (kinetic_start, kinetic_end): (f64, f64) = (budget.start.iter().sum(), particles.iter().map(|p| p.kinetic_energy()).sum());
        let elastic_end = self.watch.elastic_energy;
        let Some(elastic_start) = budget.elastic_end.replace(elastic_end).or(elastic_start) else { return Ok(()) };
        let supplied = budget.external + budget.walls + budget.placed;
        let gain = (kinetic_end + elastic_end) - (kinetic_start + elastic_start) - supplied;
        let at_collision_speed: f64 = particles.iter().map(|p| 0.5 * p.mass() * self.section.collision_speed.powi(2)).sum();
        let scale = kinetic_start + kinetic_end + elastic_start + elastic_end + budget.external.abs() + budget.walls.abs() + budget.placed + at_collision_speed;
        if gain <= ENERGY_GAIN_MAX * scale {
            return Ok(());
        }
        let worst = particles.iter().zip(&budget.start).max_by(|a, b| (a.0.kinetic_energy() - a.1).total_cmp(&(b.0.kinetic_energy() - b.1)));
        let culprit = worst.map_or(String::new(), |(p, start)| {
            format!(
                "; particle {} at [{:e}, {:e}, {:e}] m went from {start:.3e} J to {:.3e} J",
                p.id,
                p.position.x,
                p.position.y,
                p.position.z,
                p.kinetic_energy()
            )
        });
        Err(SolverError::Diverged {
            step: ctx.step,
            time: ctx.time_end(),
            what: format!(
                "the particles' kinetic energy grew from {kinetic_start:.3e} J to {kinetic_end:.3e} J, {gain:.3e} J more than gravity, the fluid, the moving walls and new contacts supplied ({supplied:.3e} J) and the contacts had stored ({elastic_start:.3e} J){culprit}"
            ),
        })
    }
}

impl ParticlePhase for ReferenceDem {
    fn name(&self) -> &'static str {
        "reference"
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
        self.load = ParticleLoad::zeros(if self.feedback.is_some() { particles.particles.len() } else { 0 });
        self.budget.start.clear();
        self.budget.start.extend(particles.particles.iter().map(|p| p.kinetic_energy()));
        (self.budget.external, self.budget.walls, self.budget.placed) = (0.0, 0.0, 0.0);
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
        self.check_energy(ctx, &particles.particles, elastic_start)?;
        self.fed_from = particles.next_id;
        self.store_history(particles);
        let max_overlap_ratio = self.samples.iter().map(|s| s.overlap / s.radius).fold(0.0, f64::max);
        report.values.extend([
            ("substeps", n as f64),
            ("contacts", self.samples.len() as f64),
            ("particle_kinetic_energy", particles.particles.iter().map(|p| p.kinetic_energy()).sum()),
            ("max_overlap_ratio", max_overlap_ratio),
        ]);
        if self.feedback.is_none() {
            return Ok(None);
        }
        // time averages over the step (§5.10: "accumulate the time average over the sub-steps")
        let mut load = std::mem::take(&mut self.load);
        for (i, p) in particles.particles.iter().enumerate() {
            load.volume[i] = p.volume();
            load.implicit_drag[i] /= ctx.dt;
            for k in 0..3 {
                load.explicit_force[i][k] /= ctx.dt;
                load.drag[i][k] /= ctx.dt;
            }
        }
        Ok(Some(load))
    }
}
