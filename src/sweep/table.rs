//! The sweep's table: per point the swept values, status, wall time, and per series column the
//! final value and the mean over an averaging window; written as `sweep.csv` (every column) and
//! `sweep.md` (a readable selection).
//!
//! The window is the last rotor revolution for a case with a turning `[rotor]`: a rotating head
//! pumps periodically with the blade passage, so a mean over a whole revolution does not depend
//! on where in the revolution the run stopped. Other cases get the last 10 % of the run.

use std::path::Path;

use anyhow::Context;
use spillage_model::case::Case;
use spillage_model::output::format_f64;
use spillage_model::output::series::SeriesTable;

/// Columns that are the run loop's clock, not results.
const CLOCK_COLUMNS: [&str; 3] = ["step", "time", "dt"];

/// The columns `sweep.md` shows when a run has them (all are in `sweep.csv`): the head's
/// out-flowing flux (face hull and interpolated contour) next to the analytic one, the production and spillage fractions next to the
/// analytic production, particle counts, and the kinetic energy of the fluid.
const MARKDOWN_COLUMNS: [&str; 12] = [
    "hull_outflow_mean",
    "contour_outflow_mean",
    "analytic_outflow",
    "outflow_ratio_mean",
    "production",
    "analytic_production",
    "spillage",
    "sucked",
    "spilled",
    "inside",
    "hull_net_flux_mean",
    "kinetic_energy",
];

/// Which part of a run is averaged.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WindowRule {
    /// The last revolution of the rotor, `period` = 2π/|ω| [s].
    LastRevolution { period: f64 },
    /// The last 10 % of the simulated time.
    LastTenth,
}

impl WindowRule {
    /// The last revolution when the case's `[rotor]` turns (rpm or omega non-zero), else the last
    /// tenth.
    pub fn for_case(case: &Case) -> Self {
        match case.rotor.as_ref().map(|rotor| rotor.angular_velocity().abs()) {
            Some(omega) if omega > 0.0 && omega.is_finite() => WindowRule::LastRevolution { period: std::f64::consts::TAU / omega },
            _ => WindowRule::LastTenth,
        }
    }

    /// (start, end) of the window of a run that ended at `end_time`; a revolution longer than the
    /// run is cut at t = 0 (the mean is then over the whole run).
    pub fn window(&self, end_time: f64) -> (f64, f64) {
        match *self {
            WindowRule::LastRevolution { period } => ((end_time - period).max(0.0), end_time),
            WindowRule::LastTenth => (0.9 * end_time, end_time),
        }
    }

    /// The rule in words, for the markdown header.
    pub fn describe(&self) -> String {
        match self {
            WindowRule::LastRevolution { period } => format!("the last rotor revolution (2π/ω = {} s)", markdown_number(*period)),
            WindowRule::LastTenth => "the last 10 % of the simulated time".to_string(),
        }
    }
}

/// Time-weighted mean of `values` over [start, end]: row i stands for the step that ended at
/// `times[i]`, i.e. the interval (times[i−1], times[i]] (the first row's step started at t = 0),
/// clipped to the window. With a fixed step this is the plain mean of the rows in the window;
/// with a Courant-controlled step, long steps weigh more, as they should. `None` without rows;
/// the last value when the window holds no time (a single row at t = 0).
pub fn window_mean(times: &[f64], values: &[f64], window: (f64, f64)) -> Option<f64> {
    let last = *values.last()?;
    let (mut weighted, mut total) = (0.0, 0.0);
    let mut previous = 0.0_f64;
    for (&time, &value) in times.iter().zip(values) {
        let weight = spillage_model::output::series::time_in_window(previous, time, window);
        weighted += weight * value;
        total += weight;
        previous = time;
    }
    Some(if total > 0.0 { weighted / total } else { last })
}

/// The final value and the window mean of one series column.
#[derive(Clone, Debug, PartialEq)]
pub struct ColumnStats {
    pub name: String,
    pub final_value: f64,
    pub mean: f64,
}

/// What a run's series says, summarised.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SeriesSummary {
    pub final_time: Option<f64>,
    pub window: Option<(f64, f64)>,
    pub columns: Vec<ColumnStats>,
}

