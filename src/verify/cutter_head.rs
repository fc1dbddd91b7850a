//! Verification of the cutter head's flow (issue 16; spillage-and-flow-verification.md §4, §5.1,
//! §5.2): the out-flowing flux of the back-plate head at 60 rpm and 0.12 m³/s is about half the
//! suction discharge (the thesis' CFD, §5.2), the net flux through the contour hull is the
//! suction discharge (Eq. 8.3; the thesis' interpolated hull missed it by −3 % to +10 %), the
//! same two on the thesis' interpolated contour surface (Eqs. 8.1–8.4, `hull_surface`), and
//! with `--full`: the out-flowing flux rises with rpm over 30–90 rpm (§5.2, Fig. 8.1) and
//! changes by less than 5 % between the two finest meshes run (the staircase of blocked
//! cells converges), and at 20 rpm the axial head has no outflow while the back-plate head
//! has (§5.2).
//!
//! The runs take the fast fluid: `tests/cutter_head.rs` holds it to the reference fluid step by
//! step on the head (≤ 1e-8). Fluxes are averaged over the last revolution run, as the thesis
//! averaged its last one (§5.1).

use anyhow::{anyhow, bail, Result};
use spillage_fast::fluid::FastFluid;
use spillage_model::case::Case;
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::step::Coupled;

use super::contour_map::ContourMeanFlow;
use super::figures::{draw, Axes, Curve};
use super::CheckRow;
use spillage_model::cutter_head::spillage::EXIT_BIN;
use std::path::Path;

/// Checks implemented here.
pub const CHECKS: &[&str] = &["cutter_head_flow", "cutter_head_twenty_rpm"];

const SOLVER: &str = "fast";

/// Runs `check`; with `plots`, draws the out-flowing flux against rpm with the analytic
/// spillage model's Q₁ on the same contour.
pub fn run_check(case: &Case, check: &str, full: bool, plots: Option<&Path>) -> Result<Vec<CheckRow>> {
    match check {
        "cutter_head_flow" => flow(case, full, plots),
        // check 2's contrast alone (also part of `cutter_head_flow --full`)
        "cutter_head_twenty_rpm" => twenty_rpm(case, plots),
        other => bail!("unknown cutter-head check `{other}`; known: {}", CHECKS.join(", ")),
    }
}

/// Means over the last revolution of a fluid-only run of `case` to its end time.
#[derive(Clone, Debug)]
pub struct HeadMeans {
    /// Out-flowing and net flux through the face hull [m³/s].
    pub outflow: f64,
    pub net: f64,
    /// The same through the interpolated contour surface (the thesis' Eqs. 8.1–8.4) [m³/s].
    pub contour_outflow: f64,
    pub contour_net: f64,
    /// Torque of the rotating walls on the water [N m] (cutter_head::torque).
    pub head_torque: f64,
    /// The whole water's angular-momentum imbalance R and the hull's [N m], signed means.
    pub imbalance: f64,
    pub hull_imbalance: f64,
    /// Mean |R| over the steps of the revolution [N m].
    pub imbalance_abs: f64,
    /// Angular momentum carried out through the hull and the mouth [N m].
    pub hull_flux: f64,
    pub mouth_flux: f64,
    /// The hull's wall torque (the rotor's faces bounding the hull's cells) [N m].
    pub hull_wall_torque: f64,
    /// The mean flow through the contour at fixed places in the laboratory.
    pub contour_mean_flow: ContourMeanFlow,
}

