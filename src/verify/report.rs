//! `spillage verify --report DIR` (issue 20): every case of the ladder run by each solver that
//! supports it, with its fast-vs-reference equivalence, written as `DIR/report.md` with the
//! checks' figures beside it.
//!
//! The report is generic over [`CheckRow`]: a new verification module's rows appear without
//! changes here; its description comes from [`super::about`] (or the case's own description).
//! Times are measured and reported, never asserted.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use spillage_model::case::Case;

use super::equivalence::{self, Equivalence};
use super::{fast_fluid_checks, run_case_with, CheckRow, FluidSolver, Options};

/// The fast-vs-reference comparison of one case.
#[derive(Clone, Debug)]
pub enum Comparison {
    Compared(Equivalence),
    /// Both solvers apply but the case says why it is not compared.
    Skipped(String),
    /// No fast counterpart (particle-only cases: there is one DEM).
    NotApplicable,
}

/// One solver pass over a case: the fluid solver it ran with (`None`: the check's own choice)
/// and its wall-clock time [s].
#[derive(Clone, Debug)]
pub struct Pass {
    pub solver: Option<FluidSolver>,
    pub seconds: f64,
}

/// Everything the report shows about one case.
#[derive(Clone, Debug)]
pub struct CaseResult {
    pub path: PathBuf,
    pub name: String,
    pub description: String,
    pub check: String,
    /// Rows of every pass, then the equivalence row.
    pub rows: Vec<CheckRow>,
    pub passes: Vec<Pass>,
    pub comparison: Comparison,
    /// Figures (PNG file names) this case drew into the report folder.
    pub figures: Vec<String>,
}

impl CaseResult {
    pub fn failed(&self) -> usize {
        self.rows.iter().filter(|r| !r.pass).count()
    }

    /// Wall-clock time of the pass with `solver` (the pass of a check with one pass counts for
    /// the solver its rows name most).
    pub fn seconds(&self, solver: FluidSolver) -> Option<f64> {
        if let Some(p) = self.passes.iter().find(|p| p.solver == Some(solver)) {
            return Some(p.seconds);
        }
        let single = self.passes.iter().find(|p| p.solver.is_none())?;
        let count = |label: &str| self.rows.iter().filter(|r| r.solver == label).count();
        let main = if count("fast") > count("reference") { FluidSolver::Fast } else { FluidSolver::Reference };
        (main == solver).then_some(single.seconds)
    }

    /// Reference time / fast time on the same steps (the equivalence comparison), or of the two
    /// passes.
    pub fn speed_ratio(&self) -> Option<f64> {
        match &self.comparison {
            Comparison::Compared(e) if e.fast_seconds > 0.0 => Some(e.reference_seconds / e.fast_seconds),
            _ => {
                let (r, f) =
                    (self.passes.iter().find(|p| p.solver == Some(FluidSolver::Reference))?, self.passes.iter().find(|p| p.solver == Some(FluidSolver::Fast))?);
                (f.seconds > 0.0).then(|| r.seconds / f.seconds)
            }
        }
    }
}

/// PNG files in `dir` (sorted), to tell which ones a case drew.
fn pngs(dir: Option<&Path>) -> Vec<(String, std::time::SystemTime)> {
    let Some(dir) = dir else { return Vec::new() };
    let Ok(entries) = std::fs::read_dir(dir) else { return Vec::new() };
    let mut found: Vec<(String, std::time::SystemTime)> = entries
        .filter_map(|e| e.ok())
        .filter(|e| e.path().extension().is_some_and(|x| x == "png"))
        .filter_map(|e| Some((e.file_name().to_string_lossy().into_owned(), e.metadata().ok()?.modified().ok()?)))
        .collect();
    found.sort();
    found
}

