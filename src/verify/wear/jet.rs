//! `wear_jet`: a jet on a plate that recedes as it wears, against the same plate held still
//! (wear-model.md §12.3; issue 17's check 6). The thesis' acceptance criteria, qualitative
//! (§12.3 [R]): (i) the two runs wear alike at first impact; (ii) afterwards the receding
//! plate's wear rate falls and its profile flattens; (iii) the still plate's rate stays about
//! the same; (iv) the volume bookkeeping is exact.
//!
//! Both runs share the particles' insertion sequence, so their difference is the plate's
//! motion alone. The wear rate is the volume deposited per unit time on the profile's bins
//! (before smoothing), so the still and the receding run are measured the same way.

use std::path::Path;

use anyhow::{anyhow, bail, Result};
use spillage_model::case::Case;
use spillage_model::output::plot::{write_png, Plot, Series};
use spillage_model::state::State;
use spillage_model::wear::profile::{wear_profile, UnwornWalls};
use spillage_model::wear::settings::ProfileSection;

use super::{budget_rows, number, run_sampling, SOLVER};
use crate::verify::CheckRow;

/// One run's deposited volume per profile bin after every step.
struct Record {
    times: Vec<f64>,
    /// `volumes[k][b]`: volume deposited on bin b up to `times[k]` [m³].
    volumes: Vec<Vec<f64>>,
    distance: Vec<f64>,
    area: Vec<f64>,
    state: State,
}

impl Record {
    fn run(case: &Case, line: &ProfileSection) -> Result<Self> {
        let mut record = Record { times: Vec::new(), volumes: Vec::new(), distance: Vec::new(), area: Vec::new(), state: State::default() };
        let unworn = UnwornWalls::of_case(case)?;
        record.state = run_sampling(case, |state| record.sample(state, line, &unworn))?;
        Ok(record)
    }

    fn sample(&mut self, state: &State, line: &ProfileSection, unworn: &UnwornWalls) -> Result<()> {
        self.times.push(state.time);
        let wear = state.wear.as_ref().ok_or_else(|| anyhow!("no wear state"))?;
        let bins = wear_profile(line, unworn, wear);
        if self.distance.is_empty() {
            self.distance = bins.iter().map(|b| b.distance).collect();
            // the bins' areas on the plate as built: the wear rate is per area of it
            self.area = bins.iter().map(|b| b.area).collect();
        }
        self.volumes.push(bins.iter().map(|b| b.volume).collect());
        Ok(())
    }

    /// The sample at time `t` (the last one not after it).
    fn at(&self, t: f64) -> usize {
        self.times.iter().rposition(|&s| s <= t + 1e-12).unwrap_or(0)
    }

    /// Volume deposited per bin over [t0, t1] [m³].
    fn gained(&self, t0: f64, t1: f64) -> Vec<f64> {
        let (a, b) = (self.at(t0), self.at(t1));
        self.volumes[b].iter().zip(&self.volumes[a]).map(|(v1, v0)| v1 - v0).collect()
    }

    /// Wear rate over [t0, t1], summed over the plate [m³/s].
    fn rate(&self, t0: f64, t1: f64) -> f64 {
        self.gained(t0, t1).iter().sum::<f64>() / (t1 - t0)
    }

    /// Time of the first deposit (the first step with an impact).
    fn first_impact(&self) -> Option<f64> {
        self.volumes.iter().position(|v| v.iter().any(|&x| x > 0.0)).map(|k| self.times[k])
    }
}

/// The relief of a wear profile: largest minus smallest volume over the bins the jet reaches.
/// The thesis normalises its profiles min–max over all times (§12.3), so a profile flattens
/// there when its relief shrinks.
fn relief(gained: &[f64], reach: &[bool]) -> f64 {
    let worn = gained.iter().zip(reach).filter(|(_, &r)| r).map(|(g, _)| *g);
    worn.clone().fold(f64::NEG_INFINITY, f64::max) - worn.fold(f64::INFINITY, f64::min)
}

