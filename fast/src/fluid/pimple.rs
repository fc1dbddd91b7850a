//! [`FastFluid`]: one PIMPLE step per call, the algorithm of the reference solver (module doc
//! of `spillage_reference::fluid`, steps 1–5) on struct-of-arrays fields with iterative solves.
//! [`FastFluid::advance`] reads top to bottom as the algorithm; each stage is a free kernel in
//! its own module, called with named inputs:
//!
//! 1. rotor: the zone turned to the step's rotor pose, its faces moved in place ([`FastFluid::turn_rotor`]);
//! 2. geometry: overlap links of the new position, orthogonality, buffer sizes (here);
//! 3. [`starting_values`]: u*, P*, φ*, the time-derivative flux correction, boundary data;
//! 4. outer loop: [`momentum::boundary_velocities`], ∇u, [`momentum::assemble`],
//!    [`momentum::predict`], [`pressure_corrector::correct`] × `piso_correctors`, convergence;
//! 5. [`diagnostics::step_diagnostics`], [`finish_step`]: state update and report.

use spillage_model::case::Case;
use spillage_model::closure::rotating_frame::RotatingFrame;
use spillage_model::coupling::CellLoad;
use spillage_model::fluid::conditions::Conditions;
use spillage_model::fluid::frozen_rotor::FrozenRotor;
use spillage_model::fluid::initial::prepare_fluid_state;
use spillage_model::fluid::sampling::FluidSample;
use spillage_model::fluid::settings::{LimiterUpdate, NumericsSection};
use spillage_model::fluid::state::FluidState;
use spillage_model::mesh::{Mesh, Overlap, PatchKind, Vec3};
use spillage_model::solver::{SolverError, StepReport};
use spillage_model::state::State;
use spillage_model::step::{FluidPhase, FluidStepOutcome, RotorPose, StepContext};
use spillage_model::walls::state::WallState;
use spillage_model::wear::fluid_mesh::MeshFollowing;

use super::buffers::StepBuffers;
use super::diagnostics::step_diagnostics;
use super::finish_step::{shift_time_levels, write_report, StepTotals};
use super::interface::{push_overlaps, Frame};
use super::layout::{solved_components, Adjacency, Boundary, Links, Rotor};
use super::momentum::{self, MomentumInputs, MomentumSolve};
use super::pressure_corrector::{self, CorrectorFields, CorrectorInputs, PressureSolver};
use super::settings::{FastSettings, SolveCounts};
use super::starting_values::{
    balance_suction, boundary_starting_values, ddt_flux_corrections, starting_link_fluxes, time_levels_from_state, BoundaryStart, MovedCells, OldLevels,
};
use super::step_inputs::{Discretisation, ParticleSources, StepConstants, StepSolution, TimeStep, VolumeFractions};
use super::turbulence::{FastTurbulence, TurbulenceInputs};
use crate::linear::bicgstab::BiCgStab;
use crate::linear::reduce::Reducer;
use spillage_model::turbulence::Viscosity;

