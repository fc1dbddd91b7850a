//! The [`ReferenceFluid`] time stepper: one PIMPLE step per call (algorithm in the module doc).

use spillage_model::case::Case;
use spillage_model::closure::rotating_frame::RotatingFrame;
use spillage_model::coupling::CellLoad;
use spillage_model::cutter_head::mouth::balancing_speed;
use spillage_model::fluid::conditions::fluid_volume_rate;
use spillage_model::fluid::frozen_rotor::FrozenRotor;
use spillage_model::fluid::initial::prepare_fluid_state;
use spillage_model::fluid::moving_cells::particle_share_of_mesh_flux;
use spillage_model::fluid::sampling::FluidSample;
use spillage_model::fluid::settings::{LimiterUpdate, NumericsSection};
use spillage_model::fluid::state::FluidState;
use spillage_model::mesh::{Mesh, Vec3};
use spillage_model::solver::{SolverError, StepReport};
use spillage_model::state::State;
use spillage_model::step::{FluidPhase, FluidStepOutcome, RotorPose, StepContext};
use spillage_model::walls::state::WallState;
use spillage_model::wear::fluid_mesh::MeshFollowing;

use super::boundary::{self, Conditions};
use super::diagnostics;
use super::geometry::{Geometry, LinkOrigin, RotorMotion};
use super::gradient::vector_gradient;
use super::interface::interface_links;
use super::momentum::{self, StepInputs};
use super::pressure::{self, CorrectorFields};
use super::turbulence::{self, TurbulenceInputs, TurbulenceModel};

/// The reference fluid solver, a fluid phase of the step driver
/// ([`spillage_model::step::Coupled`]): volume-averaged, with α_c from the state and the
/// particle load from the driver (spec §8.4, §8.5).
pub struct ReferenceFluid {
    mesh: Mesh,
    conditions: Conditions,
    numerics: NumericsSection,
    nu: f64,
    density: f64,
    body_force: Vec3,
    /// The case's rotating frame (wear-model.md §2.6), if any.
    rotating_frame: Option<RotatingFrame>,
    /// The rotor zone and its motion at the pose of the current step.
    rotor: Option<RotorMotion>,
    /// Axis and origin of the sliding interfaces (the rotor zone's rotation).
    interface_axis: Option<(Vec3, Vec3)>,
    /// Δt of the last step (sampling's local acceleration).
    dt_old: f64,
    /// `[turbulence] model`: the effective viscosity and its transport equations.
    turbulence: Box<dyn TurbulenceModel>,
    /// The receding wall the mesh follows (`[wear.fluid_mesh]`), if any.
    follower: Option<MeshFollowing>,
}

impl ReferenceFluid {
    /// Sets up the solver for `case` on `mesh`. If `state.fluid` is `None` the fluid starts
    /// from the case's initial velocity, zero pressure and α_c = 1.
    pub fn new(case: &Case, mut mesh: Mesh, state: &mut State) -> Result<Self, SolverError> {
        let fluid = case.fluid.as_ref().ok_or_else(|| SolverError::Unsupported("the case has no [fluid] section".into()))?;
        let conditions = Conditions::from_case(case, &mesh, fluid.density)?;
        let numerics = case.numerics.clone();
        let body_force = numerics.kinematic_body_force(case.physics.gravity);
        let rotating_frame =
            RotatingFrame::of_physics(&case.physics).map_err(|e| SolverError::Unsupported(format!("`{}` = {}: expected {}", e.key, e.value, e.allowed)))?;
        let interface_axis = mesh.rotating_zone_axis();
        let rotor = RotorMotion::from_case(case, &mesh).map_err(SolverError::Unsupported)?;

        prepare_fluid_state(state, case, &mesh).map_err(SolverError::Unsupported)?;
        let turbulence = turbulence::from_case(&case.turbulence, conditions.wall_patch_names(&mesh));
        let fluid_state = state.fluid.as_mut().expect("prepared above");
        let follower = MeshFollowing::from_case(case, &mut mesh, state.walls.as_ref(), fluid_state, state.dt).map_err(SolverError::Unsupported)?;
        let mut solver = ReferenceFluid {
            mesh,
            conditions,
            numerics,
            nu: fluid.kinematic_viscosity,
            density: fluid.density,
            body_force,
            rotating_frame,
            rotor,
            interface_axis,
            dt_old: state.dt,
            turbulence,
            follower,
        };
        solver.place_rotor(RotorPose::from_case(case, state.rotor_angle).as_ref())?;
        Ok(solver)
    }

    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// Cell gradient of the kinematic pressure, ∇P (Gauss, linear face values, the stored
    /// boundary pressures): the gradient the momentum equation uses.
    pub fn pressure_gradient(&self, fluid: &FluidState) -> Vec<Vec3> {
        let geo = self.geometry();
        let p_boundary: Vec<f64> = geo.boundary.iter().map(|face| fluid.boundary_pressure[face.index]).collect();
        super::gradient::scalar_gradient(&geo, &self.mesh.cell_volumes, &fluid.pressure, &p_boundary)
    }

