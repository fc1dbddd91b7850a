//! [`FastFluid`]: one PIMPLE step per call, the algorithm of the reference solver (module doc
//! of `spillage_reference::fluid`, steps 1–5) on struct-of-arrays fields with iterative solves.

use rayon::prelude::*;
use spillage_model::case::Case;
use spillage_model::closure::drag::FluidAtParticle;
use spillage_model::fluid::conditions::{Condition, Conditions};
use spillage_model::fluid::initial::initial_fluid_state;
use spillage_model::fluid::settings::{NumericsSection, PressureWallCondition};
use spillage_model::fluid::state::FluidState;
use spillage_model::mesh::{Mesh, Vec3};
use spillage_model::particles::Particle;
use spillage_model::solver::{SolverError, StepReport};
use spillage_model::state::State;
use spillage_model::step::{FluidPhase, FluidStepOutcome, ParticleLoad, RotorPose, StepContext};

use super::assembly::*;
use super::interface::{push_overlaps, Frame};
use super::layout::{rotor_velocity, solved_components, Adjacency, Boundary, Links, Rotor, NO_CELL};
use crate::linear::amg::Amg;
use crate::linear::bicgstab::BiCgStab;
use crate::linear::pcg::Pcg;
use crate::linear::reduce::Reducer;
use crate::linear::{par_update, Csr, Tolerance};

/// Linear-solver controls of the fast solver (the reference solves exactly). The defaults are
/// tight enough for the step-by-step equivalence with the reference (tests/fast_equivalence.rs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FastSettings {
    /// Pressure: AMG-preconditioned CG, normalised residual (OpenFOAM's definition).
    pub pressure: Tolerance,
    /// Momentum components: Jacobi-preconditioned BiCGStab.
    pub momentum: Tolerance,
}

impl Default for FastSettings {
    fn default() -> Self {
        FastSettings {
            pressure: Tolerance { tolerance: 1e-12, max_iterations: 2000 },
            momentum: Tolerance { tolerance: 1e-12, max_iterations: 2000 },
        }
    }
}

/// Why a solve that used its whole iteration budget is not an answer (`None` when it
/// converged): a silently unconverged solve would pass off a wrong state as a result.
fn unconverged(stats: &crate::linear::SolveStats, tolerance: Tolerance) -> Option<String> {
    (stats.iterations >= tolerance.max_iterations && stats.final_residual > tolerance.tolerance).then(|| {
        format!(
            "did not converge in {} iterations (normalised residual {:.3e} > {:.1e}); raise [numerics] max_linear_iterations or loosen linear_tolerance",
            stats.iterations, stats.final_residual, tolerance.tolerance
        )
    })
}

impl FastSettings {
    /// The controls a case file sets (`[numerics] linear_tolerance`, `max_linear_iterations`).
    pub fn from_numerics(numerics: &spillage_model::fluid::settings::NumericsSection) -> Self {
        let tolerance = Tolerance { tolerance: numerics.linear_tolerance, max_iterations: numerics.max_linear_iterations };
        FastSettings { pressure: tolerance, momentum: tolerance }
    }
}

/// Iteration counts of the last step (for benchmarks).
#[derive(Clone, Copy, Debug, Default)]
pub struct SolveCounts {
    pub pressure_solves: usize,
    pub pressure_iterations: usize,
    pub momentum_iterations: usize,
    /// Iterations of the first [`SolveCounts::PER_SOLVE`] pressure solves of the step, in order.
    pub pressure_per_solve: [u16; SolveCounts::PER_SOLVE],
    /// Wall-clock seconds of the step in the multigrid setup, the pressure solves and the
    /// momentum solves (for the benchmark's breakdown; never used by the algorithm).
    pub amg_setup_seconds: f64,
    pub pressure_seconds: f64,
    pub momentum_seconds: f64,
    pub step_seconds: f64,
}

impl SolveCounts {
    pub const PER_SOLVE: usize = 12;
}

#[derive(Default)]
struct Work {
    u: [Vec<f64>; 3],
    u_old: [Vec<f64>; 3],
    u_oo: [Vec<f64>; 3],
    p: Vec<f64>,
    p_start: Vec<f64>,
    p_work: Vec<f64>,
    p_b: Vec<f64>,
    link_flux: Vec<f64>,
    link_h: Vec<f64>,
    /// Time-derivative flux correction per link divided by rAU_f (reference
    /// `solver::ddt_flux_correction`).
    ddt_corr: Vec<f64>,
    boundary_flux: Vec<f64>,
    /// Prescribed boundary flux (NaN where the pressure is fixed).
    prescribed: Vec<f64>,
    /// Fixed boundary velocity (NaN where none).
    fixed_u: Vec<Vec3>,
    boundary_u: Vec<Vec3>,
    grad_u: Vec<[Vec3; 3]>,
    grad_p: Vec<Vec3>,
    upper: Vec<f64>,
    lower: Vec<f64>,
    link_src: Vec<Vec3>,
    source: Vec<Vec3>,
    mom: Csr,
    rhs: [Vec<f64>; 3],
    offdiag: Vec<f64>,
    hbya: Vec<Vec3>,
    rau: Vec<f64>,
    pcoef: Vec<f64>,
    ah: Vec<f64>,
    pres: Csr,
    prhs: Vec<f64>,
    ax: Vec<f64>,
    errors: Vec<f64>,
    face_sum: Vec<f64>,
    face_used: Vec<bool>,
}

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
    nu: f64,
    density: f64,
    body_force: Vec3,
    rotor: Option<Rotor>,
    frame: Option<Frame>,
    /// Δt of the step being taken.
    dt: f64,
    settings: FastSettings,
    in_rotor: Vec<bool>,
    /// Internal faces of the rotor zone (their geometry is updated in place every step).
    moving_faces: Vec<usize>,
    links: Links,
    /// Overlap buffer of the sliding interfaces (reused every step).
    overlaps: Vec<spillage_model::mesh::Overlap>,
    boundary: Boundary,
    adj: Adjacency,
    solved: [bool; 3],
    w: Work,
    pcg: Pcg,
    bicg: BiCgStab,
    amg: Amg,
    /// Momentum matrix assemblies so far, and the one the AMG hierarchy was last set up after:
    /// the pressure matrix depends on the momentum diagonal (through rAU), the volume fractions
    /// and the geometry, all fixed between two momentum assemblies, so its PISO and
    /// non-orthogonal correctors reuse the hierarchy of the first.
    momentum_assemblies: u64,
    amg_after_assembly: Option<u64>,
    red: Reducer,
    counts: SolveCounts,
    /// Whether every link's non-orthogonal part is negligible ([`Self::links_orthogonal`]);
    /// `None` after the link geometry changed.
    orthogonal: Option<bool>,
}

