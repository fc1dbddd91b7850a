//! `spillage verify`: runs the verification ladder and reports one row per checked quantity.
//!
//! Every verification case is a plain case file with a `[verify]` section naming its check; the
//! procedure that compares the run with the exact answer lives in the module of its model
//! (`fluid`, `dem`, …). The solvers never know they are being verified.

pub mod about;
pub mod contour_map;
pub mod coupling;
pub mod cutter_head;
pub mod dem;
pub mod equivalence;
pub mod figures;
pub mod fluid;
pub mod head_model;
pub mod particle_equivalence;
pub mod report;
pub mod rotating_frame;
pub mod turbulence;
pub mod turbulence_step;
pub mod wear;

pub use equivalence::equivalence_error;

use std::path::{Path, PathBuf};

use serde::Serialize;
use spillage_model::case::Case;

/// One checked quantity: the stable row of `spillage verify --json`.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct CheckRow {
    /// Case name (`[case] name`).
    pub case: String,
    /// What was measured, e.g. `u_theta rms error 64x16` or `observed order u_theta`.
    pub quantity: String,
    /// `reference`, `fast`, `analytic`, or `fast vs reference` (the step-by-step comparison).
    pub solver: String,
    pub value: f64,
    /// The exact or published value it is compared with.
    pub reference: f64,
    /// |value − reference| (or the relative form, as the check states in `quantity`).
    pub error: f64,
    /// Largest acceptable error (or smallest acceptable value for orders; see `quantity`).
    pub tolerance: f64,
    pub pass: bool,
}

impl CheckRow {
    /// A row that passes when |value − reference| ≤ tolerance.
    pub fn absolute(case: &str, quantity: impl Into<String>, solver: &str, value: f64, reference: f64, tolerance: f64) -> Self {
        let error = (value - reference).abs();
        Self { case: case.into(), quantity: quantity.into(), solver: solver.into(), value, reference, error, tolerance, pass: error <= tolerance }
    }

    /// A row that passes when |value − reference| / |reference| ≤ tolerance.
    pub fn relative(case: &str, quantity: impl Into<String>, solver: &str, value: f64, reference: f64, tolerance: f64) -> Self {
        let error = (value - reference).abs() / reference.abs().max(f64::MIN_POSITIVE);
        Self { case: case.into(), quantity: quantity.into(), solver: solver.into(), value, reference, error, tolerance, pass: error <= tolerance }
    }

    /// A row that passes when `value ≥ minimum` (observed convergence orders); `error` is the
    /// shortfall below the minimum (0 when it passes).
    pub fn at_least(case: &str, quantity: impl Into<String>, solver: &str, value: f64, minimum: f64) -> Self {
        let error = (minimum - value).max(0.0);
        Self { case: case.into(), quantity: quantity.into(), solver: solver.into(), value, reference: minimum, error, tolerance: 0.0, pass: value >= minimum }
    }

    /// A row that passes when `value ≤ maximum` (imbalances, errors with no exact target).
    pub fn at_most(case: &str, quantity: impl Into<String>, solver: &str, value: f64, maximum: f64) -> Self {
        Self {
            case: case.into(),
            quantity: quantity.into(),
            solver: solver.into(),
            value,
            reference: 0.0,
            error: value.abs(),
            tolerance: maximum,
            pass: value.abs() <= maximum,
        }
    }
}

/// How a row judges its value, as its constructor filled it in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Criterion {
    /// |value − reference| ≤ tolerance.
    Absolute,
    /// |value − reference| / |reference| ≤ tolerance.
    Relative,
    /// |value| ≤ tolerance.
    AtMost,
    /// value ≥ reference (orders; `error` is the shortfall).
    AtLeast,
    /// No bound: the value is reported (an infinite tolerance).
    Reported,
}

impl CheckRow {
    /// The row's criterion, read back from its numbers (the constructors above are the only
    /// ways rows are made, and each leaves its own signature).
    pub fn criterion(&self) -> Criterion {
        let absolute = (self.value - self.reference).abs();
        if self.tolerance.is_infinite() {
            Criterion::Reported
        } else if self.tolerance == 0.0 && self.error == (self.reference - self.value).max(0.0) {
            Criterion::AtLeast
        } else if self.reference == 0.0 && self.error == self.value.abs() {
            Criterion::AtMost
        } else if (self.error - absolute).abs() > 1e-9 * self.error.abs().max(absolute) {
            Criterion::Relative
        } else {
            Criterion::Absolute
        }
    }

    /// `pass`, `FAIL`, or `reported` for a row without a bound.
    pub fn verdict(&self) -> &'static str {
        match (self.criterion(), self.pass) {
            (Criterion::Reported, _) => "reported",
            (_, true) => "pass",
            (_, false) => "FAIL",
        }
    }
}

