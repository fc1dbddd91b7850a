//! Verification procedures of the reference fluid solver (issue #4): circular Couette flow
//! (wall velocity and sliding mesh), free-stream preservation across a sliding interface,
//! plane Poiseuille flow and the 2-D Taylor–Green vortex.
//!
//! Each check runs the case at several mesh levels (`[verify.params] levels`, plus
//! `full_levels` under `--full`), compares with the closed-form solution and reports errors and
//! observed orders as [`CheckRow`]s. Exact solutions are the formulas of the spec
//! (spillage-and-flow-verification.md §3.2; textbook Poiseuille and Taylor–Green).
// TODO(analytic): use spillage-analytic's Couette/channel closed forms once on main.

use anyhow::{anyhow, bail, Context, Result};
use spillage_fast::fluid::FastFluid;
use spillage_model::case::{Case, MeshSection};
use spillage_model::fluid::settings::{BoundaryCondition, InitialVelocity};
use spillage_model::mesh::{Mesh, Vec3};
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::step::{Coupled, FluidPhase};
use spillage_reference::fluid::ReferenceFluid;

use super::figures::convergence;
use super::{CheckRow, FluidSolver};
use std::path::Path;

/// Checks implemented here.
pub const CHECKS: &[&str] = &["fluid_couette", "fluid_free_stream", "fluid_poiseuille", "fluid_taylor_green"];

mod couette;
use couette::couette;
pub use couette::couette_u_theta_error;

/// Runs `check` with the `solver` fluid; with `plots`, draws its figures there (convergence of
/// the errors against h with a slope-2 guide; the Couette profiles against the exact ones).

pub fn run_check(case: &Case, check: &str, full: bool, plots: Option<&Path>, solver: FluidSolver) -> Result<Vec<CheckRow>> {
    match check {
        "fluid_couette" => couette(case, full, plots, solver),
        "fluid_free_stream" => free_stream(case, solver),
        "fluid_poiseuille" => poiseuille(case, full, plots, solver),
        "fluid_taylor_green" => taylor_green(case, full, plots, solver),
        other => bail!("unknown fluid check `{other}`; known: {}", CHECKS.join(", ")),
    }
}

// ---------------------------------------------------------------------------------------------
// mesh and run helpers

/// Builds the mesh of `case.mesh` (the z faces of a 2-D mesh marked empty) or of its
/// `[cutter_head]`.
pub fn build_mesh(case: &Case) -> Result<Mesh> {
    Ok(spillage_model::mesh::for_case(case).ok_or_else(|| anyhow!("the case has no [mesh] or [cutter_head]"))??)
}

/// What a run reports besides its final state.
struct RunSummary {
    max_interface_imbalance: f64,
    max_continuity_local: f64,
    max_courant: f64,
    /// Courant number of the last step.
    final_courant: f64,
    steps: u64,
    /// Steps that used all `max_outer_iterations` with the initial pressure residual still
    /// above `p_initial_residual` (their result is not the solution of the discrete equations).
    unconverged_steps: u64,
    /// Initial pressure residual of the last outer iteration of the last step.
    last_residual: f64,
}

/// The end of a run: its state, its mesh (rotor turned) and the cell gradient of its pressure.
struct Finished {
    state: State,
    mesh: Mesh,
    /// The reference solver's cell (Gauss) gradient of the kinematic pressure, for either
    /// solver's state (the field the momentum equation uses; the same operator for both so the
    /// rows compare the solutions, not two gradient codes).
    pressure_gradient: Vec<Vec3>,
}

impl Finished {
    fn fluid(&self) -> &spillage_model::fluid::state::FluidState {
        self.state.fluid.as_ref().expect("a fluid run")
    }
}

