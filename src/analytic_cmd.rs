//! `spillage analytic`: evaluate the closed-form reference solutions of `spillage-analytic` from
//! the command line, as tables, JSON or PNG curves.
//!
//! Longer than ~600 lines because it is one table: every analytic solution's parameters, defaults,
//! ranges and output columns in one place, so `--list` and the parser cannot drift apart.
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
        run: run_spillage,
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
        run: run_settling,
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
        run: run_hindered,
    },
    Solution {
        name: "restitution",
        summary: "Legendre wet restitution e = e_dry exp(-35/St) and the lubrication-only limit",
        params: &[
            p("st", "1:10000", "added-mass Stokes number (range, log-spaced)"),
            p("e-dry", "0.97", "dry restitution"),
            p("log-gap", "5", "lubrication limit: ln(h0/h_r)"),
        ],
        run: run_restitution,
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
        run: run_couette,
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
        run: run_hertz,
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
        run: run_walton,
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
        run: run_erosion,
    },
    Solution {
        name: "interface",
        summary: "1-D sliding-interface overlap oracle: [3,6,9] on 3 faces -> 4 faces (erratum 7)",
        params: &[p("source", "3,6,9", "source face values (equal faces on [0, 2])"), p("targets", "4", "number of equal target faces on [0, 2]")],
        run: run_interface,
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

fn run_spillage(params: &Params) -> Result<Report, String> {
    use an::spillage_model::{onset_omega, rpm_to_omega, solve, CutterProfile, SpillageInputs};
    let rpms = params.list("rpm", Spacing::Linear(20))?;
    let discharges = params.list("discharge", Spacing::Linear(5))?;
    let profile = match params.text("head") {
        "lab" => CutterProfile::illustrative_lab_head(),
        "cylinder" => CutterProfile::cylinder(params.number("radius")?, params.number("blade-angle")?.to_radians(), params.number("height")?).map_err(err)?,
        other => return Err(format!("--head = `{other}`: allowed values are `lab` and `cylinder`")),
    };
    let mut report = Report::new("spillage", params, &["rpm", "discharge_m3s", "omega_rad_s", "w1_m", "Q1_m3s", "u_rad1_m_s", "spillage_%", "production_%"]);
    let mut curves = Vec::new();
    for &qm in &discharges {
        let mut inputs = SpillageInputs::calibrated_water(profile.clone(), 0.0, qm);
        inputs.flow_factor = params.number("alpha")?;
        inputs.pressure_coefficient = params.number("beta")?;
        inputs.density_top = params.number("rho1")?;
        inputs.density_bottom = params.number("rho2")?;
        let onset = onset_omega(&inputs).map_err(err)?;
        report.summary(&format!("outflow onset at Q_m = {qm}"), onset * 60.0 / (2.0 * std::f64::consts::PI), "rpm");
        let mut points = Vec::new();
        for &rpm in &rpms {
            inputs.omega = rpm_to_omega(rpm);
            let s = solve(&inputs).map_err(err)?;
            report.rows.push(vec![
                rpm,
                qm,
                inputs.omega,
                s.outflow_height,
                s.outflow_discharge,
                s.outflow_velocity,
                100.0 * s.spillage_fraction,
                100.0 * s.production_fraction,
            ]);
            points.push((rpm, 100.0 * s.spillage_fraction));
        }
        curves.push(Curve { label: format!("Q_m = {qm} m3/s"), points });
    }
    report.summary("head height H", profile.height(), "m");
    if params.text("head") == "lab" {
        report.notes.push("`lab` is an illustrative 1:4 head (the thesis geometry is only in drawings); see CutterProfile::illustrative_lab_head".into());
    }
    report.plot = plot_spec("Analytical spillage model (Eq. 4.55)", "rotation speed [rpm]", "spillage S [%]", false, curves);
    Ok(report)
}

fn run_settling(params: &Params) -> Result<Report, String> {
    use an::drag_laws::DragLaw;
    use an::settling::SettlingSphere;
    let law = DragLaw::from_name(params.text("drag"))
        .ok_or_else(|| format!("--drag = `{}`: allowed values are stokes, schiller-naumann, brown-lawler, dallavalle", params.text("drag")))?;
    let sphere = SettlingSphere::new(
        params.number("d")?,
        params.number("rho-p")?,
        params.number("rho-f")?,
        params.number("nu")?,
        params.number("g")?,
        params.number("cam")?,
    )
    .map_err(err)?;
    let terminal = sphere.terminal_velocity(law).map_err(err)?;
    let (t99, x99) = sphere.time_and_distance_to_speed(law, 0.99 * terminal.velocity).map_err(err)?;
    let times = if params.text("t") == "auto" { (0..=30).map(|i| 1.5 * t99 * i as f64 / 30.0).collect() } else { params.list("t", Spacing::Linear(30))? };
    let samples = sphere.transient(law, &times).map_err(err)?;
    let mut report = Report::new("settling", params, &["t_s", "u_m_s", "x_m"]);
    report.summary("terminal velocity", terminal.velocity, "m/s");
    report.summary("Reynolds number at terminal velocity", terminal.reynolds, "-");
    report.summary("drag coefficient at terminal velocity", terminal.drag_coefficient, "-");
    report.summary("initial acceleration", sphere.initial_acceleration(), "m/s2");
    report.summary("time to 99 % of terminal velocity", t99, "s");
    report.summary("distance to 99 % of terminal velocity", x99, "m");
    report.rows = samples.iter().map(|s| vec![s.time, s.velocity, s.distance]).collect();
    let points = samples.iter().map(|s| (s.time, s.velocity)).collect();
    report.plot = plot_spec("Settling from rest", "time [s]", "settling velocity [m/s]", false, vec![Curve { label: law.name().into(), points }]);
    Ok(report)
}

fn run_hindered(params: &Params) -> Result<Report, String> {
    use an::hindered_settling::{cloud_settling_velocity, richardson_zaki_velocity, rowe_exponent, CloudReconstruction};
    use an::settling::SettlingSphere;
    let sphere =
        SettlingSphere::new(params.number("d")?, params.number("rho-p")?, params.number("rho-f")?, params.number("nu")?, an::GRAVITY, 0.5).map_err(err)?;
    let single = sphere.terminal_velocity(an::drag_laws::DragLaw::BrownLawler).map_err(err)?;
    let n = rowe_exponent(single.reynolds).map_err(err)?;
    let mut report = Report::new("hindered", params, &["phi_p", "u_p_A_m_s", "u_p_B_m_s", "u_RZ_m_s", "beta_DiFelice_A"]);
    report.summary("single-particle terminal velocity", single.velocity, "m/s");
    report.summary("Rowe exponent n", n, "-");
    let (mut a, mut b, mut rz) = (Vec::new(), Vec::new(), Vec::new());
    for phi in params.list("phi", Spacing::Linear(12))? {
        let sa = cloud_settling_velocity(&sphere, phi, CloudReconstruction::SlipVelocity).map_err(err)?;
        let sb = cloud_settling_velocity(&sphere, phi, CloudReconstruction::ParticleVelocity).map_err(err)?;
        let u_rz = richardson_zaki_velocity(single.velocity, phi, n, 0.0).map_err(err)?;
        report.rows.push(vec![phi, sa.particle_velocity, sb.particle_velocity, u_rz, sa.di_felice_exponent]);
        a.push((phi, sa.particle_velocity));
        b.push((phi, sb.particle_velocity));
        rz.push((phi, u_rz));
    }
    report.plot = plot_spec(
        "Hindered settling velocity",
        "particle volume fraction [-]",
        "settling velocity [m/s]",
        false,
        vec![
            Curve { label: "Di Felice (A)".into(), points: a },
            Curve { label: "Di Felice (B)".into(), points: b },
            Curve { label: "Richardson-Zaki (Rowe n)".into(), points: rz },
        ],
    );
    Ok(report)
}

fn run_restitution(params: &Params) -> Result<Report, String> {
    use an::restitution::{legendre_wet_restitution, lubrication_restitution};
    let e_dry = params.number("e-dry")?;
    let log_gap = params.number("log-gap")?;
    let mut report = Report::new("restitution", params, &["St_AM", "e_wet", "e_wet/e_dry", "e_lubrication"]);
    let (mut legendre, mut lubrication) = (Vec::new(), Vec::new());
    for st in params.list("st", Spacing::Log(40))? {
        let e = legendre_wet_restitution(e_dry, st).map_err(err)?;
        let l = lubrication_restitution(e_dry, st, log_gap).map_err(err)?.restitution;
        report.rows.push(vec![st, e, if e_dry > 0.0 { e / e_dry } else { 0.0 }, l]);
        legendre.push((st, e));
        lubrication.push((st, l));
    }
    report.plot = plot_spec(
        "Wet restitution",
        "Stokes number St_AM [-]",
        "restitution [-]",
        true,
        vec![
            Curve { label: "Legendre e_dry exp(-35/St)".into(), points: legendre },
            Curve { label: format!("lubrication only, ln(h0/hr) = {log_gap}"), points: lubrication },
        ],
    );
    Ok(report)
}

fn run_couette(params: &Params) -> Result<Report, String> {
    use an::couette::CircularCouette;
    let cell = CircularCouette::new(params.number("ri")?, params.number("ro")?, params.number("omega-i")?, params.number("omega-o")?).map_err(err)?;
    let rho = params.number("rho")?;
    let radii = if params.text("r") == "auto" {
        (0..=8).map(|i| cell.inner_radius + (cell.outer_radius - cell.inner_radius) * i as f64 / 8.0).collect()
    } else {
        params.list("r", Spacing::Linear(8))?
    };
    let (a, b) = cell.coefficients();
    let mut report = Report::new("couette", params, &["r_m", "u_theta_m_s", "dp_dr_Pa_m", "p_minus_p_Ri_Pa"]);
    report.summary("A in u = A r + B/r", a, "1/s");
    report.summary("B in u = A r + B/r", b, "m2/s");
    let mut points = Vec::new();
    for r in radii {
        let point = cell.point(r).map_err(err)?;
        report.rows.push(vec![r, point.tangential_velocity, rho * point.kinematic_pressure_gradient, rho * point.kinematic_pressure_rise]);
        points.push((r, point.tangential_velocity));
    }
    report.notes.push("dp/dr = +rho u^2/r (sign erratum of thesis Eq. 5.1 corrected)".into());
    report.plot = plot_spec("Circular Couette flow", "radius [m]", "u_theta [m/s]", false, vec![Curve { label: "exact".into(), points }]);
    Ok(report)
}

fn run_hertz(params: &Params) -> Result<Report, String> {
    use an::hertz::{collision_time, hertz_damping_coefficient, openfoam_collision_constant, ContactPair, ElasticMaterial};
    let material = ElasticMaterial::new(params.number("e")?, params.number("poisson")?, params.number("rho")?).map_err(err)?;
    let radius = 0.5 * params.number("d")?;
    let pair = match params.text("partner") {
        "wall" => ContactPair::sphere_rigid_wall(&material, radius),
        "sphere" => ContactPair::sphere_sphere(&material, radius, &material, radius),
        other => return Err(format!("--partner = `{other}`: allowed values are `wall` and `sphere`")),
    }
    .map_err(err)?;
    let alpha = hertz_damping_coefficient(params.number("restitution")?).map_err(err)?;
    let mut report = Report::new("hertz", params, &["u_m_s", "max_overlap_m", "max_force_N", "contact_time_s", "t_col_openfoam_s"]);
    report.summary("effective radius R*", pair.effective_radius, "m");
    report.summary("effective mass M*", pair.effective_mass, "kg");
    report.summary("effective modulus E*", pair.effective_modulus, "Pa");
    report.summary("normal stiffness k_n", pair.normal_stiffness(), "N/m^1.5");
    report.summary("tangential stiffness k_t", pair.tangential_stiffness(), "N/m^1.5");
    report.summary("damping coefficient alpha_eta (Eq. 3.101)", alpha, "-");
    let mut points = Vec::new();
    for u in params.list("u", Spacing::Log(10))? {
        let impact = pair.elastic_impact(u).map_err(err)?;
        let t_col = collision_time(openfoam_collision_constant(), material.density, pair.effective_modulus, radius, u).map_err(err)?;
        report.rows.push(vec![u, impact.max_overlap, impact.max_force, impact.contact_time, t_col]);
        points.push((u, impact.contact_time));
    }
    report.plot = plot_spec("Undamped Hertz contact time", "impact speed [m/s]", "contact time [s]", true, vec![Curve { label: "exact".into(), points }]);
    Ok(report)
}

fn run_walton(params: &Params) -> Result<Report, String> {
    use an::oblique_impact::{ImpactRegime, WaltonModel, SOLID_SPHERE_INERTIA_FACTOR};
    let model = WaltonModel::new(params.number("mu")?, params.number("e-n")?, params.number("e-t")?, SOLID_SPHERE_INERTIA_FACTOR).map_err(err)?;
    let mut report = Report::new("walton", params, &["psi_in", "psi_out", "slip(1)/stick(0)"]);
    report.summary("critical psi*", model.critical_psi(), "-");
    report.summary("slip offset 3.5 mu (1 + e_n)", model.slip_offset(), "-");
    let mut points = Vec::new();
    for psi in params.list("psi", Spacing::Linear(22))? {
        let r = model.rebound(psi).map_err(err)?;
        report.rows.push(vec![psi, r.psi_out, if r.regime == ImpactRegime::Slip { 1.0 } else { 0.0 }]);
        points.push((psi, r.psi_out));
    }
    report.plot = plot_spec("Walton oblique impact", "psi_in [-]", "psi_out [-]", false, vec![Curve { label: "Eq. 2.13".into(), points }]);
    Ok(report)
}

fn run_erosion(params: &Params) -> Result<Report, String> {
    use an::erosion::*;
    let material = match params.text("material") {
        "cs1018" => CARBON_STEEL_1018,
        "ss316" => STAINLESS_STEEL_316,
        other => return Err(format!("--material = `{other}`: allowed values are cs1018 and ss316")),
    };
    let angle_function = match params.text("angle-function") {
        "literal" => AngleFunction::ThesisLiteral,
        "continuous" => AngleFunction::Continuous,
        other => return Err(format!("--angle-function = `{other}`: allowed values are literal and continuous")),
    };
    let include_c = match params.text("include-c") {
        "true" => true,
        "false" => false,
        other => return Err(format!("--include-c = `{other}`: allowed values are true and false")),
    };
    let options = ArabnejadOptions { include_cutting_coefficient: include_c, angle_function, ..ArabnejadOptions::default() };
    let (speed, d, rho_p) = (params.number("u")?, params.number("d")?, params.number("rho-p")?);
    if !(d > 0.0 && rho_p > 0.0) {
        return Err(format!("--d and --rho-p must be > 0 (got {d}, {rho_p})"));
    }
    let mass = rho_p * std::f64::consts::PI * d.powi(3) / 6.0;
    let mut report = Report::new("erosion", params, &["angle_deg", "W_arabnejad", "W_cutting", "W_deformation", "mass_arabnejad_kg", "mass_dnv_kg", "ER_ecrc"]);
    report.summary("particle mass", mass, "kg");
    report.summary("critical angle atan K", critical_angle(material.contact_ratio).to_degrees(), "deg");
    let mut points = Vec::new();
    for deg in params.list("angle", Spacing::Linear(18))? {
        let angle = deg.to_radians().min(std::f64::consts::FRAC_PI_2);
        let w = arabnejad_wear(&material, &options, mass, rho_p, speed, angle).map_err(err)?;
        let dnv = dnv_removed_mass(DNV_STEEL_K, DNV_STEEL_N, mass, speed, angle).map_err(err)?;
        let ecrc = ecrc_erosion_ratio(ECRC_STEEL_C, ECRC_STEEL_N, 120.0, material.sharpness, speed, angle).map_err(err)?;
        report.rows.push(vec![deg, w.volume, w.cutting_volume, w.deformation_volume, w.mass, dnv, ecrc]);
        points.push((deg, w.volume));
    }
    report.notes.push(
        "W in the printed (Table 4.1/5.2) units, see wear-model.md §6.7; DNV and E/CRC use literature constants for steel (E/CRC with Brinell 120)".into(),
    );
    report.plot = plot_spec(
        "Erosion per impact (Arabnejad)",
        "impact angle [deg]",
        "removed volume W",
        false,
        vec![Curve { label: params.text("material").into(), points }],
    );
    Ok(report)
}

fn run_interface(params: &Params) -> Result<Report, String> {
    use an::sliding_interface::{map_values, overlap_weights};
    let source = params.list("source", Spacing::Linear(1))?;
    let targets = params.number("targets")?;
    if !(targets >= 1.0 && targets.fract() == 0.0 && targets <= 10_000.0) {
        return Err(format!("--targets = {targets}: must be a whole number in [1, 10000]"));
    }
    let n_s = source.len();
    let source_edges: Vec<f64> = (0..=n_s).map(|i| 2.0 * i as f64 / n_s as f64).collect();
    let target_edges: Vec<f64> = (0..=targets as usize).map(|j| 2.0 * j as f64 / targets).collect();
    let weights = overlap_weights(&source_edges, &target_edges).map_err(err)?;
    let mapped = map_values(&weights, &source).map_err(err)?;
    let mut report = Report::new("interface", params, &["target_face", "q_target", "weight_row_sum"]);
    for (j, (q, row)) in mapped.iter().zip(&weights).enumerate() {
        report.rows.push(vec![j as f64 + 1.0, *q, row.iter().sum()]);
    }
    let area_s: f64 = source.iter().map(|q| q * 2.0 / n_s as f64).sum();
    let area_t: f64 = mapped.iter().map(|q| q * 2.0 / targets).sum();
    report.summary("sum A q (source)", area_s, "");
    report.summary("sum A q (target)", area_t, "");
    report.notes.push("thesis example prints [3, 5, 8, 9]; its own weights give [3, 5, 7, 9] (erratum)".into());
    Ok(report)
}

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
