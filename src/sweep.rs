//! `spillage sweep`: one case run at several values of any of its keys, each point in its own
//! folder, then tabulated (`sweep.csv`, `sweep.md`) and plotted.
//!
//! Everything that can be checked is checked before the first run starts: the `--set`
//! arguments, that every key is in the file (or its table is), and every point's case through
//! the same validation `spillage run` applies. A sweep of hours should not stop at point five
//! for a typo. Points already completed with the same case are not run again, so an
//! interrupted or extended sweep resumes by rerunning the same command.

/// Prints a progress line to stdout, ignoring a closed stdout (`| head`, a closed log): the
/// runs and the table matter more than the lines about them.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($arg)*);
    }};
}

// the analytic spillage model on the case's contour (shared with `spillage verify`)
use spillage::verify::head_model as analytic;
mod calibration;
mod plots;
mod points;
mod runner;
pub(crate) mod table;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context};
use spillage_model::case::{Case, CaseError};
use spillage_model::output::series::read_series;

use crate::SolverChoice;
use analytic::HeadModel;
use points::{Point, SweptKey};
use runner::{Decision, Job, RunOutcome, RunSettings};
use table::{PointRow, WindowRule};

/// Arguments of `spillage sweep`.
#[derive(clap::Args, Debug, Clone)]
#[command(after_help = "Examples:
  spillage sweep cases/cutter_head.toml --set rotor.rpm=20,30,45,60,75,90
  spillage sweep cases/rotor_stator.toml --set rotor.omega=0.5,1,2 --set fluid.kinematic_viscosity=0.01,0.02 --jobs 2

Each point's folder OUT/<key>=<value>[,<key2>=<value2>]/ holds its case.toml, log.txt and the
run's results. Rerunning the same command skips points completed with the same case.toml.
Exit status: 0 all points completed, 1 some point failed (the table is still written), 2 bad
input (nothing was run).")]
pub struct SweepArgs {
    /// The case file (TOML).
    pub case: PathBuf,
    /// KEY=V1,V2,…: a dotted key of the case file (`rotor.rpm`, `cutter_head.mesh.cell_size`,
    /// `walls.0.motion.omega`) and the values to run it at, as TOML values (numbers, true/false,
    /// "strings", [arrays]; a bare word is a string). Repeat for more keys: the sweep runs every
    /// combination.
    #[arg(long = "set", value_name = "KEY=V1,V2,…", required = true)]
    pub sets: Vec<String>,
    /// Sweep folder (default: results/<case name>/sweep).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Points run at the same time (default: the number of cores, at most the number of points
    /// to run); each run gets cores / jobs threads (at least 1).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Solver of every run.
    #[arg(long, value_enum, default_value_t = SolverChoice::Fast)]
    pub solver: SolverChoice,
}

/// A point ready to run: its folder, case text and validated case.
struct PlannedPoint {
    point: Point,
    dir: PathBuf,
    case_text: String,
    case: Case,
    decision: Decision,
}

/// Runs the sweep. Bad input is an error (exit status 2) before anything runs; a failed point
/// gives exit status 1 after the table is written.
pub fn sweep(args: &SweepArgs) -> anyhow::Result<ExitCode> {
    let keys = parse_keys(&args.sets)?;
    let original_text = std::fs::read_to_string(&args.case).with_context(|| format!("cannot read the case file {}", args.case.display()))?;
    let original: toml::Table =
        toml::from_str(&original_text).map_err(|e| anyhow::anyhow!("{}: not a TOML file: {}", args.case.display(), e.message().trim()))?;
    for swept in &keys {
        points::check_key_exists(&original, &args.case, &swept.key, &swept.values[0].value)?;
    }
    let points = points::cartesian_product(&keys);
    let cases = validate_points(&args.case, &original, &points)?;
    let case_name = cases[0].1.case.name.clone();
    let out = args.out.clone().unwrap_or_else(|| Path::new("results").join(&case_name).join("sweep"));
    let planned = plan(&out, points, cases)?;

    let to_run = planned.iter().filter(|p| p.decision != Decision::DoneBefore).count();
    let settings = run_settings(args, planned.len(), to_run)?;
    let running = match to_run {
        0 => "nothing to run".to_string(),
        _ => format!("{} at a time with {} thread{} each", settings.jobs, settings.threads_per_run, if settings.threads_per_run == 1 { "" } else { "s" }),
    };
    say!("sweep of {case_name}: {} points ({} done before), {running}; results in {}", planned.len(), planned.len() - to_run, out.display());
    let labels: Vec<String> = planned.iter().map(|p| p.point.label()).collect();
    for (index, point) in planned.iter().enumerate() {
        if point.decision == Decision::DoneBefore {
            say!("[{}/{}] {}: done before", index + 1, planned.len(), labels[index]);
        }
    }
    let jobs: Vec<Job> = planned
        .iter()
        .enumerate()
        .filter_map(|(index, p)| match p.decision {
            Decision::DoneBefore => None,
            Decision::Run(reason) => Some(Job { label: &labels[index], dir: &p.dir, case_text: &p.case_text, number: index + 1, reason }),
        })
        .collect();
    let mut outcomes = runner::run_all(&jobs, &settings).into_iter();

    let rows: Vec<PointRow> = planned
        .iter()
        .map(|p| {
            let outcome = if p.decision == Decision::DoneBefore { None } else { outcomes.next() };
            point_row(p, outcome)
        })
        .collect();
    write_results(&out, args, &case_name, &keys, &planned, &rows)?;

    let failed: Vec<&str> = labels.iter().zip(&rows).filter(|(_, row)| !row.completed()).map(|(label, _)| label.as_str()).collect();
    if failed.is_empty() {
        say!("all {} points completed", rows.len());
        Ok(ExitCode::SUCCESS)
    } else {
        eprintln!("{} of {} points failed (see log.txt in their folders): {}", failed.len(), rows.len(), failed.join("; "));
        Ok(ExitCode::from(1))
    }
}