/// Runs the `solver` fluid to `case.time.end_time` (or `steps`).
fn run(case: &Case, solver: FluidSolver) -> Result<(Finished, RunSummary)> {
    let mesh = build_mesh(case)?;
    let mut state = State::default();
    let ((end_state, end_mesh, pose), summary) = match solver {
        FluidSolver::Reference => {
            let fluid = ReferenceFluid::new(case, mesh, &mut state)?;
            run_with(case, Coupled::new(case, state, Some(fluid), None)?)?
        }
        FluidSolver::Fast => {
            let fluid = FastFluid::new(case, mesh, &mut state)?;
            run_with(case, Coupled::new(case, state, Some(fluid), None)?)?
        }
    };
    let mut gradient = ReferenceFluid::new(case, build_mesh(case)?, &mut State::default())?;
    gradient.place_rotor(pose.as_ref())?;
    let pressure_gradient = gradient.pressure_gradient(end_state.fluid.as_ref().ok_or_else(|| anyhow!("no fluid state"))?);
    Ok((Finished { state: end_state, mesh: end_mesh, pressure_gradient }, summary))
}

type Ended = (State, Mesh, Option<spillage_model::step::RotorPose>);

fn run_with<F: FluidPhase>(case: &Case, mut solver: Coupled<F>) -> Result<(Ended, RunSummary)> {
    // a fixed step runs a known number of steps; `max_courant` runs until the driver lands on
    // end_time (src/run.rs, the same rule)
    let (steps, end_time) = match (case.time.dt, case.time.steps, case.time.end_time) {
        (_, Some(n), _) => (n, None),
        (Some(dt), None, Some(t)) => ((t / dt - 1e-9).ceil() as u64, None),
        (None, None, Some(t)) => (u64::MAX, Some(t)),
        (_, None, None) => bail!("the case has neither time.steps nor time.end_time"),
    };
    let mut summary = RunSummary {
        max_interface_imbalance: 0.0,
        max_continuity_local: 0.0,
        max_courant: 0.0,
        final_courant: 0.0,
        steps: 0,
        unconverged_steps: 0,
        last_residual: f64::NAN,
    };
    for _ in 0..steps {
        if end_time.is_some_and(|end| spillage_model::step::reached_end_time(solver.state().time, end)) {
            break;
        }
        summary.steps += 1;
        let report = solver.step().with_context(|| format!("case {}", case.case.name))?;
        let value = |key: &str| report.values.iter().find(|(k, _)| *k == key).map(|(_, v)| *v);
        if let (Some(outer), Some(residual)) = (value("outer_iterations"), value("p_initial_residual")) {
            summary.last_residual = residual;
            if outer as usize >= case.numerics.max_outer_iterations && residual >= case.numerics.p_initial_residual {
                summary.unconverged_steps += 1;
            }
        }
        for (name, value) in report.values {
            match name {
                "interface_imbalance" => summary.max_interface_imbalance = summary.max_interface_imbalance.max(value),
                "continuity_local" => summary.max_continuity_local = summary.max_continuity_local.max(value),
                "courant_max" => {
                    summary.max_courant = summary.max_courant.max(value);
                    summary.final_courant = value;
                }
                _ => {}
            }
        }
    }
    let mesh = solver.mesh().ok_or_else(|| anyhow!("no mesh"))?.clone();
    Ok(((solver.state().clone(), mesh, solver.rotor()), summary))
}

fn param_f64(case: &Case, key: &str) -> Result<f64> {
    let params = &case.verify.as_ref().ok_or_else(|| anyhow!("no [verify]"))?.params;
    params
        .get(key)
        .and_then(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
        .ok_or_else(|| anyhow!("[verify.params] {key}: missing; expected a number"))
}

fn param_bool(case: &Case, key: &str) -> bool {
    case.verify.as_ref().and_then(|v| v.params.get(key)).and_then(|v| v.as_bool()).unwrap_or(false)
}

fn param_f64_or(case: &Case, key: &str, default: f64) -> f64 {
    param_f64(case, key).unwrap_or(default)
}

fn param_list(case: &Case, key: &str) -> Result<Vec<Vec<f64>>> {
    let params = &case.verify.as_ref().ok_or_else(|| anyhow!("no [verify]"))?.params;
    let Some(value) = params.get(key) else { return Ok(Vec::new()) };
    let array = value.as_array().ok_or_else(|| anyhow!("[verify.params] {key}: expected an array"))?;
    array
        .iter()
        .map(|item| {
            let row = match item.as_array() {
                Some(row) => row.clone(),
                None => vec![item.clone()],
            };
            row.iter()
                .map(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)).ok_or_else(|| anyhow!("[verify.params] {key}: expected numbers")))
                .collect()
        })
        .collect()
}

