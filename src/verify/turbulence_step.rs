//! The backward-facing step of Driver & Seegmiller (1985) (issue 18 item 2): the reattachment
//! length of the separated flow behind the step, from the wall shear along the lower wall.
//!
//! Run with the fast fluid (6 000 cells, hundreds of steps: the reference's direct solves make
//! it minutes); the two solvers' agreement on this geometry (solid block, inlet, outlet, walls)
//! is tested step by step on a coarse copy in tests/turbulence.rs.

use std::path::Path;

use anyhow::{anyhow, bail, Context, Result};
use spillage_fast::fluid::FastFluid;
use spillage_model::case::Case;
use spillage_model::mesh::Mesh;
use spillage_model::output::plot::{write_png, Plot, Series};
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::step::{Coupled, FluidOnly};

use super::fluid::build_mesh;
use super::CheckRow;

/// Driver & Seegmiller (1985), 0° top wall: x_r = 6.26 H (±0.10 H).
const MEASURED_REATTACHMENT: f64 = 6.26;

/// Reattachment length in step heights and the wall-adjacent u_x(x) downstream of the step.
pub struct StepResult {
    /// Mean over the last tenth of the steps (the reattachment point keeps a small oscillation).
    pub reattachment: f64,
    /// At the last step.
    pub wall_velocity: Vec<(f64, f64)>,
    /// (largest − smallest) reattachment over the last tenth of the steps, over the mean.
    pub reattachment_spread: f64,
}

/// u_x of the cells on the lower wall (patch `y_min`) downstream of the step (x > 0), by x.
fn wall_velocity(mesh: &Mesh, state: &State) -> Result<Vec<(f64, f64)>> {
    let fluid = state.fluid.as_ref().ok_or_else(|| anyhow!("the run has no fluid state"))?;
    let patch = mesh.patch("y_min").map_err(|e| anyhow!("{e}"))?;
    let mut points: Vec<(f64, f64)> =
        patch.faces().map(|f| mesh.face_owner[f]).filter(|&c| mesh.cell_centres[c].x > 0.0).map(|c| (mesh.cell_centres[c].x, fluid.velocity[c][0])).collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    points.dedup_by(|a, b| (a.0 - b.0).abs() < 1e-12);
    Ok(points)
}

/// The downstream-most change of u_x from backward to forward flow along the wall, linearly
/// interpolated (the corner eddy right behind the step turns the other way and is skipped).
pub fn reattachment(points: &[(f64, f64)]) -> Option<f64> {
    points.windows(2).filter(|w| w[0].1 < 0.0 && w[1].1 >= 0.0).map(|w| w[0].0 + (w[1].0 - w[0].0) * (-w[0].1) / (w[1].1 - w[0].1)).last()
}

pub fn run_step(case: &Case) -> Result<StepResult> {
    let mesh = build_mesh(case)?;
    let mut state = State::default();
    let fluid = FastFluid::new(case, mesh.clone(), &mut state)?;
    let mut solver: FluidOnly<FastFluid> = Coupled::new(case, state, Some(fluid), None)?;
    let steps = case.time.steps.ok_or_else(|| anyhow!("{}: the step check needs time.steps", case.path.display()))?;
    let tail = (steps / 10).max(1);
    let (mut lo, mut hi, mut sum) = (f64::INFINITY, f64::NEG_INFINITY, 0.0);
    let mut last = None;
    for step in 0..steps {
        solver.step().with_context(|| format!("case {} step {}", case.case.name, step + 1))?;
        if step >= steps - tail {
            let wall_velocity = wall_velocity(&mesh, solver.state())?;
            let x_r = reattachment(&wall_velocity).ok_or_else(|| anyhow!("{}: the flow does not separate behind the step", case.path.display()))?;
            lo = lo.min(x_r);
            hi = hi.max(x_r);
            sum += x_r;
            last = Some(wall_velocity);
        }
    }
    let wall_velocity = last.ok_or_else(|| anyhow!("{}: no steps run", case.path.display()))?;
    let reattachment = sum / tail as f64;
    Ok(StepResult { reattachment, wall_velocity, reattachment_spread: (hi - lo) / reattachment })
}

pub fn backward_facing_step(case: &Case, plots: Option<&Path>) -> Result<Vec<CheckRow>> {
    let name = case.case.name.as_str();
    let Some(params) = case.verify.as_ref().map(|v| &v.params) else { bail!("no [verify]") };
    let step_height =
        params.get("step_height").and_then(|v| v.as_float()).ok_or_else(|| anyhow!("[verify.params] step_height: missing; expected a length in m"))?;
    let result = run_step(case)?;
    let x_r = result.reattachment / step_height;
    if let Some(dir) = plots {
        std::fs::create_dir_all(dir)?;
        let scaled: Vec<(f64, f64)> = result.wall_velocity.iter().map(|(x, u)| (x / step_height, *u)).collect();
        let measured = [(MEASURED_REATTACHMENT, -0.2), (MEASURED_REATTACHMENT, 0.2)];
        let title = format!("{name}: wall-cell velocity, reattachment x/H = {x_r:.2}");
        let series =
            vec![Series { label: "computed u_x of the wall cells", points: &scaled }, Series { label: "measured reattachment, 6.26 H", points: &measured }];
        let plot = Plot { title: &title, x_label: "x / H [-]", y_label: "u_x / U [-]", log_x: false, log_y: false, series };
        write_png(&plot, &dir.join(format!("{name}_wall_velocity.png")))?;
    }
    Ok(vec![
        // 15 %: the bound (k–ε models under-predict the measured 6.26 H)
        CheckRow::relative(name, "mean reattachment length x_r/H vs Driver & Seegmiller", "fast", x_r, MEASURED_REATTACHMENT, 0.15),
        // settled: x_r moves by less than 5 % over the last tenth of the steps, a third of the
        // tolerance above. The URANS solution keeps a small oscillation of the reattachment
        // point (measured spread 2.9 % with 5 outer iterations per step, 1.4 % with 15)
        CheckRow::at_most(name, "reattachment spread over the last 10 % of steps (rel)", "fast", result.reattachment_spread, 0.05),
    ])
}
