//! P2: a sphere settling through a stationary sliding interface, with and without the interface
//! mask (particle-verification.md §3, Table 6.4).

use super::*;
use spillage_model::coupling::InterfaceTreatment;

/// The same annulus without the interface: one block with the rotor's and stator's rings and
/// the mean of their cells around.
fn without_interface(case: &Case) -> Result<Case> {
    let mut plain = case.clone();
    let Some(MeshSection::RotorStator { r_inner, r_outer, z_min, z_max, n_r_rotor, n_r_stator, n_theta_rotor, n_theta_stator, n_z, two_d, .. }) =
        case.mesh.clone()
    else {
        bail!("{}: the interface check needs a rotor_stator mesh", case.path.display());
    };
    plain.mesh = Some(MeshSection::Annulus {
        r_inner,
        r_outer,
        z_min,
        z_max,
        n_r: n_r_rotor + n_r_stator,
        n_theta: (n_theta_rotor + n_theta_stator) / 2,
        n_z,
        radial_grading: 1.0,
        two_d,
    });
    Ok(plain)
}

/// With `plots`, draws `<case>_velocity_difference.png`: each run's |u − u_no interface| / u_t
/// against time (log scale) with Table 6.4's masked value.
pub(super) fn interface_crossing(base: &Case, full: bool, plots: Option<&Path>, solver: FluidSolver) -> Result<Vec<CheckRow>> {
    let name = base.case.name.as_str();
    // `--full` refines r and θ by `full_refinement`; a case without it (the one already at the
    // thesis' d_p/Δx = 5, interface_crossing_fine.toml) has no finer level and runs as it is
    let refinement = params(base)?.contains_key("full_refinement").then(|| number(base, "full_refinement")).transpose()?;
    let case = match refinement {
        Some(factor) if full => refined(base, factor as usize)?,
        _ => base.clone(),
    };
    // what the sphere stands for in the fluid's continuity
    let volume = case.particle_modifier() * sphere(&case, 0.5)?.volume();
    let plain = run(&without_interface(&case)?, solver)?;
    // the interface's effect: the largest velocity difference to the run without it, relative
    // to that run's final (near-terminal) velocity, as Table 6.4's relative error
    let terminal = plain.settling.last().copied().unwrap_or(f64::NAN).abs();
    let disturbance = |trace: &Trace| trace.settling.iter().zip(&plain.settling).map(|(u, v)| (u - v).abs()).fold(0.0, f64::max) / terminal;
    let with = |interface: InterfaceTreatment, mask: Option<bool>| -> Result<Trace> {
        let mut c = case.clone();
        let coupling = c.coupling.as_mut().ok_or_else(|| anyhow!("needs [coupling]"))?;
        coupling.interface = interface;
        coupling.interface_mask = mask;
        run(&c, solver)
    };
    let unmasked_run = with(InterfaceTreatment::Truncate, Some(false))?;
    let unmasked = disturbance(&unmasked_run);
    let masked = with(InterfaceTreatment::Truncate, Some(true))?;
    let masked_disturbance = disturbance(&masked);
    let mut rows = table_rows(base, name, "masked", solver, masked_disturbance, &masked, volume)?;
    // the mask's purpose (§6.7): the crossing disturbs the particle less than without it
    rows.push(CheckRow::at_least(
        name,
        "unmasked / masked velocity difference (the mask helps)",
        solver.label(),
        unmasked / masked_disturbance.max(1e-300),
        number(base, "mask_gain")?,
    ));
    // the kernel reaching across the interface (`interface = "span"`, unmasked): no footprint
    // jumps, so there is nothing to mask; held to the same rows of Table 6.4
    let mut runs = vec![("truncated, unmasked", &unmasked_run), ("truncated, masked (the thesis)", &masked)];
    let span = if case.coupling.as_ref().is_some_and(|c| c.method == MappingMethod::Kernel) {
        let span = with(InterfaceTreatment::Span, None)?;
        rows.extend(table_rows(base, name, "spanning kernel", solver, disturbance(&span), &span, volume)?);
        Some(span)
    } else {
        None
    };
    if let Some(span) = &span {
        runs.push(("spanning kernel (interface = \"span\")", span));
    }
    if plots.is_some() {
        // log scale: a difference of exactly zero (before the runs part) is drawn at 1e-8
        let difference = |trace: &Trace| -> Curve {
            trace.time.iter().zip(trace.settling.iter().zip(&plain.settling)).map(|(t, (u, v))| (*t, ((u - v).abs() / terminal).max(1e-8))).collect()
        };
        let curves: Vec<(&str, Curve)> = runs.iter().map(|(label, trace)| (*label, difference(trace))).collect();
        let table = number(base, "velocity_difference")?;
        let ends = [plain.time.first().copied().unwrap_or(0.0), plain.time.last().copied().unwrap_or(0.0)];
        let table_line: Curve = ends.iter().map(|t| (*t, table)).collect();
        let mut series: Vec<Series> = curves.iter().map(|(label, points)| Series { label, points }).collect();
        series.push(Series { label: "Table 6.4, masked run (thesis)", points: &table_line });
        let mut styles = vec![Style::Line; curves.len()];
        styles.push(Style::Exact);
        let title = format!("{name}: a sphere settling through a sliding interface");
        let plot = Plot { title: &title, x_label: "time [s]", y_label: "|u − u without the interface| / u_t", log_x: false, log_y: true, series };
        draw(plots, &format!("{name}_velocity_difference"), &plot, &styles)?;
    }
    Ok(rows)
}

/// Table 6.4's rows for one run: the velocity difference to the run without the interface and
/// the largest global, cumulative and single-cell continuity errors in units of `volume`.
fn table_rows(base: &Case, name: &str, run: &str, solver: FluidSolver, velocity: f64, trace: &Trace, volume: f64) -> Result<Vec<CheckRow>> {
    let largest = |errors: &[f64]| errors.iter().fold(0.0f64, |m, e| m.max(e.abs())) / volume;
    let mut rows = vec![CheckRow::at_most(
        name,
        format!("{run}: relative velocity difference to no interface"),
        solver.label(),
        velocity,
        number(base, "velocity_difference")?,
    )];
    for (what, errors, bound) in [
        ("largest |global continuity error| / V_p", &trace.continuity_global, "continuity_global"),
        ("largest |cumulative continuity error| / V_p", &trace.continuity_cumulative, "continuity_cumulative"),
        ("largest single-cell continuity error / V_p", &trace.continuity_cell_max, "continuity_local"),
    ] {
        rows.push(CheckRow::at_most(name, format!("{run}: {what}"), solver.label(), largest(errors), number(base, bound)?));
    }
    Ok(rows)
}

/// `case` with its rotor/stator mesh refined `factor` times in r and θ.
pub(super) fn refined(case: &Case, factor: usize) -> Result<Case> {
    let mut fine = case.clone();
    match fine.mesh.as_mut() {
        Some(MeshSection::RotorStator { n_r_rotor, n_r_stator, n_theta_rotor, n_theta_stator, .. }) => {
            *n_r_rotor *= factor;
            *n_r_stator *= factor;
            *n_theta_rotor *= factor;
            *n_theta_stator *= factor;
            Ok(fine)
        }
        _ => bail!("{}: the interface check needs a rotor_stator mesh", case.path.display()),
    }
}
