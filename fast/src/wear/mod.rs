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
use spillage_model::wear::state::{WallWear, WearState, ANGLE_BINS, SPEED_BINS};
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
        let section = case.wear.as_ref().ok_or_else(|| unsupported("the wear phase needs a [wear] section"))?;
        let law = ErosionLaw::from_section(section).map_err(|e| unsupported(format!("[wear]: key `{}` = {}: expected {}", e.key, e.value, e.allowed)))?;
        let walls = state.walls.as_ref().ok_or_else(|| unsupported("the wear phase needs the walls (set up the particle phase first)"))?;
        let eroding: Vec<usize> = if section.walls.is_empty() {
            (0..walls.walls.len()).collect()
        } else {
            let mut found = Vec::new();
            for name in &section.walls {
                let i = walls.walls.iter().position(|w| &w.name == name).ok_or_else(|| unsupported(format!("[wear] walls: no wall named {name:?}")))?;
                found.push(i);
            }
            found
        };
        // the surfaces are built on the walls' unworn shape, rebuilt from the case: a restart
        // (whose walls are worn) gets the same operators bit for bit (and the same as the
        // reference phase's)
        let dir = case.path.parent().map(|p| p.to_path_buf()).unwrap_or_default();
        let unworn = spillage_model::walls::build(case, &dir).map_err(|e| unsupported(format!("walls: {e}")))?;
        if unworn.walls.len() != walls.walls.len() {
            return Err(unsupported(format!("the state has {} walls, the case {}", walls.walls.len(), unworn.walls.len())));
        }
        let surfaces: Vec<WearSurface> = eroding.iter().map(|&i| WearSurface::new(&unworn.walls[i].vertices, &unworn.walls[i].triangles)).collect();
        for (&i, surface) in eroding.iter().zip(&surfaces) {
            // a worn wall keeps its mesh: only its vertices move
            if walls.walls[i].vertices.len() != surface.node_of_vertex.len() || walls.walls[i].triangles.len() != surface.triangles.len() {
                return Err(unsupported(format!(
                    "wall `{}` has {} vertices and {} triangles in the state, {} and {} in the case (a checkpoint of another case?)",
                    walls.walls[i].name,
                    walls.walls[i].vertices.len(),
                    walls.walls[i].triangles.len(),
                    surface.node_of_vertex.len(),
                    surface.triangles.len()
                )));
            }
        }
        match &state.wear {
            None => {
                let mut wear = WearState::default();
                for (&i, surface) in eroding.iter().zip(&surfaces) {
                    let wall = &walls.walls[i];
                    let mut w = WallWear::new(i, wall.name.clone(), wall.triangles.len(), surface.node_of_vertex.clone(), surface.n_nodes);
                    let nodes = surface.nodes(&wall.vertices);
                    let origin = nodes.iter().fold(Vec3::zeros(), |a, p| a + p) / nodes.len().max(1) as f64;
                    w.volume_origin = origin.into();
                    w.initial_volume = surface.cone_volume(&nodes, origin);
                    if surface.closed {
                        // outward winding encloses a positive volume; the material is inside
                        w.material_side = -w.initial_volume.signum();
                    }
                    wear.walls.push(w);
                }
                state.wear = Some(wear);
            }
            Some(wear) => {
                let same = wear.walls.len() == eroding.len()
                    && wear.walls.iter().zip(&eroding).zip(&surfaces).all(|((w, &i), s)| w.wall == i && w.node_rate.len() == s.n_nodes);
                // the per-triangle arrays are indexed without further checks in the step
                let sized = wear.walls.iter().zip(&surfaces).all(|(w, s)| {
                    let n = s.triangles.len();
                    w.node_depth.len() == s.n_nodes
                        && w.triangle_volume.len() == n
                        && w.triangle_impacts.len() == n
                        && w.angle_histogram.len() == n * ANGLE_BINS
                        && w.speed_histogram.len() == n * SPEED_BINS
                });
                if !(same && sized) {
                    return Err(unsupported("the wear state does not match the case's eroding walls (a checkpoint of another case?)"));
                }
            }
        }
        let smoothing = section.smoothing.as_ref().map(|s| (s.diffusivity, s.damping));
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
        Ok(FastWear {
            law,
            scale: section.modifier * section.acceleration,
            damping: smoothing.map(|s| s.1),
            receding: section.receding,
            histogram_max_speed: section.histogram_max_speed,
            walls,
        })
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
        let mut totals = Totals::default();
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
        let balance = totals.deposited - totals.receded - totals.in_flight - totals.pending;
        report.values.extend([
            ("wear_impacts", wear.impacts as f64),
            ("wear_deposited", totals.deposited),
            ("wear_receded", totals.receded),
            ("wear_in_flight", totals.in_flight),
            ("wear_geometric", totals.geometric),
            ("wear_balance_error", balance.abs() / totals.deposited.max(f64::MIN_POSITIVE)),
            ("wear_max_depth", totals.max_depth),
        ]);
        Ok(())
    }
}

/// Sums over the eroding walls for the step report (as the reference phase's).
#[derive(Default)]
struct Totals {
    deposited: f64,
    receded: f64,
    in_flight: f64,
    pending: f64,
    geometric: f64,
    max_depth: f64,
}

impl Totals {
    fn add(&mut self, w: &WallWear, surface: &WearSurface, damping: Option<f64>, geometric: f64) {
        self.deposited += w.deposited;
        self.receded += w.receded;
        self.in_flight += w.in_flight(&surface.node_area, damping);
        self.pending += w.pending;
        self.geometric += geometric;
        self.max_depth = w.node_depth.iter().fold(self.max_depth, |m, d| m.max(*d));
    }
}