fn unsupported(msg: impl Into<String>) -> SolverError {
    SolverError::Unsupported(msg.into())
}

impl FastFluid {
    /// Sets up the solver for `case` on `mesh` (as `ReferenceFluid::new`: without a fluid state
    /// the fluid starts from the case's initial velocity, zero pressure, α_c = 1).
    pub fn new(case: &Case, mesh: Mesh, state: &mut State) -> Result<Self, SolverError> {
        let fluid = case.fluid.as_ref().ok_or_else(|| unsupported("the case has no [fluid] section"))?;
        let conditions = Conditions::from_case(case, &mesh, fluid.density)?;
        let numerics = case.numerics.clone();
        let mut body_force = Vec3::from(numerics.body_force);
        if numerics.fluid_gravity {
            body_force += Vec3::from(case.physics.gravity);
        }
        let rotating_zone = mesh.zones.iter().position(|z| z.rotation.is_some());
        let frame = rotating_zone.map(|z| {
            let r = mesh.zones[z].rotation.as_ref().expect("rotating zone");
            Frame::new(r.origin, r.axis)
        });
        let rotor = match &case.rotor {
            Some(section) => {
                let zone = mesh.zones.iter().position(|z| z.name == section.zone).ok_or_else(|| unsupported(format!("rotor.zone = {:?} is not a zone of the mesh", section.zone)))?;
                if mesh.zones[zone].rotation.is_none() {
                    return Err(unsupported(format!("mesh zone {:?} cannot rotate", section.zone)));
                }
                Some(Rotor { zone, axis: Vec3::from(section.axis).normalize(), origin: Vec3::from(section.origin), omega: section.angular_velocity() })
            }
            None => None,
        };
        let has_interface_patch = mesh.patches.iter().any(|p| matches!(p.kind, spillage_model::mesh::PatchKind::Interface { .. }));
        if has_interface_patch && (mesh.interfaces.is_empty() || frame.is_none()) {
            return Err(unsupported("the mesh has interface patches but no cylindrical sliding-interface description (the fast solver needs the shared z layers)"));
        }

        let n = mesh.n_cells();
        let fluid_state = state.fluid.get_or_insert_with(|| initial_fluid_state(case, &mesh));
        fluid_state.fill_missing_old_flux(&mesh);
        fluid_state.check_matches(&mesh).map_err(unsupported)?;
        let mut mesh = mesh;
        if let Some(r) = &rotor {
            mesh.set_zone_angle(r.zone, state.rotor_angle).map_err(|e| unsupported(format!("cannot rotate the rotor zone: {e}")))?;
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
            rotor,
            frame,
            dt: 0.0,
            settings: FastSettings::from_numerics(&case.numerics),
            in_rotor,
            moving_faces,
            links,
            overlaps: Vec::new(),
            boundary,
            adj: Adjacency::default(),
            solved,
            w: Work::default(),
            pcg: Pcg::default(),
            bicg: BiCgStab::default(),
            amg: Amg::default(),
            momentum_assemblies: 0,
            amg_after_assembly: None,
            red: Reducer::default(),
            counts: SolveCounts::default(),
            orthogonal: None,
        };
        solver.rebuild_overlaps();
        solver.size_work();
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
        self.amg.level_sizes()
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
        self.adj.rebuild(self.mesh.n_cells(), &self.links);
    }

