//! `spillage verify`: runs each case of the ladder with each solver that supports it (and the
//! fast fluid against the reference step by step) and prints its rows as a table or JSON;
//! `--report DIR` also writes `DIR/report.md` with the figures (issue 20).

use std::path::PathBuf;
use std::process::ExitCode;

use spillage_model::case::Case;

use spillage::verify::report::{run_case_for_report, write, Comparison};
use spillage::verify::{ladder, CheckRow};

/// Stable JSON output of `spillage verify --json` (documented in the README).
#[derive(serde::Serialize)]
struct Report<'a> {
    format: &'static str,
    full: bool,
    passed: usize,
    failed: usize,
    rows: &'a [CheckRow],
}

pub fn verify(inputs: &[PathBuf], json: bool, full: bool, plots: Option<&std::path::Path>, report: Option<&std::path::Path>) -> anyhow::Result<ExitCode> {
    let inputs = if inputs.is_empty() {
        let ladder = PathBuf::from("cases/verification");
        if !ladder.is_dir() {
            let here = std::env::current_dir().map(|d| d.display().to_string()).unwrap_or_else(|_| ".".into());
            anyhow::bail!(
                "there is no cases/verification folder in {here}: run `spillage verify` from the repository root, or name the case files or folders to verify"
            );
        }
        vec![ladder]
    } else {
        inputs.to_vec()
    };
    let mut files = Vec::new();
    for input in &inputs {
        if input.is_dir() {
            files.extend(ladder(input)?);
        } else {
            files.push(input.clone());
        }
    }
    // the report's figures go beside it; `--plots` still names a folder of its own
    let figures = report.map(|dir| dir.join("figures"));
    let plots = figures.as_deref().or(plots);
    if let Some(dir) = report {
        std::fs::create_dir_all(dir).map_err(|e| anyhow::anyhow!("cannot create the report folder {}: {e}", dir.display()))?;
    }
    let mut rows = Vec::new();
    let mut results = Vec::new();
    for file in &files {
        let case = Case::load(file)?;
        if case.verify.is_none() && inputs.iter().all(|i| i.as_path() != file.as_path()) {
            continue; // a plain case inside a folder of the ladder: not a check
        }
        if !json {
            eprintln!("verifying {} …", file.display());
        }
        let result = run_case_for_report(&case, full, plots)?;
        if !json {
            let times: Vec<String> = result.passes.iter().map(|p| format!("{} {:.1} s", p.solver.map_or("check", |s| s.label()), p.seconds)).collect();
            let compared = match &result.comparison {
                Comparison::Compared(e) => format!(", fast vs reference {} steps {:.1e}", e.steps, e.worst),
                _ => String::new(),
            };
            eprintln!("  {}{compared}", times.join(", "));
        }
        rows.extend(result.rows.iter().cloned());
        results.push(result);
    }
    if let Some(dir) = report {
        let path = write(dir, &mut results, full)?;
        if !json {
            eprintln!("report: {}", path.display());
        }
    }
    let failed = rows.iter().filter(|r| !r.pass).count();
    if json {
        let report = Report { format: "spillage-verify/1", full, passed: rows.len() - failed, failed, rows: &rows };
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_table(&rows);
        println!("{} passed, {} failed", rows.len() - failed, failed);
    }
    Ok(if failed == 0 { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

fn print_table(rows: &[CheckRow]) {
    println!("{:<28} {:<40} {:<9} {:>12} {:>12} {:>10} {:>10}  result", "case", "quantity", "solver", "value", "reference", "error", "tolerance");
    for r in rows {
        println!(
            "{:<28} {:<40} {:<9} {:>12.5e} {:>12.5e} {:>10.3e} {:>10.3e}  {}",
            r.case,
            r.quantity,
            r.solver,
            r.value,
            r.reference,
            r.error,
            r.tolerance,
            if r.pass { "pass" } else { "FAIL" }
        );
    }
}
