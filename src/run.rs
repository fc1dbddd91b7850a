//! `spillage run`: the time loop around one solver, with progress, outputs and checkpoints.
//!
//! Nothing is lost on failure: the series is flushed every step, frames and checkpoints already
//! written stay valid (all are written atomically), and when a step fails a summary saying what
//! went wrong is still written before the error is reported.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use spillage_model::case::Case;
use spillage_model::output::plot::{write_png, Plot, Series};
use spillage_model::output::series::{read_series, SeriesWriter};
use spillage_model::output::summary::Summary;
use spillage_model::solver::{Solver, SolverError, StepReport};
use spillage_model::state::State;
use spillage_model::step::{Coupled, FluidPhase, ParticlePhase, WearPhase};

use crate::frames::{CouplingFrame, Frames};

use crate::SolverChoice;

pub struct RunOptions {
    pub case: PathBuf,
    pub solver: SolverChoice,
    pub out: Option<PathBuf>,
    pub threads: Option<usize>,
    pub restart: Option<PathBuf>,
    /// Replace the results of another run in `out`.
    pub force: bool,
}

/// Builds the run a case needs, from the initial state or a restart state: the step driver
/// with the case's fluid, particle and wear phases, all fast or all reference.
pub fn build_solver(case: &Case, choice: SolverChoice, state: Option<State>) -> anyhow::Result<Box<dyn Solver + Send>> {
    let located = |e: SolverError| anyhow::anyhow!("{}: {e}", case.path.display());
    if let Some(restart) = &state {
        spillage_model::step::check_state_matches_case(case, restart).map_err(located)?;
    }
    let mut state = state.unwrap_or_default();
    let fluid: Option<Box<dyn FluidPhase + Send>> = match (&case.fluid, spillage_model::mesh::for_case(case)) {
        (Some(_), Some(mesh)) => {
            let section = if case.cutter_head.is_some() { "[cutter_head]" } else { "[mesh]" };
            let mesh = mesh.map_err(|e| anyhow::anyhow!("{}: {section}: {e}", case.path.display()))?;
            Some(match choice {
                SolverChoice::Fast => Box::new(spillage_fast::fluid::FastFluid::new(case, mesh, &mut state).map_err(located)?),
                SolverChoice::Reference => Box::new(spillage_reference::fluid::ReferenceFluid::new(case, mesh, &mut state).map_err(located)?),
            })
        }
        (Some(_), None) => anyhow::bail!("{}: a case with [fluid] needs a [mesh]", case.path.display()),
        (None, _) => None,
    };
    let particles: Option<Box<dyn ParticlePhase + Send>> = match (&case.particles, choice) {
        (Some(_), SolverChoice::Fast) => Some(Box::new(spillage_fast::dem::FastDem::new(case, &mut state).map_err(located)?)),
        (Some(_), SolverChoice::Reference) => Some(Box::new(spillage_reference::dem::ReferenceDem::new(case, &mut state).map_err(located)?)),
        (None, _) => None,
    };
    if fluid.is_some() && particles.is_some() && case.coupling.is_none() {
        eprintln!("note: one-way coupling: the particles see the fluid, the fluid does not see the particles; add a [coupling] section for two-way coupling");
    }
    let wear: Option<Box<dyn WearPhase + Send>> = match (&case.wear, choice) {
        (Some(_), SolverChoice::Fast) => Some(Box::new(spillage_fast::wear::FastWear::new(case, &mut state).map_err(located)?)),
        (Some(_), SolverChoice::Reference) => Some(Box::new(spillage_reference::wear::ReferenceWear::new(case, &mut state).map_err(located)?)),
        (None, _) => None,
    };
    let run = Coupled::new(case, state, fluid, particles).map_err(located)?;
    let run = match choice {
        SolverChoice::Fast => run.with_mapping_solvers(spillage_fast::coupling::MAPPING_SOLVERS),
        SolverChoice::Reference => run,
    };
    Ok(Box::new(match wear {
        Some(w) => run.with_wear(w).map_err(located)?,
        None => run,
    }))
}

