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
use spillage_model::walls::state::{Vec3, WallState};
use spillage_model::wear::laws::ErosionLaw;
use spillage_model::wear::state::{WallWear, WearState};
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
        // (whose walls are worn) gets the same operators bit for bit
        let dir = case.path.parent().map(|p| p.to_path_buf()).unwrap_or_default();
        let unworn = spillage_model::walls::build(case, &dir).map_err(|e| unsupported(format!("walls: {e}")))?;
        if unworn.walls.len() != walls.walls.len() {
            return Err(unsupported(format!("the state has {} walls, the case {}", walls.walls.len(), unworn.walls.len())));
        }
        let surfaces: Vec<WearSurface> = eroding.iter().map(|&i| WearSurface::new(&unworn.walls[i].vertices, &unworn.walls[i].triangles)).collect();
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
                if !same {
                    return Err(unsupported("the wear state does not match the case's eroding walls (a checkpoint of another case?)"));
                }
            }
        }
        Ok(ReferenceWear {
            law,
            scale: section.modifier * section.acceleration,
            smoothing: section.smoothing.as_ref().map(|s| (s.diffusivity, s.damping)),
            receding: section.receding,
            histogram_max_speed: section.histogram_max_speed,
            surfaces,
        })
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
        let mut totals = Totals::default();
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
            totals.add(w, surface, self.smoothing.map(|s| s.1), &wall.vertices);
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

/// Sums over the eroding walls for the step report.
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
    fn add(&mut self, w: &WallWear, surface: &WearSurface, damping: Option<f64>, vertices: &[Vec3]) {
        self.deposited += w.deposited;
        self.receded += w.receded;
        self.in_flight += w.in_flight(&surface.node_area, damping);
        self.pending += w.pending;
        self.geometric += recession::geometric_removed_volume(surface, w, vertices);
        self.max_depth = w.node_depth.iter().fold(self.max_depth, |m, d| m.max(*d));
    }
}