/// Mean out-flowing flux, net hull flux, torque terms and the mean flow through the contour
/// ([`ContourMeanFlow`]) over the last revolution of a fluid-only run of `case` to its end
/// time (time-weighted: the adaptive step is not uniform).
/// A case with rock runs its water alone: the thesis' flux checks are of water (§5.2), and the
/// Euler-turbine model it is compared with has no rock in its Q₁.
pub fn mean_fluxes(case: &Case) -> Result<HeadMeans> {
    let water = with(case, |c| (c.particles, c.coupling, c.wear) = (None, None, None))?;
    let case = &water;
    let mut state = State::default();
    let fluid = FastFluid::new(case, super::fluid::build_mesh(case)?, &mut state)?;
    let mut run = Coupled::fluid_only(case, state, fluid)?;
    let started = std::time::Instant::now();
    let omega = case.rotor.as_ref().map_or(0.0, |r| r.angular_velocity()).abs();
    let end = case.time.end_time.ok_or_else(|| anyhow!("{}: the check needs time.revolutions or time.end_time", case.path.display()))?;
    let from = end - std::f64::consts::TAU / omega;
    const COLUMNS: [&str; 10] = [
        "hull_outflow",
        "hull_net_flux",
        "contour_outflow",
        "contour_net_flux",
        "head_torque",
        "torque_imbalance",
        "hull_torque_imbalance",
        "hull_angular_momentum_flux",
        "mouth_angular_momentum_flux",
        "hull_wall_torque",
    ];
    let (mut sums, mut abs_imbalance, mut weight) = ([0.0; COLUMNS.len()], 0.0, 0.0);
    let mut contour_mean_flow = ContourMeanFlow::new(&run.cutter_head().ok_or_else(|| anyhow!("{}: no cutter head", case.path.display()))?.1.surface);
    while !spillage_model::step::reached_end_time(run.state().time, end) {
        let report = run.step()?;
        let value = |name: &str| report.values.iter().find(|(n, _)| *n == name).map(|v| v.1).ok_or_else(|| anyhow!("no `{name}` in the step report"));
        // weighted as the sweep's and the run's means: the step straddling the window's start
        // with its part inside
        let (time, dt) = (run.state().time, run.state().dt);
        let dt = spillage_model::output::series::time_in_window(time - dt, time, (from, f64::INFINITY));
        if dt > 0.0 {
            for (sum, name) in sums.iter_mut().zip(COLUMNS) {
                *sum += value(name)? * dt;
            }
            abs_imbalance += value("torque_imbalance")?.abs() * dt;
            weight += dt;
            let (mesh, fluid) = (run.mesh().expect("a fluid run"), run.state().fluid.as_ref().expect("a fluid run"));
            let fluxes = run.cutter_head().expect("checked above").1.laboratory_contour_fluxes(mesh, fluid, run.rotor().as_ref());
            contour_mean_flow.add(&fluxes, dt);
        }
    }
    if weight == 0.0 {
        bail!("{}: the run is shorter than a revolution", case.path.display());
    }
    let revolutions = end * omega / std::f64::consts::TAU;
    let cells = run.mesh().map_or(0, |m| m.n_cells());
    eprintln!("{}: {cells} cells, {} steps, {:.1} s per revolution", case.case.name, run.state().step, started.elapsed().as_secs_f64() / revolutions);
    let m = sums.map(|s| s / weight);
    let means = HeadMeans {
        outflow: m[0],
        net: m[1],
        contour_outflow: m[2],
        contour_net: m[3],
        head_torque: m[4],
        imbalance: m[5],
        hull_imbalance: m[6],
        imbalance_abs: abs_imbalance / weight,
        hull_flux: m[7],
        mouth_flux: m[8],
        hull_wall_torque: m[9],
        contour_mean_flow,
    };
    eprintln!(
        "{}: torque terms over the last revolution: head {:.2}, imbalance {:.2} (hull {:.2}), out through hull {:.2}, mouth {:.2}, hull walls {:.2} N m",
        case.case.name, means.head_torque, means.imbalance, means.hull_imbalance, means.hull_flux, means.mouth_flux, means.hull_wall_torque
    );
    Ok(means)
}