pub fn run(opts: &RunOptions) -> anyhow::Result<ExitCode> {
    let case = Case::load(&opts.case)?;
    // what `spillage check` would warn of, for a run started without it
    for warning in spillage::check::warnings(&case) {
        eprintln!("warning: {warning}");
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let mut threads = opts.threads.unwrap_or(cores);
    if threads == 0 {
        anyhow::bail!("--threads 0: expected a whole number ≥ 1");
    }
    if threads > cores {
        // more workers than cores only slow the run down (results do not depend on the count)
        eprintln!("note: --threads {threads} is more than the {cores} cores of this machine; using {cores}");
        threads = cores;
    }
    rayon::ThreadPoolBuilder::new().num_threads(threads).build_global().context("cannot set up the thread pool")?;
    let restart = match &opts.restart {
        Some(path) => Some(spillage_model::checkpoint::read(path, &case)?),
        None => None,
    };
    if restart.is_none() {
        // initial particles overlapping a wall or each other blow up in the first step
        let dir = opts.case.parent().unwrap_or(Path::new(""));
        spillage_model::particles::placement::check_initial_placement(&case, dir).map_err(|field| {
            let text = std::fs::read_to_string(&opts.case).unwrap_or_default();
            Case::located(&text, &opts.case, field)
        })?;
    }
    let default = Path::new("results").join(&case.case.name);
    let out = crate::results_folder::prepare(opts.out.as_deref(), &default, restart.as_ref().map(|s| s.step), opts.force)?;
    let restart_time = restart.as_ref().map(|s| s.time);
    let restart_step = restart.as_ref().map(|s| s.step);
    let restart_angle = restart.as_ref().map_or(0.0, |s| s.rotor_angle);
    let mut solver = build_solver(&case, opts.solver, restart)?;

    let mut summary = Summary::new(&case.case.name, solver.name());
    summary.set_detail("case_file", case.path.display().to_string());
    summary.set_detail("threads", threads as u64);
    if case.particles.is_some() && opts.solver == SolverChoice::Fast {
        // the particle-steps per second of a run depend on it (docs/performance.md)
        summary.set_detail("dem_pair_kernel", spillage_fast::dem::pair_forces::PairKernel::detect().describe());
        // the particles' drag laws in lanes (docs/performance.md, "The drag law in lanes"), where they take them
        use spillage_fast::dem::drag_lanes::{takes_lanes, LaneWidth};
        if let Some(section) = &case.particles {
            let in_fluid = case.fluid.is_some() || section.ambient.as_ref().is_some_and(|a| a.forces);
            if in_fluid && takes_lanes(section.motion, case.physics.rotating_frame.is_some(), section.fluid_forces) {
                summary.set_detail("dem_drag_kernel", LaneWidth::detect().describe());
            }
        }
    }
    summary.set_detail("derived", serde_json::to_value(spillage::check::derive(&case))?);
    if let Some(head) = &case.cutter_head {
        // the current past the head (cutter_head::current), [0, 0, 0] in still water
        summary.set_detail("haul_velocity", serde_json::to_value(head.haul_velocity)?);
        // which way gravity pulls along the axis decides where the rock leaves (cutter_head::ladder)
        summary.set_detail("gravity_axial_pull", spillage_model::cutter_head::ladder::LadderTilt::of(case.physics.gravity).pull_name());
    }
    if let Some(path) = &opts.restart {
        summary.set_detail("restarted_from", path.display().to_string());
    }

    let started = Instant::now();
    let mut progress = crate::progress::Progress::new(&case, solver.state());
    let mut run = Running {
        case: &case,
        out: &out,
        frames: Frames::new(&out, restart_time)?,
        series: None,
        restart_time,
        restart_step,
        steps: 0,
        step_seconds: 0.0,
        particle_substeps: 0.0,
        outer: OuterLoop::default(),
        packing: Packing::default(),
        start_up: (0, 0.0),
    };
    // the time loop runs on one of the pool's workers: its parallel loops then start there,
    // not by handing each one over from this thread and sleeping until it is done (the
    // hand-offs cost ~3 % of a 1-thread settling bed); the other workers spin meanwhile,
    // taking each loop's work as it is queued (`fast/src/team.rs`)
    let result = rayon::scope(|_| spillage_fast::team::keep_awake(|| run.time_loop(solver.as_mut(), &mut progress)));
    progress.finish();
    let wall = started.elapsed().as_secs_f64();

    let state = solver.state();
    summary.set_timing("wall", wall);
    summary.set_timing("steps", run.step_seconds);
    if run.steps > 0 {
        summary.set_timing("per_step", run.step_seconds / run.steps as f64);
        let cells = solver.mesh().map_or(0, |m| m.n_cells());
        if cells > 0 {
            summary.set_result("microseconds_per_cell_step", 1e6 * run.step_seconds / (run.steps as f64 * cells as f64));
        }
        if run.particle_substeps > 0.0 {
            // of the whole step's time: with a fluid, the fluid's share is in it too
            summary.set_result("particle_substeps_per_second", run.particle_substeps / run.step_seconds);
        }
        let turned = (state.rotor_angle - restart_angle).abs() / std::f64::consts::TAU;
        if turned > 0.0 {
            // the frozen-rotor start-up does not turn the rotor: its time is not a revolution's
            summary.set_result("seconds_per_revolution", (run.step_seconds - run.start_up.1) / turned);
        }
        if run.start_up.0 > 0 {
            summary.set_result("start_up_steps", run.start_up.0 as f64);
            summary.set_timing("start_up", run.start_up.1);
        }
    }
    summary.set_result("final_time", state.time);
    summary.set_result("final_step", state.step as f64);
    summary.set_result("outer_loop_capped_steps", run.outer.capped as f64);
    summary.set_result("retried_steps", run.outer.retried as f64);
    summary.set_result("total_dt_halvings", run.outer.halvings as f64);
    if let Some((_, last, _)) = &run.series {
        for (name, value) in &last.values {
            summary.set_result(name, *value);
        }
    }
    summary.set_detail(
        "status",
        match &result {
            Ok(()) => "completed".to_string(),
            Err(e) => format!("failed: {e}"),
        },
    );
    summary.write(&out.join("summary.json"))?;
    if case.output.plots {
        draw_plots(&out, &case.case.name)?;
    }
    if let Some(particles) = state.particles.as_ref().filter(|_| case.cutter_head.is_none()) {
        eprintln!("{}", particle_exits_line(particles));
    }
    if let Some(warning) = run.outer.warning(&case, run.steps) {
        eprintln!("{warning}");
    }
    if let Some(note) = run.outer.retry_note(run.steps) {
        eprintln!("{note}");
    }
    if let Some(warning) = run.packing.warning(&case, run.steps) {
        eprintln!("{warning}");
    }
    if run.start_up.0 > 0 {
        eprintln!("frozen-rotor start-up: {} steps (t ≤ 0 in series.csv) in {:.1} s", run.start_up.0, run.start_up.1);
    }
    for line in crate::head_report::report(&case, state, &out)?.into_iter().chain(crate::wear_report::report(&case, state, &out)?) {
        eprintln!("{line}");
    }
    match result {
        Ok(()) => {
            eprintln!("{}: {} steps to t = {:.6e} s in {wall:.1} s; results in {}", case.case.name, run.steps, state.time, out.display());
            if case.output.paraview {
                // name the time series this run wrote (a particle-only run has no fluid.pvd)
                let written: Vec<String> =
                    ["fluid.pvd", "particles.pvd", "walls.pvd"].iter().filter(|f| out.join(f).exists()).map(|f| out.join(f).display().to_string()).collect();
                eprintln!("ParaView: open {}; plots in {}", written.join(", "), out.join("plots").display());
            }
            Ok(ExitCode::SUCCESS)
        }
        Err(e) => Err(anyhow::anyhow!("{e} (after {wall:.1} s; results up to the failure are in {})", out.display())),
    }
}

/// Columns the run loop writes itself from the state; a solver reporting them too is not
/// written twice.
const SERIES_CLOCK: [&str; 3] = ["step", "time", "dt"];

struct Running<'a> {
    case: &'a Case,
    out: &'a Path,
    frames: Frames,
    /// The series file, the last step's report and a reusable row buffer (no allocation per
    /// step once the first row is written).
    series: Option<(SeriesWriter, StepReport, Vec<f64>)>,
    restart_time: Option<f64>,
    /// Step of the restart state: series rows after it are dropped and computed again.
    restart_step: Option<u64>,
    steps: u64,
    step_seconds: f64,
    /// Σ DEM sub-steps × particles over the steps run (the DEM's work, for its speed).
    particle_substeps: f64,
    outer: OuterLoop,
    packing: Packing,
    /// Steps and seconds of a frozen-rotor start-up (the steps that end at t ≤ 0,
    /// spillage_model::fluid::frozen_rotor).
    start_up: (u64, f64),
}

