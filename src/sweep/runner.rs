//! Running the points: each as a `spillage run` subprocess of this executable in its own folder,
//! several at a time, skipping points an earlier sweep completed with the same case.
//!
//! Subprocesses rather than threads: a run sets up a global thread pool and may fail or be
//! killed on its own; each point gets its own log and exit status, and a crash of one point
//! cannot take the sweep down.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use anyhow::Context;
use spillage_model::output::summary::Summary;

use crate::SolverChoice;

/// The file a point's case is written to, in its folder.
pub const CASE_FILE: &str = "case.toml";
/// The run's stdout and stderr.
pub const LOG_FILE: &str = "log.txt";
/// The status a completed run writes into `summary.json` (`details.status`).
pub const COMPLETED: &str = "completed";

/// Whether a point needs running.
#[derive(Clone, Debug, PartialEq)]
pub enum Decision {
    /// An earlier sweep completed this very case in this folder.
    DoneBefore,
    /// Run it, for this reason (shown to the user).
    Run(&'static str),
}

/// The resumability rule: skip only a completed run whose `case.toml` is the text this sweep
/// would write (byte for byte: any change of the case, including a changed STL location, reruns).
pub fn resume_decision(existing_case: Option<&str>, existing_status: Option<&str>, case_text: &str) -> Decision {
    match (existing_case, existing_status) {
        (None, _) => Decision::Run("new"),
        (Some(existing), _) if existing != case_text => Decision::Run("case changed"),
        (Some(_), Some(COMPLETED)) => Decision::DoneBefore,
        (Some(_), Some(_)) => Decision::Run("failed before"),
        (Some(_), None) => Decision::Run("unfinished before"),
    }
}

/// Reads what an earlier sweep left in `dir` and applies [`resume_decision`].
pub fn decide(dir: &Path, case_text: &str) -> Decision {
    let existing_case = std::fs::read_to_string(dir.join(CASE_FILE)).ok();
    let status = summary_status(dir);
    resume_decision(existing_case.as_deref(), status.as_deref(), case_text)
}

/// `details.status` of the point's `summary.json`, if there is a readable one.
pub fn summary_status(dir: &Path) -> Option<String> {
    let summary = Summary::read(&dir.join("summary.json")).ok()?;
    summary.details.get("status")?.as_str().map(str::to_string)
}

/// Wall seconds an earlier run recorded in its `summary.json`.
pub fn summary_wall_seconds(dir: &Path) -> Option<f64> {
    Summary::read(&dir.join("summary.json")).ok()?.timings_s.get("wall").copied()
}

/// A folder the sweep may delete and refill: absent, empty, or holding a point's `case.toml`
/// (written by an earlier sweep). Anything else is someone's data and is refused.
pub fn check_folder_is_ours(dir: &Path) -> anyhow::Result<()> {
    if !dir.exists() || dir.join(CASE_FILE).is_file() {
        return Ok(());
    }
    let mut entries = std::fs::read_dir(dir).with_context(|| format!("cannot read the point folder {}", dir.display()))?;
    if entries.next().is_some() {
        anyhow::bail!("{} exists and holds files but no {CASE_FILE}: not a sweep point folder, so the sweep will not overwrite it", dir.display());
    }
    Ok(())
}

/// One point to run.
pub struct Job<'a> {
    /// `key=value,…`
    pub label: &'a str,
    pub dir: &'a Path,
    pub case_text: &'a str,
    /// Position in the whole sweep (1-based) for the progress lines.
    pub number: usize,
    /// Why it runs ([`Decision::Run`]), shown unless the point is new.
    pub reason: &'static str,
}

/// How a point's run ended.
#[derive(Clone, Debug, PartialEq)]
pub struct RunOutcome {
    /// `completed` or `failed: …`.
    pub status: String,
    pub wall_seconds: f64,
}

/// How to start each run.
pub struct RunSettings {
    pub executable: PathBuf,
    pub solver: SolverChoice,
    pub threads_per_run: usize,
    pub jobs: usize,
    /// Number of points in the sweep, for the progress lines.
    pub total: usize,
}