/// Final values and window means of every result column of a series.
pub fn summarise_series(series: &SeriesTable, rule: WindowRule) -> SeriesSummary {
    let Some(times) = series.column("time") else { return SeriesSummary::default() };
    let Some(&end_time) = times.last() else { return SeriesSummary::default() };
    let window = rule.window(end_time);
    let columns = series
        .columns
        .iter()
        .filter(|name| !CLOCK_COLUMNS.contains(&name.as_str()))
        .filter_map(|name| {
            let values = series.column(name)?;
            Some(ColumnStats { name: name.clone(), final_value: *values.last()?, mean: window_mean(&times, &values, window)? })
        })
        .collect();
    SeriesSummary { final_time: Some(end_time), window: Some(window), columns }
}

/// One row of the table.
#[derive(Clone, Debug, PartialEq)]
pub struct PointRow {
    /// The swept values' labels, in the order of the keys.
    pub values: Vec<String>,
    pub status: String,
    pub wall_seconds: Option<f64>,
    pub rule: Option<WindowRule>,
    pub series: SeriesSummary,
    /// Further numbers (the analytic model's), by column name.
    pub extras: Vec<(String, f64)>,
}

impl PointRow {
    pub fn completed(&self) -> bool {
        self.status == super::runner::COMPLETED
    }

    /// Every numeric column of the row in table order: time and window, extras, then per series
    /// column `<col>` (final) and `<col>_mean`.
    pub fn numbers(&self) -> Vec<(String, f64)> {
        let mut numbers = Vec::new();
        numbers.extend(self.wall_seconds.map(|w| ("wall_s".to_string(), w)));
        numbers.extend(self.series.final_time.map(|t| ("final_time".to_string(), t)));
        if let Some((start, end)) = self.series.window {
            numbers.push(("window_start".to_string(), start));
            numbers.push(("window_end".to_string(), end));
        }
        numbers.extend(self.extras.iter().cloned());
        for column in &self.series.columns {
            numbers.push((column.name.clone(), column.final_value));
            numbers.push((format!("{}_mean", column.name), column.mean));
        }
        numbers
    }

    /// The value of a numeric column, if the row has it.
    pub fn number(&self, name: &str) -> Option<f64> {
        self.numbers().into_iter().find(|(n, _)| n == name).map(|(_, v)| v)
    }
}

/// Numeric column names of all rows, in order of first appearance.
fn numeric_columns(rows: &[PointRow]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for row in rows {
        for (name, _) in row.numbers() {
            if !names.contains(&name) {
                names.push(name);
            }
        }
    }
    names
}

/// `sweep.csv`: the swept keys, status, then every numeric column; an empty cell where a point
/// has no value (a failed run without a series).
pub fn write_csv(path: &Path, keys: &[String], rows: &[PointRow]) -> anyhow::Result<()> {
    let numeric = numeric_columns(rows);
    let mut header: Vec<String> = keys.to_vec();
    header.push("status".to_string());
    header.extend(numeric.iter().cloned());
    let mut text = csv_line(&header);
    for row in rows {
        let mut cells = row.values.clone();
        cells.push(row.status.clone());
        cells.extend(numeric.iter().map(|name| row.number(name).map(format_f64).unwrap_or_default()));
        text.push_str(&csv_line(&cells));
    }
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

fn csv_line(cells: &[String]) -> String {
    let quoted: Vec<String> = cells.iter().map(|cell| csv_field(cell)).collect();
    format!("{}\n", quoted.join(","))
}

/// A CSV field, quoted (RFC 4180) when it holds a comma, a quote or a line break.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// What the markdown header says about the sweep.
pub struct MarkdownHeader<'a> {
    pub case_name: &'a str,
    pub case_file: &'a Path,
    pub solver: &'a str,
}