/// Mesh levels: `levels`, plus `full_levels` under `--full`; each level is a list of numbers
/// and the matching entry of `dt` (and `full_dt`) is its time step.
fn levels(case: &Case, full: bool) -> Result<Vec<(Vec<f64>, f64)>> {
    let mut levels = param_list(case, "levels")?;
    let mut dts: Vec<f64> = param_list(case, "dt")?.into_iter().flatten().collect();
    if full {
        levels.extend(param_list(case, "full_levels")?);
        dts.extend(param_list(case, "full_dt")?.into_iter().flatten());
    }
    if levels.len() < 2 || dts.len() != levels.len() {
        bail!("[verify.params]: need ≥ 2 `levels` and one `dt` per level (got {} levels, {} dt)", levels.len(), dts.len());
    }
    Ok(levels.into_iter().zip(dts).collect())
}

fn observed_order(e_coarse: f64, e_fine: f64, h_ratio: f64) -> f64 {
    (e_coarse / e_fine).ln() / h_ratio.ln()
}

fn with_dt(case: &Case, dt: f64) -> Case {
    let mut c = case.clone();
    c.time.dt = Some(dt);
    c
}

// ---------------------------------------------------------------------------------------------
// free-stream preservation across a non-conformal interface

fn free_stream(case: &Case, solver: FluidSolver) -> Result<Vec<CheckRow>> {
    let name = &case.case.name;
    let label = solver.label();
    let Some(fluid) = &case.fluid else { bail!("no [fluid]") };
    let InitialVelocity::Uniform { velocity } = fluid.initial else { bail!("free-stream check needs fluid.initial.type = \"uniform\"") };
    let u0 = Vec3::from(velocity);
    let (end, summary) = run(case, solver)?;
    let f = end.fluid();
    let dev = f.velocity.iter().map(|u| (Vec3::from(*u) - u0).norm()).fold(0.0, f64::max) / u0.norm();
    let p_spread = f.pressure.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b)) - f.pressure.iter().fold(f64::INFINITY, |a, &b| a.min(b));
    // round-off: a few hundred operations on numbers of order 1 per cell and step
    let tol = param_f64_or(case, "tolerance", 1e-12);
    Ok(vec![
        CheckRow::at_most(name, format!("max |u − U|/|U| after {} steps", summary.steps), label, dev, tol),
        CheckRow::at_most(name, "pressure spread / |U|²", label, p_spread / u0.norm_squared(), tol),
        CheckRow::at_most(name, "interface flux imbalance (max over steps)", label, summary.max_interface_imbalance, tol),
    ])
}

// ---------------------------------------------------------------------------------------------
// plane Poiseuille flow

/// Box mesh level: `cells[dir] = n` for the wall-normal direction y, x scaled alike if
/// `scale_x` (inlet/outlet channels keep the cell aspect ratio).
fn box_level(case: &Case, n_y: usize, scale_x: bool) -> Result<Case> {
    let mut c = case.clone();
    match c.mesh.as_mut() {
        Some(MeshSection::Box { cells, .. }) => {
            if scale_x {
                cells[0] = cells[0] * n_y / cells[1];
            }
            cells[1] = n_y;
        }
        _ => bail!("the channel check needs mesh.generator = \"box\""),
    }
    Ok(c)
}