/// Runs the jobs, `settings.jobs` at a time, printing a line as each starts and ends. The
/// outcomes are in the order of `jobs`.
pub fn run_all(jobs: &[Job], settings: &RunSettings) -> Vec<RunOutcome> {
    let next = AtomicUsize::new(0);
    let outcomes: Mutex<Vec<Option<RunOutcome>>> = Mutex::new(vec![None; jobs.len()]);
    std::thread::scope(|scope| {
        for _ in 0..settings.jobs.min(jobs.len()) {
            scope.spawn(|| loop {
                let index = next.fetch_add(1, Ordering::Relaxed);
                let Some(job) = jobs.get(index) else { break };
                let reason = if job.reason == "new" { String::new() } else { format!(" ({})", job.reason) };
                say!("[{}/{}] {}: started{reason}", job.number, settings.total, job.label);
                let outcome = run_one(job, settings);
                say!("[{}/{}] {}: {} ({:.1} s)", job.number, settings.total, job.label, outcome.status, outcome.wall_seconds);
                outcomes.lock().unwrap_or_else(|poisoned| poisoned.into_inner())[index] = Some(outcome);
            });
        }
    });
    let outcomes = outcomes.into_inner().unwrap_or_else(|poisoned| poisoned.into_inner());
    outcomes.into_iter().map(|o| o.unwrap_or_else(|| RunOutcome { status: "failed: the sweep lost track of this run".into(), wall_seconds: 0.0 })).collect()
}

/// Runs one point: a fresh folder with its `case.toml`, then `spillage run` into it.
fn run_one(job: &Job, settings: &RunSettings) -> RunOutcome {
    let started = Instant::now();
    let status = match start_and_wait(job, settings) {
        Ok(status) => status,
        Err(e) => format!("failed: {e:#}"),
    };
    RunOutcome { status, wall_seconds: started.elapsed().as_secs_f64() }
}

fn start_and_wait(job: &Job, settings: &RunSettings) -> anyhow::Result<String> {
    prepare_folder(job.dir, job.case_text)?;
    let log_path = job.dir.join(LOG_FILE);
    let log = File::create(&log_path).with_context(|| format!("cannot create {}", log_path.display()))?;
    let log_for_stderr = log.try_clone().with_context(|| format!("cannot share {} between stdout and stderr", log_path.display()))?;
    let exit = Command::new(&settings.executable)
        .arg("run")
        .arg(job.dir.join(CASE_FILE))
        .arg("--out")
        .arg(job.dir)
        .arg("--threads")
        .arg(settings.threads_per_run.to_string())
        .arg("--solver")
        .arg(solver_name(settings.solver))
        .stdin(Stdio::null())
        .stdout(log)
        .stderr(log_for_stderr)
        .status()
        .with_context(|| format!("cannot start {}", settings.executable.display()))?;
    let recorded = summary_status(job.dir);
    Ok(match (exit.success(), recorded) {
        (true, Some(status)) if status == COMPLETED => status,
        (_, Some(status)) if status.starts_with("failed") => status,
        (_, _) => match last_error_line(&log_path) {
            Some(error) => format!("failed: {error}"),
            None => format!("failed: `spillage run` exited with {exit} (see {})", log_path.display()),
        },
    })
}

/// The `--solver` value of a choice.
pub fn solver_name(choice: SolverChoice) -> &'static str {
    match choice {
        SolverChoice::Fast => "fast",
        SolverChoice::Reference => "reference",
    }
}

/// Empties the point's folder (results of another case must not mix with this run's) and
/// writes its case.
fn prepare_folder(dir: &Path, case_text: &str) -> anyhow::Result<()> {
    if dir.exists() {
        check_folder_is_ours(dir)?;
        std::fs::remove_dir_all(dir).with_context(|| format!("cannot clear the point folder {}", dir.display()))?;
    }
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create the point folder {}", dir.display()))?;
    let path = dir.join(CASE_FILE);
    std::fs::write(&path, case_text).with_context(|| format!("cannot write {}", path.display()))
}

/// The message of the last `error:` line of a run's log (what `spillage run` reports before
/// exiting with status 2).
fn last_error_line(log_path: &Path) -> Option<String> {
    let text = std::fs::read_to_string(log_path).ok()?;
    text.lines().rev().find_map(|line| line.trim().strip_prefix("error:")).map(|message| message.trim().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_completed_run_of_the_same_case_is_skipped() {
        let case = "[rotor]\nrpm = 30.0\n";
        assert_eq!(resume_decision(Some(case), Some("completed"), case), Decision::DoneBefore);
        assert_eq!(resume_decision(Some("[rotor]\nrpm = 45.0\n"), Some("completed"), case), Decision::Run("case changed"));
        assert_eq!(resume_decision(Some(case), Some("failed: diverged"), case), Decision::Run("failed before"));
        assert_eq!(resume_decision(Some(case), None, case), Decision::Run("unfinished before"));
        assert_eq!(resume_decision(None, Some("completed"), case), Decision::Run("new"));
    }
}