/// Runs one verification case for the report: the check with each fluid solver it supports
/// (figures from the first pass into `plots`), then the step-by-step fast-vs-reference
/// comparison if both fluid solvers apply.
pub fn run_case_for_report(case: &Case, full: bool, plots: Option<&Path>) -> Result<CaseResult> {
    let verify = case.verify.as_ref().ok_or_else(|| anyhow::anyhow!("{}: not a verification case (it has no [verify] section)", case.path.display()))?;
    let check = verify.check.clone();
    let solvers: Vec<Option<FluidSolver>> = if fast_fluid_checks().contains(&check.as_str()) {
        // the check's own solver first: it draws the figures (the reference for the fluid
        // checks, the fast fluid for the coupling checks, as `--plots` always did)
        if super::coupling::CHECKS.contains(&check.as_str()) {
            vec![Some(FluidSolver::Fast), Some(FluidSolver::Reference)]
        } else {
            vec![Some(FluidSolver::Reference), Some(FluidSolver::Fast)]
        }
    } else {
        vec![None]
    };
    let before = pngs(plots);
    let mut rows = Vec::new();
    let mut passes = Vec::new();
    for (k, solver) in solvers.into_iter().enumerate() {
        let options = Options { full, plots: if k == 0 { plots } else { None }, fluid: solver };
        let started = Instant::now();
        rows.extend(run_case_with(case, &options)?);
        passes.push(Pass { solver, seconds: started.elapsed().as_secs_f64() });
    }
    let figures = pngs(plots).into_iter().filter(|f| !before.contains(f)).map(|(name, _)| name).collect();
    let comparison = if !equivalence::applies(case) {
        Comparison::NotApplicable
    } else if let Some(reason) = equivalence::skipped(case) {
        Comparison::Skipped(reason)
    } else {
        let e = equivalence::compare_case(case, equivalence::steps_for(case)?)?;
        rows.push(e.row(&case.case.name));
        Comparison::Compared(e)
    };
    if case.particles.is_some() {
        // the particle phases, step by step from the same state (issue 19)
        let e = super::particle_equivalence::compare_particle_phases(case, super::particle_equivalence::MIN_SUBSTEPS, PARTICLE_STEPS_MAX)?;
        rows.push(e.row(&case.case.name));
    }
    Ok(CaseResult {
        path: case.path.clone(),
        name: case.case.name.clone(),
        description: case.case.description.clone(),
        check,
        rows,
        passes,
        comparison,
        figures,
    })
}

/// Outer steps the particle-phase comparison may take to reach its sub-steps.
const PARTICLE_STEPS_MAX: u64 = 120;

/// How numbers are printed: as measured (the report) or rounded to their tolerance with no
/// times (the golden snapshot, so noise far below a tolerance does not churn it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Numbers {
    Measured,
    Rounded,
}

/// A number to 4 significant digits (∞ and NaN spelled out).
fn sig(v: f64, digits: usize) -> String {
    if v.is_nan() {
        "NaN".into()
    } else if v.is_infinite() {
        if v > 0.0 { "∞" } else { "−∞" }.into()
    } else if v == 0.0 {
        "0".into()
    } else {
        format!("{:.*e}", digits - 1, v)
    }
}

/// The absolute tolerance of a row on its value: `tolerance` for absolute rows, tolerance ×
/// |reference| for relative ones, none for unbounded rows and lower bounds.
fn absolute_tolerance(r: &CheckRow) -> Option<f64> {
    if !(r.tolerance.is_finite() && r.tolerance > 0.0) {
        return None;
    }
    Some(if r.criterion() == super::Criterion::Relative { r.tolerance * r.reference.abs() } else { r.tolerance })
}

/// `v` rounded to a tenth of the row's absolute tolerance (three significant digits when the
/// row has none; two decimals for lower bounds such as orders), as text.
fn rounded(v: f64, r: &CheckRow) -> String {
    if !v.is_finite() || v == 0.0 {
        return sig(v, 3);
    }
    if r.tolerance == 0.0 && r.reference != 0.0 {
        return format!("{v:.2}");
    }
    match absolute_tolerance(r) {
        Some(tol) => {
            let quantum = 10f64.powf((tol / 10.0).log10().floor());
            let q = (v / quantum).round() * quantum;
            if q == 0.0 {
                return format!("< {}", sig(quantum, 1));
            }
            // as many significant digits as the quantum resolves, at most 10
            let digits = ((q.abs().log10().floor() - quantum.log10().floor()) as i64 + 1).clamp(1, 10) as usize;
            sig(q, digits)
        }
        None if v != 0.0 && v.abs() < 1e-11 => "< 1e-11".into(),
        None => sig(v, 3),
    }
}

fn cell(v: f64, r: &CheckRow, numbers: Numbers) -> String {
    match numbers {
        Numbers::Measured => sig(v, 4),
        Numbers::Rounded => rounded(v, r),
    }
}

fn seconds(v: Option<f64>) -> String {
    v.map_or("—".into(), |s| format!("{s:.2}"))
}

/// Markdown table cell text: pipes escaped.
fn md(text: &str) -> String {
    text.replace('|', "\\|")
}

