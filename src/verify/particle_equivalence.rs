//! Fast vs reference particle path, step by step (issue 19): a case runs with the reference DEM,
//! wear phase and kernel stencils and with the fast ones, the same fluid phase (the fast one, bit-deterministic),
//! from the same initial state; after every step the whole states are compared field by field
//! ([`spillage_model::state_diff`]): particle positions, velocities, spins, contact forces,
//! the contact histories (same contacts, same tangential springs), the impact log and the
//! fluid the particles load. Contact records and impacts must match one for one: a missing or
//! extra contact is a structural difference, never "close".

use anyhow::{bail, Context, Result};
use spillage_fast::dem::FastDem;
use spillage_fast::fluid::FastFluid;
use spillage_fast::wear::FastWear;
use spillage_model::case::Case;
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::state_diff::diff;
use spillage_model::step::{Coupled, FluidPhase, ParticlePhase, WearPhase};
use spillage_reference::dem::ReferenceDem;
use spillage_reference::wear::ReferenceWear;

/// Agreement required after every step (issue 19): positions and velocities to 1e-10 of
/// their scale. Both phases evaluate every contact with the same model functions in the same
/// order, so they agree to the bit unless a sum is reordered; 1e-10 leaves room for
/// reordered sums (1e-16 each) growing through ~100 sub-steps of contacts.
pub const PARTICLE_TOLERANCE: f64 = 1e-10;

/// DEM sub-steps compared at least per case (issue 19).
pub const MIN_SUBSTEPS: u64 = 100;

/// What a step-by-step comparison of the particle phases found.
#[derive(Clone, Debug, PartialEq)]
pub struct ParticleEquivalence {
    pub steps: u64,
    pub substeps: u64,
    /// Largest scale-relative difference over fields and steps, its field and step ("" and 0
    /// when every step agrees to the bit).
    pub worst: f64,
    pub worst_field: String,
    pub worst_step: u64,
    /// Wall-clock seconds of each run's steps (measured, reported, never asserted).
    pub reference_seconds: f64,
    pub fast_seconds: f64,
}

impl ParticleEquivalence {
    /// The row of `spillage verify`: the largest per-step difference against
    /// [`PARTICLE_TOLERANCE`].
    pub fn row(&self, case: &str) -> super::CheckRow {
        let quantity = format!("fast vs reference DEM: largest per-step difference over {} steps ({} sub-steps)", self.steps, self.substeps);
        super::CheckRow::at_most(case, quantity, "fast vs reference", self.worst, PARTICLE_TOLERANCE)
    }
}

/// Which particle path: the DEM and, with `[wear]`, the wear phase.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Path {
    Reference,
    Fast,
}

/// A run of `case` with the fast fluid (if it has one) and the `path` DEM and wear phase.
fn run_with(case: &Case, path: Path) -> Result<Box<dyn Solver>> {
    let mut state = State::default();
    let fluid: Option<Box<dyn FluidPhase>> = match (&case.fluid, spillage_model::mesh::for_case(case)) {
        (Some(_), Some(mesh)) => Some(Box::new(FastFluid::new(case, mesh.map_err(|e| anyhow::anyhow!("{e}"))?, &mut state)?)),
        (Some(_), None) => bail!("a case with [fluid] needs a [mesh]"),
        (None, _) => None,
    };
    let dem: Box<dyn ParticlePhase> = match path {
        Path::Reference => Box::new(ReferenceDem::new(case, &mut state)?),
        Path::Fast => Box::new(FastDem::new(case, &mut state)?),
    };
    let wear: Option<Box<dyn WearPhase + Send>> = match (&case.wear, path) {
        (None, _) => None,
        (Some(_), Path::Reference) => Some(Box::new(ReferenceWear::new(case, &mut state)?)),
        (Some(_), Path::Fast) => Some(Box::new(FastWear::new(case, &mut state)?)),
    };
    let run = Coupled::new(case, state, fluid, Some(dem))?;
    let run = match path {
        Path::Reference => run,
        Path::Fast => run.with_mapping_solvers(spillage_fast::coupling::MAPPING_SOLVERS),
    };
    Ok(match wear {
        Some(wear) => Box::new(run.with_wear(wear)?),
        None => Box::new(run),
    })
}

/// The fast particle path's run of `case` (fast fluid, DEM and wear), for the thread-count check.
pub fn fast_run(case: &Case) -> Result<Box<dyn Solver>> {
    run_with(case, Path::Fast)
}

/// The reference particle path's run of `case` (the fast fluid, the reference DEM, wear and mapping).
pub fn reference_run(case: &Case) -> Result<Box<dyn Solver>> {
    run_with(case, Path::Reference)
}

/// Runs `case` with both particle phases until both have taken `min_substeps` DEM sub-steps
/// (at most `max_steps` steps), comparing after every step.
pub fn compare_particle_phases(case: &Case, min_substeps: u64, max_steps: u64) -> Result<ParticleEquivalence> {
    let mut reference = run_with(case, Path::Reference)?;
    let mut fast = run_with(case, Path::Fast)?;
    let mut out =
        ParticleEquivalence { steps: 0, substeps: 0, worst: 0.0, worst_field: String::new(), worst_step: 0, reference_seconds: 0.0, fast_seconds: 0.0 };
    while out.substeps < min_substeps && out.steps < max_steps {
        let step = out.steps + 1;
        let started = std::time::Instant::now();
        let r = reference.step().with_context(|| format!("{}: reference DEM, step {step}", case.case.name))?;
        out.reference_seconds += started.elapsed().as_secs_f64();
        let started = std::time::Instant::now();
        let f = fast.step().with_context(|| format!("{}: fast DEM, step {step}", case.case.name))?;
        out.fast_seconds += started.elapsed().as_secs_f64();
        if r.values.iter().map(|v| v.0).ne(f.values.iter().map(|v| v.0)) {
            bail!("{}: step {step}: the step reports name different quantities", case.case.name);
        }
        let d = diff(reference.state(), fast.state());
        if !d.mismatches.is_empty() {
            bail!("{}: step {step}: the fast and reference DEM states differ in structure (contacts or impacts):\n{}", case.case.name, d.report());
        }
        for (name, field) in &d.fields {
            if field.max_rel_to_scale > out.worst {
                out.worst = field.max_rel_to_scale;
                out.worst_field = name.clone();
                out.worst_step = step;
            }
        }
        out.steps = step;
        out.substeps += r.values.iter().find(|v| v.0 == "substeps").map_or(0, |v| v.1 as u64);
    }
    Ok(out)
}