/// The `--set` arguments, each key once.
fn parse_keys(sets: &[String]) -> anyhow::Result<Vec<SweptKey>> {
    let keys = sets.iter().map(|s| points::parse_set(s)).collect::<anyhow::Result<Vec<_>>>()?;
    for (i, swept) in keys.iter().enumerate() {
        if keys[..i].iter().any(|k| k.key == swept.key) {
            bail!("--set {}: the key is given twice; list all its values in one --set", swept.key);
        }
    }
    if keys.is_empty() {
        bail!("nothing to sweep: give at least one --set KEY=V1,V2,…");
    }
    Ok(keys)
}

/// Every point's case text and validated case; all failures are reported together, each naming
/// its point.
fn validate_points(case_file: &Path, original: &toml::Table, points: &[Point]) -> anyhow::Result<Vec<(String, Case)>> {
    let original_dir = absolute_folder_of(case_file)?;
    let original_name = case_file.file_name().map_or_else(|| case_file.display().to_string(), |n| n.to_string_lossy().into_owned());
    let mut cases = Vec::new();
    // (message, labels of the points with it): a mistake shared by many points is told once
    let mut errors: Vec<(String, Vec<String>)> = Vec::new();
    for point in points {
        let text = points::point_case_text(original, point, &original_dir, &original_name)?;
        match Case::from_toml(&text, case_file) {
            Ok(case) => cases.push((text, case)),
            Err(error) => {
                let message = without_position(error).to_string();
                match errors.iter_mut().find(|(m, _)| *m == message) {
                    Some((_, labels)) => labels.push(point.label()),
                    None => errors.push((message, vec![point.label()])),
                }
            }
        }
    }
    if !errors.is_empty() {
        let failed: usize = errors.iter().map(|(_, labels)| labels.len()).sum();
        let lines: Vec<String> =
            errors.iter().map(|(message, labels)| format!("{} {}: {message}", if labels.len() == 1 { "point" } else { "points" }, labels.join("; "))).collect();
        bail!("{failed} of {} points have an invalid case; nothing was run:\n  {}", points.len(), lines.join("\n  "));
    }
    Ok(cases)
}

/// A point's case error names the original file, but its line and column would point into the
/// rewritten text; the message names the key instead.
fn without_position(error: CaseError) -> CaseError {
    CaseError { line: None, column: None, ..error }
}

/// The absolute folder of the case file, which relative paths in it (STL walls) start from.
fn absolute_folder_of(case_file: &Path) -> anyhow::Result<PathBuf> {
    let folder = case_file.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    std::fs::canonicalize(folder).with_context(|| format!("cannot resolve the folder of {}", case_file.display()))
}

/// Point folders, checked to be distinct and the sweep's own, with the resume decisions.
fn plan(out: &Path, points: Vec<Point>, cases: Vec<(String, Case)>) -> anyhow::Result<Vec<PlannedPoint>> {
    let mut planned: Vec<PlannedPoint> = Vec::new();
    for (point, (case_text, case)) in points.into_iter().zip(cases) {
        let dir = out.join(point.folder_name());
        if let Some(other) = planned.iter().find(|p| p.dir == dir) {
            bail!("points {} and {} would share the folder {}; give the values distinct spellings", other.point.label(), point.label(), dir.display());
        }
        runner::check_folder_is_ours(&dir)?;
        let decision = runner::decide(&dir, &case_text);
        planned.push(PlannedPoint { point, dir, case_text, case, decision });
    }
    Ok(planned)
}