/// The fast fluid solver, a fluid phase of the step driver ([`spillage_model::step::Coupled`]).
pub struct FastFluid {
    mesh: Mesh,
    /// The fluid state being advanced: swapped in from the driver's state for the duration of
    /// a step ([`FluidPhase::advance`]; a swap of vectors, no copy), empty between steps.
    fluid: FluidState,
    /// Step number and tⁿ⁺¹ of the step being taken (error messages).
    step_number: u64,
    step_time_end: f64,
    /// Time coefficients of the step being taken.
    time_coefficients: [f64; 3],
    /// Δt of the last step (sampling's local acceleration).
    dt_old: f64,
    conditions: Conditions,
    numerics: NumericsSection,
    /// Kinematic viscosity ν [m²/s] and density ρ [kg/m³].
    nu: f64,
    density: f64,
    /// Kinematic body force (gravity + `[numerics] body_force`) [m/s²].
    body_force: Vec3,
    /// The case's rotating frame (wear-model.md §2.6), if any.
    rotating_frame: Option<RotatingFrame>,
    /// The frame term of the step being taken if it is a frozen-rotor step.
    frozen_rotor: Option<FrozenRotor>,
    rotor: Option<Rotor>,
    /// Axis frame of the sliding interfaces (the rotating zone's rotation).
    frame: Option<Frame>,
    /// Δt of the step being taken.
    dt: f64,
    settings: FastSettings,
    /// Per cell: whether it belongs to the rotor zone.
    in_rotor: Vec<bool>,
    /// Internal faces of the rotor zone (their geometry is updated in place every step).
    moving_faces: Vec<usize>,
    links: Links,
    /// Overlap buffer of the sliding interfaces (reused every step).
    overlaps: Vec<Overlap>,
    boundary: Boundary,
    adjacency: Adjacency,
    /// Velocity components solved (false along the normal of empty patches: 2-D meshes).
    solved: [bool; 3],
    buffers: StepBuffers,
    /// The particle load of the step being taken, kinematic, and whether there is one.
    particle_sources: ParticleSources,
    particles_active: bool,
    momentum_solver: BiCgStab,
    pressure_solver: PressureSolver,
    reducer: Reducer,
    counts: SolveCounts,
    /// Whether every link's non-orthogonal part is negligible ([`Links::all_orthogonal`]);
    /// `None` before the first step's geometry.
    orthogonal: Option<bool>,
    /// The k–ε model (`[turbulence] model = "realizable-k-epsilon"`), `None` for laminar flow.
    turbulence: Option<FastTurbulence>,
    /// The receding wall the mesh follows (`[wear.fluid_mesh]`), if any.
    follower: Option<MeshFollowing>,
}

fn unsupported(msg: impl Into<String>) -> SolverError {
    SolverError::Unsupported(msg.into())
}

impl FastFluid {
    /// Sets up the solver for `case` on `mesh` (as `ReferenceFluid::new`: without a fluid state
    /// the fluid starts from the case's initial velocity, zero pressure, α_c = 1).
    /// Missing parts of `state` (the fluid) are filled in.
    pub fn new(case: &Case, mesh: Mesh, state: &mut State) -> Result<Self, SolverError> {
        let fluid = case.fluid.as_ref().ok_or_else(|| unsupported("the case has no [fluid] section"))?;
        let conditions = Conditions::from_case(case, &mesh, fluid.density)?;
        let numerics = case.numerics.clone();
        let body_force = numerics.kinematic_body_force(case.physics.gravity);
        let rotating_frame = RotatingFrame::of_physics(&case.physics).map_err(|e| unsupported(format!("`{}` = {}: expected {}", e.key, e.value, e.allowed)))?;
        let frame = mesh.rotating_zone_axis().map(|(axis, origin)| Frame::new(origin, axis));
        let rotor = Rotor::from_case(case, &mesh).map_err(unsupported)?;
        let has_interface_patch = mesh.patches.iter().any(|p| matches!(p.kind, PatchKind::Interface { .. }));
        if has_interface_patch && (mesh.interfaces.is_empty() || frame.is_none()) {
            return Err(unsupported(
                "the mesh has interface patches but no cylindrical sliding-interface description (the fast solver needs the shared z layers)",
            ));
        }

        let n = mesh.n_cells();
        prepare_fluid_state(state, case, &mesh).map_err(unsupported)?;
        let mut mesh = mesh;
        // a mesh that follows a receding wall, where the state left it (spillage_model::wear::fluid_mesh)
        let fluid_state = state.fluid.as_mut().expect("prepared above");
        let follower = MeshFollowing::from_case(case, &mut mesh, state.walls.as_ref(), fluid_state, state.dt).map_err(unsupported)?;
        let mut rotor = rotor;
        if let Some(r) = rotor.as_mut() {
            // the rotor where the state left it, before the link geometry is built from the mesh
            let pose = RotorPose { angle: state.rotor_angle, ..r.pose };
            r.place(&mut mesh, &pose).map_err(unsupported)?;
        }
        let mut in_rotor = vec![false; n];
        let mut moving_faces = Vec::new();
        if let Some(r) = &rotor {
            for &c in &mesh.zones[r.zone].cells {
                in_rotor[c] = true;
            }
            moving_faces = mesh.zones[r.zone].faces.iter().copied().filter(|&f| f < mesh.n_internal_faces).collect();
        }
        let links = Links::from_internal_faces(&mesh, rotor.as_ref(), &in_rotor);
        let boundary = Boundary::build(&mesh, &conditions, rotor.as_ref(), &in_rotor);
        let solved = solved_components(&mesh);
        let turbulence = case.turbulence.is_k_epsilon().then(|| FastTurbulence::new(case.turbulence.clone(), conditions.wall_patch_names(&mesh)));
        // a deforming mesh aggregates each step's hierarchy afresh, as a turning one: one
        // aggregated on the geometry of the run's start would differ after a restart
        let pressure_solver = if rotor.is_some() || follower.is_some() { PressureSolver::default() } else { PressureSolver::on_a_fixed_mesh() };
        let mut solver = FastFluid {
            mesh,
            fluid: FluidState::default(),
            step_number: state.step,
            step_time_end: state.time,
            time_coefficients: [1.0, -1.0, 0.0],
            dt_old: state.dt,
            conditions,
            numerics,
            nu: fluid.kinematic_viscosity,
            density: fluid.density,
            body_force,
            rotating_frame,
            frozen_rotor: None,
            rotor,
            frame,
            dt: 0.0,
            settings: FastSettings::from_numerics(&case.numerics),
            in_rotor,
            moving_faces,
            links,
            overlaps: Vec::new(),
            boundary,
            adjacency: Adjacency::default(),
            solved,
            buffers: StepBuffers::default(),
            particle_sources: ParticleSources::default(),
            particles_active: false,
            momentum_solver: BiCgStab::default(),
            pressure_solver,
            reducer: Reducer::default(),
            counts: SolveCounts::default(),
            orthogonal: None,
            turbulence,
            follower,
        };
        if solver.follower.is_some() {
            solver.refresh_deformed_geometry();
        }
        solver.rebuild_overlaps();
        solver.resize_buffers();
        Ok(solver)
    }

