//! `spillage analytic`: evaluate the closed-form reference solutions of `spillage-analytic` from
//! the command line, as tables, JSON or PNG curves.
//!
//! This module is the command: the table of solutions with their parameters and defaults (one
//! place, so `--list` and the parser cannot drift apart), parameter and range parsing, and the
//! report (table, JSON, plot). [`solutions`] evaluates each solution into a report.
//!
//! Usage: `spillage analytic <name> [--param value …] [--json] [--plot FILE.png]` and
//! `spillage analytic --list`. Ranges are `a:b:step`, `a:b` (a natural spacing: linear, or
//! logarithmic for Stokes numbers), or comma lists `a,b,c`. Bad parameters print an error naming
//! the parameter and exit with code 2.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use serde::Serialize;
use spillage_analytic as an;
use spillage_model::output::plot::{write_png, Plot, Series};

mod solutions;

/// Arguments of `spillage analytic`.
#[derive(clap::Args, Debug, Clone)]
pub struct AnalyticArgs {
    /// Solution to evaluate (see --list).
    pub name: Option<String>,
    /// List the available solutions and their parameters.
    #[arg(long)]
    pub list: bool,
    /// Print the result as JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Also draw the main curve to this PNG file.
    #[arg(long, value_name = "FILE.png")]
    pub plot: Option<PathBuf>,
    /// Parameters as `--name value` pairs; values may be ranges `a:b:step`, `a:b` or lists `a,b`.
    #[arg(trailing_var_arg = true, allow_hyphen_values = true, value_name = "--PARAM VALUE")]
    pub params: Vec<String>,
}