/// Jobs and threads per run from `--jobs` and the cores.
fn run_settings(args: &SweepArgs, total: usize, to_run: usize) -> anyhow::Result<RunSettings> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let jobs = match args.jobs {
        Some(0) => bail!("--jobs 0: expected a whole number ≥ 1"),
        Some(jobs) => jobs,
        None => cores,
    };
    let jobs = jobs.min(to_run).max(1);
    let executable = std::env::current_exe().context("cannot find this program's executable to run the points with")?;
    Ok(RunSettings { executable, solver: args.solver, threads_per_run: (cores / jobs).max(1), jobs, total })
}

/// The table row of a point: its run's status and wall time (from this sweep, or from the
/// summary of the earlier run it skipped), the series summary and the analytic model's numbers.
fn point_row(planned: &PlannedPoint, outcome: Option<RunOutcome>) -> PointRow {
    let (status, wall_seconds) = match outcome {
        Some(outcome) => (outcome.status, Some(outcome.wall_seconds)),
        None => (runner::COMPLETED.to_string(), runner::summary_wall_seconds(&planned.dir)),
    };
    let rule = WindowRule::for_case(&planned.case);
    let series_path = planned.dir.join("series.csv");
    let series = match read_series(&series_path) {
        Ok(series) => table::summarise_series(&series, rule),
        Err(error) => {
            if series_path.exists() {
                eprintln!("warning: point {}: {error}; its series columns are left empty", planned.point.label());
            }
            table::SeriesSummary::default()
        }
    };
    let extras = match HeadModel::of_case(&planned.case).map(|model| model.and_then(|m| m.answer_at_case())) {
        Some(Ok(answer)) => vec![("analytic_outflow".to_string(), answer.outflow_water), ("analytic_production".to_string(), answer.production_mixture)],
        Some(Err(error)) => {
            eprintln!("warning: point {}: {error:#}; no analytic columns", planned.point.label());
            Vec::new()
        }
        None => Vec::new(),
    };
    let values = planned.point.assignments.iter().map(|(_, value)| value.label.clone()).collect();
    PointRow { values, status, wall_seconds, rule: Some(rule), series, extras }
}

/// `sweep.csv`, `sweep.md` and, for one numeric key, the plots.
fn write_results(out: &Path, args: &SweepArgs, case_name: &str, keys: &[SweptKey], planned: &[PlannedPoint], rows: &[PointRow]) -> anyhow::Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("cannot create the sweep folder {}", out.display()))?;
    let key_names: Vec<String> = keys.iter().map(|k| k.key.clone()).collect();
    table::write_csv(&out.join("sweep.csv"), &key_names, rows)?;
    let header = table::MarkdownHeader { case_name, case_file: &args.case, solver: runner::solver_name(args.solver) };
    table::write_markdown(&out.join("sweep.md"), &header, &key_names, rows)?;
    say!("table: {} and {}", out.join("sweep.csv").display(), out.join("sweep.md").display());

    let [swept] = keys else { return Ok(()) };
    let Some(xs) = swept_numbers(planned) else { return Ok(()) };
    let mut models: Vec<HeadModel> = planned.iter().find_map(|p| HeadModel::of_case(&p.case)).and_then(Result::ok).into_iter().collect();
    if let (Some(thesis), Some(axis)) = (models.first().cloned(), plots::OperatingAxis::of_key(&swept.key)) {
        match calibration::calibrate_on_rows(axis, &xs, rows, &thesis) {
            Some(Ok(fit)) => {
                say!("{}", fit.summary());
                // the fit's table solves the model once more per point; if that fails, the
                // plots are still drawn
                match fit.markdown_section(&swept.key) {
                    Ok(section) => {
                        let path = out.join("sweep.md");
                        let table = std::fs::read_to_string(&path).with_context(|| format!("cannot read {}", path.display()))?;
                        std::fs::write(&path, table + &section).with_context(|| format!("cannot write {}", path.display()))?;
                    }
                    Err(error) => eprintln!("warning: {error:#}; sweep.md has no section on the fitted model"),
                }
                models.push(fit.model);
            }
            Some(Err(error)) => eprintln!("warning: {error:#}; the sweep has no fitted model"),
            None => {}
        }
    }
    let written = plots::draw_sweep_plots(&out.join("plots"), &swept.key, &xs, rows, &models)?;
    if !written.is_empty() {
        say!("plots: {} in {}", written.len(), out.join("plots").display());
    }
    Ok(())
}

/// Each point's value of the (only) swept key as a number, if all are numbers.
fn swept_numbers(planned: &[PlannedPoint]) -> Option<Vec<f64>> {
    planned.iter().map(|p| p.point.assignments.first()?.1.as_number()).collect()
}

/// The Euler-turbine model of the shipped head, `cases/cutter_head.toml` (the sweep's tests).
#[cfg(test)]
fn shipped_head_model() -> HeadModel {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/cutter_head.toml");
    let case = Case::from_toml(&std::fs::read_to_string(&path).unwrap(), &path).unwrap();
    HeadModel::of_case(&case).unwrap().unwrap()
}