pub fn jet(base: &Case, full: bool, plots: Option<&Path>) -> Result<Vec<CheckRow>> {
    let name = base.case.name.as_str();
    let mut moving = base.clone();
    if !full {
        moving.time.end_time = Some(number(base, "coarse_end_time")?);
    }
    let section = moving.wear.as_mut().ok_or_else(|| anyhow!("{}: wear_jet needs [wear]", base.path.display()))?;
    if !section.receding {
        bail!("{}: wear_jet compares a receding plate with a still one; the case has [wear] receding = false", base.path.display());
    }
    let line = section.profile.clone().ok_or_else(|| anyhow!("{}: wear_jet needs [wear.profile]", base.path.display()))?;
    let mut still = moving.clone();
    if let Some(w) = still.wear.as_mut() {
        w.receding = false;
    }
    let (recedes, stays) = (Record::run(&moving, &line)?, Record::run(&still, &line)?);
    let first = stays.first_impact().ok_or_else(|| anyhow!("{name}: no particle reached the plate"))?;
    let end = *stays.times.last().unwrap_or(&0.0);

    let mut rows = Vec::new();
    let impacts = |r: &Record| r.state.wear.as_ref().map_or(0, |w| w.walls.iter().flat_map(|w| &w.triangle_impacts).sum::<u64>());
    rows.push(CheckRow::at_least(
        name,
        "impacts on the receding plate",
        SOLVER,
        impacts(&recedes) as f64,
        number(base, if full { "min_impacts" } else { "coarse_min_impacts" })?,
    ));
    // (i) first impact: up to the first impact both runs are the same bits; after it the plate
    // has receded by d, which moves later impacts' points by d / sin θ along the path
    let window = number(base, "first_window")?;
    rows.push(CheckRow::relative(
        name,
        format!("volume removed in the first {:.0} ms of impacts, receding vs still plate (relative)", 1e3 * window),
        SOLVER,
        recedes.gained(first - 1e-9, first + window).iter().sum(),
        stays.gained(first - 1e-9, first + window).iter().sum(),
        number(base, "first_tolerance")?,
    ));
    let span = number(base, "rate_window")?;
    let arrival = first + number(base, "arrival")?;
    let early = (arrival, arrival + span);
    let late = (end - span, end);
    if full {
        if late.0 < early.1 {
            bail!("{name}: the run ends before its late window ({:.3} s) clears the early one ({:.3} s)", late.0, early.1);
        }
        // (iii) the still plate: the same stream, so the same rate within the shot noise of the
        // impacts a window holds (≈ 1/√N)
        let still_trend = stays.rate(late.0, late.1) / stays.rate(early.0, early.1);
        rows.push(CheckRow::absolute(name, "still plate: late over early wear rate (stationary)", SOLVER, still_trend, 1.0, number(base, "still_tolerance")?));
        // (ii) the receding plate's rate falls, measured against the still plate's so that
        // both runs' common fluctuations cancel
        let moving_trend = recedes.rate(late.0, late.1) / recedes.rate(early.0, early.1);
        rows.push(CheckRow::at_most(
            name,
            "receding plate: late over early wear rate, relative to the still plate's (falls)",
            SOLVER,
            moving_trend / still_trend,
            number(base, "max_receding_trend")?,
        ));
        // (ii) and its profile flattens: the relief over the bins either run wears, late over
        // early, again relative to the still plate's and beyond the same noise
        let reach: Vec<bool> = stays.gained(early.0, late.1).iter().zip(recedes.gained(early.0, late.1)).map(|(&a, b)| a > 0.0 || b > 0.0).collect();
        let flattening = |r: &Record| relief(&r.gained(late.0, late.1), &reach) / relief(&r.gained(early.0, early.1), &reach);
        rows.push(CheckRow::at_most(
            name,
            "receding plate: relief of the wear-rate profile (max − min), late over early, relative to the still plate's (flattens)",
            SOLVER,
            flattening(&recedes) / flattening(&stays),
            number(base, "max_receding_trend")?,
        ));
    }
    // (iv) the volume bookkeeping on the worn plate
    rows.extend(budget_rows(name, &moving, &recedes.state)?);
    if let Some(dir) = plots {
        draw(dir, name, &recedes, &stays, early, if full { Some(late) } else { None })?;
    }
    Ok(rows)
}

/// `DIR/<case>_rates.png`: the wear rate along the plate in the early and the late window, both
/// runs; `DIR/<case>_rate_history.png`: the whole plate's rate against time, both runs.
fn draw(dir: &Path, name: &str, recedes: &Record, stays: &Record, early: (f64, f64), late: Option<(f64, f64)>) -> Result<()> {
    std::fs::create_dir_all(dir)?;
    let along = |r: &Record, (t0, t1): (f64, f64)| -> Vec<(f64, f64)> {
        let g = r.gained(t0, t1);
        r.distance.iter().zip(&r.area).zip(&g).filter(|((_, &a), _)| a > 0.0).map(|((&x, &a), &v)| (1e3 * x, 1e3 * v / (a * (t1 - t0)))).collect()
    };
    let windows: Vec<(String, (f64, f64))> =
        std::iter::once(("early", early)).chain(late.map(|w| ("late", w))).map(|(l, w)| (format!("{l} ({:.0}–{:.0} ms)", 1e3 * w.0, 1e3 * w.1), w)).collect();
    let mut labelled = Vec::new();
    for (label, w) in &windows {
        labelled.push((format!("receding, {label}"), along(recedes, *w)));
        labelled.push((format!("still, {label}"), along(stays, *w)));
    }
    let series = labelled.iter().map(|(l, p)| Series { label: l, points: p }).collect();
    let title = format!("{name}: wear rate along the plate");
    let plot = Plot { title: &title, x_label: "distance along the profile line [mm]", y_label: "wear rate [mm/s]", log_x: false, log_y: false, series };
    write_png(&plot, &dir.join(format!("{name}_rates.png"))).map_err(|e| anyhow!("{e}"))?;

    // the plate's rate over windows of 10 steps
    let history = |r: &Record| -> Vec<(f64, f64)> {
        r.times.windows(11).step_by(10).map(|w| (1e3 * 0.5 * (w[0] + w[10]), r.rate(w[0], w[10]))).filter(|p| p.1 > 0.0).collect()
    };
    let (h_moving, h_still) = (history(recedes), history(stays));
    let title = format!("{name}: removed volume per second");
    let plot = Plot {
        title: &title,
        x_label: "time [ms]",
        y_label: "wear rate over the plate [m³/s]",
        log_x: false,
        log_y: false,
        series: vec![Series { label: "receding plate", points: &h_moving }, Series { label: "still plate", points: &h_still }],
    };
    write_png(&plot, &dir.join(format!("{name}_rate_history.png"))).map_err(|e| anyhow!("{e}"))?;
    Ok(())
}