/// Runs the command. Returns exit code 2 (after printing the reason) for bad parameters.
pub fn run(args: &AnalyticArgs) -> anyhow::Result<ExitCode> {
    if args.list {
        print!("{}", list_text());
        return Ok(ExitCode::SUCCESS);
    }
    let Some(name) = args.name.as_deref() else {
        eprintln!("error: name a solution, e.g. `spillage analytic spillage`, or use --list\n");
        eprint!("{}", list_text());
        return Ok(ExitCode::from(2));
    };
    let Some(solution) = SOLUTIONS.iter().find(|s| s.name == name) else {
        eprintln!("error: unknown solution `{name}`; available: {}", names());
        return Ok(ExitCode::from(2));
    };
    let mut json = args.json;
    let mut plot_path = args.plot.clone();
    let params = match Params::parse(solution, &args.params, &mut json, &mut plot_path) {
        Ok(p) => p,
        Err(message) => return Ok(usage_error(solution, &message)),
    };
    let report = match (solution.run)(&params) {
        Ok(report) => report,
        Err(message) => return Ok(usage_error(solution, &message)),
    };
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", report.table());
    }
    if let Some(path) = plot_path {
        draw(&report, &path).map_err(|e| anyhow::anyhow!("could not write plot {}: {e}", path.display()))?;
        if !json {
            println!("plot written to {}", path.display());
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn usage_error(solution: &Solution, message: &str) -> ExitCode {
    eprintln!("error: {message}");
    eprintln!("usage: spillage analytic {} {}", solution.name, solution.usage());
    ExitCode::from(2)
}

// ------------------------------------------------------------------------------------------
// Solutions and their parameters.

struct ParamSpec {
    name: &'static str,
    default: &'static str,
    help: &'static str,
}

struct Solution {
    name: &'static str,
    summary: &'static str,
    params: &'static [ParamSpec],
    run: fn(&Params) -> Result<Report, String>,
}

impl Solution {
    fn usage(&self) -> String {
        self.params.iter().map(|p| format!("[--{} {}]", p.name, p.default)).collect::<Vec<_>>().join(" ")
    }
}

const fn p(name: &'static str, default: &'static str, help: &'static str) -> ParamSpec {
    ParamSpec { name, default, help }
}

const SOLUTIONS: &[Solution] = &[
    Solution {
        name: "spillage",
        summary: "Euler-turbine spillage model: w1, Q1, spillage vs rpm (spillage-and-flow §2)",
        params: &[
            p("rpm", "20:120:5", "rotation speed n_c [rpm] (range)"),
            p("discharge", "0.12", "suction discharge Q_m [m3/s] (range)"),
            p("alpha", "0.375", "flow factor, in (0, 1)"),
            p("beta", "0.774", "pressure coefficient, in [0, 1]"),
            p("rho1", "998.2", "density of the top segment [kg/m3]"),
            p("rho2", "998.2", "density of the bottom segment [kg/m3]"),
            p("head", "lab", "geometry: `lab` (illustrative 1:4 head) or `cylinder`"),
            p("radius", "0.375", "cylinder radius [m] (head=cylinder)"),
            p("height", "0.44", "cylinder height [m] (head=cylinder)"),
            p("blade-angle", "30", "cylinder blade angle [deg] (head=cylinder)"),
        ],
        run: solutions::run_spillage,
    },
    Solution {
        name: "settling",
        summary: "single sphere: terminal velocity and u(t) from rest (particle-verification P1)",
        params: &[
            p("d", "0.01", "diameter [m]"),
            p("rho-p", "2650", "particle density [kg/m3]"),
            p("rho-f", "998.2", "fluid density [kg/m3]"),
            p("nu", "1.0034e-6", "kinematic viscosity [m2/s]"),
            p("g", "9.81", "gravity [m/s2]"),
            p("cam", "0.5", "added-mass coefficient"),
            p("drag", "brown-lawler", "stokes | schiller-naumann | brown-lawler | dallavalle"),
            p("t", "auto", "output times [s] (range; auto = 0 … 1.5 t99)"),
        ],
        run: solutions::run_settling,
    },
    Solution {
        name: "hindered",
        summary: "cloud settling velocity vs particle fraction: Di Felice (A), (B), Richardson-Zaki",
        params: &[
            p("phi", "0:0.3:0.025", "particle volume fraction (range)"),
            p("d", "0.01", "diameter [m]"),
            p("rho-p", "2650", "particle density [kg/m3]"),
            p("rho-f", "998.2", "fluid density [kg/m3]"),
            p("nu", "1.0034e-6", "kinematic viscosity [m2/s]"),
        ],
        run: solutions::run_hindered,
    },
    Solution {
        name: "restitution",
        summary: "Legendre wet restitution e = e_dry exp(-35/St) and the lubrication-only limit",
        params: &[
            p("st", "1:10000", "added-mass Stokes number (range, log-spaced)"),
            p("e-dry", "0.97", "dry restitution"),
            p("log-gap", "5", "lubrication limit: ln(h0/h_r)"),
        ],
        run: solutions::run_restitution,
    },
    Solution {
        name: "couette",
        summary: "circular Couette flow u(r), dp/dr, p(r)-p(Ri) (spillage-and-flow §3.2)",
        params: &[
            p("ri", "1", "inner radius [m]"),
            p("ro", "2", "outer radius [m]"),
            p("omega-i", "1", "inner angular velocity [rad/s]"),
            p("omega-o", "0", "outer angular velocity [rad/s]"),
            p("rho", "1", "density [kg/m3]"),
            p("r", "auto", "radii [m] (range; auto = Ri:Ro in 8 steps)"),
        ],
        run: solutions::run_couette,
    },
    Solution {
        name: "hertz",
        summary: "Hertz sphere impact: max overlap, force, contact time, damping (fluid-dem §7)",
        params: &[
            p("d", "0.01", "sphere diameter [m]"),
            p("rho", "2540", "sphere density [kg/m3]"),
            p("e", "60e9", "Young's modulus [Pa]"),
            p("poisson", "0.23", "Poisson ratio"),
            p("partner", "wall", "`wall` (rigid) or `sphere` (identical sphere)"),
            p("u", "0.01,0.1,1,10", "impact (relative normal) speed [m/s] (range)"),
            p("restitution", "0.97", "normal restitution for the damping coefficient"),
        ],
        run: solutions::run_hertz,
    },
    Solution {
        name: "walton",
        summary: "Walton hard-sphere oblique wall impact: psi_out vs psi_in (particle-verif. 1.6)",
        params: &[
            p("psi", "0:2.2:0.1", "psi_in = u_t/u_n (range)"),
            p("mu", "0.15", "friction coefficient"),
            p("e-n", "0.88013", "normal restitution"),
            p("e-t", "0.35", "tangential restitution (stick)"),
        ],
        run: solutions::run_walton,
    },
    Solution {
        name: "erosion",
        summary: "erosion per impact vs angle: Arabnejad, with DNV and E/CRC columns (wear §6)",
        params: &[
            p("angle", "0:90:5", "impact angle from the surface [deg] (range)"),
            p("u", "10", "impact speed [m/s]"),
            p("d", "0.001", "particle diameter [m]"),
            p("rho-p", "2500", "particle density [kg/m3]"),
            p("material", "cs1018", "cs1018 | ss316"),
            p("angle-function", "literal", "literal (Eq. 2.36 as printed) | continuous"),
            p("include-c", "true", "multiply cutting by C (canonical) or not (Eq. 2.39 as printed)"),
        ],
        run: solutions::run_erosion,
    },
    Solution {
        name: "interface",
        summary: "1-D sliding-interface overlap oracle: [3,6,9] on 3 faces -> 4 faces (erratum 7)",
        params: &[p("source", "3,6,9", "source face values (equal faces on [0, 2])"), p("targets", "4", "number of equal target faces on [0, 2]")],
        run: solutions::run_interface,
    },
];

fn names() -> String {
    SOLUTIONS.iter().map(|s| s.name).collect::<Vec<_>>().join(", ")
}

fn list_text() -> String {
    let mut out = String::from("Closed-form reference solutions (spillage analytic <name> [--param value ...]):\n");
    for s in SOLUTIONS {
        out.push_str(&format!("\n  {:<12} {}\n", s.name, s.summary));
        for prm in s.params {
            out.push_str(&format!("      --{:<15} {:<15} {}\n", prm.name, prm.default, prm.help));
        }
    }
    out.push_str("\nRanges: a:b:step, a:b (natural spacing), or a,b,c. Add --json for JSON, --plot FILE.png for a curve.\n");
    out
}

// ------------------------------------------------------------------------------------------
// Parameter parsing.

struct Params {
    values: BTreeMap<&'static str, String>,
}

#[derive(Clone, Copy)]
enum Spacing {
    Linear(usize),
    Log(usize),
}

impl Params {
    fn parse(solution: &Solution, raw: &[String], json: &mut bool, plot: &mut Option<PathBuf>) -> Result<Self, String> {
        let mut values: BTreeMap<&'static str, String> = solution.params.iter().map(|p| (p.name, p.default.to_string())).collect();
        let mut i = 0;
        while i < raw.len() {
            let token = &raw[i];
            let Some(key) = token.strip_prefix("--") else {
                return Err(format!("unexpected argument `{token}`; parameters are written `--name value`"));
            };
            let (key, inline) = match key.split_once('=') {
                Some((k, v)) => (k, Some(v.to_string())),
                None => (key, None),
            };
            if key == "json" {
                *json = true;
                i += 1;
                continue;
            }
            let value = match inline {
                Some(v) => v,
                None => {
                    i += 1;
                    raw.get(i).cloned().ok_or_else(|| format!("parameter --{key} needs a value"))?
                }
            };
            if key == "plot" {
                *plot = Some(PathBuf::from(value));
            } else if let Some(spec) = solution.params.iter().find(|p| p.name == key) {
                values.insert(spec.name, value);
            } else {
                let allowed: Vec<_> = solution.params.iter().map(|p| format!("--{}", p.name)).collect();
                return Err(format!("unknown parameter --{key} for `{}`; allowed: {}", solution.name, allowed.join(", ")));
            }
            i += 1;
        }
        Ok(Self { values })
    }

    fn text(&self, name: &str) -> &str {
        self.values.get(name).map(String::as_str).unwrap_or("")
    }

    fn number(&self, name: &str) -> Result<f64, String> {
        parse_number(name, self.text(name))
    }

    fn list(&self, name: &str, natural: Spacing) -> Result<Vec<f64>, String> {
        parse_range(name, self.text(name), natural)
    }
}

fn parse_number(name: &str, text: &str) -> Result<f64, String> {
    let value: f64 = text.trim().parse().map_err(|_| format!("--{name} = `{text}` is not a number"))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("--{name} = `{text}` must be finite"))
    }
}

