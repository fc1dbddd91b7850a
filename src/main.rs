//! `spillage`: the command-line program. Thin: parses, calls the library crates, reports.

mod analytic_cmd;
mod frames;
mod head_report;
mod progress;
mod results_folder;
mod run;
mod sweep;
mod verify_cmd;
mod wear_report;

use std::path::PathBuf;

use spillage::check;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

#[derive(Parser)]
#[command(name = "spillage", version, about = "Rock spillage in rotating cutter heads: verified fluid–DEM–wear simulation")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SolverChoice {
    /// The optimised solver.
    Fast,
    /// The clear, slow solver the fast one is checked against.
    Reference,
}

#[derive(Subcommand)]
enum Command {
    /// Run a case and write the results folder (summary.json, series.csv, ParaView files, plots,
    /// checkpoints).
    Run {
        /// The case file (TOML).
        case: PathBuf,
        #[arg(long, value_enum, default_value_t = SolverChoice::Fast)]
        solver: SolverChoice,
        /// Results folder (default: results/<case name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Worker threads (default: all cores). Results do not depend on it.
        #[arg(long)]
        threads: Option<usize>,
        /// Continue from a checkpoint file written by an earlier run of the same case.
        #[arg(long)]
        restart: Option<PathBuf>,
        /// Replace another run's results in --out (a new run refuses to mix with them).
        #[arg(long)]
        force: bool,
    },
    /// Validate a case file and print the derived numbers (cells, Courant number, DEM step,
    /// Stokes numbers, memory estimate).
    Check { case: PathBuf },
    /// Evaluate the closed-form and semi-analytic answers the solvers are checked against
    /// (`spillage analytic --list`).
    Analytic(analytic_cmd::AnalyticArgs),
    /// Run a case at several values of any of its keys and tabulate and plot the results.
    ///
    /// `--set rotor.rpm=30,60,90` (several --set give every combination): each point runs as a
    /// `spillage run` in its own folder, several at a time; then the final values and window
    /// means of every series column go into sweep.csv and sweep.md and are plotted against the
    /// swept value (with the analytic spillage model for a cutter head). Resumable: completed
    /// points with an unchanged case are skipped.
    Sweep(sweep::SweepArgs),
    /// Run the verification ladder (cases/verification): one row per checked quantity against its
    /// exact or published value; exit status 1 if any fails.
    Verify {
        /// Case files or folders (default: cases/verification).
        cases: Vec<PathBuf>,
        /// Print the rows as JSON (stable format, see README).
        #[arg(long)]
        json: bool,
        /// Include the fine levels (slow).
        #[arg(long)]
        full: bool,
        /// Draw the checks' figures (PNG) into this folder: settling velocity against time with
        /// the analytic curve, cloud velocity against particle fraction, …
        #[arg(long)]
        plots: Option<PathBuf>,
        /// Write the verification report into this folder: report.md (summary with pass/fail and
        /// times per solver, each case's description, reference and rows, the fast-vs-reference
        /// equivalence) and its figures in DIR/figures.
        #[arg(long, value_name = "DIR")]
        report: Option<PathBuf>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run { case, solver, out, threads, restart, force } => run::run(&run::RunOptions { case, solver, out, threads, restart, force }),
        Command::Check { case } => check::check(&case),
        // on a pool worker, as `run`'s time loop (run.rs): no hand-off per parallel loop
        Command::Verify { cases, json, full, plots, report } => rayon::scope(|_| verify_cmd::verify(&cases, json, full, plots.as_deref(), report.as_deref())),
        Command::Analytic(args) => analytic_cmd::run(&args),
        Command::Sweep(args) => sweep::sweep(&args),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}