    fn size_work(&mut self) {
        let n = self.mesh.n_cells();
        let nb = self.boundary.len();
        let nl = self.links.len();
        let w = &mut self.w;
        for j in 0..3 {
            w.u[j].resize(n, 0.0);
            w.u_old[j].resize(n, 0.0);
            w.u_oo[j].resize(n, 0.0);
            w.rhs[j].resize(n, 0.0);
        }
        for v in [&mut w.p, &mut w.p_start, &mut w.p_work, &mut w.offdiag, &mut w.rau, &mut w.prhs, &mut w.ax, &mut w.errors] {
            v.resize(n, 0.0);
        }
        for v in [&mut w.p_b, &mut w.boundary_flux, &mut w.prescribed] {
            v.resize(nb, 0.0);
        }
        for v in [&mut w.fixed_u, &mut w.boundary_u] {
            v.resize(nb, Vec3::zeros());
        }
        for v in [&mut w.link_flux, &mut w.link_h, &mut w.ddt_corr, &mut w.upper, &mut w.lower, &mut w.pcoef, &mut w.ah] {
            v.resize(nl, 0.0);
        }
        w.link_src.resize(nl, Vec3::zeros());
        w.grad_u.resize(n, [Vec3::zeros(); 3]);
        w.grad_p.resize(n, Vec3::zeros());
        w.source.resize(n, Vec3::zeros());
        w.hbya.resize(n, Vec3::zeros());
        w.face_sum.resize(self.mesh.n_faces(), 0.0);
        w.face_used.resize(self.mesh.n_faces(), false);
        // matrix structure = adjacency
        for m in [&mut w.mom, &mut w.pres] {
            m.n = n;
            m.row_start.clone_from(&self.adj.row_start);
            m.col.clone_from(&self.adj.col);
            m.val.resize(self.adj.col.len(), 0.0);
            m.diag.resize(n, 0.0);
        }
    }

    /// True when every link's non-orthogonal area part (T4.26 over-relaxed split) is below
    /// 1e-12 of its area: rounding of area − δ·|A|²/(δ·A) on an orthogonal face, not geometry.
    /// The explicit non-orthogonal flux term is then below 1e-12 of the gradient flux, so a
    /// further non-orthogonal corrector assembles the same pressure equation to that relative
    /// level, starts converged and leaves the pressure as it is (measured on the lid-driven
    /// cavity: 0 iterations in every such solve); [`Self::correct`] skips those passes.
    fn links_orthogonal(&self) -> bool {
        let links = &self.links;
        (0..links.len()).all(|l| links.non_orthogonal[l].norm_squared() <= 1e-24 * links.area[l].norm_squared())
    }

    /// Turns the rotor zone to the pose's angle (from its reference geometry), takes the pose's
    /// motion and updates the moving link and boundary geometry in place.
    fn turn_rotor(&mut self, pose: Option<&RotorPose>) -> Result<(), SolverError> {
        if let (Some(r), Some(pose)) = (self.rotor.as_mut(), pose) {
            r.axis = pose.axis;
            r.origin = pose.origin;
            r.omega = pose.omega;
            self.mesh.set_zone_angle(r.zone, pose.angle).map_err(|e| unsupported(format!("cannot rotate the rotor zone: {e}")))?;
            for &f in &self.moving_faces {
                self.links.update_face(&self.mesh, f, self.rotor.as_ref(), &self.in_rotor);
            }
            self.boundary.update(&self.mesh, self.rotor.as_ref(), &self.in_rotor);
        }
        Ok(())
    }

    fn advance_timed(&mut self, report: &mut StepReport) -> Result<FluidStepOutcome, SolverError> {
        let clock = std::time::Instant::now();
        let result = self.advance_inner(report);
        self.counts.step_seconds = clock.elapsed().as_secs_f64();
        result
    }

