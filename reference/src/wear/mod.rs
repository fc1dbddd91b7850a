//! The reference wear phase (wear-model.md §7, §11 steps 5, 9, 10), one step read top to bottom:
//!
//! 1. [`deposit`]: each impact on an eroding wall → removed volume by the erosion law, times the
//!    representative-particle modifier and the acceleration factor, booked on the triangle hit
//!    (volume, count, angle and speed histograms) and spread to its three nodes by the P1 hat
//!    functions at the contact point;
//! 2. [`smoothing`]: the damped diffusion of the wear rate w on the wall surface (implicit
//!    Euler, direct solve), or, without `[wear.smoothing]`, each node's share receding at once;
//! 3. [`recession`]: the nodes move into the wall material along their area-weighted normals so
//!    that the volume swept is exactly the volume removed this step.
//!
//! Every step reports the bookkeeping: deposited = receded + in flight + pending, and the
//! geometric volume change of the walls next to the receded volume.

pub mod deposit;
pub mod recession;
pub mod smoothing;

use spillage_model::case::Case;
use spillage_model::particles::ImpactRecord;
use spillage_model::solver::{SolverError, StepReport};
use spillage_model::state::State;
use spillage_model::step::{StepContext, WearPhase};
use spillage_model::walls::state::WallState;
use spillage_model::wear::laws::ErosionLaw;
use spillage_model::wear::setup::{WearSetup, WearTotals};
use spillage_model::wear::state::WearState;
use spillage_model::wear::surface::WearSurface;

/// The reference wear phase: the case's law and constants and each eroding wall's surface; the
/// wear itself lives in the state it is handed.
pub struct ReferenceWear {
    law: ErosionLaw,
    /// modifier × acceleration: deposited volume per law volume (§7.1, §8).
    scale: f64,
    /// (κ, λ) of the smoothing, if on.
    smoothing: Option<(f64, f64)>,
    receding: bool,
    histogram_max_speed: f64,
    /// Surface of each eroding wall, in the order of `WearState::walls`.
    surfaces: Vec<WearSurface>,
}

fn unsupported(what: impl Into<String>) -> SolverError {
    SolverError::Unsupported(what.into())
}

impl ReferenceWear {
    /// Sets up wear for `case`; a missing wear state in `state` starts from unworn walls (the
    /// walls must be there: build the particle phase first).
    pub fn new(case: &Case, state: &mut State) -> Result<Self, SolverError> {
        let WearSetup { law, scale, smoothing, receding, histogram_max_speed, surfaces } = WearSetup::new(case, state).map_err(unsupported)?;
        Ok(ReferenceWear { law, scale, smoothing, receding, histogram_max_speed, surfaces })
    }

    /// The surface of each eroding wall (output: node areas, triangles over nodes).
    pub fn surfaces(&self) -> &[WearSurface] {
        &self.surfaces
    }
}

impl WearPhase for ReferenceWear {
    fn name(&self) -> &'static str {
        "reference"
    }

    fn advance(
        &mut self,
        ctx: &StepContext,
        impacts: &[ImpactRecord],
        wear: &mut WearState,
        walls: &mut WallState,
        report: &mut StepReport,
    ) -> Result<(), SolverError> {
        let mut step_impacts = 0u64;
        let mut totals = WearTotals::default();
        for (w, surface) in wear.walls.iter_mut().zip(&self.surfaces) {
            let wall = &mut walls.walls[w.wall];
            // 1. deposit
            let nodes = surface.nodes(&wall.vertices);
            let booked = deposit::deposit(&self.law, self.scale, self.histogram_max_speed, surface, &nodes, impacts, w);
            step_impacts += booked.impacts;
            // 2. smooth: the depth each node recedes by this step
            let depth = match self.smoothing {
                Some((kappa, lambda)) => smoothing::smooth(surface, kappa, lambda, ctx.dt, &booked.node_volume, &mut w.node_rate)?,
                None => smoothing::direct(surface, ctx.dt, &booked.node_volume, &mut w.node_rate),
            };
            // 3. recede
            recession::recede(surface, &nodes, &depth, self.receding, wall, w).map_err(|what| SolverError::Diverged {
                step: ctx.step,
                time: ctx.time_end(),
                what,
            })?;
            totals.add(w, surface, self.smoothing.map(|s| s.1), recession::geometric_removed_volume(surface, w, &wall.vertices));
        }
        wear.impacts += step_impacts;
        totals.report(wear.impacts, report);
        Ok(())
    }
}
