//! A rotor/stator cylindrical mesh whose rotor block has solid (blocked) slots: the cells a
//! body occupies are left out and their faces toward the fluid become one wall patch that
//! turns with the rotor (the cutter head's blades, ring, hub and pipe, DESIGN.md "mesh").
//!
//! Patches, in this order: `shaft` (the rotor's inner radius), `tank` (the stator's outer
//! radius), `floor` (z_min), `top` (z_max, except the suction), `interface_rotor`,
//! `interface_stator`, `head` (faces toward blocked slots), `suction` (rotor z_max faces whose
//! centre lies within `suction_radius` of the axis, and faces toward `stationary` blocked slots:
//! a solid at rest, such as the back plate of an eccentric mouth). Zones `rotor` (0, turning about z) and
//! `stator` (1). Blocked slots must not touch the sliding interface.

use std::collections::VecDeque;

use super::assemble::{assemble_with_baffles, HexCells};
use super::cylindrical::{add_block, LOCAL_INNER, LOCAL_OUTER, LOCAL_Z_MAX, LOCAL_Z_MIN};
use super::{InterfaceSide, Locator, Mesh, MeshError, PatchKind};

/// Names of the patches of [`Mesh::rotor_stator_blocked`], in patch order.
pub const BLOCKED_ROTOR_STATOR_PATCHES: [&str; 8] = ["shaft", "tank", "floor", "top", "interface_rotor", "interface_stator", "head", "suction"];

/// Input of [`Mesh::rotor_stator_blocked`].
#[derive(Clone, Debug)]
pub struct BlockedRotorStator {
    /// Radial edges of the rotor (first = shaft radius, last = interface radius).
    pub rotor_r: Vec<f64>,
    /// Radial edges of the stator (first = interface radius).
    pub stator_r: Vec<f64>,
    pub z_edges: Vec<f64>,
    pub n_theta_rotor: usize,
    pub n_theta_stator: usize,
    /// Rotor slot `i + n_r (j + n_θ k)` is solid.
    pub blocked: Vec<bool>,
    /// Per rotor slot, bit `local` set: its face `local` (the hexahedron's local face numbers)
    /// is a baffle, a wall of patch `head` on both sides (a zero-thickness blade). Empty: none.
    /// Both slots of a face carry its bit.
    pub baffles: Vec<u8>,
    pub suction_radius: f64,
    /// Per rotor slot: a blocked slot that belongs to a solid at rest; its faces toward the fluid
    /// are patch `suction`, not `head`. Empty: none.
    pub stationary: Vec<bool>,
}

impl BlockedRotorStator {
    fn n_r(&self) -> usize {
        self.rotor_r.len() - 1
    }
    /// (i, j, k) of a rotor slot.
    fn ijk(&self, slot: usize) -> (usize, usize, usize) {
        let n_r = self.n_r();
        (slot % n_r, (slot / n_r) % self.n_theta_rotor, slot / (n_r * self.n_theta_rotor))
    }
    fn slot(&self, i: usize, j: usize, k: usize) -> usize {
        i + self.n_r() * (j % self.n_theta_rotor + self.n_theta_rotor * k)
    }
    /// Whether face `local` of `slot` is a baffle.
    fn is_baffle(&self, slot: usize, local: usize) -> bool {
        self.baffles.get(slot).is_some_and(|bits| bits & (1 << local) != 0)
    }

    /// Marks face `local` of `slot` as a baffle on both of its sides (an open rotor slot's face
    /// toward another rotor slot; a face on the block's boundary is left alone).
    fn add_baffle(&mut self, slot: usize, local: usize) {
        if let Some(other) = self.neighbour(slot, local) {
            self.baffles.resize(self.blocked.len(), 0);
            self.baffles[slot] |= 1 << local;
            self.baffles[other] |= 1 << OPPOSITE[local];
        }
    }

    /// Makes a baffle of every face between two open rotor slots whose centres (cylindrical
    /// [r, θ, z], mid-edges) `separates` says a wall lies between.
    pub fn add_baffles_where(&mut self, separates: impl Fn([f64; 3], [f64; 3]) -> bool) {
        let n_t = self.n_theta_rotor;
        let centre = |(i, j, k): (usize, usize, usize)| {
            [
                0.5 * (self.rotor_r[i] + self.rotor_r[i + 1]),
                std::f64::consts::TAU * (j as f64 + 0.5) / n_t as f64,
                0.5 * (self.z_edges[k] + self.z_edges[k + 1]),
            ]
        };
        let mut faces = Vec::new();
        for slot in (0..self.blocked.len()).filter(|&s| !self.blocked[s]) {
            // each face once: from the slot on its inner, θ− or lower side
            for local in [1, 3, 5] {
                if let Some(other) = self.neighbour(slot, local) {
                    if !self.blocked[other] && separates(centre(self.ijk(slot)), centre(self.ijk(other))) {
                        faces.push((slot, local));
                    }
                }
            }
        }
        for (slot, local) in faces {
            self.add_baffle(slot, local);
        }
    }

