//! What a wear phase reads from the case and the state, resolved once and the same for both
//! solvers: the erosion law and its scale, the smoothing constants, and the wear surface of each
//! eroding wall, built on the wall's unworn shape; a fresh run's wear state, or the checks that a
//! restart's wear state belongs to the case.

use super::laws::ErosionLaw;
use super::settings::WearSection;
use super::state::{WallWear, WearState, ANGLE_BINS, SPEED_BINS};
use super::surface::WearSurface;
use crate::case::Case;
use crate::state::State;
use crate::walls::state::{Vec3, WallState};

/// The case's wear constants and surfaces.
pub struct WearSetup {
    pub law: ErosionLaw,
    /// modifier × acceleration: deposited volume per law volume (§7.1, §8).
    pub scale: f64,
    /// (κ, λ) of the smoothing, if on.
    pub smoothing: Option<(f64, f64)>,
    pub receding: bool,
    pub histogram_max_speed: f64,
    /// Surface of each eroding wall, in the order of `WearState::walls`.
    pub surfaces: Vec<WearSurface>,
}

fn fail(what: impl Into<String>) -> String {
    what.into()
}

/// Indices of the walls `[wear] walls` names (all of them when it names none).
pub fn eroding_walls(section: &WearSection, walls: &WallState) -> Result<Vec<usize>, String> {
    if section.walls.is_empty() {
        return Ok((0..walls.walls.len()).collect());
    }
    section
        .walls
        .iter()
        .map(|name| walls.walls.iter().position(|w| &w.name == name).ok_or_else(|| fail(format!("[wear] walls: no wall named {name:?}"))))
        .collect()
}

/// Per wall: whether its contacts book sliding wear (`[wear] sliding` on an eroding wall).
pub fn sliding_walls(case: &Case, walls: &WallState) -> Result<Vec<bool>, String> {
    let mut sliding = vec![false; walls.walls.len()];
    if let Some(section) = case.wear.as_ref().filter(|w| w.sliding) {
        for i in eroding_walls(section, walls)? {
            sliding[i] = true;
        }
    }
    Ok(sliding)
}

impl WearSetup {
    /// Resolves `case`; a missing wear state in `state` starts from unworn walls (the walls
    /// must be there: set up the particle phase first). Errors are sentences.
    pub fn new(case: &Case, state: &mut State) -> Result<Self, String> {
        let section = case.wear.as_ref().ok_or_else(|| fail("the wear phase needs a [wear] section"))?;
        let law = ErosionLaw::from_section(section).map_err(|e| fail(format!("[wear]: key `{}` = {}: expected {}", e.key, e.value, e.allowed)))?;
        let walls = state.walls.as_ref().ok_or_else(|| fail("the wear phase needs the walls (set up the particle phase first)"))?;
        let eroding = eroding_walls(section, walls)?;
        // the surfaces are built on the walls' unworn shape, rebuilt from the case: a restart
        // (whose walls are worn) gets the same operators bit for bit (and the same as the
        // reference phase's)
        let dir = case.path.parent().map(|p| p.to_path_buf()).unwrap_or_default();
        let unworn = crate::walls::build(case, &dir).map_err(|e| fail(format!("walls: {e}")))?;
        if unworn.walls.len() != walls.walls.len() {
            return Err(fail(format!("the state has {} walls, the case {}", walls.walls.len(), unworn.walls.len())));
        }
        let surfaces: Vec<WearSurface> = eroding.iter().map(|&i| WearSurface::new(&unworn.walls[i].vertices, &unworn.walls[i].triangles)).collect();
        for (&i, surface) in eroding.iter().zip(&surfaces) {
            // a worn wall keeps its mesh: only its vertices move
            if walls.walls[i].vertices.len() != surface.node_of_vertex.len() || walls.walls[i].triangles.len() != surface.triangles.len() {
                return Err(fail(format!(
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
                    return Err(fail("the wear state does not match the case's eroding walls (a checkpoint of another case?)"));
                }
            }
        }
        Ok(WearSetup {
            law,
            scale: case.particle_modifier() * section.acceleration,
            smoothing: section.smoothing.as_ref().map(|s| (s.diffusivity, s.damping)),
            receding: section.receding,
            histogram_max_speed: section.histogram_max_speed,
            surfaces,
        })
    }
}

/// The wear bookkeeping of a step, summed over the eroding walls (wear-model.md §7.3): what
/// was deposited = receded + in flight (smoothed, not yet receded) + pending, next to the
/// geometric volume change of the walls.
#[derive(Default)]
pub struct WearTotals {
    pub deposited: f64,
    pub receded: f64,
    pub in_flight: f64,
    pub pending: f64,
    pub geometric: f64,
    pub max_depth: f64,
}

impl WearTotals {
    /// Adds wall `w` (its surface, the smoothing's damping λ if on, and the geometric volume
    /// its wall has lost).
    pub fn add(&mut self, w: &WallWear, surface: &WearSurface, damping: Option<f64>, geometric: f64) {
        self.deposited += w.deposited;
        self.receded += w.receded;
        self.in_flight += w.in_flight(&surface.node_area, damping);
        self.pending += w.pending;
        self.geometric += geometric;
        self.max_depth = w.node_depth.iter().fold(self.max_depth, |m, d| m.max(*d));
    }

    /// The step report's wear values (`impacts`: the impacts on eroding walls so far).
    pub fn report(&self, impacts: u64, report: &mut crate::solver::StepReport) {
        let balance = self.deposited - self.receded - self.in_flight - self.pending;
        report.values.extend([
            ("wear_impacts", impacts as f64),
            ("wear_deposited", self.deposited),
            ("wear_receded", self.receded),
            ("wear_in_flight", self.in_flight),
            ("wear_geometric", self.geometric),
            ("wear_balance_error", balance.abs() / self.deposited.max(f64::MIN_POSITIVE)),
            ("wear_max_depth", self.max_depth),
        ]);
    }
}
