//! U-33 in its static form (fluid-dem-model.md §2.6, §12 U-33; issue 13 verification item 5):
//! a uniform suspension held at its terminal settling velocity in a closed column
//! (`[particles] motion = "held"`) must give the fluid a pressure gradient of ρ_m g to solver
//! tolerance, with the water at rest, and with the literal feedback of T3.2 it must not.
//!
//! Why it is exact: held particles leave α_c constant in time, so the pressure equation has no
//! ∂α_c/∂t source; at the hindered terminal slip u_s the drag K u_s on each particle equals its
//! submerged weight V_p (ρ_p − ρ_c) g; the drag feedback puts −F_d = K u_p into the fluid (with
//! K u_c implicit, zero at rest), so per unit volume the fluid carries ρ_c g + α_p (ρ_p − ρ_c) g =
//! ρ_m g. A uniform body force in a closed box is balanced by a linear pressure exactly in the
//! discrete equations (Gauss gradient of a linear field, fixed-flux wall pressure), so what is
//! left is the pressure solve's tolerance.

use std::path::Path;

use anyhow::{anyhow, bail, Result};
use spillage_analytic::hindered_settling::{cloud_settling_velocity, CloudReconstruction};
use spillage_model::case::Case;
use spillage_model::coupling::Feedback;
use spillage_model::output::plot::{Plot, Series, Style};
use spillage_model::particles::settings::{GroupSection, Motion};

use super::{box_size, draw, method, number, parse_mapping, pressure_profile, run, set_mapping, sphere, strings, CheckRow, FluidSolver, Trace};

/// Particle fraction of one sphere per cell of the case's box mesh, (π/6) d³ / V_cell.
fn one_per_cell_fraction(case: &Case, diameter: f64) -> Result<f64> {
    let (max, cells) = box_size(case)?;
    let min = match &case.mesh {
        Some(spillage_model::case::MeshSection::Box { min, .. }) => *min,
        _ => bail!("needs a box mesh"),
    };
    let cell: f64 = (0..3).map(|k| (max[k] - min[k]) / cells[k] as f64).product();
    Ok(std::f64::consts::PI / 6.0 * diameter.powi(3) / cell)
}

/// The case with its lattice given velocity `velocity` (held particles keep it).
fn with_velocity(base: &Case, velocity: [f64; 3]) -> Result<Case> {
    let mut case = base.clone();
    let section = case.particles.as_mut().ok_or_else(|| anyhow!("needs [particles]"))?;
    if section.motion != Motion::Held {
        bail!("{}: the held suspension needs [particles] motion = \"held\"", base.path.display());
    }
    match section.groups.first_mut() {
        Some(GroupSection::Lattice { velocity: v, .. }) => *v = velocity,
        _ => bail!("{}: the held suspension needs a lattice particle group", base.path.display()),
    }
    Ok(case)
}

/// −dp/dy between the bottom and the top row of cells and the largest deviation of a cell-wise
/// vertical gradient (adjacent cells of one column) from it, both kinematic × ρ_c [Pa/m]; the
/// largest fluid speed [m/s]; the spread max − min of α_c.
struct Column {
    mean_gradient: f64,
    cell_gradients: Vec<f64>,
    speed: f64,
    alpha_spread: f64,
}