/// The report's text (figures are linked from `figures/`, beside the report).
pub fn render(results: &[CaseResult], full: bool, numbers: Numbers) -> String {
    let mut out = String::new();
    let (rows, failed): (usize, usize) = (results.iter().map(|c| c.rows.len()).sum(), results.iter().map(|c| c.failed()).sum());
    let _ = writeln!(out, "# spillage verification report\n");
    let _ = writeln!(
        out,
        "Produced by `spillage verify --report{}`: every case of the verification ladder (`cases/verification/`) run by each solver that supports it, checked against its exact or published answer, and the fast fluid solver held to the reference step by step. Rerun the command on a fresh clone to reproduce it.\n",
        if full { " --full" } else { "" }
    );
    let _ = writeln!(
        out,
        "Levels: {}. **{} rows: {} passed, {} failed.**\n",
        if full { "full (coarse and fine)" } else { "coarse (add `--full` for the fine levels)" },
        rows,
        rows - failed,
        failed
    );
    let _ = writeln!(out, "## Summary\n");
    if numbers == Numbers::Measured {
        let _ = writeln!(out, "Wall-clock times of this machine (measured, not asserted). The speed ratio is reference time / fast time over the same steps of the equivalence comparison (or of the two check passes where there is none).\n");
        let _ = writeln!(out, "| case | check | result | reference [s] | fast [s] | equivalence steps: reference / fast [s] | speed ratio |");
        let _ = writeln!(out, "|---|---|---|---:|---:|---:|---:|");
    } else {
        let _ = writeln!(out, "| case | check | result |");
        let _ = writeln!(out, "|---|---|---|");
    }
    for c in results {
        let result = if c.failed() == 0 { format!("pass ({} rows)", c.rows.len()) } else { format!("**FAIL** ({} of {} rows)", c.failed(), c.rows.len()) };
        let link = format!("[{}](#{})", c.name, anchor(&c.name));
        if numbers == Numbers::Measured {
            let equivalence = match &c.comparison {
                Comparison::Compared(e) => format!("{:.2} / {:.2}", e.reference_seconds, e.fast_seconds),
                _ => "—".into(),
            };
            let ratio = c.speed_ratio().map_or("—".into(), |r| format!("{r:.1}×"));
            let _ = writeln!(
                out,
                "| {link} | `{}` | {result} | {} | {} | {equivalence} | {ratio} |",
                c.check,
                seconds(c.seconds(FluidSolver::Reference)),
                seconds(c.seconds(FluidSolver::Fast))
            );
        } else {
            let _ = writeln!(out, "| {link} | `{}` | {result} |", c.check);
        }
    }
    let _ = writeln!(out);
    equivalence_summary(&mut out, results, numbers);
    for c in results {
        case_section(&mut out, c, numbers);
    }
    out
}

/// GitHub's heading anchor of a case name (lower case; `_` and `-` kept).
fn anchor(name: &str) -> String {
    name.chars().filter(|c| c.is_alphanumeric() || *c == '_' || *c == '-' || *c == ' ').map(|c| if c == ' ' { '-' } else { c.to_ascii_lowercase() }).collect()
}

fn equivalence_summary(out: &mut String, results: &[CaseResult], numbers: Numbers) {
    let compared: Vec<(&CaseResult, &Equivalence)> = results
        .iter()
        .filter_map(|c| match &c.comparison {
            Comparison::Compared(e) => Some((c, e)),
            _ => None,
        })
        .collect();
    if compared.is_empty() {
        return;
    }
    let _ = writeln!(out, "## Fast vs reference fluid solver\n");
    let _ = writeln!(
        out,
        "Both fluid solvers run each case with a fluid from the same initial state (with the reference DEM where there are particles); after every step every field of the state is compared. Each field's largest difference is measured against a scale of that field (its maximum; pressures against max|u|², the cumulative continuity error against Δt·max|φ|). Bound: {:e} (issue #6).\n",
        equivalence::TOLERANCE
    );
    if results.iter().any(|c| c.figures.iter().any(|f| f == EQUIVALENCE_FIGURE)) {
        let _ = writeln!(out, "![largest per-step difference per case](figures/{EQUIVALENCE_FIGURE})\n");
    }
    let _ = writeln!(out, "| case | steps | largest difference | worst field | result |");
    let _ = writeln!(out, "|---|---:|---:|---|---|");
    for (c, e) in compared {
        let worst = match numbers {
            Numbers::Measured => sig(e.worst, 3),
            Numbers::Rounded => order_of_magnitude(e.worst),
        };
        // which field is worst is decided by round-off-sized differences: not in the snapshot
        let field = match (e.worst_field(), numbers) {
            (_, Numbers::Rounded) => "—".to_string(),
            ("", _) => "(identical)".to_string(),
            (f, _) => format!("`{f}`"),
        };
        let _ = writeln!(out, "| {} | {} | {worst} | {field} | {} |", c.name, e.steps, if e.worst <= equivalence::TOLERANCE { "pass" } else { "**FAIL**" });
    }
    for c in results {
        if let Comparison::Skipped(reason) = &c.comparison {
            let _ = writeln!(out, "\n{}: not compared: {}", c.name, reason);
        }
    }
    let _ = writeln!(out);
}

/// "≤ 1e-9"-style bound on a round-off-sized number, for the snapshot: the equivalence
/// differences are solver-tolerance noise whose digits mean nothing; their decade does.
fn order_of_magnitude(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("< 1e{}", v.log10().floor() as i64 + 1)
    }
}

