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
use spillage_model::closure::drag::{fluid_force_update, DragLaw, FluidAtParticle};
use spillage_model::particles::initial::{new_particle, place_without_overlap};
use spillage_model::particles::settings::{Diameter, ParticlesSection};
use spillage_model::particles::state::Vec3;
use spillage_model::particles::{initial_state, ContactRecord, Particle, ParticleState, Partner};
use spillage_model::solver::{Solver, SolverError, StepReport};
use spillage_model::state::State;
use spillage_model::walls::geometry::WallMesh;

pub use contacts::ContactSample;
use materials::MaterialTable;

/// Fluid seen by the particles: none, or per particle (coupling or a still ambient fluid).
pub type FluidSampler<'a> = &'a dyn Fn(&Particle) -> Option<FluidAtParticle>;

/// The reference DEM solver.
pub struct ReferenceDem {
    state: State,
    section: ParticlesSection,
    materials: MaterialTable,
    gravity: Vec3,
    /// Outer step [s] (time.dt).
    dt: f64,
    /// Rotor angular velocity, to keep `state.rotor_angle` current.
    rotor_omega: f64,
    wall_meshes: Vec<WallMesh>,
    /// Fluid density and viscosity for the wet restitution (T3.103), if wet.
    wet_fluid: Option<(f64, f64)>,
    drag_law: DragLaw,
    /// Contact history being worked on, keyed by (particle id, partner); several records per
    /// key only for a particle touching one wall in several places (a concave corner).
    history: BTreeMap<(u64, Partner), Vec<ContactRecord>>,
    /// Contacts of the last sub-step (diagnostics).
    samples: Vec<ContactSample>,
    last_substeps: u64,
}

fn unsupported(what: impl Into<String>) -> SolverError {
    SolverError::Unsupported(what.into())
}