/// Steps whose PIMPLE outer loop stopped at `[numerics] max_outer_iterations` with the pressure
/// residual still above `p_initial_residual` (`outer_capped` in the series; issue 15 item 1: a run "completed" with every
/// step capped and no word about it), and steps whose fluid diverged and were taken again with
/// a smaller Δt (`dt_halvings`, adaptive runs).
#[derive(Default)]
struct OuterLoop {
    capped: u64,
    worst_residual: f64,
    retried: u64,
    halvings: u64,
    most_halvings: u64,
}

impl OuterLoop {
    fn record(&mut self, report: &StepReport) {
        let value = |key: &str| report.values.iter().find(|(k, _)| *k == key).map(|(_, v)| *v);
        if let Some(h) = value("dt_halvings").filter(|h| *h > 0.0) {
            self.retried += 1;
            self.halvings += h as u64;
            self.most_halvings = self.most_halvings.max(h as u64);
        }
        if let (Some(1.0), Some(residual)) = (value("outer_capped"), value("p_initial_residual")) {
            self.capped += 1;
            self.worst_residual = self.worst_residual.max(residual);
        }
    }

    /// The note to print at the end, if any step was retried.
    fn retry_note(&self, steps: u64) -> Option<String> {
        (self.retried > 0).then(|| {
            format!(
                "note: the fluid diverged in {} of {steps} steps, which were taken again with a smaller time step (up to {} halvings; `dt_halvings` in series.csv); a smaller max_courant, more PISO correctors or under-relaxation would avoid the retries",
                self.retried, self.most_halvings
            )
        })
    }