fn with(case: &Case, edit: impl FnOnce(&mut Case)) -> Result<Case> {
    let mut c = case.clone();
    edit(&mut c);
    c.finish().map_err(|e| anyhow!("{}: {} = {}: expected {}", case.path.display(), e.key, e.value, e.allowed))?;
    Ok(c)
}

fn flow(case: &Case, full: bool, plots: Option<&Path>) -> Result<Vec<CheckRow>> {
    let name = &case.case.name;
    let head = case.cutter_head.as_ref().ok_or_else(|| anyhow!("{}: the check needs a [cutter_head]", case.path.display()))?;
    let q_m = head.suction_discharge;
    let means = mean_fluxes(case)?;
    let (outflow, net) = (means.outflow, means.net);
    let mut rows = vec![
        // thesis §5.2: "about half the suction discharge"; the band 0.4–0.6 is the issue's
        CheckRow::absolute(name, "out-flowing flux / Q_m, mean over the last revolution (thesis ≈ 0.5)", SOLVER, outflow / q_m, 0.5, 0.1),
        // the face-flux hull is exact up to the solver's continuity tolerance; 5 % is the issue's
        CheckRow::relative(name, "net inflow through the contour hull / Q_m", SOLVER, -net / q_m, 1.0, 0.05),
        // the thesis' own measure (Eqs. 8.1–8.4: velocities interpolated onto r = R(z),
        // cutter_head::hull_surface), held to the same band: the face hull lies up to a cell
        // outside R(z), the contour does not move with the mesh
        CheckRow::absolute(name, "out-flowing flux through the contour R(z) / Q_m, interpolated (thesis ≈ 0.5)", SOLVER, means.contour_outflow / q_m, 0.5, 0.1),
        // the thesis' consistency check of its interpolated hull (§5.1): net flux within −3 % to
        // +10 % of Q_m, i.e. 1.035 ± 0.065
        CheckRow::absolute(
            name,
            "net inflow through the contour R(z) / Q_m, interpolated (thesis: −3 % … +10 %)",
            SOLVER,
            -means.contour_net / q_m,
            1.035,
            0.065,
        ),
    ];
    // where the mean flow leaves (verify::contour_map): the thesis' Q_out is the mean of
    // Eq. 8.4 per sample (the rows above); this one leaves out the water each blade pushes out
    // ahead of it and draws back behind it, and is reported beside it
    let (mean_flow_out, _) = means.contour_mean_flow.outflow();
    rows.push(CheckRow::at_most(name, "out-flowing flux of the mean flow through the contour / Q_m (reported)", SOLVER, mean_flow_out / q_m, f64::INFINITY));
    if let Some(dir) = plots {
        means.contour_mean_flow.draw(dir, &format!("{name}_contour_mean_flow"), &format!("{name}: mean flow through the contour"))?;
    }
    if let Some(mouth) = head.eccentric_mouth() {
        rows.extend(inflow_centre_row(case, mouth.angle, means.contour_mean_flow.inflow_centre()));
    }
    // Check 3, the rotor's torque balance (spillage_model::cutter_head::torque): the head's
    // torque against what the water's angular momentum does, over the last revolution. A
    // collocated finite-volume scheme conserves linear momentum to solver tolerance but angular
    // momentum only to truncation error (the internal face fluxes' moments do not cancel), so
    // the imbalance R is a discretisation error, not a solver tolerance: measured |R̄|/T̄ =
    // 0.131 on this head at 5 cm cells with k–ε (T̄ = 83.8 N m, R̄ = 11.0 N m); laminar 0.219
    // (T̄ = 78.0, R̄ = 17.1 N m) at 5 cm and 0.099 at 4 cm (T̄ = 115.4, R̄ = 11.4 N m); on the
    // coarse test head R falls with the cell size (6.9 → 6.1 → 3.3 N m at 5, 4, 3.3 cm;
    // tests/cutter_head.rs).
    // Issue 16 asks for the balance "to solver tolerance"; it closes only to truncation error,
    // so both rows are reported (no bound) rather than given a bound fitted to the measurement.
    // The budget's terms are checked to add up, and to balance on Couette flow, in
    // tests/cutter_head.rs and tests/head_torque.rs.
    rows.push(CheckRow::at_most(
        name,
        format!("angular-momentum imbalance of the water |R̄| / T̄ (head torque T̄ = {:.1} N m), last revolution", means.head_torque),
        SOLVER,
        means.imbalance.abs() / means.head_torque.abs(),
        f64::INFINITY,
    ));
    // the Euler turbine equation on the hull's control volume: its walls' torque against the
    // angular momentum carried out through hull and mouth; the same truncation error: measured
    // |R̄_hull|/T̄ = 0.130 at 5 cm with k–ε (walls 66.7, hull 18.9, mouth 50.7 N m); laminar
    // 0.196 at 5 cm (walls 61.4, hull 16.8, mouth 59.5 N m), 0.072 at 4 cm (walls 56.6, hull
    // 12.8, mouth 51.8 N m); reported too
    rows.push(CheckRow::at_most(
        name,
        format!(
            "Euler turbine balance on the hull |R̄_hull| / T̄ (walls {:.1}, out through hull {:.1}, mouth {:.1} N m)",
            means.hull_wall_torque, means.hull_flux, means.mouth_flux
        ),
        SOLVER,
        means.hull_imbalance.abs() / means.head_torque.abs(),
        f64::INFINITY,
    ));
    let rpm_case = rpm(case);
    let mut computed = vec![(rpm_case, outflow)];
    if full {
        computed.clear();
        let mut previous = f64::NEG_INFINITY;
        let mut decreases = 0.0;
        for rpm in [30.0, 45.0, 60.0, 75.0, 90.0] {
            // `time.revolutions` runs the same number of revolutions at every speed
            let c = with(case, |c| {
                let rotor = c.rotor.as_mut().expect("validated");
                (rotor.rpm, rotor.omega) = (Some(rpm), None);
            })?;
            let q = mean_fluxes(&c)?.outflow;
            computed.push((rpm, q));
            eprintln!("{name}: {rpm} rpm: out-flowing flux {q:.5} m³/s");
            rows.push(CheckRow::at_least(name, format!("out-flowing flux at {rpm} rpm [m³/s] (> 0)"), SOLVER, q, 0.0));
            if q < previous {
                decreases += 1.0;
            }
            previous = q;
        }
        rows.push(CheckRow::at_most(name, "decreases of the out-flowing flux from 30 to 90 rpm (thesis: rises)", SOLVER, decreases, 0.0));
        let sizes = [head.mesh.cell_size, 0.8 * head.mesh.cell_size, 0.7 * head.mesh.cell_size];
        let mut fluxes = Vec::new();
        for h in sizes {
            let c = with(case, |c| c.cutter_head.as_mut().expect("validated").mesh.cell_size = h)?;
            let m = mean_fluxes(&c)?;
            eprintln!("{name}: cell size {h:.4} m: out-flowing flux {:.5} m³/s (face hull), {:.5} m³/s (contour)", m.outflow, m.contour_outflow);
            fluxes.push((m.outflow, m.contour_outflow));
        }
        for (label, pick) in [("face hull", 0), ("contour R(z)", 1)] {
            let q = |k: usize| if pick == 0 { fluxes[k].0 } else { fluxes[k].1 };
            rows.push(CheckRow::at_most(
                name,
                format!("change of the out-flowing flux ({label}) between the two finest meshes ({:.3} and {:.3} m cells)", sizes[1], sizes[2]),
                SOLVER,
                (q(2) - q(1)).abs() / q(2),
                0.05,
            ));
        }
    }
    if full {
        rows.extend(twenty_rpm(case, plots)?);
    }
    if plots.is_some() {
        let model =
            super::head_model::HeadModel::of_case(case).ok_or_else(|| anyhow!("{}: the figure needs [cutter_head] and [rotor]", case.path.display()))??;
        let curve: Vec<(f64, f64)> =
            (0..=40).map(|k| 20.0 + 2.0 * k as f64).map(|rpm| Ok((rpm, model.answer(rpm, q_m)?.outflow_water))).collect::<Result<_>>()?;
        let half: Vec<(f64, f64)> = vec![(20.0, 0.5 * q_m), (100.0, 0.5 * q_m)];
        draw(
            plots,
            name,
            &Axes {
                title: &format!("{name}: out-flowing flux against rotor speed, Q_m = {q_m} m³/s"),
                x: "rotor speed [rpm]",
                y: "out-flowing flux Q₁ [m³/s]",
                log_x: false,
                log_y: false,
            },
            &[
                Curve::computed("computed (fast fluid, mean over the last revolution)", computed),
                Curve::exact("analytic spillage model Q₁ (water, same contour)", curve),
                Curve::guide("thesis CFD at 60 rpm: ≈ Q_m / 2", half),
            ],
        )?;
    }
    Ok(rows)
}