/// Plane Poiseuille flow between walls at y = y_min and y_max, along x.
///
/// Periodic variant (`drive = "body_force"`): u = g/(2ν)(y − y₀)(H − (y − y₀)). Inlet/outlet
/// variant (`drive = "inlet"`): the developed profile of mean velocity U, u = 6U η(H − η)/H².
///
/// On a *uniform* mesh the exact solution of the discrete equations is known in closed form:
/// the cell-centre parabola satisfies the interior three-point Laplacian exactly, and the
/// two-point wall gradient (u₁ − 0)/(h/2) is short of the exact wall shear by a constant, so the
/// discrete profile is the parabola shifted by δ = g h²/(8ν) (periodic, fixed g), or, at fixed
/// flow rate (midpoint sum of the parabola = H³/6 + h²H/12), u_i = 6U/(H² + 2h²)·[η_i(H − η_i) + h²/4]. The uniform levels are compared with this
/// discrete solution to solver tolerance, and the graded levels with the exact profile for the
/// observed order.
fn poiseuille(case: &Case, full: bool, plots: Option<&Path>, solver: FluidSolver) -> Result<Vec<CheckRow>> {
    let name = &case.case.name;
    let label = solver.label();
    let Some(MeshSection::Box { min, max, grading, .. }) = case.mesh.as_ref() else { bail!("needs a box mesh") };
    let (y0, height) = (min[1], max[1] - min[1]);
    let nu = case.fluid.as_ref().ok_or_else(|| anyhow!("no [fluid]"))?.kinematic_viscosity;
    let params = &case.verify.as_ref().ok_or_else(|| anyhow!("no [verify]"))?.params;
    let drive = params.get("drive").and_then(|v| v.as_str()).unwrap_or("body_force");
    let uniform = grading[1] == 1.0;
    let (g, mean_u) = match drive {
        "body_force" => (case.numerics.body_force[0], None),
        "inlet" => match case.boundary.get("x_min") {
            Some(BoundaryCondition::VelocityInlet { velocity, .. }) => (0.0, Some(velocity[0])),
            _ => bail!("drive = \"inlet\" needs a velocity_inlet on x_min"),
        },
        other => bail!("[verify.params] drive = {other:?}: expected \"body_force\" or \"inlet\""),
    };
    // cells compared: those with x in [x_lo, x_hi] (fraction of the length), all for periodic
    let x_lo = param_f64_or(case, "compare_x_from", 0.0);
    let x_hi = param_f64_or(case, "compare_x_to", 1.0);
    let mut rows = Vec::new();
    let mut errors = Vec::new();
    for (level, dt) in levels(case, full)? {
        let n_y = level[0] as usize;
        let c = with_dt(&box_level(case, n_y, drive == "inlet")?, dt);
        let (end, _) = run(&c, solver)?;
        let (mesh, fluid) = (&end.mesh, end.fluid());
        let h = height / n_y as f64;
        let (mut sum2, mut count, mut max_err, mut u_max) = (0.0, 0usize, 0.0f64, 0.0f64);
        for cell in 0..mesh.cell_volumes.len() {
            let x = mesh.cell_centres[cell];
            let fx = (x.x - min[0]) / (max[0] - min[0]);
            if fx < x_lo || fx > x_hi {
                continue;
            }
            let eta = x.y - y0;
            let (exact, discrete) = match mean_u {
                None => {
                    let e = g / (2.0 * nu) * eta * (height - eta);
                    (e, e + g * h * h / (8.0 * nu))
                }
                Some(u) => {
                    (6.0 * u * eta * (height - eta) / (height * height), 6.0 * u / (height * height + 2.0 * h * h) * (eta * (height - eta) + h * h / 4.0))
                }
            };
            let target = if uniform { discrete } else { exact };
            let err = fluid.velocity[cell][0] - target;
            sum2 += (fluid.velocity[cell][0] - exact).powi(2);
            count += 1;
            max_err = max_err.max(err.abs());
            u_max = u_max.max(exact.abs());
        }
        let rms = (sum2 / count as f64).sqrt() / u_max;
        if uniform {
            let tol = param_f64(case, "discrete_tolerance")?;
            rows.push(CheckRow::at_most(name, format!("max |u − u_discrete|/u_max, uniform {n_y} cells"), label, max_err / u_max, tol));
        }
        rows.push(CheckRow::at_most(name, format!("rms |u − u_exact|/u_max {n_y} cells"), label, rms, f64::INFINITY));
        errors.push((n_y as f64, rms));
    }
    if let Ok(min_order) = param_f64(case, "min_order_u") {
        for w in errors.windows(2) {
            let p = observed_order(w[0].1, w[1].1, w[1].0 / w[0].0);
            rows.push(CheckRow::at_least(name, format!("observed order u {}→{} cells", w[0].0, w[1].0), label, p, min_order));
        }
    }
    let spacing: Vec<(f64, f64)> = errors.iter().map(|(n, e)| (height / n, *e)).collect();
    let title = format!("{name}: error against the wall-normal cell size");
    convergence(
        plots,
        &format!("{name}_convergence"),
        &title,
        "wall-normal cell size Δy [m]",
        "rms |u − u_exact| / u_max [−]",
        &[("velocity error", spacing)],
    )?;
    Ok(rows)
}