    /// Neighbouring slots across the six hexahedron faces (None across the block's boundary).
    fn neighbour(&self, slot: usize, local: usize) -> Option<usize> {
        let (i, j, k) = self.ijk(slot);
        let (n_r, n_t, n_z) = (self.n_r(), self.n_theta_rotor, self.z_edges.len() - 1);
        match local {
            0 => (i > 0).then(|| self.slot(i - 1, j, k)),
            1 => (i + 1 < n_r).then(|| self.slot(i + 1, j, k)),
            2 => Some(self.slot(i, j + n_t - 1, k)),
            3 => Some(self.slot(i, j + 1, k)),
            4 => (k > 0).then(|| self.slot(i, j, k - 1)),
            _ => (k + 1 < n_z).then(|| self.slot(i, j, k + 1)),
        }
    }
}

/// The local face across the slot from each local face (inner/outer, θ−/θ+, z−/z+).
const OPPOSITE: [usize; 6] = [1, 0, 3, 2, 5, 4];

impl BlockedRotorStator {
    /// Blocks the open slots the solids cut off from the sliding interface (water enclosed by
    /// a staircase, e.g. between a coarse ring and pipe): such a pocket would be a separate
    /// fluid whose pressure no boundary fixes. Returns how many slots it blocked.
    pub fn close_pockets(&mut self) -> usize {
        let n_r = self.n_r();
        let n_slots = self.blocked.len();
        let mut reached = vec![false; n_slots];
        let mut queue: VecDeque<usize> = (0..n_slots).filter(|&s| !self.blocked[s] && self.ijk(s).0 == n_r - 1).collect();
        for &s in &queue {
            reached[s] = true;
        }
        while let Some(s) = queue.pop_front() {
            for local in 0..6 {
                if self.is_baffle(s, local) {
                    continue;
                }
                if let Some(t) = self.neighbour(s, local) {
                    if !self.blocked[t] && !reached[t] {
                        reached[t] = true;
                        queue.push_back(t);
                    }
                }
            }
        }
        let mut closed = 0;
        for s in 0..n_slots {
            if !self.blocked[s] && !reached[s] {
                self.blocked[s] = true;
                closed += 1;
            }
        }
        closed
    }
}