    fn advance_inner(&mut self, report: &mut StepReport) -> Result<FluidStepOutcome, SolverError> {
        let dt = self.dt;
        let tc = self.time_coefficients;
        // step 2: the rotor at the step's pose (turned by `FluidPhase::advance`), the overlaps rebuilt
        if self.frame.is_some() && (self.rotor.is_some() || self.links.len() == self.links.n_internal) {
            self.rebuild_overlaps();
        }
        // link geometry changes on the first step and whenever the rotor or the overlaps move
        let geometry_changed = self.orthogonal.is_none() || self.rotor.is_some() || self.frame.is_some();
        if geometry_changed {
            self.orthogonal = Some(self.links_orthogonal());
        }
        self.size_work();
        if geometry_changed {
            self.boundary.update_across(&self.links, &self.adj);
        }

        let n = self.mesh.n_cells();
        let nb = self.boundary.len();
        let nl = self.links.len();
        let n_internal_faces = self.mesh.n_internal_faces;
        {
            // step 3: starting values
            let fluid = &self.fluid;
            let w = &mut self.w;
            for c in 0..n {
                for j in 0..3 {
                    w.u[j][c] = fluid.velocity[c][j];
                    w.u_old[j][c] = fluid.velocity[c][j];
                    w.u_oo[j][c] = fluid.velocity_old[c][j];
                }
            }
            w.p.copy_from_slice(&fluid.pressure);
            let links = &self.links;
            let moved = &self.in_rotor;
            let rotor_moves = self.rotor.is_some();
            let u = &w.u;
            let o = Out::of(&mut w.link_flux);
            par_for(nl, |l| {
                let (p, q) = (links.owner[l] as usize, links.neighbour[l] as usize);
                let v = if l < links.n_internal && !(rotor_moves && moved[p]) {
                    fluid.flux[l]
                } else {
                    let wt = links.weight[l];
                    (vec_of(u, p) * wt + vec_of(u, q) * (1.0 - wt)).dot(&links.area[l])
                };
                unsafe { o.set(l, v) };
            });
            // time-derivative flux correction (reference `solver::ddt_flux_correction`): zero
            // on moved faces and overlap links, whose geometry changed since φᵒ was stored
            let (_, c1, c2) = (tc[0], tc[1], tc[2]);
            let enabled = self.numerics.ddt_flux_correction;
            let (alpha_o, alpha_oo) = (&fluid.alpha_old, &fluid.alpha_old_old);
            let (u_o, u_oo) = (&w.u_old, &w.u_oo);
            let o = Out::of(&mut w.ddt_corr);
            par_for(nl, |l| {
                let (p, q) = (links.owner[l] as usize, links.neighbour[l] as usize);
                let v = if enabled && l < links.n_internal && !(rotor_moves && moved[p]) {
                    let wt = links.weight[l];
                    let old = links.interpolate(l, alpha_o[p], alpha_o[q]) * fluid.flux[l]
                        - (vec_of(u_o, p) * alpha_o[p] * wt + vec_of(u_o, q) * alpha_o[q] * (1.0 - wt)).dot(&links.area[l]);
                    let old_old = links.interpolate(l, alpha_oo[p], alpha_oo[q]) * fluid.flux_old[l]
                        - (vec_of(u_oo, p) * alpha_oo[p] * wt + vec_of(u_oo, q) * alpha_oo[q] * (1.0 - wt)).dot(&links.area[l]);
                    -(c1 * old + c2 * old_old) / dt
                } else {
                    0.0
                };
                unsafe { o.set(l, v) };
            });
            let bnd = &self.boundary;
            for b in 0..nb {
                let cond = bnd.condition[b] as usize;
                let face = bnd.face[b] as usize;
                w.p_b[b] = fluid.boundary_pressure[face - n_internal_faces];
                w.fixed_u[b] = self.conditions.fixed_velocity(cond, &bnd.centre[b], rotor_velocity(self.rotor.as_ref())).unwrap_or(Vec3::repeat(f64::NAN));
                let pres = self.conditions.prescribed_flux(cond, &bnd.centre[b], &bnd.area[b], bnd.mesh_flux[b], rotor_velocity(self.rotor.as_ref()));
                w.prescribed[b] = pres.unwrap_or(f64::NAN);
                w.boundary_flux[b] = pres.unwrap_or(fluid.flux[face]);
            }
        }

        self.counts = SolveCounts::default();
        let mut outer_iterations = 0;
        let mut last_residual = f64::NAN;
        for _outer in 0..self.numerics.max_outer_iterations {
            outer_iterations += 1;
            self.boundary_velocities();
            {
                let w = &mut self.w;
                vector_gradient(&self.links, &self.adj, &self.boundary, &self.mesh.cell_volumes, &w.u, &w.boundary_u, &mut w.grad_u);
            }
            self.assemble_momentum(tc);
            self.predictor()?;
            let mut first_residual = f64::NAN;
            for corrector in 0..self.numerics.piso_correctors {
                let residual = self.correct(tc)?;
                if corrector == 0 {
                    first_residual = residual;
                }
            }
            last_residual = first_residual;
            let finite = self.w.u.iter().all(|c| c.iter().all(|x| x.is_finite()));
            if !first_residual.is_finite() || !finite {
                return Err(SolverError::Diverged { step: self.step_number, time: self.step_time_end, what: "non-finite velocity or pressure".into() });
            }
            if first_residual < self.numerics.p_initial_residual {
                break;
            }
        }
        let courant_max = self.finish_step(tc, outer_iterations, last_residual, report);
        Ok(FluidStepOutcome { courant_max })
    }

    /// Boundary velocity of every boundary face from the latest cell velocity.
    fn boundary_velocities(&mut self) {
        let w = &mut self.w;
        let bnd = &self.boundary;
        for b in 0..bnd.len() {
            let c = bnd.cell[b] as usize;
            let uc = vec_of(&w.u, c);
            w.boundary_u[b] = if !w.fixed_u[b].x.is_nan() {
                w.fixed_u[b]
            } else if let Condition::Symmetry = self.conditions.conditions[bnd.condition[b] as usize] {
                let nrm = bnd.area[b].normalize();
                uc - nrm * uc.dot(&nrm)
            } else {
                uc
            };
        }
    }