const MAX_POINTS: usize = 100_000;

fn parse_range(name: &str, text: &str, natural: Spacing) -> Result<Vec<f64>, String> {
    if text.contains(',') {
        return text.split(',').map(|t| parse_number(name, t)).collect();
    }
    let parts: Vec<&str> = text.split(':').collect();
    match parts.as_slice() {
        [single] => Ok(vec![parse_number(name, single)?]),
        [a, b] => {
            let (a, b) = (parse_number(name, a)?, parse_number(name, b)?);
            if b < a {
                return Err(format!("--{name} = `{text}`: the end must not be below the start"));
            }
            Ok(match natural {
                Spacing::Linear(n) => (0..=n).map(|i| a + (b - a) * i as f64 / n as f64).collect(),
                Spacing::Log(n) => {
                    if a <= 0.0 {
                        return Err(format!("--{name} = `{text}`: a logarithmic range needs a start > 0"));
                    }
                    (0..=n).map(|i| a * (b / a).powf(i as f64 / n as f64)).collect()
                }
            })
        }
        [a, b, step] => {
            let (a, b, step) = (parse_number(name, a)?, parse_number(name, b)?, parse_number(name, step)?);
            if step <= 0.0 {
                return Err(format!("--{name} = `{text}`: the step must be > 0"));
            }
            if b < a {
                return Err(format!("--{name} = `{text}`: the end must not be below the start"));
            }
            let count = ((b - a) / step + 1e-9).floor() as usize + 1;
            if count > MAX_POINTS {
                return Err(format!("--{name} = `{text}` gives {count} points; at most {MAX_POINTS} allowed"));
            }
            Ok((0..count).map(|i| a + step * i as f64).collect())
        }
        _ => Err(format!("--{name} = `{text}` is not a number, a range a:b[:step] or a list a,b,c")),
    }
}