    /// Per-cell continuity error e_c = ∂α/∂t V + Σ α_f φ_f of the stored state, without the
    /// ∂α/∂t part (single phase) [m³/s]; on overlap links the stored face sums are used.
    pub fn flux_divergence(&self, fluid: &FluidState) -> Vec<f64> {
        let mut div = vec![0.0; self.mesh.cell_volumes.len()];
        for f in 0..self.mesh.face_areas.len() {
            let owner = self.mesh.face_owner[f];
            div[owner] += fluid.flux[f];
            if f < self.mesh.n_internal_faces {
                div[self.mesh.face_neighbour[f]] -= fluid.flux[f];
            }
        }
        div
    }

    /// The links and boundary faces of the current mesh position.
    pub fn geometry(&self) -> Geometry {
        let links = match self.interface_axis {
            Some((axis, origin)) => interface_links(&self.mesh, axis, origin, self.rotor.as_ref()),
            None => Vec::new(),
        };
        let deforming = self.follower.as_ref().map_or(&[][..], |f| f.face_mesh_flux());
        Geometry::build(&self.mesh, &self.conditions.patch_condition, self.rotor.as_ref(), deforming, links)
    }

    /// Sets the suction mouth's speed of the step (`suction` is its condition): the speed at
    /// which the water leaves through it what continuity leaves for it
    /// (spillage_model::cutter_head::mouth::balancing_speed): the prescribed fluxes at unit
    /// speed, each weighted by α of its cell, less every boundary face's particle share of its
    /// mesh flux (spillage_model::fluid::moving_cells), and the cells' Σ V ∂α/∂t.
    fn balance_suction(&mut self, suction: usize, geo: &Geometry, fluid: &FluidState, ctx: &StepContext) -> Result<(), SolverError> {
        self.conditions.set_suction_speed(1.0);
        let (mut unit, mut other) = (0.0, 0.0);
        for face in &geo.boundary {
            if let Some(flux) = boundary::prescribed_flux(&self.conditions, face, self.rotor.as_ref()) {
                let weighted = fluid.alpha[face.cell] * flux;
                if face.patch == suction {
                    unit += weighted;
                } else {
                    other += weighted;
                }
            }
            other -= particle_share_of_mesh_flux(fluid.alpha[face.cell], face.mesh_flux);
        }
        let alpha = [fluid.alpha.as_slice(), fluid.alpha_old.as_slice(), fluid.alpha_old_old.as_slice()];
        let rate = fluid_volume_rate(alpha, &self.mesh.cell_volumes, ctx.time_coefficients, ctx.dt);
        let speed = balancing_speed(unit, other, rate).map_err(SolverError::Unsupported)?;
        self.conditions.set_suction_speed(speed);
        Ok(())
    }

