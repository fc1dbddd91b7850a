//! The fast wear phase (wear-model.md §7, §8, §11 steps 5, 9, 10): the same model as the
//! reference phase, stage for stage, with its work arrays sized once and parallel loops whose
//! results do not depend on the number of threads.
//!
//! 1. [`deposit`]: the impacts on each eroding wall are grouped by triangle (a stable counting
//!    sort, so every triangle sees its impacts in time order), the erosion law runs once per
//!    impact in parallel, each triangle sums its own impacts, and each node gathers its corners'
//!    shares in a fixed order: no atomics, no float sum whose order depends on scheduling;
//! 2. [`smoothing`]: the damped diffusion (implicit Euler, §7.3) by Jacobi-preconditioned
//!    conjugate gradients on a matrix whose structure is built once (its values only when Δt
//!    changes), solved far below the reference's 1e-10 comparison bound; the discrete
//!    conservation identity is then restored exactly by one scale factor (see there);
//! 3. [`recession`]: nodes move along their area-weighted normals by the one factor that
//!    removes exactly this step's volume, with the same refusal of a wall turning inside out.
//!
//! The step report carries the same values as the reference phase's.

pub mod deposit;
pub mod recession;
pub mod smoothing;
mod topology;

use spillage_model::case::Case;
use spillage_model::particles::ImpactRecord;
use spillage_model::solver::{SolverError, StepReport};
use spillage_model::state::State;
use spillage_model::step::{StepContext, WearPhase};
use spillage_model::walls::state::{Vec3, WallState};
use spillage_model::wear::laws::ErosionLaw;
use spillage_model::wear::setup::{WearSetup, WearTotals};
use spillage_model::wear::state::WearState;
use spillage_model::wear::surface::WearSurface;

use deposit::DepositWork;
use recession::RecessionWork;
use smoothing::Smoothing;
use topology::Topology;

/// One eroding wall: its surface, the adjacency the parallel loops gather over, and the work
/// arrays of the three stages (sized in [`FastWear::new`], reused every step).
struct WallWork {
    surface: WearSurface,
    topology: Topology,
    /// Node positions of the wall at the start of the step (then after the recession).
    nodes: Vec<Vec3>,
    deposit: DepositWork,
    smoothing: Option<Smoothing>,
    /// Depth each node recedes by this step [m] (the smoothing's Δt wⁿ⁺¹, or the direct share).
    depth: Vec<f64>,
    recession: RecessionWork,
}

/// The fast wear phase: the case's law and constants and each eroding wall's surface and work
/// arrays; the wear itself lives in the state it is handed.
pub struct FastWear {
    law: ErosionLaw,
    /// modifier × acceleration: deposited volume per law volume (§7.1, §8).
    scale: f64,
    /// λ of the smoothing, if on (the bookkeeping's in-flight volume needs it).
    damping: Option<f64>,
    receding: bool,
    histogram_max_speed: f64,
    /// In the order of `WearState::walls`.
    walls: Vec<WallWork>,
}

fn unsupported(what: impl Into<String>) -> SolverError {
    SolverError::Unsupported(what.into())
}

impl FastWear {
    /// Sets up wear for `case`; a missing wear state in `state` starts from unworn walls (the
    /// walls must be there: build the particle phase first). The same contract and the same
    /// errors as the reference phase's constructor.
    pub fn new(case: &Case, state: &mut State) -> Result<Self, SolverError> {
        let WearSetup { law, scale, smoothing, receding, histogram_max_speed, surfaces } = WearSetup::new(case, state).map_err(unsupported)?;
        let walls = surfaces
            .into_iter()
            .map(|surface| {
                let topology = Topology::new(&surface);
                let n = surface.n_nodes;
                WallWork {
                    nodes: vec![Vec3::zeros(); n],
                    deposit: DepositWork::new(&surface),
                    smoothing: smoothing.map(|(kappa, lambda)| Smoothing::new(&surface, kappa, lambda)),
                    depth: vec![0.0; n],
                    recession: RecessionWork::new(&surface),
                    topology,
                    surface,
                }
            })
            .collect();
        Ok(FastWear { law, scale, damping: smoothing.map(|s| s.1), receding, histogram_max_speed, walls })
    }

    /// The surface of each eroding wall (output: node areas, triangles over nodes).
    pub fn surfaces(&self) -> impl Iterator<Item = &WearSurface> {
        self.walls.iter().map(|w| &w.surface)
    }
}

impl WearPhase for FastWear {
    fn name(&self) -> &'static str {
        "fast"
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
        let diverged = |what: String| SolverError::Diverged { step: ctx.step, time: ctx.time_end(), what };
        for (w, work) in wear.walls.iter_mut().zip(&mut self.walls) {
            let n_walls = walls.walls.len();
            let wall = walls.walls.get_mut(w.wall).ok_or_else(|| unsupported(format!("wear of wall {} but the state has {n_walls} walls", w.wall)))?;
            if wall.vertices.len() != work.surface.node_of_vertex.len() {
                return Err(unsupported(format!(
                    "wall `{}` has {} vertices, its wear surface {}",
                    wall.name,
                    wall.vertices.len(),
                    work.surface.node_of_vertex.len()
                )));
            }
            let WallWork { surface, topology, nodes, deposit: booking, smoothing: smoother, depth, recession: receding } = work;
            topology.nodes(&wall.vertices, nodes);
            // 1. deposit
            step_impacts +=
                deposit::deposit(&self.law, self.scale, self.histogram_max_speed, surface, topology, nodes, impacts, w, booking).map_err(diverged)?;
            // 2. smooth: the depth each node recedes by this step
            match smoother {
                Some(s) => s.smooth(surface, ctx.dt, &booking.node_volume, &mut w.node_rate, depth, &w.name)?,
                None => smoothing::direct(surface, ctx.dt, &booking.node_volume, &mut w.node_rate, depth),
            }
            // 3. recede
            recession::recede(surface, topology, nodes, depth, self.receding, wall, w, receding).map_err(diverged)?;
            let geometric = receding.geometric_removed_volume(surface, nodes, w);
            totals.add(w, surface, self.damping, geometric);
        }
        wear.impacts += step_impacts;
        totals.report(wear.impacts, report);
        Ok(())
    }
}