    fn assemble_momentum(&mut self, tc: [f64; 3]) {
        self.momentum_assemblies += 1;
        let [c0, c1, c2] = tc;
        let n = self.mesh.n_cells();
        let fluid = &self.fluid;
        let (alpha, alpha_o, alpha_oo) = (&fluid.alpha, &fluid.alpha_old, &fluid.alpha_old_old);
        let links = &self.links;
        let numerics = &self.numerics;
        let nu = self.nu;
        let w = &mut self.w;
        {
            let (u, grad) = (&w.u, &w.grad_u);
            let link_flux = &w.link_flux;
            let (ou, ol, os) = (Out::of(&mut w.upper), Out::of(&mut w.lower), Out::of(&mut w.link_src));
            par_for(links.len(), |l| {
                let (p, q) = (links.owner[l] as usize, links.neighbour[l] as usize);
                let alpha_f = links.interpolate(l, alpha[p], alpha[q]);
                let f = link_flux[l] - links.mesh_flux[l];
                let lambda = convection_weight(numerics.convection, numerics.linear_fraction, links.weight[l], &links.delta[l], f, vec_of(u, p), vec_of(u, q), |owner_upwind| {
                    grad[if owner_upwind { p } else { q }]
                });
                let gamma = nu * alpha_f;
                let d = gamma * links.laplacian[l];
                let grad_f = interpolate_tensor(links.weight[l], &grad[p], &grad[q]);
                let src = directional(&grad_f, &links.non_orthogonal[l]) * gamma + explicit_stress(&grad_f, &links.area[l]) * gamma;
                unsafe {
                    ou.set(l, alpha_f * f * (1.0 - lambda) - d);
                    ol.set(l, -alpha_f * f * lambda - d);
                    os.set(l, src);
                }
            });
        }
        let vol = &self.mesh.cell_volumes;
        let adj = &self.adj;
        let bnd = &self.boundary;
        let conditions = &self.conditions;
        let (dt, body) = (self.dt, self.body_force);
        let relax = numerics.relax_velocity;
        let (upper, lower, link_src) = (&w.upper, &w.lower, &w.link_src);
        let (u, grad, bflux, bu) = (&w.u, &w.grad_u, &w.boundary_flux, &w.boundary_u);
        let (od, os, ov) = (Out::of(&mut w.mom.diag), Out::of(&mut w.source), Out::of(&mut w.mom.val));
        par_for(n, |c| {
            let v = vol[c];
            let mut diag = c0 * alpha[c] * v / dt;
            let mut src = -(vec_of(&w.u_old, c) * (c1 * alpha_o[c]) + vec_of(&w.u_oo, c) * (c2 * alpha_oo[c])) * (v / dt);
            src += body * v;
            for k in adj.row_start[c] as usize..adj.row_start[c + 1] as usize {
                let e = adj.entry[k] as usize;
                let l = e >> 1;
                if e & 1 == 1 {
                    diag -= lower[l];
                    src += link_src[l];
                    unsafe { ov.set(k, upper[l]) };
                } else {
                    diag -= upper[l];
                    src -= link_src[l];
                    unsafe { ov.set(k, lower[l]) };
                }
            }
            for &b in &bnd.faces_of_cell[bnd.cell_start[c] as usize..bnd.cell_start[c + 1] as usize] {
                let b = b as usize;
                let alpha_p = alpha[c];
                let f = bflux[b] - bnd.mesh_flux[b];
                let gamma = nu * alpha_p;
                let d = gamma * bnd.area[b].norm() / bnd.normal_distance[b];
                match &conditions.conditions[bnd.condition[b] as usize] {
                    Condition::FixedVelocity { .. } => {
                        src -= bu[b] * (alpha_p * f);
                        diag += d;
                        src += bu[b] * d;
                    }
                    Condition::FixedPressure { .. } => diag += alpha_p * f,
                    Condition::Symmetry => {
                        diag += d;
                        src += bu[b] * d;
                    }
                }
                src += explicit_stress(&grad[c], &bnd.area[b]) * gamma;
            }
            let relaxed = diag / relax;
            src += vec_of(u, c) * (relaxed - diag);
            unsafe {
                od.set(c, relaxed);
                os.set(c, src);
            }
        });
    }

    /// Momentum predictor M u = b − V∇P* for every solved component.
    fn predictor(&mut self) -> Result<(), SolverError> {
        let w = &mut self.w;
        scalar_gradient(&self.links, &self.adj, &self.boundary, &self.mesh.cell_volumes, &w.p, &w.p_b, &mut w.grad_p);
        for j in 0..3 {
            if !self.solved[j] {
                continue;
            }
            let (src, gp, vol) = (&w.source, &w.grad_p, &self.mesh.cell_volumes);
            par_update(&mut w.rhs[j][..], |c, r| *r = src[c][j] - vol[c] * gp[c][j]);
            let clock = std::time::Instant::now();
            let stats = self.bicg.solve(&w.mom, &w.rhs[j], &mut w.u[j], self.settings.momentum);
            self.counts.momentum_seconds += clock.elapsed().as_secs_f64();
            self.counts.momentum_iterations += stats.iterations;
            if !stats.final_residual.is_finite() {
                return Err(SolverError::LinearSolve(format!("momentum predictor (component {j}): residual not finite")));
            }
            if let Some(message) = unconverged(&stats, self.settings.momentum) {
                return Err(SolverError::LinearSolve(format!("momentum predictor (component {j}): {message}")));
            }
        }
        Ok(())
    }

    /// Boundary pressures for cell pressure `p` (reference `pressure::boundary_pressures`).
    fn boundary_pressures(&self, p: &[f64], out: &mut [f64]) {
        let bnd = &self.boundary;
        let w = &self.w;
        for b in 0..bnd.len() {
            let c = bnd.cell[b] as usize;
            out[b] = match &self.conditions.conditions[bnd.condition[b] as usize] {
                Condition::FixedPressure { pressure } => *pressure,
                _ if !w.prescribed[b].is_nan() => {
                    let from_cell = |c: usize| (w.hbya[c].dot(&bnd.area[b]) - w.prescribed[b]) / (w.rau[c] * bnd.area[b].norm());
                    let g = match self.numerics.pressure_wall {
                        PressureWallCondition::ZeroGradient => 0.0,
                        PressureWallCondition::FixedFluxLinear if bnd.across[b] != NO_CELL => {
                            let (at_cell, at_across) = (from_cell(c), from_cell(bnd.across[b] as usize));
                            at_cell + bnd.across_ratio[b] * (at_cell - at_across)
                        }
                        PressureWallCondition::FixedFluxExtrapolated | PressureWallCondition::FixedFluxLinear => from_cell(c),
                    };
                    p[c] + bnd.normal_distance[b] * g
                }
                _ => p[c],
            };
        }
    }