/// The fluid solver a check runs with (the particles are always the reference DEM).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FluidSolver {
    Reference,
    Fast,
}

impl FluidSolver {
    /// The `solver` of the rows it produces.
    pub fn label(self) -> &'static str {
        match self {
            FluidSolver::Reference => "reference",
            FluidSolver::Fast => "fast",
        }
    }
}

/// How a check runs.
#[derive(Clone, Copy, Debug)]
pub struct Options<'a> {
    /// Add the fine levels (slow).
    pub full: bool,
    /// Draw the check's figures into this folder (checks that have figures).
    pub plots: Option<&'a Path>,
    /// The fluid solver, for the checks in [`fast_fluid_checks`]; `None` is the check's own
    /// choice (the reference fluid, except the coupling, cutter-head and wear checks, which take
    /// the fast one for speed).
    pub fluid: Option<FluidSolver>,
}

/// Checks that run with either fluid solver ([`Options::fluid`]): `spillage verify` runs them
/// with both.
pub fn fast_fluid_checks() -> Vec<&'static str> {
    let mut checks = Vec::new();
    checks.extend_from_slice(fluid::CHECKS);
    checks.extend_from_slice(coupling::CHECKS);
    checks
}

/// Runs the check named in `case.verify`. `full` adds the fine levels.
pub fn run_case(case: &Case, full: bool) -> anyhow::Result<Vec<CheckRow>> {
    run_case_with_plots(case, full, None)
}

/// [`run_case`], drawing the check's figures into `plots` (checks that have figures).
pub fn run_case_with_plots(case: &Case, full: bool, plots: Option<&Path>) -> anyhow::Result<Vec<CheckRow>> {
    run_case_with(case, &Options { full, plots, fluid: None })
}

/// [`run_case`] with all its [`Options`].
pub fn run_case_with(case: &Case, options: &Options) -> anyhow::Result<Vec<CheckRow>> {
    let Some(verify) = &case.verify else {
        anyhow::bail!("{}: not a verification case (it has no [verify] section)", case.path.display());
    };
    let check = verify.check.as_str();
    let rows = dispatch(case, check, options)?;
    if rows.is_empty() {
        anyhow::bail!("{}: check `{check}` produced no rows", case.path.display());
    }
    Ok(rows)
}

/// Each model's verification module lists its checks in `CHECKS` and runs them in `run_check`.
fn dispatch(case: &Case, check: &str, options: &Options) -> anyhow::Result<Vec<CheckRow>> {
    let (full, plots) = (options.full, options.plots);
    if dem::CHECKS.contains(&check) {
        return dem::run_check(case, check, full, plots);
    }
    if fluid::CHECKS.contains(&check) {
        return fluid::run_check(case, check, full, plots, options.fluid.unwrap_or(FluidSolver::Reference));
    }
    if coupling::CHECKS.contains(&check) {
        return coupling::run_check(case, check, full, plots, options.fluid.unwrap_or(FluidSolver::Fast));
    }
    if cutter_head::CHECKS.contains(&check) {
        return cutter_head::run_check(case, check, full, plots);
    }
    if wear::CHECKS.contains(&check) {
        return wear::run_check(case, check, full, plots);
    }
    if rotating_frame::CHECKS.contains(&check) {
        return rotating_frame::run_check(case, check, full);
    }
    if turbulence::CHECKS.contains(&check) {
        return turbulence::run_check(case, check, full, plots);
    }
    anyhow::bail!("{}: unknown verification check `{check}` in [verify] check; known checks: {}", case.path.display(), known_checks().join(", "))
}

/// Names accepted in `[verify] check`.
pub fn known_checks() -> Vec<&'static str> {
    let mut checks = Vec::new();
    checks.extend_from_slice(dem::CHECKS);
    checks.extend_from_slice(fluid::CHECKS);
    checks.extend_from_slice(coupling::CHECKS);
    checks.extend_from_slice(cutter_head::CHECKS);
    checks.extend_from_slice(wear::CHECKS);
    checks.extend_from_slice(rotating_frame::CHECKS);
    checks.extend_from_slice(turbulence::CHECKS);
    checks
}

/// The case files of the verification ladder, sorted by path.
pub fn ladder(root: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let mut found = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let entries = std::fs::read_dir(&dir).map_err(|e| anyhow::anyhow!("cannot list {}: {e}", dir.display()))?;
        for entry in entries {
            let path = entry?.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "toml") {
                found.push(path);
            }
        }
    }
    found.sort();
    Ok(found)
}

pub mod dem_rig;