fn err(e: an::AnalyticError) -> String {
    e.to_string()
}

// ------------------------------------------------------------------------------------------
// Reports.

#[derive(Serialize)]
struct SummaryItem {
    name: String,
    value: f64,
    unit: String,
}

#[derive(Serialize)]
struct Curve {
    label: String,
    points: Vec<(f64, f64)>,
}

#[derive(Serialize)]
struct PlotSpec {
    title: String,
    x_label: String,
    y_label: String,
    log_x: bool,
    log_y: bool,
    curves: Vec<Curve>,
}

#[derive(Serialize)]
struct Report {
    solution: String,
    parameters: BTreeMap<String, String>,
    summary: Vec<SummaryItem>,
    columns: Vec<String>,
    rows: Vec<Vec<f64>>,
    notes: Vec<String>,
    #[serde(skip)]
    plot: Option<PlotSpec>,
}

impl Report {
    fn new(solution: &str, params: &Params, columns: &[&str]) -> Self {
        Self {
            solution: solution.to_string(),
            parameters: params.values.iter().map(|(k, v)| (k.to_string(), v.clone())).collect(),
            summary: Vec::new(),
            columns: columns.iter().map(|c| c.to_string()).collect(),
            rows: Vec::new(),
            notes: Vec::new(),
            plot: None,
        }
    }

    fn summary(&mut self, name: &str, value: f64, unit: &str) {
        self.summary.push(SummaryItem { name: name.into(), value, unit: unit.into() });
    }

    fn table(&self) -> String {
        let mut out = String::new();
        for item in &self.summary {
            out.push_str(&format!("{:<44} {:>14} {}\n", item.name, format_value(item.value), item.unit));
        }
        if !self.summary.is_empty() && !self.rows.is_empty() {
            out.push('\n');
        }
        if !self.rows.is_empty() {
            let widths: Vec<usize> = self.columns.iter().map(|c| c.chars().count().max(12)).collect();
            let header: Vec<String> = self.columns.iter().zip(&widths).map(|(c, w)| format!("{c:>w$}")).collect();
            out.push_str(&header.join("  "));
            out.push('\n');
            for row in &self.rows {
                let cells: Vec<String> = row.iter().zip(&widths).map(|(v, w)| format!("{:>w$}", format_value(*v))).collect();
                out.push_str(&cells.join("  "));
                out.push('\n');
            }
        }
        for note in &self.notes {
            out.push_str(&format!("note: {note}\n"));
        }
        out
    }
}