/// The figure of the equivalence bars (one bar per case), drawn by [`write`].
pub const EQUIVALENCE_FIGURE: &str = "equivalence.png";

fn case_section(out: &mut String, c: &CaseResult, numbers: Numbers) {
    let _ = writeln!(out, "## {}\n", c.name);
    let _ = writeln!(out, "`{}` — check `{}`. {}\n", c.path.display(), c.check, c.description);
    match super::about::about(&c.check) {
        Some(a) => {
            let _ = writeln!(out, "- **Checks:** {}\n- **Against:** {}\n- **Spec:** {}\n", a.checks, a.reference, a.spec);
        }
        None => {
            let _ = writeln!(out, "- (no description registered for `{}` in src/verify/about.rs)\n", c.check);
        }
    }
    let _ = writeln!(out, "| quantity | solver | value | reference | error | tolerance | result |");
    let _ = writeln!(out, "|---|---|---:|---:|---:|---:|---|");
    for r in &c.rows {
        let tolerance = if r.tolerance.is_infinite() { "(reported)".to_string() } else { cell(r.tolerance, r, Numbers::Measured) };
        let error = match numbers {
            Numbers::Measured => sig(r.error, 3),
            Numbers::Rounded if r.criterion() == super::Criterion::Reported => "—".to_string(),
            Numbers::Rounded if r.pass => "within".to_string(),
            Numbers::Rounded => "outside".to_string(),
        };
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {error} | {tolerance} | {} |",
            md(&r.quantity),
            r.solver,
            cell(r.value, r, numbers),
            cell(r.reference, r, numbers),
            if r.verdict() == "FAIL" { "**FAIL**" } else { r.verdict() }
        );
    }
    let _ = writeln!(out);
    if let Comparison::Compared(e) = &c.comparison {
        let _ = writeln!(out, "Fast vs reference, {} steps: largest scaled difference per field (bound {:e}):\n", e.steps, equivalence::TOLERANCE);
        let _ = writeln!(out, "| field | largest difference |");
        let _ = writeln!(out, "|---|---:|");
        for (field, v) in &e.fields {
            let text = match numbers {
                Numbers::Measured => sig(*v, 3),
                Numbers::Rounded => order_of_magnitude(*v),
            };
            let _ = writeln!(out, "| `{field}` | {text} |");
        }
        let _ = writeln!(out);
    }
    for f in &c.figures {
        let _ = writeln!(out, "![{f}](figures/{f})\n");
    }
}

/// Writes `dir/report.md` and the equivalence figure; the checks' figures are already in
/// `dir/figures`.
pub fn write(dir: &Path, results: &mut [CaseResult], full: bool) -> Result<PathBuf> {
    let figures = dir.join("figures");
    let bars: Vec<(String, f64)> = results
        .iter()
        .filter_map(|c| match &c.comparison {
            Comparison::Compared(e) => Some((c.name.clone(), e.worst)),
            _ => None,
        })
        .collect();
    if !bars.is_empty() {
        draw_equivalence(&figures, &bars)?;
        if let Some(first) = results.iter_mut().find(|c| matches!(c.comparison, Comparison::Compared(_))) {
            first.figures.retain(|f| f != EQUIVALENCE_FIGURE);
            first.figures.push(EQUIVALENCE_FIGURE.into());
        }
    }
    let text = render(results, full, Numbers::Measured);
    let path = dir.join("report.md");
    spillage_model::output::write_atomically(&path, |w| {
        use std::io::Write as _;
        w.write_all(text.as_bytes()).map_err(|source| spillage_model::output::OutputError::Io { path: path.clone(), source })
    })
    .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(path)
}

/// The equivalence bars: each case's largest per-step difference (log scale) against the 1e-8
/// bound; a case whose fields agree to the last bit gets a stub at the axis floor.
fn draw_equivalence(dir: &Path, bars: &[(String, f64)]) -> Result<()> {
    use spillage_model::output::bar_chart::{write_bar_chart_png, Bar};
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let smallest = bars.iter().map(|b| b.1).filter(|v| *v > 0.0).fold(equivalence::TOLERANCE, f64::min);
    let floor = 10f64.powf(smallest.log10().floor() - 1.0);
    let labelled: Vec<Bar> = bars.iter().map(|(name, value)| Bar { label: name, value: *value }).collect();
    write_bar_chart_png(
        "fast vs reference fluid: largest per-step difference",
        "largest difference over the steps, scaled per field [−]",
        &labelled,
        floor,
        Some(("bound 1e-8 (issue #6)", equivalence::TOLERANCE)),
        &dir.join(EQUIVALENCE_FIGURE),
    )?;
    Ok(())
}