    /// One PIMPLE step from tⁿ to tⁿ⁺¹ (module doc, steps 2–5).
    fn advance_fluid(
        &mut self,
        ctx: &StepContext,
        fluid_state: &mut FluidState,
        load: Option<&CellLoad>,
        report: &mut StepReport,
    ) -> Result<FluidStepOutcome, SolverError> {
        let dt = ctx.dt;
        let time_coefficients = ctx.time_coefficients;
        self.place_rotor(ctx.rotor.as_ref())?;
        // a mesh that follows a receding wall was moved for this step ([`FluidPhase::follow_walls`])
        if let Some(following) = &self.follower {
            following.check_moved().map_err(SolverError::Unsupported)?;
        }
        let deforming = self.follower.is_some();
        let geo = self.geometry();
        let fluid = &*fluid_state;
        let n = geo.n_cells();
        let volumes = self.mesh.cell_volumes.clone();
        let following_volumes = self.follower.as_ref().map(|f| f.volumes_old().to_vec());
        let volumes_old: &[f64] = following_volumes.as_deref().unwrap_or(&volumes);
        let u_old: Vec<Vec3> = fluid.velocity.iter().map(|v| Vec3::from(*v)).collect();
        let u_old_old: Vec<Vec3> = fluid.velocity_old.iter().map(|v| Vec3::from(*v)).collect();
        if let Some(suction) = self.conditions.suction_condition() {
            self.balance_suction(suction, &geo, fluid, ctx)?;
        }
        let boundary_velocity: Vec<Option<Vec3>> =
            geo.boundary.iter().map(|face| boundary::fixed_velocity(&self.conditions, face, self.rotor.as_ref())).collect();
        let prescribed: Vec<Option<f64>> = geo.boundary.iter().map(|face| boundary::prescribed_flux(&self.conditions, face, self.rotor.as_ref())).collect();
        let moved = super::geometry::cell_in_rotor(&self.mesh, self.rotor.as_ref());
        // faces whose geometry changed since the stored fluxes: the rotor's, or all of a
        // deforming mesh
        let all_cells;
        let fresh: &[bool] = if deforming {
            all_cells = vec![true; n];
            &all_cells
        } else {
            &moved
        };
        let ddt_flux_correction = ddt_flux_correction(&geo, fluid, fresh, &u_old, &u_old_old, time_coefficients, dt, self.numerics.ddt_flux_correction);
        let inputs = StepInputs {
            geo: &geo,
            conditions: &self.conditions,
            rotor: self.rotor.as_ref(),
            numerics: &self.numerics,
            volumes: &volumes,
            volumes_old,
            deforming,
            viscosity: self.turbulence.viscosity(fluid, self.nu),
            dt,
            time_coefficients,
            alpha: &fluid.alpha,
            alpha_old: &fluid.alpha_old,
            alpha_old_old: &fluid.alpha_old_old,
            u_old: &u_old,
            u_old_old: &u_old_old,
            body_force: self.body_force,
            rotating_frame: self.rotating_frame,
            cell_centres: &self.mesh.cell_centres,
            frozen_rotor: FrozenRotor::of_step(ctx),
            in_rotor: &moved,
            boundary_velocity: &boundary_velocity,
            ddt_flux_correction: &ddt_flux_correction,
            load,
            density: self.density,
        };

        // starting values (step 3 of the algorithm)
        let mut u = u_old.clone();
        let mut p = fluid.pressure.clone();
        let mut p_boundary: Vec<f64> = geo.boundary.iter().map(|face| fluid.boundary_pressure[face.index]).collect();
        // faces that moved (rotor zone) or were rebuilt (overlaps) start from the interpolated
        // velocity on the new geometry; mixing old-geometry fluxes with new faces would open the
        // cells of the first outer iteration
        let mut link_flux: Vec<f64> = geo
            .links
            .iter()
            .map(|link| match link.origin {
                LinkOrigin::Face(f) if !fresh[link.owner] => fluid.flux[f],
                _ => link.interpolate_vec(u[link.owner], u[link.neighbour]).dot(&link.area),
            })
            .collect();
        let mut boundary_flux: Vec<f64> = geo.boundary.iter().enumerate().map(|(b, face)| prescribed[b].unwrap_or(fluid.flux[face.face])).collect();

        let mut outer_iterations = 0;
        let (mut first_outer_residual, mut last_residual) = (f64::NAN, f64::NAN);
        // the limiter's velocity and gradient, when it is evaluated once per step
        let limiter_per_step = self.numerics.limiter_update == LimiterUpdate::TimeStep;
        let mut limiter_field: Option<(Vec<Vec3>, Vec<[Vec3; 3]>)> = None;
        for _outer in 0..self.numerics.max_outer_iterations {
            outer_iterations += 1;
            let boundary_u = momentum::boundary_velocities(&inputs, &u);
            let grad_u = vector_gradient(&geo, &volumes, &u, &boundary_u);
            if limiter_per_step && limiter_field.is_none() {
                limiter_field = Some((u.clone(), grad_u.clone()));
            }
            let limiter = limiter_field.as_ref().map_or((u.as_slice(), grad_u.as_slice()), |(lu, lg)| (lu.as_slice(), lg.as_slice()));
            let system = momentum::assemble(&inputs, &link_flux, &boundary_flux, (&u, &grad_u), limiter);

            // momentum predictor: M u = b − V∇P*
            let grad_p = super::gradient::scalar_gradient(&geo, &volumes, &p, &p_boundary);
            let mut rhs = Vec::new();
            let mut solved = Vec::new();
            for j in 0..3 {
                if geo.solved_components[j] {
                    rhs.push((0..n).map(|c| system.source[c][j] - volumes[c] * grad_p[c][j]).collect::<Vec<f64>>());
                    solved.push(j);
                }
            }
            let solution = system.matrix.solve_on_cells(&rhs, "momentum predictor", &self.mesh.cell_centres)?;
            for (k, j) in solved.iter().enumerate() {
                for c in 0..n {
                    u[c][*j] = solution[k][c];
                }
            }

            let mut first_residual = f64::NAN;
            for corrector in 0..self.numerics.piso_correctors {
                let residual = pressure::correct(
                    &inputs,
                    &system,
                    &prescribed,
                    CorrectorFields { u: &mut u, p: &mut p, p_boundary: &mut p_boundary, link_flux: &mut link_flux, boundary_flux: &mut boundary_flux },
                )?;
                if corrector == 0 {
                    first_residual = residual;
                }
            }
            last_residual = first_residual;
            if outer_iterations == 1 {
                first_outer_residual = first_residual;
            }
            if !first_residual.is_finite() || u.iter().any(|v| !v.iter().all(|x| x.is_finite())) {
                return Err(SolverError::Diverged { step: ctx.step, time: ctx.time_end(), what: "non-finite velocity or pressure".into() });
            }
            if first_residual < self.numerics.p_initial_residual {
                break;
            }
        }

        // diagnostics before the time levels shift (∂α/∂t uses this step's levels)
        let errors = diagnostics::continuity_errors(&inputs, &link_flux, &boundary_flux);
        let local = dt * errors.iter().map(|e| e.abs()).sum::<f64>();
        let cell_max = dt * errors.iter().fold(0.0f64, |m, e| m.max(e.abs()));
        let global = dt * errors.iter().sum::<f64>();
        let courant = diagnostics::max_courant(&geo, &volumes, dt, &link_flux, &boundary_flux);
        let imbalance = diagnostics::interface_imbalance(&geo, &link_flux, self.mesh.face_areas.len());
        let alpha = fluid.alpha.clone();
        let kinetic = diagnostics::kinetic_energy(&u, &alpha, &volumes);
        let boundary_u = momentum::boundary_velocities(&inputs, &u);
        let alpha_before = fluid.alpha_old.clone();

        // step 5: shift the time levels
        let n_faces = self.mesh.face_areas.len();
        let fluid = fluid_state;
        if let Some(following) = self.follower.as_mut() {
            following.finish_step(fluid);
        }
        fluid.velocity_old = fluid.velocity.clone();
        fluid.velocity = u.iter().map(|v| [v.x, v.y, v.z]).collect();
        fluid.pressure = p;
        let mut flux = vec![0.0; n_faces];
        for (l, link) in geo.links.iter().enumerate() {
            match link.origin {
                LinkOrigin::Face(f) => flux[f] = link_flux[l],
                LinkOrigin::Interface { rotor_face, stator_face } => {
                    flux[rotor_face] += link_flux[l];
                    flux[stator_face] -= link_flux[l];
                }
            }
        }
        for (b, face) in geo.boundary.iter().enumerate() {
            flux[face.face] = boundary_flux[b];
            fluid.boundary_pressure[face.index] = p_boundary[b];
        }
        fluid.flux_old = std::mem::replace(&mut fluid.flux, flux);
        fluid.alpha_old_old = fluid.alpha_old.clone();
        fluid.alpha_old = fluid.alpha.clone();
        fluid.cumulative_continuity_error += global;
        let cumulative = fluid.cumulative_continuity_error;
        self.dt_old = dt;

        report.values.extend([
            ("courant_max", courant),
            ("continuity_local", local),
            ("continuity_cell_max", cell_max),
            ("continuity_global", global),
            ("continuity_cumulative", cumulative),
            ("kinetic_energy", kinetic),
            ("outer_iterations", outer_iterations as f64),
            ("p_initial_residual", last_residual),
            ("interface_imbalance", imbalance),
        ]);

        // turbulence, once per step after the outer loop (spec §8.7 Algorithm 1 line 25)
        let turbulence_inputs = TurbulenceInputs {
            geo: &geo,
            conditions: &self.conditions,
            volumes: &volumes,
            cell_centres: &self.mesh.cell_centres,
            nu: self.nu,
            dt,
            alpha: &alpha,
            alpha_old: &alpha_before,
            u: &u,
            boundary_u: &boundary_u,
            link_flux: &link_flux,
            boundary_flux: &boundary_flux,
            step: ctx.step,
            time: ctx.time_end(),
        };
        self.turbulence.correct(&turbulence_inputs, fluid, &mut report.values)?;
        Ok(FluidStepOutcome {
            courant_max: courant,
            outer_iterations,
            outer_capped: outer_iterations >= self.numerics.max_outer_iterations && !(last_residual < self.numerics.p_initial_residual),
            first_residual: first_outer_residual,
            last_residual,
            under_relaxed: self.numerics.relax_velocity < 1.0 || self.numerics.relax_pressure < 1.0,
        })
    }
}

