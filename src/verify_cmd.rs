//! `spillage verify`: runs each case of the ladder with each solver that supports it (and the
//! fast fluid against the reference step by step) and prints its rows as a table or JSON;
//! `--report DIR` also writes `DIR/report.md` with the figures (issue 20).

use std::path::PathBuf;
use std::process::ExitCode;

use spillage_model::case::Case;

use spillage::verify::report::{run_case_for_report, write, Comparison};
use spillage::verify::{ladder, CheckRow, Criterion};

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

/// Width of the quantity column; longer quantities get a line of their own.
const QUANTITY_WIDTH: usize = 50;

/// The rows, grouped under their case, at most ~125 characters wide; each says what its error
/// is (absolute or relative to the reference) and its bound, and unbounded rows are `reported`.
fn print_table(rows: &[CheckRow]) {
    print!("{}", table(rows));
}

fn table(rows: &[CheckRow]) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let _ = writeln!(out, "  {:<QUANTITY_WIDTH$} {:<8} {:>11}  {:<39} result", "quantity", "solver", "value", "criterion");
    let mut case = "";
    for r in rows {
        if r.case != case {
            case = &r.case;
            let _ = writeln!(out, "{case}");
        }
        let solver = match r.solver.as_str() {
            "reference" => "ref",
            "fast vs reference" => "fast↔ref",
            other => other,
        };
        let criterion = match r.criterion() {
            Criterion::Absolute => format!("vs {:.4e}: err {:.2e} ≤ {:.1e} abs", r.reference, r.error, r.tolerance),
            Criterion::Relative => format!("vs {:.4e}: err {:.2e} ≤ {:.1e} rel", r.reference, r.error, r.tolerance),
            Criterion::AtMost => format!("≤ {:.1e}", r.tolerance),
            Criterion::AtLeast => format!("≥ {:.4e}", r.reference),
            Criterion::Reported => "no bound".to_string(),
        };
        let quantity = if r.quantity.chars().count() > QUANTITY_WIDTH {
            let _ = writeln!(out, "  {}", r.quantity);
            ""
        } else {
            r.quantity.as_str()
        };
        let _ = writeln!(out, "  {quantity:<QUANTITY_WIDTH$} {solver:<8} {:>11.4e}  {criterion:<39} {}", r.value, r.verdict());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 15 item 6: rows say whether their error is absolute or relative, an unbounded row
    /// is `reported` (never `pass`), and lines stay near 125 characters (they ran to 164).
    #[test]
    fn the_table_names_each_criterion_and_stays_narrow() {
        let long = "a quantity whose description runs far beyond the width of its column, as some do";
        let rows = [
            CheckRow::absolute("case_a", "absolute row", "reference", 1.0, 1.1, 0.2),
            CheckRow::relative("case_a", "relative row", "fast", 2.0, 2.2, 0.05),
            CheckRow::at_least("case_a", "observed order", "reference", 1.97, 1.9),
            CheckRow::at_most("case_b", long, "fast vs reference", 3e-12, 1e-10),
            CheckRow::at_most("case_b", "reported row", "analytic", 0.3, f64::INFINITY),
        ];
        let text = table(&rows);
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines.iter().all(|l| l.chars().count() <= 130), "{text}");
        let line = |needle: &str| *lines.iter().find(|l| l.contains(needle)).unwrap_or_else(|| panic!("no `{needle}` in\n{text}"));
        assert!(line("absolute row").contains("≤ 2.0e-1 abs") && line("absolute row").ends_with("pass"), "{text}");
        assert!(line("relative row").contains("≤ 5.0e-2 rel") && line("relative row").ends_with("FAIL"), "{text}");
        assert!(line("observed order").contains("≥ 1.9000e0"), "{text}");
        assert!(line("reported row").ends_with("reported"), "{text}");
        // the long quantity has a line of its own, its numbers the next
        let at = lines.iter().position(|l| l.contains(long)).unwrap();
        assert!(lines[at + 1].contains("fast↔ref") && lines[at + 1].contains("≤ 1.0e-10"), "{text}");
        assert_eq!(lines.iter().filter(|l| **l == "case_a" || **l == "case_b").count(), 2, "one header per case:\n{text}");
    }
}