impl Mesh {
    /// Generate the rotor/stator mesh of `spec` without its blocked rotor slots.
    pub fn rotor_stator_blocked(spec: &BlockedRotorStator) -> Result<Mesh, MeshError> {
        let n_r = spec.n_r();
        let n_z = spec.z_edges.len() - 1;
        let n_slots = n_r * spec.n_theta_rotor * n_z;
        if spec.blocked.len() != n_slots {
            return Err(MeshError::input("blocked", spec.blocked.len(), &format!("one flag per rotor slot ({n_slots})")));
        }
        if spec.n_theta_rotor < 3 || spec.n_theta_stator < 3 || n_r < 2 || spec.stator_r.len() < 2 || n_z < 1 {
            return Err(MeshError::input(
                "resolution",
                format!("{n_r} × {} rotor, {} stator, {n_z} layers", spec.n_theta_rotor, spec.n_theta_stator),
                "at least 2 radial cells in the rotor and 3 around",
            ));
        }
        if (0..n_slots).any(|s| spec.blocked[s] && spec.ijk(s).0 == n_r - 1) {
            return Err(MeshError::input("blocked", "(a solid next to the sliding interface)", "solids at least one cell inside the interface radius"));
        }
        if !spec.baffles.is_empty() && spec.baffles.len() != n_slots {
            return Err(MeshError::input("baffles", spec.baffles.len(), &format!("none, or one bit set per rotor slot ({n_slots})")));
        }
        if !spec.stationary.is_empty() && spec.stationary.len() != n_slots {
            return Err(MeshError::input("stationary", spec.stationary.len(), &format!("none, or one flag per rotor slot ({n_slots})")));
        }
        if spec.blocked.iter().all(|&b| b) {
            return Err(MeshError::input("blocked", "(every rotor slot)", "some open rotor cells"));
        }
        let (mut points, mut all_cells) = (Vec::new(), Vec::new());
        let mut rotor = add_block(&mut points, &mut all_cells, spec.rotor_r.clone(), spec.n_theta_rotor, spec.z_edges.clone(), 0);
        let mut cells: Vec<[usize; 8]> = Vec::with_capacity(all_cells.len());
        let mut slot_of_cell = Vec::with_capacity(n_slots);
        let mut cell_of_slot = vec![usize::MAX; n_slots];
        for (slot, ids) in all_cells.iter().enumerate() {
            if !spec.blocked[slot] {
                cell_of_slot[slot] = cells.len();
                slot_of_cell.push(slot);
                cells.push(*ids);
            }
        }
        let n_rotor_cells = cells.len();
        let mut stator_cells = Vec::new();
        let stator = add_block(&mut points, &mut stator_cells, spec.stator_r.clone(), spec.n_theta_stator, spec.z_edges.clone(), 1);
        let stator = super::locate::CylinderBlock { first_cell: n_rotor_cells, ..stator };
        cells.extend(stator_cells);
        let n_cells = cells.len();
        // every blocked slot points at the nearest open cell (breadth-first from all open slots)
        let mut queue: VecDeque<usize> = (0..n_slots).filter(|&s| !spec.blocked[s]).collect();
        while let Some(s) = queue.pop_front() {
            for local in 0..6 {
                if let Some(t) = spec.neighbour(s, local) {
                    if cell_of_slot[t] == usize::MAX {
                        cell_of_slot[t] = cell_of_slot[s];
                        queue.push_back(t);
                    }
                }
            }
        }
        rotor.cell_of_slot = cell_of_slot;
        rotor.blocked = spec.blocked.clone();

        let interface_kind = |side| PatchKind::Interface { interface: 0, side };
        let patches: Vec<(String, PatchKind)> = BLOCKED_ROTOR_STATOR_PATCHES
            .iter()
            .map(|name| {
                let kind = match *name {
                    "interface_rotor" => interface_kind(InterfaceSide::Rotor),
                    "interface_stator" => interface_kind(InterfaceSide::Stator),
                    "head" => PatchKind::Wall,
                    _ => PatchKind::Patch,
                };
                (name.to_string(), kind)
            })
            .collect();
        let rotor_centre_radius = |slot: usize| {
            let (i, _, _) = spec.ijk(slot);
            0.5 * (spec.rotor_r[i] + spec.rotor_r[i + 1]) * (std::f64::consts::PI / spec.n_theta_rotor as f64).cos()
        };
        let input = HexCells {
            canonical: (0..points.len()).collect(),
            points,
            cells,
            patches,
            periodic: Vec::new(),
            zones: super::cylindrical::rotor_stator_zones(n_rotor_cells, n_cells),
            locator: Locator::Cylindrical { blocks: vec![rotor, stator] },
        };
        const HEAD: usize = 6;
        let baffle_of = |cell: usize, local: usize| (cell < n_rotor_cells && spec.is_baffle(slot_of_cell[cell], local)).then_some(HEAD);
        let mut mesh = assemble_with_baffles(
            input,
            |cell, local| {
                if cell >= n_rotor_cells {
                    return match local {
                        LOCAL_OUTER => Ok(1),
                        LOCAL_Z_MIN => Ok(2),
                        LOCAL_Z_MAX => Ok(3),
                        LOCAL_INNER => Ok(5),
                        _ => Err(MeshError::Topology(format!("θ face {local} of stator cell {cell} is unmatched"))),
                    };
                }
                let slot = slot_of_cell[cell];
                match spec.neighbour(slot, local) {
                    Some(t) if spec.blocked[t] && spec.stationary.get(t) == Some(&true) => Ok(7),
                    Some(t) if spec.blocked[t] => Ok(6),
                    Some(_) => Err(MeshError::Topology(format!("face {local} of rotor cell {cell} is unmatched next to an open cell"))),
                    None => Ok(match local {
                        LOCAL_INNER => 0,
                        LOCAL_OUTER => 4,
                        LOCAL_Z_MIN => 2,
                        _ if rotor_centre_radius(slot) < spec.suction_radius => 7,
                        _ => 3,
                    }),
                }
            },
            baffle_of,
        )?;
        let rotor_jk = |cell: usize| {
            let (_, j, k) = spec.ijk(slot_of_cell[cell]);
            (j, k)
        };
        let n_r_stator = spec.stator_r.len() - 1;
        let stator_jk = |cell: usize| {
            let local = cell - n_rotor_cells;
            ((local / n_r_stator) % spec.n_theta_stator, local / (n_r_stator * spec.n_theta_stator))
        };
        let rotor_faces = super::cylindrical::interface_faces_by(&mesh, "interface_rotor", spec.n_theta_rotor, rotor_jk)?;
        let stator_faces = super::cylindrical::interface_faces_by(&mesh, "interface_stator", spec.n_theta_stator, stator_jk)?;
        let radius = *spec.rotor_r.last().expect("≥ 2 edges");
        let n_theta = [spec.n_theta_rotor, spec.n_theta_stator];
        mesh.interfaces.push(super::cylindrical::cylinder_interface(radius, spec.z_edges.clone(), n_theta, rotor_faces, stator_faces));
        Ok(mesh)
    }
}
