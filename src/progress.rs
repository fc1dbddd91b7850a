//! Progress of `spillage run`: a bar on a terminal, plain lines elsewhere (a batch job's log
//! sees where the run is every 10 s of wall time and at every tenth of the run).
//!
//! The bar shows the fraction done, the elapsed time, the ETA and a message that fits the
//! terminal's width (`{wide_msg}` truncates it rather than wrapping the line): simulated time,
//! step of the expected total, and the first values of the step report.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use spillage_model::case::Case;
use spillage_model::solver::StepReport;
use spillage_model::state::State;

/// Wall time between two plain progress lines.
const PLAIN_EVERY: Duration = Duration::from_secs(10);

pub struct Progress {
    bar: Option<indicatif::ProgressBar>,
    /// The expected number of steps (fixed Δt or `steps`), if known.
    total_steps: Option<u64>,
    start: Instant,
    last_line: Instant,
    /// The tenth of the run last reported on a plain line.
    last_tenth: u64,
    /// A cutter-head case (its progress shows revolutions and spillage).
    head: bool,
}

/// Fraction of the run done (steps or simulated time), in [0, 1].
fn fraction(case: &Case, state: &State) -> f64 {
    let f = match (case.time.steps, case.time.end_time) {
        (Some(n), _) => state.step as f64 / n as f64,
        (None, Some(end)) => state.time / end,
        _ => 1.0,
    };
    f.clamp(0.0, 1.0)
}

/// A count prints as an integer, anything else with 4 significant digits.
fn number(value: f64) -> String {
    if value.fract() == 0.0 && value.abs() < 1e15 {
        format!("{}", value as i64)
    } else {
        format!("{value:.3e}")
    }
}

impl Progress {
    pub fn new(case: &Case, state: &State) -> Self {
        let total_steps = case.time.steps.or_else(|| match (case.time.dt, case.time.end_time) {
            (Some(dt), Some(end)) => Some((end / dt - 1e-9).ceil() as u64),
            _ => None,
        });
        let bar = std::io::stderr().is_terminal().then(|| {
            let bar = indicatif::ProgressBar::new(1000);
            bar.set_style(
                indicatif::ProgressStyle::with_template("{spinner} {percent:>3}% [{bar:24}] {elapsed_precise} ETA {eta}  {wide_msg}")
                    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            bar.set_position((fraction(case, state) * 1000.0).round() as u64);
            bar
        });
        let now = Instant::now();
        Self { bar, total_steps, start: now, last_line: now, last_tenth: (fraction(case, state) * 10.0 + 1e-9) as u64, head: case.cutter_head.is_some() }
    }

    /// What the run is at: simulated time, step (of the total) and the report's first values;
    /// for a cutter head the revolutions done and the live spillage, production and
    /// out-flowing flux instead.
    fn message(&self, state: &State, report: &StepReport) -> String {
        let mut msg = match self.total_steps {
            Some(n) => format!("t = {:.4e} s, step {}/{n}", state.time, state.step),
            None => format!("t = {:.4e} s, step {}", state.time, state.step),
        };
        if state.time < 0.0 {
            // spillage_model::fluid::frozen_rotor: the run starts at t = −T
            msg.push_str(", frozen-rotor start-up");
        }
        if self.head {
            msg.push_str(&format!(", revolution {:.2}", state.rotor_angle.abs() / std::f64::consts::TAU));
            let value = |name: &str| report.values.iter().find(|(n, _)| *n == name).map(|(_, v)| *v);
            for (name, label, percent) in [("spillage", "spilled", true), ("production", "sucked", true), ("outflow_ratio", "Q_out/Q_m", false)] {
                if let Some(v) = value(name) {
                    msg.push_str(&if percent { format!(", {label} {:.1} %", 100.0 * v) } else { format!(", {label} {v:.3}") });
                }
            }
            return msg;
        }
        for (name, value) in report.values.iter().take(3) {
            msg.push_str(&format!(", {name} {}", number(*value)));
        }
        msg
    }

    /// After a step.
    pub fn update(&mut self, case: &Case, state: &State, report: &StepReport) {
        let f = fraction(case, state);
        match &self.bar {
            Some(bar) => {
                bar.set_position((f * 1000.0).round() as u64);
                bar.set_message(self.message(state, report));
            }
            None => {
                let tenth = (f * 10.0 + 1e-9) as u64;
                if self.last_line.elapsed() >= PLAIN_EVERY || tenth > self.last_tenth {
                    let elapsed = self.start.elapsed().as_secs_f64();
                    let eta = if f > 0.0 { format!("{:.0} s", elapsed * (1.0 - f) / f) } else { "?".into() };
                    eprintln!("{:5.1} % after {elapsed:.0} s, ETA {eta}: {}", 100.0 * f, self.message(state, report));
                    self.last_line = Instant::now();
                    self.last_tenth = tenth;
                }
            }
        }
    }

    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::number;

    #[test]
    fn counts_print_as_integers() {
        assert_eq!(number(200.0), "200");
        assert_eq!(number(0.0), "0");
        assert_eq!(number(1.5e-3), "1.500e-3");
    }
}