// ---------------------------------------------------------------------------------------------
// 2-D Taylor–Green vortex

/// Periodic box of side 2πL, u = U sin(x/L) cos(y/L) e^{−2νt/L²}, v = −U cos(x/L) sin(y/L) e^{−2νt/L²};
/// kinetic energy decays as e^{−4νt/L²}. Space and time are refined together (Δt ∝ h).
fn taylor_green(case: &Case, full: bool, plots: Option<&Path>, solver: FluidSolver) -> Result<Vec<CheckRow>> {
    let name = &case.case.name;
    let label = solver.label();
    let fluid = case.fluid.as_ref().ok_or_else(|| anyhow!("no [fluid]"))?;
    let InitialVelocity::TaylorGreen { speed, length } = fluid.initial else { bail!("needs fluid.initial.type = \"taylor_green\"") };
    let nu = fluid.kinematic_viscosity;
    let mut rows = Vec::new();
    let mut errors = Vec::new();
    for (level, dt) in levels(case, full)? {
        let n = level[0] as usize;
        let mut c = with_dt(case, dt);
        if let Some(MeshSection::Box { cells, .. }) = c.mesh.as_mut() {
            cells[0] = n;
            cells[1] = n;
        } else {
            bail!("needs a box mesh");
        }
        let mesh = build_mesh(&c)?;
        let u0: Vec<Vec3> = mesh.cell_centres.iter().map(|x| Vec3::from(fluid.initial.velocity_at([x.x, x.y, x.z], None))).collect();
        let ke0: f64 = u0.iter().zip(&mesh.cell_volumes).map(|(u, v)| 0.5 * u.norm_squared() * v).sum();
        let (end, summary) = run(&c, solver)?;
        let t = end.state.time;
        let (mesh, f) = (&end.mesh, end.fluid());
        let decay = (-2.0 * nu * t / (length * length)).exp();
        let ke: f64 = f.velocity.iter().zip(&mesh.cell_volumes).map(|(u, v)| 0.5 * Vec3::from(*u).norm_squared() * v).sum();
        let ke_error = (ke / ke0 - decay * decay).abs();
        let mut sum2 = 0.0;
        for (cell, u) in f.velocity.iter().enumerate() {
            let exact = u0[cell] * decay;
            sum2 += (Vec3::from(*u) - exact).norm_squared();
        }
        let u_rms = (sum2 / f.velocity.len() as f64).sqrt() / speed;
        rows.push(CheckRow::at_most(name, format!("|KE/KE0 − exp(−4νt/L²)| {n}x{n}"), label, ke_error, f64::INFINITY));
        rows.push(CheckRow::at_most(name, format!("rms |u − u_exact|/U {n}x{n}"), label, u_rms, f64::INFINITY));
        // an unconverged outer loop leaves an error that does not shrink with h or Δt
        rows.push(CheckRow::at_most(name, format!("steps without outer-loop convergence {n}x{n}"), label, summary.unconverged_steps as f64, 0.0));
        errors.push((n as f64, ke_error, u_rms));
    }
    let min_order = param_f64(case, "min_order")?;
    for w in errors.windows(2) {
        let h = w[1].0 / w[0].0;
        let pair = format!("{}→{}", w[0].0, w[1].0);
        rows.push(CheckRow::at_least(name, format!("observed order KE decay {pair}"), label, observed_order(w[0].1, w[1].1, h), min_order));
        rows.push(CheckRow::at_least(name, format!("observed order velocity {pair}"), label, observed_order(w[0].2, w[1].2, h), min_order));
    }
    let side = std::f64::consts::TAU * length;
    let ke: Vec<(f64, f64)> = errors.iter().map(|(n, e, _)| (side / n, *e)).collect();
    let u: Vec<(f64, f64)> = errors.iter().map(|(n, _, e)| (side / n, *e)).collect();
    let title = format!("{name}: error against the cell size (Δt ∝ h)");
    convergence(plots, &format!("{name}_convergence"), &title, "cell size h [m]", "error [−]", &[("|KE/KE₀ − exact|", ke), ("rms |u − u_exact| / U", u)])?;
    Ok(rows)
}