    /// Replaces the linear-solver controls.
    pub fn with_settings(mut self, settings: FastSettings) -> Self {
        self.settings = settings;
        self
    }

    pub fn settings(&self) -> FastSettings {
        self.settings
    }

    /// (rows, off-diagonal entries, colours) of the pressure multigrid levels (diagnostics).
    pub fn pressure_levels(&self) -> Vec<(usize, usize, usize)> {
        self.pressure_solver.level_sizes()
    }

    /// Iteration counts of the last step.
    pub fn last_counts(&self) -> SolveCounts {
        self.counts
    }

    /// Overlap links of the current rotor position and the adjacency of all links.
    fn rebuild_overlaps(&mut self) {
        self.links.clear_overlaps();
        if let Some(frame) = &self.frame {
            for interface in &self.mesh.interfaces {
                let angle = self.mesh.zones[interface.rotor_zone].rotation.as_ref().map_or(0.0, |r| r.angle);
                push_overlaps(&self.mesh, interface, frame, angle, self.rotor.as_ref(), &mut self.overlaps, &mut self.links);
            }
        }
        self.adjacency.rebuild(self.mesh.n_cells(), &self.links);
    }

    fn resize_buffers(&mut self) {
        self.buffers.resize(self.mesh.n_cells(), self.boundary.len(), self.links.len(), self.mesh.n_faces(), &self.adjacency);
    }