    /// One PISO corrector (reference `pressure::correct`); returns the initial residual.
    fn correct(&mut self, tc: [f64; 3]) -> Result<f64, SolverError> {
        let n = self.mesh.n_cells();
        let nb = self.boundary.len();
        let [c0, c1, c2] = tc;
        let dt = self.dt;
        // HbyA and rAU from the latest velocity
        {
            let w = &mut self.w;
            for j in 0..3 {
                if !self.solved[j] {
                    continue;
                }
                w.mom.multiply_off_diagonal(&w.u[j], &mut w.offdiag);
                let (src, off, diag) = (&w.source, &w.offdiag, &w.mom.diag);
                let o = Out::of(&mut w.hbya);
                par_for(n, |c| unsafe { (&mut *o.ptr(c))[j] = (src[c][j] - off[c]) / diag[c] });
            }
            for j in 0..3 {
                if !self.solved[j] {
                    w.hbya.par_iter_mut().for_each(|h| h[j] = 0.0);
                }
            }
            let (vol, diag) = (&self.mesh.cell_volumes, &w.mom.diag);
            par_update(&mut w.rau[..], |c, r| *r = vol[c] / diag[c]);
            for b in 0..nb {
                if !w.prescribed[b].is_nan() {
                    w.boundary_flux[b] = w.prescribed[b];
                }
            }
            w.p_start.copy_from_slice(&w.p);
            w.p_work.copy_from_slice(&w.p);
        }
        let fluid = &self.fluid;
        let (alpha, alpha_o, alpha_oo) = (&fluid.alpha, &fluid.alpha_old, &fluid.alpha_old_old);
        let mut initial_residual = 0.0;
        let mut p_b = std::mem::take(&mut self.w.p_b);
        let non_orthogonal_correctors = if self.orthogonal == Some(true) { 0 } else { self.numerics.non_orthogonal_correctors };
        for corrector in 0..=non_orthogonal_correctors {
            // the pressure gradient enters only the explicit non-orthogonal flux term, below
            // 1e-12 of the gradient flux on orthogonal links ([`Self::links_orthogonal`]):
            // there it is dropped instead of computed (one gradient per corrector less)
            let orthogonal = self.orthogonal == Some(true);
            if !orthogonal {
                self.boundary_pressures(&self.w.p_work, &mut p_b);
            }
            let links = &self.links;
            let w = &mut self.w;
            if !orthogonal {
                scalar_gradient(links, &self.adj, &self.boundary, &self.mesh.cell_volumes, &w.p_work, &p_b, &mut w.grad_p);
            }
            {
                let (rau, hbya, gp, ddt_corr, gu) = (&w.rau, &w.hbya, &w.grad_p, &w.ddt_corr, &w.grad_u);
                let (oh, oc, oa) = (Out::of(&mut w.link_h), Out::of(&mut w.pcoef), Out::of(&mut w.ah));
                par_for(links.len(), |l| {
                    let (p, q) = (links.owner[l] as usize, links.neighbour[l] as usize);
                    let wt = links.weight[l];
                    let alpha_f = wt * alpha[p] + (1.0 - wt) * alpha[q];
                    let rau_f = wt * rau[p] + (1.0 - wt) * rau[q];
                    let mut hbya_f = hbya[p] * wt + hbya[q] * (1.0 - wt);
                    if l >= links.n_internal {
                        // overlap link: skewness correction (k·∇u)_f, as the reference's `pressure` (issue 12)
                        hbya_f += directional(&interpolate_tensor(wt, &gu[p], &gu[q]), &links.skew[l - links.n_internal]);
                    }
                    let non_orthogonal_flux = if orthogonal {
                        0.0
                    } else {
                        let grad_f = gp[p] * wt + gp[q] * (1.0 - wt);
                        rau_f * grad_f.dot(&links.non_orthogonal[l])
                    };
                    let h_flux = hbya_f.dot(&links.area[l]) - non_orthogonal_flux + rau_f * ddt_corr[l];
                    unsafe {
                        oh.set(l, h_flux);
                        oc.set(l, alpha_f * rau_f * links.laplacian[l]);
                        oa.set(l, alpha_f * h_flux);
                    }
                });
            }
            {
                let (adj, bnd, conditions, vol) = (&self.adj, &self.boundary, &self.conditions, &self.mesh.cell_volumes);
                let (pcoef, ah, rau, hbya, prescribed) = (&w.pcoef, &w.ah, &w.rau, &w.hbya, &w.prescribed);
                let (od, ov, orhs) = (Out::of(&mut w.pres.diag), Out::of(&mut w.pres.val), Out::of(&mut w.prhs));
                par_for(n, |c| {
                    let mut diag = 0.0;
                    let mut rhs = 0.0;
                    for k in adj.row_start[c] as usize..adj.row_start[c + 1] as usize {
                        let e = adj.entry[k] as usize;
                        let l = e >> 1;
                        diag += pcoef[l];
                        unsafe { ov.set(k, -pcoef[l]) };
                        if e & 1 == 1 {
                            rhs -= ah[l];
                        } else {
                            rhs += ah[l];
                        }
                    }
                    for &b in &bnd.faces_of_cell[bnd.cell_start[c] as usize..bnd.cell_start[c + 1] as usize] {
                        let b = b as usize;
                        match &conditions.conditions[bnd.condition[b] as usize] {
                            Condition::FixedPressure { pressure } => {
                                let k = alpha[c] * rau[c] * bnd.area[b].norm() / bnd.normal_distance[b];
                                diag += k;
                                rhs += k * pressure - alpha[c] * hbya[c].dot(&bnd.area[b]);
                            }
                            _ if !prescribed[b].is_nan() => rhs -= alpha[c] * prescribed[b],
                            _ => {}
                        }
                    }
                    rhs -= (c0 * alpha[c] + c1 * alpha_o[c] + c2 * alpha_oo[c]) * vol[c] / dt;
                    unsafe {
                        od.set(c, diag);
                        orhs.set(c, rhs);
                    }
                });
            }
            if !self.conditions.has_fixed_pressure {
                w.pres.diag[0] *= 2.0;
            }
            // once per momentum assembly (the matrix is the same until the next one); the
            // aggregation is rebuilt only when the sparsity pattern changed (the overlap links
            // moved), otherwise only the hierarchy's values follow the new matrix
            if self.amg_after_assembly != Some(self.momentum_assemblies) {
                let clock = std::time::Instant::now();
                self.amg.setup(&w.pres);
                self.amg_after_assembly = Some(self.momentum_assemblies);
                self.counts.amg_setup_seconds += clock.elapsed().as_secs_f64();
            }
            let clock = std::time::Instant::now();
            let stats = self.pcg.solve(&w.pres, &w.prhs, &mut w.p_work, &mut self.amg, self.settings.pressure);
            self.counts.pressure_seconds += clock.elapsed().as_secs_f64();
            if let Some(slot) = self.counts.pressure_per_solve.get_mut(self.counts.pressure_solves) {
                *slot = stats.iterations.min(u16::MAX as usize) as u16;
            }
            self.counts.pressure_solves += 1;
            self.counts.pressure_iterations += stats.iterations;
            if corrector == 0 {
                // CG starts from p_work = p_start, so its initial residual is this corrector's
                initial_residual = stats.initial_residual;
            }
            if !stats.final_residual.is_finite() {
                self.w.p_b = p_b;
                return Err(SolverError::LinearSolve("pressure equation: residual not finite".into()));
            }
            if let Some(message) = unconverged(&stats, self.settings.pressure) {
                self.w.p_b = p_b;
                return Err(SolverError::LinearSolve(format!("pressure equation: {message}")));
            }
        }
        // conservative fluxes from the final pressure (T4.28)
        {
            let links = &self.links;
            let w = &mut self.w;
            let (rau, pw, lh) = (&w.rau, &w.p_work, &w.link_h);
            par_update(&mut w.link_flux[..], |l, f| {
                let (p, q) = (links.owner[l] as usize, links.neighbour[l] as usize);
                let rau_f = links.interpolate(l, rau[p], rau[q]);
                *f = lh[l] - rau_f * links.laplacian[l] * (pw[q] - pw[p]);
            });
            let bnd = &self.boundary;
            for b in 0..nb {
                if let Condition::FixedPressure { pressure } = &self.conditions.conditions[bnd.condition[b] as usize] {
                    let c = bnd.cell[b] as usize;
                    w.boundary_flux[b] = w.hbya[c].dot(&bnd.area[b]) - w.rau[c] * bnd.area[b].norm() / bnd.normal_distance[b] * (pressure - w.p_work[c]);
                }
            }
            let relax = self.numerics.relax_pressure;
            let (ps, pw) = (&w.p_start, &w.p_work);
            par_update(&mut w.p[..], |c, p| *p = ps[c] + relax * (pw[c] - ps[c]));
        }
        self.boundary_pressures(&self.w.p, &mut p_b);
        let w = &mut self.w;
        w.p_b = p_b;
        scalar_gradient(&self.links, &self.adj, &self.boundary, &self.mesh.cell_volumes, &w.p, &w.p_b, &mut w.grad_p);
        for j in 0..3 {
            let (h, r, g) = (&w.hbya, &w.rau, &w.grad_p);
            let solved = self.solved[j];
            par_update(&mut w.u[j][..], |c, u| *u = if solved { h[c][j] - r[c] * g[c][j] } else { 0.0 });
        }
        Ok(initial_residual)
    }