/// Per link, the time-derivative flux correction divided by rAU_f (module doc step 4d, OpenFOAM
/// `fvc::ddtCorr` with coupling coefficient 1): the momentum source carries the old levels as
/// −(c₁αᵒuᵒ + c₂αᵒᵒuᵒᵒ)V/Δt, so (A⁻¹H)_f·S carries rAU_f(−1/Δt)[c₁(αᵒuᵒ)_f + c₂(αᵒᵒuᵒᵒ)_f]·S;
/// this term swaps those interpolated old velocities for the old fluxes,
/// −(1/Δt)[c₁(α_fᵒ φᵒ − (αᵒuᵒ)_f·S) + c₂(α_fᵒᵒ φᵒᵒ − (αᵒᵒuᵒᵒ)_f·S)].
/// Zero on links whose geometry changed since the old fluxes were stored (faces of the moving
/// zone, overlap links) and when `enabled` is false; boundary faces have none.
#[allow(clippy::too_many_arguments)]
fn ddt_flux_correction(
    geo: &Geometry,
    fluid: &FluidState,
    moved: &[bool],
    u_old: &[Vec3],
    u_old_old: &[Vec3],
    time_coefficients: [f64; 3],
    dt: f64,
    enabled: bool,
) -> Vec<f64> {
    let [_, c1, c2] = time_coefficients;
    let (alpha_o, alpha_oo) = (&fluid.alpha_old, &fluid.alpha_old_old);
    geo.links
        .iter()
        .map(|link| match link.origin {
            LinkOrigin::Face(f) if enabled && !moved[link.owner] => {
                let (p, nb) = (link.owner, link.neighbour);
                let old = link.interpolate(alpha_o[p], alpha_o[nb]) * fluid.flux[f]
                    - link.interpolate_vec(u_old[p] * alpha_o[p], u_old[nb] * alpha_o[nb]).dot(&link.area);
                let old_old = link.interpolate(alpha_oo[p], alpha_oo[nb]) * fluid.flux_old[f]
                    - link.interpolate_vec(u_old_old[p] * alpha_oo[p], u_old_old[nb] * alpha_oo[nb]).dot(&link.area);
                -(c1 * old + c2 * old_old) / dt
            }
            _ => 0.0,
        })
        .collect()
}