/// `sweep.md`: a header stating the averaging window, and a table of the swept values, status,
/// wall time, window and the [`MARKDOWN_COLUMNS`] the runs have.
pub fn write_markdown(path: &Path, header: &MarkdownHeader, keys: &[String], rows: &[PointRow]) -> anyhow::Result<()> {
    let available = numeric_columns(rows);
    let shown: Vec<&str> = MARKDOWN_COLUMNS.iter().copied().filter(|c| available.iter().any(|a| a == c)).collect();
    let mut text = format!("# Sweep of `{}`\n\n", header.case_name);
    text.push_str(&format!(
        "Case file `{}`, {} points, `{}` solver. Swept: {}.\n\n",
        header.case_file.display(),
        rows.len(),
        header.solver,
        keys.iter().map(|k| format!("`{k}`")).collect::<Vec<_>>().join(" × ")
    ));
    text.push_str(&format!(
        "Averaging window: {} Columns ending in `_mean` are time-weighted means over the window (the `window` column); the others are values at \
         the end of the run.",
        window_statement(rows)
    ));
    if available.iter().any(|c| c.starts_with("analytic_")) {
        text.push_str(
            " `analytic_outflow`: the Euler-turbine model's out-flowing flux Q₁ [m³/s] on the case's contour (water, α = 0.375, β = 0.774); \
             `analytic_production`: its production fraction with a cutting-side mixture of 1254 kg/m³ (Tab. 8.5).",
        );
    }
    text.push_str(" This table shows a selection; `sweep.csv` has every column of `series.csv`, final and mean.\n\n");

    let mut heading: Vec<String> = keys.to_vec();
    heading.extend(["status", "wall [s]", "window [s]"].map(String::from));
    heading.extend(shown.iter().map(|c| c.to_string()));
    text.push_str(&markdown_line(&heading));
    text.push_str(&markdown_line(&vec!["---".to_string(); heading.len()]));
    for row in rows {
        let mut cells = row.values.clone();
        cells.push(shortened(&row.status, MARKDOWN_STATUS_CHARS));
        cells.push(row.wall_seconds.map_or_else(String::new, |w| format!("{w:.1}")));
        cells.push(row.series.window.map_or_else(String::new, |(a, b)| format!("{}–{}", markdown_number(a), markdown_number(b))));
        cells.extend(shown.iter().map(|name| row.number(name).map(markdown_number).unwrap_or_default()));
        text.push_str(&markdown_line(&cells));
    }
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

/// The averaging rule in words, as sentences: one rule for all points, or the general rule when they differ
/// (e.g. swept `rotor.rpm`: a different revolution per point).
fn window_statement(rows: &[PointRow]) -> String {
    let rules: Vec<WindowRule> = rows.iter().filter_map(|r| r.rule).collect();
    let cut = rows.iter().any(|row| match (row.rule, row.series.final_time) {
        (Some(WindowRule::LastRevolution { period }), Some(end)) => period > end,
        _ => false,
    });
    let note = if cut { " A run shorter than a revolution is averaged whole." } else { "" };
    let rule = match rules.first() {
        Some(first) if rules.iter().all(|r| r == first) => first.describe(),
        Some(_) if rules.iter().all(|r| matches!(r, WindowRule::LastRevolution { .. })) => {
            "the last rotor revolution of each run (2π/ω of the point's rotor speed)".to_string()
        }
        Some(_) => "the last rotor revolution (2π/ω) for a point with a turning rotor, else the last 10 % of the simulated time".to_string(),
        None => "none (no point has a valid case)".to_string(),
    };
    format!("{rule}.{note}")
}

/// Longest status shown in `sweep.md` (a failure's whole message is in `sweep.csv`).
const MARKDOWN_STATUS_CHARS: usize = 120;

/// `text` cut to `limit` characters, with `…` when cut.
fn shortened(text: &str, limit: usize) -> String {
    match text.char_indices().nth(limit) {
        Some((cut, _)) => format!("{}…", &text[..cut]),
        None => text.to_string(),
    }
}

fn markdown_line(cells: &[String]) -> String {
    let escaped: Vec<String> = cells.iter().map(|c| c.replace('|', "\\|").replace(['\n', '\r'], " ")).collect();
    format!("| {} |\n", escaped.join(" | "))
}

/// Four significant digits: plain for ordinary magnitudes, exponent form for tiny or huge ones.
pub fn markdown_number(value: f64) -> String {
    let magnitude = value.abs();
    if magnitude == 0.0 {
        return "0".to_string();
    }
    if (1e-3..1e5).contains(&magnitude) {
        let decimals = (3 - magnitude.log10().floor() as i32).max(0) as usize;
        let text = format!("{value:.decimals$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        }
    } else {
        format!("{value:.3e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shipped_case(relative: &str) -> Case {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(relative);
        Case::from_toml(&std::fs::read_to_string(&path).unwrap(), &path).unwrap()
    }

    #[test]
    fn the_window_is_the_last_revolution_with_a_rotor_else_the_last_tenth() {
        let rule = WindowRule::LastRevolution { period: 1.5 };
        assert_eq!(rule.window(4.0), (2.5, 4.0));
        assert_eq!(rule.window(1.0), (0.0, 1.0), "a revolution longer than the run is cut at t = 0");
        let (start, end) = WindowRule::LastTenth.window(2.0);
        // 0.9 · 2.0 is not exact in binary; a few ulps of 1.8 is round-off, not a different rule.
        assert!((start - 1.8).abs() < 1e-15 && end == 2.0);
        assert_eq!(WindowRule::for_case(&shipped_case("cases/verification/fluid/taylor_green.toml")), WindowRule::LastTenth);
    }

    #[test]
    fn the_rule_of_a_rotor_case_has_the_period_of_its_speed() {
        let case = shipped_case("cases/rotor_stator.toml");
        // omega = 1 rad/s: the period is 2π s, computed the same way, so exactly equal.
        assert_eq!(WindowRule::for_case(&case), WindowRule::LastRevolution { period: std::f64::consts::TAU });
    }

    #[test]
    fn window_means_weigh_rows_by_their_step_inside_the_window() {
        let times = [0.5, 1.0, 1.5, 2.0];
        let values = [10.0, 20.0, 30.0, 40.0];
        // Window (1.0, 2.0]: the steps ending at 1.5 and 2.0, equal weights.
        assert_eq!(window_mean(&times, &values, (1.0, 2.0)), Some(35.0));
        // Window (1.25, 2.0]: half of the step ending at 1.5 (weight 0.25) and the step ending at 2.0 (0.5).
        let expected = (0.25 * 30.0 + 0.5 * 40.0) / 0.75;
        // Sums of a few products of exact binary fractions: only the final division rounds.
        assert!((window_mean(&times, &values, (1.25, 2.0)).unwrap() - expected).abs() < 1e-12);
        // Unequal steps: 0 → 1 (value 1) and 1 → 1.5 (value 4) over the whole run.
        assert_eq!(window_mean(&[1.0, 1.5], &[1.0, 4.0], (0.0, 1.5)), Some(2.0));
        assert_eq!(window_mean(&[], &[], (0.0, 1.0)), None);
        assert_eq!(window_mean(&[0.0], &[7.0], (0.0, 0.0)), Some(7.0), "no time in the window: the last value");
    }

    #[test]
    fn series_summaries_skip_the_clock_and_keep_final_and_mean() {
        let series = SeriesTable {
            columns: ["step", "time", "dt", "kinetic_energy"].map(String::from).to_vec(),
            rows: (1..=10).map(|i| vec![i as f64, 0.1 * i as f64, 0.1, i as f64]).collect(),
        };
        let summary = summarise_series(&series, WindowRule::LastRevolution { period: 0.2 });
        assert_eq!(summary.columns.len(), 1);
        assert_eq!(summary.columns[0].final_value, 10.0);
        // The window is the last two steps (9 and 10) up to the round-off of 0.1·i: mean 9.5 to a
        // few ulps of the times.
        assert!((summary.columns[0].mean - 9.5).abs() < 1e-9, "{:?}", summary.columns[0]);
        let row = PointRow { values: vec!["1".into()], status: "completed".into(), wall_seconds: Some(1.0), rule: None, series: summary, extras: vec![] };
        assert_eq!(row.number("kinetic_energy"), Some(10.0));
        assert!(row.number("kinetic_energy_mean").is_some() && row.number("time").is_none());
    }

    #[test]
    fn csv_fields_are_quoted_and_numbers_are_short() {
        assert_eq!(csv_field("failed: a, b"), "\"failed: a, b\"");
        assert_eq!(csv_field("say \"x\""), "\"say \"\"x\"\"\"");
        assert_eq!(csv_field("completed"), "completed");
        assert_eq!(markdown_number(0.079123), "0.07912");
        assert_eq!(markdown_number(1234.56), "1235");
        assert_eq!(markdown_number(2.0), "2");
        assert_eq!(markdown_number(1.5e-6), "1.500e-6");
        assert_eq!(shortened("failed: diverged", 6), "failed…");
        assert_eq!(shortened("ok", 6), "ok");
    }
}