    /// Diagnostics and step 5 (shift the time levels).
    fn finish_step(&mut self, tc: [f64; 3], outer_iterations: usize, last_residual: f64, report: &mut StepReport) -> f64 {
        let [c0, c1, c2] = tc;
        let dt = self.dt;
        let n = self.mesh.n_cells();
        let links = &self.links;
        let bnd = &self.boundary;
        let adj = &self.adj;
        let vol = &self.mesh.cell_volumes;
        let w = &mut self.w;
        let fluid = &mut self.fluid;
        let (local, global, courant, kinetic);
        {
            let (alpha, alpha_o, alpha_oo) = (&fluid.alpha, &fluid.alpha_old, &fluid.alpha_old_old);
            let (lf, bf) = (&w.link_flux, &w.boundary_flux);
            let o = Out::of(&mut w.errors);
            let oc = Out::of(&mut w.ax);
            par_for(n, |c| {
                let mut e = (c0 * alpha[c] + c1 * alpha_o[c] + c2 * alpha_oo[c]) * vol[c] / dt;
                let mut s = 0.0;
                for k in adj.row_start[c] as usize..adj.row_start[c + 1] as usize {
                    let ent = adj.entry[k] as usize;
                    let l = ent >> 1;
                    let alpha_f = links.interpolate(l, alpha[links.owner[l] as usize], alpha[links.neighbour[l] as usize]);
                    if ent & 1 == 1 {
                        e += alpha_f * lf[l];
                    } else {
                        e -= alpha_f * lf[l];
                    }
                    s += (lf[l] - links.mesh_flux[l]).abs();
                }
                for &b in &bnd.faces_of_cell[bnd.cell_start[c] as usize..bnd.cell_start[c + 1] as usize] {
                    let b = b as usize;
                    e += alpha[c] * bf[b];
                    s += (bf[b] - bnd.mesh_flux[b]).abs();
                }
                unsafe {
                    o.set(c, e);
                    oc.set(c, 0.5 * dt * s / vol[c]);
                }
            });
            let (errors, cour, u) = (&w.errors, &w.ax, &w.u);
            let [sa, sg] = self.red.sum2(n, |c| [errors[c].abs(), errors[c]]);
            local = dt * sa;
            global = dt * sg;
            courant = self.red.max(n, |c| cour[c]).max(0.0);
            kinetic = self.red.sum(n, |c| 0.5 * alpha[c] * (u[0][c] * u[0][c] + u[1][c] * u[1][c] + u[2][c] * u[2][c]) * vol[c]);
        }
        // interface imbalance and the face fluxes of the state
        let nf = self.mesh.n_faces();
        let mut throughput = 0.0;
        for k in 0..links.len() - links.n_internal {
            let l = links.n_internal + k;
            let (r, s) = (links.rotor_face[k] as usize, links.stator_face[k] as usize);
            w.face_sum[r] = 0.0;
            w.face_sum[s] = 0.0;
            let _ = l;
        }
        for k in 0..links.len() - links.n_internal {
            let l = links.n_internal + k;
            let (r, s) = (links.rotor_face[k] as usize, links.stator_face[k] as usize);
            w.face_sum[r] += w.link_flux[l];
            w.face_sum[s] -= w.link_flux[l];
            w.face_used[r] = true;
            w.face_used[s] = true;
            throughput += w.link_flux[l].abs();
        }
        let imbalance = if throughput == 0.0 {
            0.0
        } else {
            let mut net = 0.0;
            for f in 0..nf {
                if w.face_used[f] {
                    net += w.face_sum[f];
                }
            }
            net.abs() / throughput
        };

        for c in 0..n {
            fluid.velocity_old[c] = fluid.velocity[c];
            fluid.velocity[c] = [w.u[0][c], w.u[1][c], w.u[2][c]];
        }
        fluid.pressure.copy_from_slice(&w.p);
        std::mem::swap(&mut fluid.flux, &mut fluid.flux_old);
        fluid.flux.fill(0.0);
        fluid.flux[..links.n_internal].copy_from_slice(&w.link_flux[..links.n_internal]);
        for f in 0..nf {
            if w.face_used[f] {
                fluid.flux[f] = w.face_sum[f];
                w.face_used[f] = false;
            }
        }
        let nif = self.mesh.n_internal_faces;
        for b in 0..bnd.len() {
            let face = bnd.face[b] as usize;
            fluid.flux[face] = w.boundary_flux[b];
            fluid.boundary_pressure[face - nif] = w.p_b[b];
        }
        fluid.alpha_old_old.copy_from_slice(&fluid.alpha_old);
        fluid.alpha_old.copy_from_slice(&fluid.alpha);
        fluid.cumulative_continuity_error += global;
        let cumulative = fluid.cumulative_continuity_error;
        self.dt_old = dt;
        // appended: a report reused across steps keeps its storage
        report.values.extend_from_slice(&[
            ("courant_max", courant),
            ("continuity_local", local),
            ("continuity_global", global),
            ("continuity_cumulative", cumulative),
            ("kinetic_energy", kinetic),
            ("outer_iterations", outer_iterations as f64),
            ("p_initial_residual", last_residual),
            ("interface_imbalance", imbalance),
        ]);
        courant
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
    fn advance(&mut self, ctx: &StepContext, fluid: &mut FluidState, load: Option<&ParticleLoad>, report: &mut StepReport) -> Result<FluidStepOutcome, SolverError> {
        if load.is_some() {
            return Err(unsupported("two-way coupling (a particle load on the fluid) is not implemented yet"));
        }
        self.dt = ctx.dt;
        self.time_coefficients = ctx.time_coefficients;
        self.step_number = ctx.step;
        self.step_time_end = ctx.time_end();
        self.turn_rotor(ctx.rotor.as_ref())?;
        std::mem::swap(&mut self.fluid, fluid);
        // Called from outside the thread pool, every parallel loop of the step would be handed
        // to a worker and waited for (a cross-thread wake-up per loop, hundreds per step);
        // running the whole step on a worker hands over once. Same arithmetic either way.
        let result = if rayon::current_thread_index().is_some() { self.advance_timed(report) } else { rayon::scope(|_| self.advance_timed(report)) };
        std::mem::swap(&mut self.fluid, fluid);
        result
    }

    fn sample(&self, fluid: &FluidState, particles: &[Particle], out: &mut Vec<Option<FluidAtParticle>>) {
        spillage_model::fluid::sampling::sample_containing_cell(&self.mesh, fluid, self.density, self.nu, self.dt_old, particles, out);
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