fn measure(trace: &Trace, density: f64) -> Result<Column> {
    let mesh = trace.mesh.as_ref().ok_or_else(|| anyhow!("no mesh"))?;
    let fluid = trace.state.fluid.as_ref().ok_or_else(|| anyhow!("no fluid"))?;
    let profile = pressure_profile(trace, density)?;
    let (first, last) = (profile.first().ok_or_else(|| anyhow!("no cells"))?, profile.last().ok_or_else(|| anyhow!("no cells"))?);
    if last.0 <= first.0 {
        bail!("the column has a single row of cells");
    }
    let mean_gradient = -(last.1 - first.1) / (last.0 - first.0);
    // columns keyed by the centre's x (µm), cells sorted by height within each
    let mut columns: std::collections::BTreeMap<i64, Vec<(f64, f64)>> = Default::default();
    for (c, x) in mesh.cell_centres.iter().enumerate() {
        columns.entry((x.x * 1e6).round() as i64).or_default().push((x.y, density * fluid.pressure[c]));
    }
    let mut cell_gradients = Vec::new();
    for cells in columns.values_mut() {
        cells.sort_by(|a, b| a.0.total_cmp(&b.0));
        cell_gradients.extend(cells.windows(2).map(|w| -(w[1].1 - w[0].1) / (w[1].0 - w[0].0)));
    }
    let speed = fluid.velocity.iter().map(|u| (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt()).fold(0.0, f64::max);
    let (lo, hi) = fluid.alpha.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), a| (lo.min(*a), hi.max(*a)));
    Ok(Column { mean_gradient, cell_gradients, speed, alpha_spread: hi - lo })
}