/// Below this fraction of Q_m an out-flowing flux through the interpolated contour cannot be
/// told from its interpolation error (the thesis' net hull flux missed Q_m by −3 % to +10 %,
/// §5.1; ours by 2.4 % at 5 cm cells).
const NEGLIGIBLE_OUTFLOW: f64 = 0.05;

/// The rotor's speed [rpm] (NaN without a rotor).
fn rpm(case: &Case) -> f64 {
    case.rotor.as_ref().map_or(f64::NAN, |r| r.angular_velocity().abs() * 60.0 / std::f64::consts::TAU)
}

/// Where the water enters closest to the ring of a head with an eccentric mouth at `mouth_angle`
/// [rad]: the mean inflow's centre `centre` [rad] ([`ContourMeanFlow::inflow_centre`]) from the
/// mouth, positive in the direction of rotation. With the mouth facing the bed, as the thesis'
/// and [`THESIS_MOUTH`] do, that is toward the under-cut side: in under-cutting the blades rise
/// through the bank, so they turn from the bed toward it. The thesis puts the centre 30°–45°
/// toward the under-cut side at 60 rpm (§5.2), which the row holds at 60 rpm and reports at
/// others. Without a notch (`None`: the outflow equally deep all round) the 60 rpm row fails with
/// NaN rather than leave the comparison out; at other speeds there is nothing to report.
fn inflow_centre_row(case: &Case, mouth_angle: f64, centre: Option<f64>) -> Option<CheckRow> {
    let rotor = case.rotor.as_ref().expect("validated with [cutter_head]");
    // the axis is +z (validated with [cutter_head]); azimuths turn about +z
    let degrees = centre.map_or(f64::NAN, |centre| {
        let turned = rotor.angular_velocity().signum() * (centre - mouth_angle);
        turned.sin().atan2(turned.cos()).to_degrees()
    });
    let rpm = rpm(case);
    let what = "centre of the mean inflow's reach toward the ring, from the mouth in the direction of rotation [°]";
    if (rpm - 60.0).abs() < 1e-9 {
        Some(CheckRow::absolute(&case.case.name, format!("{what} (thesis at 60 rpm: 30–45, toward the under-cut side)"), SOLVER, degrees, 37.5, 7.5))
    } else {
        centre
            .map(|_| CheckRow::at_most(&case.case.name, format!("{what} at {rpm:.0} rpm (reported; the thesis gives 60 rpm)"), SOLVER, degrees, f64::INFINITY))
    }
}

