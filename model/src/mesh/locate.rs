//! Point location: which cell contains a point (particles, probes).
//!
//! Block meshes invert their index map: O(log n) per direction for a box, and for a cylindrical
//! block an (r, θ, z) guess that is then confirmed by the exact inside test and, where the
//! guess misses because cells have chord (planar) faces rather than arcs, corrected by a short
//! walk across faces. Meshes without an index map fall back to testing every cell.

use super::geometry::hex_face;
use super::{Mesh, Vec3};
use std::f64::consts::TAU;

/// One cylindrical (r, θ, z) block about the z axis; cell `first_cell + i + n_r (j + n_θ k)`
/// spans r in `r_edges[i..=i+1]`, θ in `[j, j+1]·2π/n_θ` (at zone angle 0) and z in
/// `z_edges[k..=k+1]`.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct CylinderBlock {
    pub r_edges: Vec<f64>,
    pub n_theta: usize,
    pub z_edges: Vec<f64>,
    pub first_cell: usize,
    /// Zone of the block's cells (its rotation angle is undone before inverting the map).
    pub zone: usize,
    /// For a block with blocked (solid) slots: the cell of each slot `i + n_r (j + n_θ k)`;
    /// a blocked slot holds the nearest open cell instead (see `blocked`). Empty when every
    /// slot is a cell (`first_cell + slot`).
    #[serde(default)]
    pub cell_of_slot: Vec<usize>,
    /// Which slots are solid (empty when none is).
    #[serde(default)]
    pub blocked: Vec<bool>,
}

/// Index map kept by the generators for [`Mesh::locate`].
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub enum Locator {
    /// No index map: brute-force search.
    None,
    /// Axis-aligned box; slot `i + n_x (j + n_y k)` spans `edges[d][index..=index+1]` and is
    /// that cell, or with solids `cell_of_slot[slot]` (`None`: solid, outside the mesh).
    Box {
        edges: [Vec<f64>; 3],
        #[serde(default)]
        cell_of_slot: Vec<Option<usize>>,
        /// The points have moved off the generator's grid ([`Mesh::move_points`]): the grid
        /// slot is only where a walk to the containing cell starts.
        #[serde(default)]
        deformed: bool,
        /// The moved points' bounding box (min, max), outside of which no cell lies.
        #[serde(default)]
        moved_bounds: [[f64; 3]; 2],
    },
    Cylindrical {
        blocks: Vec<CylinderBlock>,
    },
}

/// Index of the interval of sorted `edges` holding `x`, or `None` if outside.
fn interval(edges: &[f64], x: f64) -> Option<usize> {
    let n = edges.len() - 1;
    if !(x >= edges[0] && x <= edges[n]) {
        return None;
    }
    Some((edges.partition_point(|&e| e <= x).max(1) - 1).min(n - 1))
}

impl Mesh {
    /// True if `point` lies inside `cell` (or on its boundary, within 1e-12 of its size).
    ///
    /// Uses the cell's own six faces (for a periodic neighbour the stored face is the owner's
    /// copy, elsewhere) and assumes a convex cell with planar faces, which the block generators
    /// produce.
    pub fn contains(&self, cell: usize, point: &Vec3) -> bool {
        let ids = &self.cell_points[cell];
        // Round-off of face centres and of the point itself is ~1e-16 of the cell size.
        let tolerance = 1e-12 * self.cell_volumes[cell].abs().cbrt();
        (0..6).all(|local| {
            let (centre, area) = hex_face(&self.points, ids, local);
            (point - centre).dot(&area) <= tolerance * area.norm()
        })
    }