    /// The warning to print at the end, if any step was capped.
    fn warning(&self, case: &Case, steps: u64) -> Option<String> {
        (self.capped > 0).then(|| {
            format!(
                "warning: the outer loop stopped at its cap of {} iterations in {} of {steps} steps with the pressure residual above its target (up to {:.2e} > {:.1e}): those steps are not converged; raise [numerics] max_outer_iterations or lower the time step",
                case.numerics.max_outer_iterations, self.capped, self.worst_residual, case.numerics.p_initial_residual
            )
        })
    }
}

/// Steps in which cells were held at `[coupling] min_fluid_fraction` (`alpha_c_clamped` in the
/// series): the particles there stood for more volume than the fluid equations can give up, so
/// the water saw less of them than there was.
#[derive(Default)]
struct Packing {
    steps: u64,
    most_cells: f64,
    largest_fraction: f64,
}

impl Packing {
    fn record(&mut self, report: &StepReport) {
        let value = |key: &str| report.values.iter().find(|(k, _)| *k == key).map(|(_, v)| *v);
        if let Some(cells) = value("alpha_c_clamped").filter(|c| *c > 0.0) {
            self.steps += 1;
            self.most_cells = self.most_cells.max(cells);
            self.largest_fraction = self.largest_fraction.max(value("alpha_p_max").unwrap_or(0.0));
        }
    }

    /// The warning to print at the end, if any cell was held at the floor.
    fn warning(&self, case: &Case, steps: u64) -> Option<String> {
        let floor = case.coupling.as_ref()?.min_fluid_fraction;
        (self.steps > 0).then(|| {
            format!(
                "warning: α_c was held at its floor [coupling] min_fluid_fraction = {floor} in up to {} cells (in {} of {steps} steps; α_p up to {:.3}; `alpha_c_clamped` in series.csv): the particles there stand for more volume than the cells hold. A wider kernel ([coupling] distance_factor) spreads a particle larger than its cells{}",
                self.most_cells,
                self.steps,
                self.largest_fraction,
                match (case.particle_modifier(), case.particles.as_ref().is_some_and(|p| p.solids_pressure.is_some())) {
                    (1.0, _) => String::new(),
                    (m, false) => format!("; particles counting {m} times ([particles] modifier) pack past α_max = {}, since nothing but their own contacts keeps them apart: the thesis' solids pressure ([particles.solids_pressure], wear-model.md §4.3) does", spillage::check::MAX_PACKING),
                    (m, true) => format!("; particles counting {m} times ([particles] modifier) packed past it despite [particles.solids_pressure] (its α_p is each cell's own count; the kernel's is spread)"),
                }
            )
        })
    }
}