/// The thesis' back-plate head's mouth as `cases/cutter_head_eccentric.toml` has it: a 103° kidney
/// between 0.07 and 0.2 m (0.0316 m², §2.11) at rest, facing the bed (azimuth 180°).
const THESIS_MOUTH: spillage_model::cutter_head::Suction = spillage_model::cutter_head::Suction::Eccentric { angle: 180.0, width: 103.0, radii: [0.07, 0.2] };

/// Check 2's second half (§5.2): at 20 rpm the axial head draws water in over its whole contour
/// while the back-plate head already lets water out far from its mouth: the case's own
/// suction, and the thesis' eccentric mouth at rest ([`THESIS_MOUTH`]) unless the case has it
/// already. Each head is held to it on two measures: the thesis' Q_out (the mean of Eq. 8.4 per
/// step, its Fig. 8.1, which also counts the water each passing blade pushes out ahead of it
/// and draws back behind it), and Q_out of the mean flow through places fixed in the laboratory
/// ([`ContourMeanFlow`], where the thesis' words about in- and outflow over the contour point).
/// The second is never the larger, so it favours the axial half and is harder on the other.
/// With `plots`, a map of the mean outward velocity over the contour per head,
/// `<case>_20rpm_{back_plate,eccentric_mouth,axial}.png` with its `.csv`.
fn twenty_rpm(case: &Case, plots: Option<&Path>) -> Result<Vec<CheckRow>> {
    use spillage_model::cutter_head::Suction;
    let name = &case.case.name;
    let head = case.cutter_head.as_ref().ok_or_else(|| anyhow!("{name}: check 2 needs [cutter_head]"))?;
    let q_m = head.suction_discharge;
    let mut heads = vec![("back-plate", "back_plate", None)];
    if !matches!(head.suction, Suction::Eccentric { .. }) {
        heads.push(("back-plate with the eccentric mouth at rest", "eccentric_mouth", Some(THESIS_MOUTH)));
    }
    heads.push(("axial", "axial", Some(Suction::Axial)));
    let mut rows = Vec::new();
    for (label, file, suction) in heads {
        let axial = suction == Some(Suction::Axial);
        let c = with(case, |c| {
            let rotor = c.rotor.as_mut().expect("validated");
            (rotor.rpm, rotor.omega) = (Some(20.0), None);
            if let Some(s) = &suction {
                c.cutter_head.as_mut().expect("validated").suction = s.clone();
            }
        })?;
        let means = mean_fluxes(&c)?;
        let mean_flow = &means.contour_mean_flow;
        let (outflow, top) = mean_flow.outflow();
        let ratio = outflow / q_m;
        eprintln!(
            "{name}: {label} head at 20 rpm: mean flow out through the contour {outflow:.5} m³/s ({ratio:.3} Q_m; {top:.5} m³/s in the top {} cm; through {:.1} % of its area); mean of the out-flowing flux {:.5} m³/s ({:.3} Q_m), face hull {:.5}",
            100.0 * EXIT_BIN,
            100.0 * mean_flow.outflow_area_fraction(),
            means.contour_outflow,
            means.contour_outflow / q_m,
            means.outflow
        );
        if let Some(dir) = plots {
            mean_flow.draw(dir, &format!("{name}_20rpm_{file}"), &format!("{name}, {}, 20 rpm: mean flow through the contour", file.replace('_', " ")))?;
        }
        if let Some(mouth) = c.cutter_head.as_ref().and_then(|h| h.eccentric_mouth()) {
            rows.extend(inflow_centre_row(&c, mouth.angle, mean_flow.inflow_centre()));
        }
        for (measure, value) in [("mean of Eq. 8.4", means.contour_outflow / q_m), ("of the mean flow", ratio)] {
            let what = |thesis: &str| format!("{label} head at 20 rpm: out-flowing flux through the contour / Q_m, {measure} ({thesis})");
            rows.push(if axial {
                CheckRow::at_most(name, what("thesis: inflow over the whole contour"), SOLVER, value, NEGLIGIBLE_OUTFLOW)
            } else {
                CheckRow::at_least(name, what("thesis: outflow already, far from the mouth"), SOLVER, value, NEGLIGIBLE_OUTFLOW)
            });
        }
    }
    Ok(rows)
}
