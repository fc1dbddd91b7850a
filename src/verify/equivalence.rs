//! Fast vs reference fluid solver, step by step (issue #6, issue 20): both solvers run the same
//! case from the same initial state; after every step the states are compared field by field
//! ([`spillage_model::state_diff`]) and each field's difference is measured against a physical
//! scale of that field. The largest over the steps is what `spillage verify` reports and what
//! `tests/fast_equivalence.rs` and `tests/coupling_verification.rs` assert.
//!
//! Coupled cases run both fluids with the reference DEM (there is one particle solver), so the
//! comparison isolates the fluid solvers while the particles load the fluid.

use anyhow::{anyhow, bail, Context, Result};
use spillage_fast::fluid::FastFluid;
use spillage_model::case::Case;
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::state_diff::{diff, StateDiff};
use spillage_model::step::{Coupled, FluidPhase};
use spillage_reference::dem::ReferenceDem;
use spillage_reference::fluid::ReferenceFluid;
use spillage_reference::wear::ReferenceWear;

use super::CheckRow;

/// Agreement required after every step (issue #6): the reference solves exactly (sparse LU), the
/// fast solver iteratively to a normalised residual of 1e-12 (`[numerics] linear_tolerance`),
/// which bounds their difference well below 1e-8 of each field's scale.
pub const TOLERANCE: f64 = 1e-8;

/// Steps compared on a fluid-only case (issue #6: at least 50).
pub const FLUID_STEPS: u64 = 50;

/// Steps compared on a case with particles: the DEM sub-steps make each step dearer; 30 steps
/// cover the start of the settling transient, where the load on the fluid changes fastest.
pub const COUPLED_STEPS: u64 = 30;

/// The scaled difference of each field, in the order of the state's fields: its largest
/// difference relative to a physical scale of the field. The scale is the field's own maximum,
/// except where a field can be identically zero in exact arithmetic (pressure in a free stream
/// or a body-force-driven periodic channel, the cumulative continuity error, which is
/// round-off): pressures are measured against max|u|² (kinematic dynamic pressure) and the
/// continuity volume against Δt·max|φ|.
pub fn field_errors(reference: &State, d: &StateDiff) -> Result<Vec<(String, f64)>> {
    if !d.mismatches.is_empty() {
        bail!("the states differ in structure: {:?}", d.mismatches);
    }
    let f = reference.fluid.as_ref().ok_or_else(|| anyhow!("the fast-vs-reference comparison needs a fluid state"))?;
    let u_max = f.velocity.iter().flat_map(|v| v.iter()).fold(0.0f64, |m, x| m.max(x.abs()));
    let flux_max = f.flux.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut out = Vec::with_capacity(d.fields.len());
    for (name, fd) in &d.fields {
        let scaled = if fd.max_abs == 0.0 {
            0.0
        } else if name.contains("pressure") {
            let own = fd.max_abs / fd.max_rel_to_scale.max(1e-300);
            fd.max_abs / own.max(u_max * u_max).max(1e-300)
        } else if name.contains("cumulative_continuity_error") {
            fd.max_abs / (reference.dt * flux_max).max(1e-300)
        } else {
            fd.max_rel_to_scale
        };
        out.push((name.clone(), scaled));
    }
    Ok(out)
}

/// Largest difference over all fields ([`field_errors`]).
///
/// Panics if the states differ in structure or carry no fluid (test helper).
pub fn equivalence_error(reference: &State, d: &StateDiff) -> f64 {
    field_errors(reference, d).unwrap_or_else(|e| panic!("{e}")).iter().fold(0.0, |m, (_, e)| m.max(*e))
}

/// What a step-by-step comparison found.
#[derive(Clone, Debug, PartialEq)]
pub struct Equivalence {
    pub steps: u64,
    /// Per field, the largest scaled difference over the steps.
    pub fields: Vec<(String, f64)>,
    /// Largest over fields and steps, the step it occurred at, and the state-diff report of
    /// that step (for failure messages).
    pub worst: f64,
    pub worst_step: u64,
    pub worst_report: String,
    /// Wall-clock time of each solver's steps [s] (measured, reported, never asserted).
    pub reference_seconds: f64,
    pub fast_seconds: f64,
}

impl Equivalence {
    /// The field with the largest difference ("" when every field agrees exactly).
    pub fn worst_field(&self) -> &str {
        self.fields.iter().filter(|(_, e)| *e > 0.0).max_by(|a, b| a.1.total_cmp(&b.1)).map_or("", |(n, _)| n.as_str())
    }

    /// The row of `spillage verify`: the largest per-step difference against [`TOLERANCE`] (the
    /// field it occurs in is in the report's equivalence table).
    pub fn row(&self, case: &str) -> CheckRow {
        let quantity = format!("fast vs reference: largest per-step difference over {} steps", self.steps);
        CheckRow::at_most(case, quantity, "fast vs reference", self.worst, TOLERANCE)
    }
}