impl Running<'_> {
    fn finished(&self, state: &State) -> bool {
        let t = &self.case.time;
        match (t.steps, t.end_time) {
            (Some(n), _) => state.step >= n,
            // Half a step of slack so round-off in the accumulated time never adds a step.
            (None, Some(end)) => match t.dt {
                Some(dt) => state.time >= end - 0.5 * dt,
                None => spillage_model::step::reached_end_time(state.time, end),
            },
            (None, None) => true,
        }
    }

    fn time_loop(&mut self, solver: &mut dyn Solver, progress: &mut crate::progress::Progress) -> anyhow::Result<()> {
        let output = &self.case.output;
        let write_every = self.case.time.write_every;
        if self.restart_time.is_none() && output.paraview {
            self.frames.write(solver.mesh(), solver.state(), &coupling_frame(solver))?;
        }
        // one report for the whole run: the solver refills it in place each step
        let mut report = StepReport::default();
        while !self.finished(solver.state()) {
            let t0 = Instant::now();
            solver.step_into(&mut report)?;
            let seconds = t0.elapsed().as_secs_f64();
            self.step_seconds += seconds;
            self.steps += 1;
            let state = solver.state();
            if state.time <= 0.0 {
                self.start_up.0 += 1;
                self.start_up.1 += seconds;
            }
            if let Some((name, value)) = report.values.iter().find(|(_, v)| !v.is_finite()) {
                return Err(SolverError::Diverged { step: state.step, time: state.time, what: format!("{name} = {value}") }.into());
            }
            self.record(state, &report)?;
            if output.paraview && write_every > 0 && state.step % write_every == 0 {
                self.frames.write(solver.mesh(), state, &coupling_frame(solver))?;
            }
            if output.checkpoint_every > 0 && state.step % output.checkpoint_every == 0 {
                self.checkpoint(state)?;
            }
            progress.update(self.case, state, &report);
        }
        let state = solver.state();
        let last_written = write_every > 0 && state.step % write_every == 0;
        if output.paraview && !last_written && self.steps > 0 {
            self.frames.write(solver.mesh(), state, &coupling_frame(solver))?;
        }
        self.checkpoint(state)?;
        Ok(())
    }

    fn record(&mut self, state: &State, report: &StepReport) -> anyhow::Result<()> {
        if self.series.is_none() {
            let mut columns = vec!["step", "time", "dt"];
            columns.extend(report.values.iter().map(|(n, _)| *n).filter(|n| !SERIES_CLOCK.contains(n)));
            let path = self.out.join("series.csv");
            // the series' first column is the step: rows after the restart step are recomputed
            let writer = match self.restart_step {
                Some(step) if path.exists() => SeriesWriter::resume(&path, &columns, Some(step as f64))?,
                _ => SeriesWriter::create(&path, &columns)?,
            };
            self.series = Some((writer, report.clone(), Vec::with_capacity(columns.len())));
        }
        self.outer.record(report);
        self.packing.record(report);
        let value = |key: &str| report.values.iter().find(|(k, _)| *k == key).map(|(_, v)| *v);
        if let (Some(substeps), Some(particles)) = (value("substeps"), value("particles")) {
            self.particle_substeps += substeps * particles;
        }
        let (writer, last, row) = self.series.as_mut().expect("just created");
        row.clear();
        row.extend([state.step as f64, state.time, state.dt]);
        row.extend(report.values.iter().filter(|(n, _)| !SERIES_CLOCK.contains(n)).map(|(_, v)| *v));
        writer.write_row(row)?;
        last.values.clone_from(&report.values);
        Ok(())
    }

    fn checkpoint(&self, state: &State) -> anyhow::Result<()> {
        let path = self.out.join("checkpoints").join(format!("step_{:08}.ckpt", state.step));
        spillage_model::checkpoint::write(&path, self.case, state)?;
        Ok(())
    }
}