impl ReferenceDem {
    /// Sets up the solver from a case and a state; missing particle or wall states are built from
    /// the case (walls with STL paths relative to the case file's folder).
    pub fn new(case: &Case, mut state: State) -> Result<Self, SolverError> {
        let section = case.particles.clone().ok_or_else(|| unsupported("the reference DEM needs a [particles] section"))?;
        let dt = case.time.dt.ok_or_else(|| unsupported("the reference DEM needs a fixed time.dt for its outer step"))?;
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
        let materials = MaterialTable::new(&section.materials, section.slip_test);
        let wet_fluid = match (&case.fluid, &section.ambient) {
            (Some(f), _) => Some((f.density, f.kinematic_viscosity)),
            (None, Some(a)) if a.wet_restitution => Some((a.density, a.kinematic_viscosity)),
            _ => None,
        };
        let drag_law = section.ambient.as_ref().map(|a| a.drag).unwrap_or_default();
        let history = Self::history_from_records(&state.particles.as_ref().expect("set above").contacts);
        let particles = state.particles.as_mut().expect("set above");
        if particles.feed_debt.len() != section.feed.len() {
            return Err(unsupported(format!("the state has {} feeds, the case {}", particles.feed_debt.len(), section.feed.len())));
        }
        Ok(Self {
            state,
            gravity: Vec3::from(case.physics.gravity),
            dt,
            rotor_omega: case.rotor.as_ref().map(|r| r.angular_velocity()).unwrap_or(0.0),
            wall_meshes,
            wet_fluid,
            drag_law,
            history,
            samples: Vec::new(),
            last_substeps: 0,
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

    /// The particles, sorted by id.
    pub fn particles(&self) -> &[Particle] {
        &self.particle_state().particles
    }

    pub fn particle_state(&self) -> &ParticleState {
        self.state.particles.as_ref().expect("the DEM always has a particle state")
    }

    fn particle_state_mut(&mut self) -> &mut ParticleState {
        self.state.particles.as_mut().expect("the DEM always has a particle state")
    }

    /// The contacts evaluated at the last sub-step.
    pub fn contact_samples(&self) -> &[ContactSample] {
        &self.samples
    }

    /// DEM sub-steps used in the last outer step.
    pub fn last_substeps(&self) -> u64 {
        self.last_substeps
    }

    /// Overrides the fluid used by the wet restitution law (the coupled solver sets its fluid).
    pub fn set_wet_fluid(&mut self, fluid: Option<(f64, f64)>) {
        self.wet_fluid = fluid;
    }

    /// The still ambient fluid of `[particles.ambient]` when it exerts forces.
    fn ambient_fluid(&self) -> Option<FluidAtParticle> {
        self.section.ambient.as_ref().filter(|a| a.forces).map(|a| FluidAtParticle::still(a.density, a.kinematic_viscosity))
    }

    /// Worst-case collision time (T3.105 as OpenFOAM evaluates it, §7.6): smallest radius,
    /// largest density, stiffest pair, largest speed |u| + |ω| r (plus the fastest wall
    /// surface), never below `collision_speed`; for pairs R = d_min/4 and the speed doubled.
    pub fn collision_time(&self) -> f64 {
        let particles = self.particles();
        if particles.is_empty() {
            return f64::INFINITY;
        }
        let d_min = particles.iter().map(|p| p.diameter).fold(f64::INFINITY, f64::min);
        let rho_max = particles.iter().map(|p| p.density).fold(0.0, f64::max);
        let speed_max = particles.iter().map(|p| p.velocity.norm() + p.spin.norm() * p.radius()).fold(0.0, f64::max);
        let walls = self.state.walls.as_ref().map(|w| w.walls.as_slice()).unwrap_or(&[]);
        let wall_speed = walls.iter().flat_map(|w| w.vertices.iter().map(move |v| w.surface_velocity(w.to_world(*v)).norm())).fold(0.0, f64::max);
        let e_star = self.materials.stiffest();
        let wall_contact = collision_time(rho_max, e_star, 0.5 * d_min, (speed_max + wall_speed).max(self.section.collision_speed));
        let pair_contact = collision_time(rho_max, e_star, 0.25 * d_min, (2.0 * speed_max).max(self.section.collision_speed));
        wall_contact.min(pair_contact)
    }

    /// Number of sub-steps for an outer step `dt` (T3.106, or the fixed `particles.substep`).
    pub fn substeps_for(&self, dt: f64) -> u64 {
        match self.section.substep {
            Some(fixed) => substeps(dt, fixed, 1.0),
            None => substeps(dt, self.collision_time(), self.section.steps_per_collision),
        }
    }

    /// Advances particles and walls by `dt` in DEM sub-steps; `fluid` gives the fluid each
    /// particle sees (held fixed over the step, §5.10), or `None` for a dry particle.
    /// Returns the number of sub-steps.
    pub fn advance(&mut self, dt: f64, fluid: FluidSampler<'_>) -> u64 {
        self.feed(dt);
        let n = self.substeps_for(dt);
        let dt_s = dt / n as f64;
        let t0 = self.state.time;
        for k in 0..n {
            self.substep(t0 + k as f64 * dt_s, dt_s, fluid);
        }
        self.remove_escaped();
        self.store_history();
        self.last_substeps = n;
        n
    }

    /// One DEM sub-step from time `t` (velocity Verlet, §5.10): half-kick with the stored contact
    /// force and torque, half the fluid-force update, move, new contact forces, the other half
    /// of the fluid update, second half-kick. The fluid update is split symmetrically so the
    /// step stays second order and symplectic for conservative forces (gravity).
    pub fn substep(&mut self, t: f64, dt: f64, fluid: FluidSampler<'_>) {
        let gravity = self.gravity;
        let law = self.drag_law;
        let kick_and_fluid = |p: &mut Particle| {
            p.velocity += 0.5 * dt * p.contact_force / p.mass();
            p.spin += 0.5 * dt * p.contact_torque / p.moment_of_inertia();
            let f = fluid(p);
            p.velocity = fluid_force_update(law, p.velocity, p.diameter, p.density, f.as_ref(), gravity, 0.5 * dt);
        };
        for p in &mut self.particle_state_mut().particles {
            kick_and_fluid(p);
            p.position += dt * p.velocity;
        }
        if let Some(walls) = self.state.walls.as_mut() {
            for w in &mut walls.walls {
                w.advance(dt);
            }
        }
        self.evaluate_contacts(t + dt, dt);
        for p in &mut self.particle_state_mut().particles {
            let f = fluid(p);
            p.velocity = fluid_force_update(law, p.velocity, p.diameter, p.density, f.as_ref(), gravity, 0.5 * dt);
            p.velocity += 0.5 * dt * p.contact_force / p.mass();
            p.spin += 0.5 * dt * p.contact_torque / p.moment_of_inertia();
        }
    }

    /// Contact forces and torques at the current positions (fluid-dem-model.md §7.8).
    fn evaluate_contacts(&mut self, time: f64, dt: f64) {
        let mut particles = std::mem::take(&mut self.particle_state_mut().particles);
        let mut impacts = Vec::new();
        let context = contacts::Context {
            materials: &self.materials,
            walls: self.state.walls.as_ref().map(|w| w.walls.as_slice()).unwrap_or(&[]),
            meshes: &self.wall_meshes,
            wet_fluid: self.wet_fluid,
            time,
            dt,
        };
        self.samples = contacts::evaluate(&context, &mut particles, &mut self.history, &mut impacts);
        let state = self.particle_state_mut();
        state.particles = particles;
        state.impacts.extend(impacts);
    }

    /// Creates fed particles owed for this step (rate × dt, carried over when not yet placeable).
    fn feed(&mut self, dt: f64) {
        let time = self.state.time;
        let section = self.section.clone();
        let state = self.particle_state_mut();
        for (f, feed) in section.feed.iter().enumerate() {
            let active = time >= feed.start && feed.end.is_none_or(|end| time < end);
            if !active {
                continue;
            }
            state.feed_debt[f] += feed.rate * dt;
            let material = section.material_index(&feed.material).expect("validated feed material");
            while state.feed_debt[f] >= 1.0 {
                let d = match feed.diameter {
                    Diameter::Fixed(d) => d,
                    Diameter::Uniform { min, max } => state.feed_random[f].uniform(min, max),
                };
                let mut random = state.feed_random[f].clone();
                let Some(position) = place_without_overlap(&feed.region, d, &state.particles, &mut random) else { break };
                state.feed_random[f] = random;
                let particle = new_particle(&section, state, material, d, position, Vec3::from(feed.velocity));
                state.particles.push(particle);
                state.counts.created += 1;
                state.feed_debt[f] -= 1.0;
            }
        }
    }

    /// Removes particles whose centre left `particles.domain`.
    fn remove_escaped(&mut self) {
        let Some(domain) = self.section.domain.clone() else { return };
        let state = self.particle_state_mut();
        let before = state.particles.len();
        let mut gone = Vec::new();
        state.particles.retain(|p| {
            let inside = domain.contains([p.position.x, p.position.y, p.position.z]);
            if !inside {
                gone.push(p.id);
            }
            inside
        });
        state.counts.escaped += (before - state.particles.len()) as u64;
        if !gone.is_empty() {
            self.history.retain(|(id, partner), _| !gone.contains(id) && !matches!(partner, Partner::Particle(j) if gone.contains(j)));
        }
    }

    /// Writes the working contact history into the state (sorted, for checkpoints).
    fn store_history(&mut self) {
        let records: Vec<ContactRecord> = self.history.values().flatten().cloned().collect();
        self.particle_state_mut().contacts = records;
    }

    /// Total kinetic energy (translation + rotation) [J].
    pub fn kinetic_energy(&self) -> f64 {
        self.particles().iter().map(|p| p.kinetic_energy()).sum()
    }
}

impl Solver for ReferenceDem {
    fn name(&self) -> &'static str {
        "reference"
    }

    /// One outer step of `time.dt` containing the DEM sub-steps (particles-only cases; the
    /// particles feel `[particles.ambient]` if it exerts forces, else gravity only).
    fn step_into(&mut self, report: &mut StepReport) -> Result<(), SolverError> {
        let ambient = self.ambient_fluid();
        let sampler = move |_: &Particle| ambient;
        let n = self.advance(self.dt, &sampler);
        self.state.time += self.dt;
        self.state.step += 1;
        self.state.dt = self.dt;
        self.state.rotor_angle += self.rotor_omega * self.dt;
        if let Some(p) = self.particles().iter().find(|p| !(p.position.iter().chain(p.velocity.iter()).all(|v| v.is_finite()))) {
            return Err(SolverError::Diverged { step: self.state.step, time: self.state.time, what: format!("particle {} has a non-finite position or velocity", p.id) });
        }
        let particles = self.particle_state();
        let max_overlap_ratio = self.samples.iter().map(|s| s.overlap / s.radius).fold(0.0, f64::max);
        *report = StepReport {
            values: vec![
                ("substeps", n as f64),
                ("particles", particles.particles.len() as f64),
                ("escaped", particles.counts.escaped as f64),
                ("contacts", self.samples.len() as f64),
                ("kinetic_energy", self.kinetic_energy()),
                ("max_overlap_ratio", max_overlap_ratio),
                ("impacts", particles.impacts.len() as f64),
            ],
        };
        Ok(())
    }

    fn state(&self) -> &State {
        &self.state
    }
}