    /// Stage 2: the link geometry of the new position. Overlap links rebuilt (every step with a
    /// turning rotor), orthogonality re-measured and the neighbours across boundary faces
    /// re-found whenever links may have changed, buffers sized for the link count.
    fn update_geometry(&mut self) {
        if self.frame.is_some() && (self.rotor.is_some() || self.links.len() == self.links.n_internal) {
            self.rebuild_overlaps();
        }
        // link geometry changes on the first step and whenever the rotor or the overlaps move
        let geometry_changed = self.orthogonal.is_none() || self.rotor.is_some() || self.frame.is_some() || self.follower.is_some();
        if geometry_changed {
            self.orthogonal = Some(self.links.all_orthogonal());
        }
        self.resize_buffers();
        if geometry_changed {
            self.boundary.update_across(&self.links, &self.adjacency);
        }
    }

    /// Stage 1: turns the rotor zone to the pose's angle (from its reference geometry), takes
    /// the pose's motion and moves the zone's faces and boundary faces in place.
    /// Nothing to do when the zone is at `pose` already (the driver places it before sampling).
    fn turn_rotor(&mut self, pose: Option<&RotorPose>) -> Result<(), SolverError> {
        if let (Some(r), Some(pose)) = (self.rotor.as_mut(), pose) {
            if r.pose == *pose {
                return Ok(());
            }
            r.place(&mut self.mesh, pose).map_err(unsupported)?;
            for &f in &self.moving_faces {
                self.links.update_face(&self.mesh, f, self.rotor.as_ref(), &self.in_rotor);
            }
            self.boundary.update(&self.mesh, self.rotor.as_ref(), &self.in_rotor);
        }
        Ok(())
    }

    /// A mesh that follows a receding wall, moved: every link and boundary face takes the mesh's
    /// moved geometry and the step's face mesh fluxes (swept volume · c₀/Δt).
    fn refresh_deformed_geometry(&mut self) {
        let Some(following) = &self.follower else { return };
        let flux = following.face_mesh_flux();
        for f in 0..self.mesh.n_internal_faces {
            self.links.update_face(&self.mesh, f, None, &self.in_rotor);
            self.links.mesh_flux[f] += flux[f];
        }
        self.boundary.update(&self.mesh, None, &self.in_rotor);
        for (mesh_flux, &f) in self.boundary.mesh_flux.iter_mut().zip(&self.boundary.face) {
            *mesh_flux += flux[f as usize];
        }
    }

    fn advance_timed(&mut self, report: &mut StepReport) -> Result<FluidStepOutcome, SolverError> {
        let clock = std::time::Instant::now();
        let result = self.advance_inner(report);
        self.counts.step_seconds = clock.elapsed().as_secs_f64();
        result
    }