pub(super) fn held_suspension(base: &Case, plots: Option<&Path>, solver: FluidSolver) -> Result<Vec<CheckRow>> {
    let name = base.case.name.as_str();
    let mappings = strings(base, "mappings")?;
    let tolerance = number(base, "tolerance")?;
    let velocity_tolerance = number(base, "velocity_tolerance")?;
    let fluid = base.fluid.as_ref().ok_or_else(|| anyhow!("needs [fluid]"))?;
    let sphere = sphere(base, 0.5)?;
    let alpha_p = one_per_cell_fraction(base, sphere.diameter)?;
    // the hindered terminal slip at α_c = 1 − α_p: ½ C_d(Re_s) A ρ_c u_s² α_c^(1−β(α_c Re_s)) =
    // V_p (ρ_p − ρ_c) g, the model's drag closure, solved by the analytic crate to 1e-15
    let slip = cloud_settling_velocity(&sphere, alpha_p, CloudReconstruction::SlipVelocity)?.slip_velocity;
    let g = base.physics.gravity;
    let down = {
        let n = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
        [g[0] / n, g[1] / n, g[2] / n]
    };
    let held = with_velocity(base, [slip * down[0], slip * down[1], slip * down[2]])?;
    let mixture = ((1.0 - alpha_p) * fluid.density + alpha_p * sphere.particle_density) * sphere.gravity;
    let mut rows = Vec::new();
    let mut profiles = Vec::new();
    for mapping in &mappings {
        let (m, gamma) = parse_mapping(mapping)?;
        let mut case = held.clone();
        set_mapping(&mut case, method(m)?, gamma)?;
        let trace = run(&case, solver)?;
        let column = measure(&trace, fluid.density)?;
        let label = format!("{m} γ={gamma}");
        // uniformity of the mapped field: the premise of the exact balance (round-off of the
        // mapping's sums, ~1e-16 per term)
        rows.push(CheckRow::at_most(name, format!("{label}: α_c spread max − min"), solver.label(), column.alpha_spread, 1e-12));
        // `tolerance`: the pressure solve's own (the reference factorises exactly; the fast
        // solver converges to a normalised residual of 1e-12), with the round-off of ~100 cells'
        // sums; the literal feedback misses by 10 %
        rows.push(CheckRow::relative(
            name,
            format!("{label}: −dp/dy / (ρ_m g), bottom to top row"),
            solver.label(),
            column.mean_gradient / mixture,
            1.0,
            tolerance,
        ));
        let worst = column.cell_gradients.iter().map(|g| (g / mixture - 1.0).abs()).fold(0.0, f64::max);
        rows.push(CheckRow::at_most(name, format!("{label}: max |cell-wise −dp/dy / (ρ_m g) − 1|"), solver.label(), worst, tolerance));
        // the water stays at rest: what the solves leave (u ~ Δt × residual force / ρ)
        rows.push(CheckRow::at_most(name, format!("{label}: largest fluid speed [m/s]"), solver.label(), column.speed, velocity_tolerance));
        if profiles.is_empty() {
            profiles.push((format!("drag fed back ({label})"), pressure_profile(&trace, fluid.density)?));
        }
    }
    // mappings whose field is not uniform in this column (the kernel's single mirrored ghost,
    // see the case file): asserted non-uniform, so the statement stays true; the deviation of
    // the pressure gradient is shown beside it
    for mapping in strings(base, "nonuniform_mappings")? {
        let (m, gamma) = parse_mapping(&mapping)?;
        let mut case = held.clone();
        set_mapping(&mut case, method(m)?, gamma)?;
        let column = measure(&run(&case, solver)?, fluid.density)?;
        let label = format!("{m} γ={gamma}");
        rows.push(CheckRow::at_least(
            name,
            format!("{label}: α_c spread max − min (not uniform: single wall ghost)"),
            solver.label(),
            column.alpha_spread,
            1e-6,
        ));
        let worst = column.cell_gradients.iter().map(|g| (g / mixture - 1.0).abs()).fold(0.0, f64::max);
        rows.push(CheckRow::at_least(name, format!("{label}: max |cell-wise −dp/dy / (ρ_m g) − 1| (not uniform)"), solver.label(), worst, 100.0 * tolerance));
    }
    // the documented failure (§2.6): with gravity and buoyancy fed back the fluid gets nothing
    // from a particle at terminal velocity and carries ρ_c g
    let (m, gamma) = parse_mapping(mappings.first().ok_or_else(|| anyhow!("verify.params.mappings is empty"))?)?;
    let mut literal = held.clone();
    set_mapping(&mut literal, method(m)?, gamma)?;
    literal.coupling.as_mut().ok_or_else(|| anyhow!("needs [coupling]"))?.feedback = Feedback::Literal;
    let trace = run(&literal, solver)?;
    let column = measure(&trace, fluid.density)?;
    let miss = (column.mean_gradient / mixture - 1.0).abs();
    // it must miss by at least half the submerged weight's share of ρ_m g, 1 − ρ_c/ρ_m
    let share = 1.0 - fluid.density * sphere.gravity / mixture;
    rows.push(CheckRow::at_least(name, format!("{m} γ={gamma}: |−dp/dy / (ρ_m g) − 1|, literal T3.2 feedback (must fail)"), solver.label(), miss, 0.5 * share));
    rows.push(CheckRow::relative(
        name,
        format!("{m} γ={gamma}: −dp/dy / (ρ_c g), literal T3.2 feedback"),
        solver.label(),
        column.mean_gradient / (fluid.density * sphere.gravity),
        1.0,
        tolerance,
    ));
    profiles.push(("literal T3.2 feedback".to_string(), pressure_profile(&trace, fluid.density)?));
    if plots.is_some() {
        let (y0, y1) = (profiles[0].1.first().map_or(0.0, |p| p.0), profiles[0].1.last().map_or(0.0, |p| p.0));
        let lines = [
            ("ρ_m g (mixture)".to_string(), vec![(y0, 0.0), (y1, -mixture * (y1 - y0))]),
            ("ρ_c g (water alone)".to_string(), vec![(y0, 0.0), (y1, -fluid.density * sphere.gravity * (y1 - y0))]),
        ];
        let mut series: Vec<Series> = profiles.iter().map(|(label, points)| Series { label, points }).collect();
        series.extend(lines.iter().map(|(label, points)| Series { label, points }));
        let styles = [Style::Computed, Style::Computed, Style::Exact, Style::Line];
        let title = format!("{name}: pressure in a column of held particles, α_p = {alpha_p:.4}");
        draw(plots, name, &Plot { title: &title, x_label: "height y [m]", y_label: "p − p(bottom row) [Pa]", log_x: false, log_y: false, series }, &styles)?;
    }
    Ok(rows)
}