/// The coupling fields of the solver's last step for a frame (none unless two-way coupled).
fn coupling_frame(solver: &dyn Solver) -> CouplingFrame {
    let (Some(exchange), Some(mesh), Some(fluid)) = (solver.coupling_output(), solver.mesh(), &solver.state().fluid) else {
        return CouplingFrame::default();
    };
    CouplingFrame {
        force_density: Some(exchange.cells.force_density(mesh, &fluid.velocity)),
        fluid_velocity: Some(exchange.fluid_at_particles.iter().map(|f| f.map_or([0.0; 3], |f| f.velocity.into())).collect()),
        drag_force: Some(exchange.particles.drag.clone()),
        slip_reynolds: Some(exchange.particles.slip_reynolds.clone()),
    }
}

/// One PNG per series column against time, in `plots/`.
fn draw_plots(out: &Path, case_name: &str) -> anyhow::Result<()> {
    let path = out.join("series.csv");
    if !path.exists() {
        return Ok(());
    }
    let table = read_series(&path)?;
    let dir = out.join("plots");
    std::fs::create_dir_all(&dir)?;
    // the rotor angle is a straight line in time: not worth a plot
    for column in table.columns.iter().filter(|c| !matches!(c.as_str(), "step" | "time" | "dt" | "rotor_angle")) {
        let Some(points) = table.pairs("time", column) else { continue };
        if points.is_empty() {
            continue;
        }
        let (unit, residual) = column_unit(column);
        // residuals and errors span decades: a log axis, when every value is positive
        let log_y = residual && points.iter().all(|p| p.1 > 0.0);
        let title = format!("{case_name}: {column}");
        let y_label = if unit.is_empty() { column.clone() } else { format!("{column} [{unit}]") };
        let plot = Plot { title: &title, x_label: "time [s]", y_label: &y_label, log_x: false, log_y, series: vec![Series { label: column, points: &points }] };
        write_png(&plot, &dir.join(format!("{column}.png")))?;
    }
    Ok(())
}

/// The unit of a series column ("" when dimensionless or a count) and whether it is a residual or
/// an error (drawn on a log axis).
fn column_unit(column: &str) -> (&'static str, bool) {
    match column {
        // the fluid's ½ Σ |u|² V: energy per unit density
        "kinetic_energy" => ("J/(kg/m³) = m⁵/s²", false),
        "particle_kinetic_energy" => ("J", false),
        "p_initial_residual" | "continuity_local" | "continuity_cell_max" | "interface_imbalance" => ("", true),
        "continuity_global" | "continuity_cumulative" | "particle_volume" => ("m³", false),
        "hull_outflow" | "hull_net_flux" | "suction_flux" | "hull_outflow_top" | "contour_outflow" | "contour_net_flux" | "contour_outflow_top" => {
            ("m³/s", false)
        }
        "settling_velocity" => ("m/s", false),
        // the rotor's torque balance (cutter_head::torque)
        "head_torque"
        | "static_wall_torque"
        | "open_boundary_torque"
        | "gravity_torque"
        | "boundary_angular_momentum_outflow"
        | "angular_momentum_rate"
        | "torque_imbalance"
        | "hull_wall_torque"
        | "hull_gravity_torque"
        | "hull_angular_momentum_flux"
        | "mouth_angular_momentum_flux"
        | "hull_stress_torque"
        | "hull_angular_momentum_rate"
        | "hull_torque_imbalance" => ("N m", false),
        "shaft_power" => ("W", false),
        _ => ("", false),
    }
}

/// Where the particles went: created, still inside, and how many left by each route (a
/// cutter head prints its own production and spillage instead).
fn particle_exits_line(particles: &spillage_model::particles::ParticleState) -> String {
    use spillage_model::particles::bookkeeping::ExitRoute;
    let mut routes: std::collections::BTreeMap<String, u64> = std::collections::BTreeMap::new();
    for exit in &particles.exits {
        let name = match &exit.route {
            ExitRoute::Domain => "the [particles] domain".to_string(),
            ExitRoute::Patch(p) => format!("patch {p}"),
            ExitRoute::Sucked => "sucked".to_string(),
            ExitRoute::Spilled => "spilled".to_string(),
        };
        *routes.entry(name).or_default() += 1;
    }
    let left: Vec<String> = routes.iter().map(|(route, n)| format!("{n} through {route}")).collect();
    format!(
        "particles         {} created, {} inside{}{}",
        particles.counts.created,
        particles.particles.len(),
        if left.is_empty() { "" } else { "; left: " },
        left.join(", ")
    )
}