/// Steps both solvers `reference` and `fast` for `steps` steps, comparing after every step.
pub fn step_by_step(reference: &mut dyn Solver, fast: &mut dyn Solver, steps: u64) -> Result<Equivalence> {
    let mut fields: std::collections::BTreeMap<String, f64> = Default::default();
    let mut out = Equivalence { steps, fields: Vec::new(), worst: 0.0, worst_step: 0, worst_report: String::new(), reference_seconds: 0.0, fast_seconds: 0.0 };
    for step in 1..=steps {
        let started = std::time::Instant::now();
        let r = reference.step().with_context(|| format!("reference step {step}"))?;
        out.reference_seconds += started.elapsed().as_secs_f64();
        let started = std::time::Instant::now();
        let f = fast.step().with_context(|| format!("fast step {step}"))?;
        out.fast_seconds += started.elapsed().as_secs_f64();
        let (names_r, names_f): (Vec<_>, Vec<_>) = (r.values.iter().map(|v| v.0).collect(), f.values.iter().map(|v| v.0).collect());
        if names_r != names_f {
            bail!("step {step}: the step reports name different quantities: {names_r:?} vs {names_f:?}");
        }
        let d = diff(reference.state(), fast.state());
        let errors = field_errors(reference.state(), &d).with_context(|| format!("step {step}"))?;
        // fields come and go (contact records appear with the first contact): keyed by name
        for (name, e) in &errors {
            let worst = fields.entry(name.clone()).or_insert(0.0);
            *worst = worst.max(*e);
        }
        let step_worst = errors.iter().fold(0.0f64, |m, (_, e)| m.max(*e));
        if step_worst > out.worst || step == 1 {
            out.worst = out.worst.max(step_worst);
            out.worst_step = step;
            out.worst_report = d.report();
        }
    }
    out.fields = fields.into_iter().collect();
    Ok(out)
}

/// Steps compared for `case`: `[verify.params] equivalence_steps`, else [`FLUID_STEPS`] or
/// [`COUPLED_STEPS`], never more than the case itself runs.
pub fn steps_for(case: &Case) -> Result<u64> {
    let param = case.verify.as_ref().and_then(|v| v.params.get("equivalence_steps"));
    let steps = match param {
        Some(v) => match v.as_integer() {
            Some(n) if n >= 1 => n as u64,
            _ => bail!("{}: verify.params.equivalence_steps = {v}: expected a whole number ≥ 1", case.path.display()),
        },
        None if case.particles.is_some() => COUPLED_STEPS,
        None => FLUID_STEPS,
    };
    let own = match (case.time.steps, case.time.dt, case.time.end_time) {
        (Some(n), _, _) => n,
        (None, Some(dt), Some(end)) => (end / dt - 1e-9).ceil() as u64,
        _ => u64::MAX,
    };
    Ok(steps.min(own).max(1))
}

/// Why `case` is not compared (`[verify.params] equivalence_skipped = "reason"`), if it is not.
pub fn skipped(case: &Case) -> Option<String> {
    case.verify.as_ref().and_then(|v| v.params.get("equivalence_skipped")).map(|v| v.as_str().map_or_else(|| v.to_string(), str::to_string))
}

/// True when both fluid solvers apply to `case` (it has a fluid).
pub fn applies(case: &Case) -> bool {
    case.fluid.is_some()
}

fn reference_fluid(case: &Case, state: &mut State) -> Result<ReferenceFluid> {
    Ok(ReferenceFluid::new(case, super::fluid::build_mesh(case)?, state)?)
}

fn fast_fluid(case: &Case, state: &mut State) -> Result<FastFluid> {
    Ok(FastFluid::new(case, super::fluid::build_mesh(case)?, state)?)
}

fn fluid_only<F: FluidPhase + 'static>(case: &Case, make: fn(&Case, &mut State) -> Result<F>) -> Result<Box<dyn Solver>> {
    let mut state = State::default();
    let fluid = make(case, &mut state)?;
    Ok(Box::new(Coupled::fluid_only(case, state, fluid)?))
}

/// A coupled run of `case` with the `make` fluid and the reference DEM (and the reference wear
/// phase when the case has `[wear]`: both fluid solvers run with the same one).
fn coupled<F: FluidPhase + Send + 'static>(case: &Case, make: fn(&Case, &mut State) -> Result<F>) -> Result<Box<dyn Solver>> {
    let mut state = State::default();
    let fluid = make(case, &mut state)?;
    let dem = ReferenceDem::new(case, &mut state)?;
    if case.wear.is_some() {
        let wear = ReferenceWear::new(case, &mut state)?;
        return Ok(Box::new(Coupled::new(case, state, Some(fluid), Some(dem))?.with_wear(Box::new(wear))?));
    }
    Ok(Box::new(Coupled::new(case, state, Some(fluid), Some(dem))?))
}

/// Runs `case` in both fluid solvers (with the reference DEM if it has particles) for `steps`
/// steps, comparing after every step.
pub fn compare_case(case: &Case, steps: u64) -> Result<Equivalence> {
    let (mut reference, mut fast) = if case.particles.is_some() {
        (coupled(case, reference_fluid)?, coupled(case, fast_fluid)?)
    } else {
        (fluid_only(case, reference_fluid)?, fluid_only(case, fast_fluid)?)
    };
    step_by_step(reference.as_mut(), fast.as_mut(), steps).with_context(|| format!("case {}: fast vs reference", case.case.name))
}