fn format_value(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v.is_infinite() {
        if v > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        }
    } else if v.abs() >= 1e5 || v.abs() < 1e-3 {
        format!("{v:.6e}")
    } else {
        format!("{v:.6}")
    }
}

fn draw(report: &Report, path: &Path) -> std::io::Result<()> {
    let Some(spec) = &report.plot else {
        return Err(std::io::Error::other(format!("`{}` has no curve to plot", report.solution)));
    };
    let plot = Plot {
        title: &spec.title,
        x_label: &spec.x_label,
        y_label: &spec.y_label,
        log_x: spec.log_x,
        log_y: spec.log_y,
        series: spec.curves.iter().map(|c| Series { label: &c.label, points: &c.points }).collect(),
    };
    write_png(&plot, path).map_err(std::io::Error::from)
}

fn plot_spec(title: &str, x: &str, y: &str, log_x: bool, curves: Vec<Curve>) -> Option<PlotSpec> {
    Some(PlotSpec { title: title.into(), x_label: x.into(), y_label: y.into(), log_x, log_y: false, curves })
}

// ------------------------------------------------------------------------------------------
// The solutions.

#[cfg(test)]
mod tests {
    use super::*;

    fn args(name: &str, params: &[&str]) -> AnalyticArgs {
        AnalyticArgs { name: Some(name.into()), list: false, json: false, plot: None, params: params.iter().map(|s| s.to_string()).collect() }
    }

    #[test]
    fn ranges_parse() {
        assert_eq!(parse_range("x", "1:2:0.5", Spacing::Linear(3)).unwrap(), vec![1.0, 1.5, 2.0]);
        assert_eq!(parse_range("x", "0:3", Spacing::Linear(3)).unwrap(), vec![0.0, 1.0, 2.0, 3.0]);
        let log = parse_range("x", "1:100", Spacing::Log(2)).unwrap();
        assert!((log[1] - 10.0).abs() < 1e-12);
        assert_eq!(parse_range("x", "1,5", Spacing::Linear(3)).unwrap(), vec![1.0, 5.0]);
        assert!(parse_range("x", "2:1", Spacing::Linear(3)).is_err());
        assert!(parse_range("x", "1:2:0", Spacing::Linear(3)).is_err());
        assert!(parse_range("x", "0:1", Spacing::Log(3)).is_err());
        assert!(parse_range("x", "abc", Spacing::Linear(3)).is_err());
    }

    #[test]
    fn every_solution_runs_with_defaults() {
        for s in SOLUTIONS {
            let code = run(&args(s.name, &["--json"])).unwrap();
            assert_eq!(code, ExitCode::SUCCESS, "{}", s.name);
        }
    }

    #[test]
    fn bad_parameters_exit_with_code_2() {
        assert_eq!(run(&args("spillage", &["--alpha", "1.5"])).unwrap(), ExitCode::from(2));
        assert_eq!(run(&args("spillage", &["--discharge", "-0.1"])).unwrap(), ExitCode::from(2));
        assert_eq!(run(&args("settling", &["--rho-p", "500"])).unwrap(), ExitCode::from(2));
        assert_eq!(run(&args("settling", &["--bogus", "1"])).unwrap(), ExitCode::from(2));
        assert_eq!(run(&args("couette", &["--ro", "0.5"])).unwrap(), ExitCode::from(2));
        assert_eq!(run(&args("nonexistent", &[])).unwrap(), ExitCode::from(2));
        assert_eq!(run(&args("hertz", &["--u"])).unwrap(), ExitCode::from(2));
    }

    #[test]
    fn spillage_report_has_one_row_per_point() {
        let solution = SOLUTIONS.iter().find(|s| s.name == "spillage").unwrap();
        let (mut json, mut plot) = (false, None);
        let params = Params::parse(solution, &["--rpm".into(), "20:90:10".into(), "--discharge".into(), "0.06,0.12".into()], &mut json, &mut plot).unwrap();
        let report = (solution.run)(&params).unwrap();
        assert_eq!(report.rows.len(), 16);
        assert_eq!(report.plot.as_ref().unwrap().curves.len(), 2);
    }
}