impl FluidPhase for ReferenceFluid {
    fn name(&self) -> &'static str {
        "reference"
    }

    fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// Turns the rotor zone to the pose's angle (from its reference geometry, so no drift
    /// accumulates) and takes the pose's motion for the mesh fluxes and wall velocities.
    fn place_rotor(&mut self, pose: Option<&RotorPose>) -> Result<(), SolverError> {
        if let (Some(r), Some(pose)) = (self.rotor.as_mut(), pose) {
            // (the driver places the zone before sampling; the fluid step asks again)
            if r.pose != *pose {
                r.place(&mut self.mesh, pose).map_err(SolverError::Unsupported)?;
            }
        }
        Ok(())
    }

    fn advance(
        &mut self,
        ctx: &StepContext,
        fluid: &mut FluidState,
        load: Option<&CellLoad>,
        report: &mut StepReport,
    ) -> Result<FluidStepOutcome, SolverError> {
        self.advance_fluid(ctx, fluid, load, report)
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

    fn rewind(&mut self, dt_old: f64) {
        self.dt_old = dt_old;
        if let Some(following) = self.follower.as_mut() {
            following.rewind(&mut self.mesh);
        }
    }

    fn follow_walls(&mut self, ctx: &StepContext, walls: &WallState, fluid: &FluidState) -> Result<(), SolverError> {
        if let Some(following) = self.follower.as_mut() {
            following.move_for_step(&mut self.mesh, walls, &fluid.mesh_displacement, ctx.time_coefficients, ctx.dt).map_err(SolverError::Unsupported)?;
        }
        Ok(())
    }

    /// ½ Σ_f |φ_f − φ_mesh,f| / V per second, with the interpolated cell velocities on every
    /// link (the stored fluxes of overlap links are summed per face).
    fn courant_rate(&self, fluid: &FluidState) -> f64 {
        let geo = self.geometry();
        let u: Vec<Vec3> = fluid.velocity.iter().map(|v| Vec3::from(*v)).collect();
        let link_flux: Vec<f64> = geo.links.iter().map(|l| l.interpolate_vec(u[l.owner], u[l.neighbour]).dot(&l.area)).collect();
        let boundary_flux: Vec<f64> = geo.boundary.iter().map(|b| fluid.flux[b.face]).collect();
        diagnostics::max_courant(&geo, &self.mesh.cell_volumes, 1.0, &link_flux, &boundary_flux)
    }
}