    /// The cell containing `point`, or `None` if it lies outside the mesh.
    pub fn locate(&self, point: &Vec3) -> Option<usize> {
        match &self.locator {
            Locator::None => (0..self.n_cells()).find(|&c| self.contains(c, point)),
            Locator::Box { edges, cell_of_slot, deformed: true, moved_bounds: [lo, hi] } => {
                if (0..3).any(|k| !(point[k] >= lo[k] && point[k] <= hi[k])) {
                    return None;
                }
                let clamped = |d: usize, x: f64| interval(&edges[d], x.clamp(edges[d][0], edges[d][edges[d].len() - 1]));
                let (i, j, k) = (clamped(0, point.x)?, clamped(1, point.y)?, clamped(2, point.z)?);
                let (nx, ny) = (edges[0].len() - 1, edges[1].len() - 1);
                let slot = i + nx * (j + ny * k);
                let start = if cell_of_slot.is_empty() { Some(slot) } else { cell_of_slot[slot] };
                // a walk stopped at a warped face, or a slot of a solid, searches every cell
                start.and_then(|cell| self.walk_to(cell, point)).or_else(|| (0..self.n_cells()).find(|&c| self.contains(c, point)))
            }
            Locator::Box { edges, cell_of_slot, .. } => {
                let i = interval(&edges[0], point.x)?;
                let j = interval(&edges[1], point.y)?;
                let k = interval(&edges[2], point.z)?;
                let (nx, ny) = (edges[0].len() - 1, edges[1].len() - 1);
                let slot = i + nx * (j + ny * k);
                if cell_of_slot.is_empty() {
                    Some(slot)
                } else {
                    cell_of_slot[slot]
                }
            }
            Locator::Cylindrical { blocks } => blocks.iter().find_map(|block| self.locate_in_block(block, point)),
        }
    }

    /// Whether `point` lies in a solid's staircase slot of a cylindrical block (blocked cells:
    /// the rotor's material where the mesh has no cell).
    pub fn in_solid(&self, point: &Vec3) -> bool {
        match &self.locator {
            Locator::Cylindrical { blocks } => blocks.iter().any(|b| !b.blocked.is_empty() && self.slot_in_block(b, point).is_some_and(|s| b.blocked[s])),
            _ => false,
        }
    }

    /// The (r, θ, z) slot of `block` whose index ranges hold `point` (θ in the zone's reference
    /// pose); `None` outside the block's ranges.
    fn slot_in_block(&self, block: &CylinderBlock, point: &Vec3) -> Option<usize> {
        let angle = self.zones[block.zone].rotation.as_ref().map_or(0.0, |r| r.angle);
        let r = point.x.hypot(point.y);
        let n_r = block.r_edges.len() - 1;
        // A chord dips inside its circle by at most r (1 − cos(π/n_θ)): points that far in
        // may still belong to the block.
        let r_min = block.r_edges[0] * (std::f64::consts::PI / block.n_theta as f64).cos();
        if r < r_min || r > block.r_edges[n_r] {
            return None;
        }
        let k = interval(&block.z_edges, point.z)?;
        let theta = (point.y.atan2(point.x) - angle).rem_euclid(TAU);
        let j = ((theta / TAU * block.n_theta as f64) as usize).min(block.n_theta - 1);
        let i = interval(&block.r_edges, r).unwrap_or(0);
        Some(i + n_r * (j + block.n_theta * k))
    }

    fn locate_in_block(&self, block: &CylinderBlock, point: &Vec3) -> Option<usize> {
        let slot = self.slot_in_block(block, point)?;
        if block.cell_of_slot.is_empty() {
            return self.walk_to(block.first_cell + slot, point);
        }
        if block.blocked[slot] {
            // a point in a solid's staircase cell (the cells stand in for a thinner true
            // surface) belongs to the nearest open cell
            return Some(block.cell_of_slot[slot]);
        }
        self.walk_to(block.cell_of_slot[slot], point)
    }

    /// Walk from `start` across the face the point lies most beyond until a cell contains it;
    /// `None` when the walk leaves through a boundary face.
    fn walk_to(&self, start: usize, point: &Vec3) -> Option<usize> {
        let mut cell = start;
        for _ in 0..self.n_cells() {
            if self.contains(cell, point) {
                return Some(cell);
            }
            let exit = self.faces_of_cell(cell).iter().copied().max_by(|&a, &b| {
                let beyond = |f: usize| {
                    let area = self.outward_area(f, cell);
                    (point - self.face_centres[f]).dot(&area) / area.norm()
                };
                beyond(a).total_cmp(&beyond(b))
            })?;
            if exit >= self.n_internal_faces || self.periodic_shift_of(exit) != Vec3::zeros() {
                return None;
            }
            cell = if self.face_owner[exit] == cell { self.face_neighbour[exit] } else { self.face_owner[exit] };
        }
        None
    }
}