    /// One time step, steps 2–5 of the algorithm (module doc of `spillage_reference::fluid`;
    /// step 1, the rotor, is [`FastFluid::turn_rotor`], called by [`FluidPhase::advance`]).
    fn advance_inner(&mut self, report: &mut StepReport) -> Result<FluidStepOutcome, SolverError> {
        let time = TimeStep { dt: self.dt, coefficients: self.time_coefficients };

        // 2. geometry of the new position
        self.update_geometry();
        if let Some(suction) = self.conditions.suction_condition() {
            balance_suction(&self.boundary, &mut self.conditions, suction, self.rotor.as_ref(), &self.fluid, &self.mesh.cell_volumes, time)?;
        }

        // 3. starting values
        let fluid = &self.fluid;
        let b = &mut self.buffers;
        let moved = MovedCells { rotor_turns: self.rotor.is_some(), mesh_deforms: self.follower.is_some(), in_rotor: &self.in_rotor };
        time_levels_from_state(fluid, &mut b.velocity, &mut b.velocity_old, &mut b.velocity_old_old, &mut b.pressure);
        starting_link_fluxes(&self.links, moved, &fluid.flux, &b.velocity, &mut b.link_flux);
        let old = OldLevels {
            velocity_old: &b.velocity_old,
            velocity_old_old: &b.velocity_old_old,
            alpha_old: &fluid.alpha_old,
            alpha_old_old: &fluid.alpha_old_old,
            flux_old: &fluid.flux,
            flux_old_old: &fluid.flux_old,
        };
        ddt_flux_corrections(&self.links, moved, self.numerics.ddt_flux_correction, time, old, &mut b.ddt_flux_correction);
        let boundary_start = BoundaryStart {
            boundary_pressure: &mut b.boundary_pressure,
            fixed_velocity: &mut b.fixed_boundary_velocity,
            prescribed_flux: &mut b.prescribed_boundary_flux,
            boundary_flux: &mut b.boundary_flux,
        };
        boundary_starting_values(&self.boundary, &self.conditions, self.rotor.as_ref(), fluid, self.mesh.n_internal_faces, boundary_start);

        // 4. outer (SIMPLE) loop
        let disc = Discretisation {
            links: &self.links,
            adjacency: &self.adjacency,
            boundary: &self.boundary,
            cell_volumes: &self.mesh.cell_volumes,
            cell_volumes_old: self.follower.as_ref().map_or(&self.mesh.cell_volumes, |f| f.volumes_old()),
            deforming: self.follower.is_some(),
            cell_centres: &self.mesh.cell_centres,
            conditions: &self.conditions,
            solved: self.solved,
            particles_in_turning_cells: (self.rotor.is_some() || self.follower.is_some()) && self.particles_active,
        };
        // field by field, so that the turbulence state stays free to be updated after the loop
        let alpha = VolumeFractions { current: &self.fluid.alpha, old: &self.fluid.alpha_old, old_old: &self.fluid.alpha_old_old };
        let viscosity = match (&self.turbulence, &self.fluid.turbulence) {
            (Some(_), Some(t)) => t.viscosity(self.nu),
            _ => Viscosity::Uniform(self.nu),
        };
        let particles = self.particles_active.then_some(&self.particle_sources);
        let step = StepConstants { disc, time, alpha, numerics: &self.numerics, particles };
        self.counts = SolveCounts::default();
        self.pressure_solver.new_step();
        let mut outer_iterations = 0;
        let (mut first_outer_residual, mut last_residual) = (f64::NAN, f64::NAN);
        let limiter_per_step = self.numerics.limiter_update == LimiterUpdate::TimeStep;
        for _outer in 0..self.numerics.max_outer_iterations {
            outer_iterations += 1;
            // a. boundary velocities and ∇u*
            momentum::boundary_velocities(&disc, &b.fixed_boundary_velocity, &b.velocity, &mut b.boundary_velocity);
            disc.vector_gradient(&b.velocity, &b.boundary_velocity, &mut b.velocity_gradient);
            if limiter_per_step && outer_iterations == 1 {
                for (kept, u) in b.limiter_velocity.iter_mut().zip(&b.velocity) {
                    kept.clone_from(u);
                }
                b.limiter_gradient.clone_from(&b.velocity_gradient);
            }
            // b. momentum matrix
            let momentum_inputs = MomentumInputs {
                step,
                viscosity,
                body_force: self.body_force,
                rotating_frame: self.rotating_frame.as_ref(),
                cell_centres: &self.mesh.cell_centres,
                frozen_rotor: self.frozen_rotor,
                in_rotor: &self.in_rotor,
                velocity: &b.velocity,
                velocity_old: &b.velocity_old,
                velocity_old_old: &b.velocity_old_old,
                velocity_gradient: &b.velocity_gradient,
                limiter_velocity: if limiter_per_step { &b.limiter_velocity } else { &b.velocity },
                limiter_gradient: if limiter_per_step { &b.limiter_gradient } else { &b.velocity_gradient },
                boundary_velocity: &b.boundary_velocity,
                link_flux: &b.link_flux,
                boundary_flux: &b.boundary_flux,
            };
            momentum::assemble(&momentum_inputs, &mut b.momentum_links, &mut b.momentum);
            // c. predictor M u = b − V∇P*
            disc.scalar_gradient(&b.pressure, &b.boundary_pressure, &mut b.pressure_gradient);
            let solve = MomentumSolve { solver: &mut self.momentum_solver, tolerance: self.settings.momentum, counts: &mut self.counts };
            momentum::predict(&disc, &b.momentum, &b.pressure_gradient, &mut b.momentum_rhs, &mut b.velocity, solve)?;
            // d. PISO correctors
            let corrector_inputs = CorrectorInputs {
                step,
                orthogonal: self.orthogonal == Some(true),
                momentum: &b.momentum,
                ddt_flux_correction: &b.ddt_flux_correction,
                prescribed_boundary_flux: &b.prescribed_boundary_flux,
                velocity_gradient: &b.velocity_gradient,
                tolerance: self.settings.pressure,
            };
            let mut first_residual = f64::NAN;
            for corrector in 0..self.numerics.piso_correctors {
                let fields = CorrectorFields {
                    velocity: &mut b.velocity,
                    pressure: &mut b.pressure,
                    boundary_pressure: &mut b.boundary_pressure,
                    pressure_gradient: &mut b.pressure_gradient,
                    link_flux: &mut b.link_flux,
                    boundary_flux: &mut b.boundary_flux,
                };
                let residual = pressure_corrector::correct(&corrector_inputs, fields, &mut b.corrector, &mut self.pressure_solver, &mut self.counts)?;
                if corrector == 0 {
                    first_residual = residual;
                }
            }
            // e. convergence
            last_residual = first_residual;
            if outer_iterations == 1 {
                first_outer_residual = first_residual;
            }
            let finite = b.velocity.iter().all(|c| c.iter().all(|x| x.is_finite()));
            if !first_residual.is_finite() || !finite {
                return Err(SolverError::Diverged { step: self.step_number, time: self.step_time_end, what: "non-finite velocity or pressure".into() });
            }
            if first_residual < self.numerics.p_initial_residual {
                break;
            }
        }

        // 5. diagnostics (before the time levels shift: ∂α/∂t uses this step's levels), state update, report
        let solution = StepSolution {
            velocity: &b.velocity,
            pressure: &b.pressure,
            boundary_pressure: &b.boundary_pressure,
            link_flux: &b.link_flux,
            boundary_flux: &b.boundary_flux,
        };
        let diagnostics = step_diagnostics(&disc, time, alpha, solution, &mut b.diagnostics, &mut self.reducer);
        // turbulence, once per step after the outer loop (spec §8.7 Algorithm 1 line 25), from
        // the final velocity and fluxes, before the α levels shift
        if let Some(model) = self.turbulence.as_mut() {
            momentum::boundary_velocities(&disc, &b.fixed_boundary_velocity, &b.velocity, &mut b.boundary_velocity);
            disc.vector_gradient(&b.velocity, &b.boundary_velocity, &mut b.velocity_gradient);
            let inputs = TurbulenceInputs {
                disc,
                time,
                alpha,
                nu: self.nu,
                velocity: &b.velocity,
                boundary_velocity: &b.boundary_velocity,
                velocity_gradient: &b.velocity_gradient,
                link_flux: &b.link_flux,
                boundary_flux: &b.boundary_flux,
                tolerance: self.settings.momentum,
                step: self.step_number,
                time_end: self.step_time_end,
            };
            model.correct(&inputs, self.fluid.turbulence.as_mut())?;
        }
        let fluid = &mut self.fluid;
        shift_time_levels(fluid, &self.links, &self.boundary, self.mesh.n_internal_faces, solution, &mut b.diagnostics, diagnostics.continuity_global);
        let continuity_cumulative = fluid.cumulative_continuity_error;
        self.dt_old = time.dt;
        let totals = StepTotals { continuity_cumulative, outer_iterations, p_initial_residual: last_residual };
        write_report(report, &diagnostics, &totals);
        if let Some(model) = &self.turbulence {
            report.values.extend_from_slice(model.values());
        }
        Ok(FluidStepOutcome {
            courant_max: diagnostics.courant_max,
            outer_iterations,
            outer_capped: outer_iterations >= self.numerics.max_outer_iterations && !(last_residual < self.numerics.p_initial_residual),
            first_residual: first_outer_residual,
            last_residual,
            under_relaxed: self.numerics.relax_velocity < 1.0 || self.numerics.relax_pressure < 1.0,
        })
    }
}

impl FluidPhase for FastFluid {
    fn name(&self) -> &'static str {
        "fast"
    }

    fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    fn place_rotor(&mut self, pose: Option<&RotorPose>) -> Result<(), SolverError> {
        self.turn_rotor(pose)
    }

    /// Allocation-free once `report` has held one step's values.
    fn advance(
        &mut self,
        ctx: &StepContext,
        fluid: &mut FluidState,
        load: Option<&CellLoad>,
        report: &mut StepReport,
    ) -> Result<FluidStepOutcome, SolverError> {
        self.particles_active = load.is_some();
        if let Some(load) = load {
            self.particle_sources.set(load, self.density);
        }
        self.dt = ctx.dt;
        self.time_coefficients = ctx.time_coefficients;
        self.step_number = ctx.step;
        self.step_time_end = ctx.time_end();
        self.frozen_rotor = FrozenRotor::of_step(ctx);
        // 1. rotor (a mesh that follows a receding wall was moved by `follow_walls`)
        self.turn_rotor(ctx.rotor.as_ref())?;
        if let Some(following) = &self.follower {
            following.check_moved().map_err(unsupported)?;
        }
        std::mem::swap(&mut self.fluid, fluid);
        // Called from outside the thread pool, every parallel loop of the step would be handed
        // to a worker and waited for (a cross-thread wake-up per loop, hundreds per step);
        // running the whole step on a worker hands over once. Same arithmetic either way.
        let result = if rayon::current_thread_index().is_some() { self.advance_timed(report) } else { rayon::scope(|_| self.advance_timed(report)) };
        std::mem::swap(&mut self.fluid, fluid);
        if let (Some(following), Ok(_)) = (self.follower.as_mut(), &result) {
            following.finish_step(fluid);
        }
        result
    }

    fn rewind(&mut self, dt_old: f64) {
        self.dt_old = dt_old;
        if let Some(following) = self.follower.as_mut() {
            following.rewind(&mut self.mesh);
            self.refresh_deformed_geometry();
        }
    }

    fn follow_walls(&mut self, ctx: &StepContext, walls: &WallState, fluid: &FluidState) -> Result<(), SolverError> {
        if let Some(following) = self.follower.as_mut() {
            following.move_for_step(&mut self.mesh, walls, &fluid.mesh_displacement, ctx.time_coefficients, ctx.dt).map_err(unsupported)?;
            self.refresh_deformed_geometry();
        }
        Ok(())
    }

    fn sample_source<'a>(&'a self, fluid: &'a FluidState) -> FluidSample<'a> {
        let deforming_flux = self.follower.as_ref().map_or(&[][..], |f| f.finished_mesh_flux());
        FluidSample {
            mesh: &self.mesh,
            rotor: self.rotor.as_ref(),
            fluid,
            density: self.density,
            kinematic_viscosity: self.nu,
            dt_old: self.dt_old,
            deforming_flux,
        }
    }

    /// ½ Σ_f |φ_f − φ_mesh,f| / V per second, with the interpolated cell velocities on every link.
    fn courant_rate(&self, fluid: &FluidState) -> f64 {
        let links = &self.links;
        let bnd = &self.boundary;
        let mut sum = vec![0.0; self.mesh.n_cells()];
        let u = |c: usize| Vec3::from(fluid.velocity[c]);
        for l in 0..links.len() {
            let (p, q) = (links.owner[l] as usize, links.neighbour[l] as usize);
            let wt = links.weight[l];
            let relative = ((u(p) * wt + u(q) * (1.0 - wt)).dot(&links.area[l]) - links.mesh_flux[l]).abs();
            sum[p] += relative;
            sum[q] += relative;
        }
        for b in 0..bnd.len() {
            let face = bnd.face[b] as usize;
            let c = self.mesh.face_owner[face];
            sum[c] += (fluid.flux[face] - bnd.mesh_flux[b]).abs();
        }
        sum.iter().zip(&self.mesh.cell_volumes).map(|(s, v)| 0.5 * s / v).fold(0.0, f64::max)
    }
}
