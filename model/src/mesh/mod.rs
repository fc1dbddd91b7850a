//! Face-addressed finite-volume mesh (owner/neighbour faces, as OpenFOAM's polyMesh) and its
//! block-structured generators.
//!
//! Conventions (every solver relies on these):
//! - Faces `0..n_internal_faces` are internal; boundary faces follow, grouped by patch
//!   (`patches[k].start .. patches[k].start + patches[k].len`).
//! - `face_areas[f]` is the area vector S_f; for an internal face it points from
//!   `face_owner[f]` to `face_neighbour[f]`, for a boundary face out of the domain.
//! - Periodic faces are stored once, as internal faces whose neighbour lies across the periodic
//!   boundary; `face_delta[f]` (owner centre → neighbour centre) already includes the shift, so
//!   solvers treat them like any internal face.
//! - Cells that belong to a rotating zone move rigidly; [`Mesh::set_zone_angle`] updates all
//!   geometry of that zone from its reference (angle 0) geometry, so rotation never accumulates
//!   round-off.

use nalgebra::Vector3;

pub type Vec3 = Vector3<f64>;

/// Geometric type of a boundary patch. Boundary *conditions* come from the case file.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum PatchKind {
    /// Ordinary boundary (inlet, outlet, symmetry…: decided by the case's boundary conditions).
    Patch,
    /// Solid wall.
    Wall,
    /// Front/back of a one-cell-thick 2-D mesh: no flux, no gradient normal to it.
    Empty,
    /// One side of a sliding interface (index into `Mesh::interfaces`).
    Interface { interface: usize, side: InterfaceSide },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum InterfaceSide {
    Rotor,
    Stator,
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Patch {
    pub name: String,
    pub kind: PatchKind,
    /// First face of the patch.
    pub start: usize,
    /// Number of faces.
    pub len: usize,
}

impl Patch {
    pub fn faces(&self) -> std::ops::Range<usize> {
        self.start..self.start + self.len
    }
}

/// Rigid rotation of a cell zone about an axis.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct ZoneRotation {
    /// Unit axis.
    pub axis: Vec3,
    /// A point on the axis.
    pub origin: Vec3,
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct CellZone {
    pub name: String,
    /// Cells of the zone, ascending.
    pub cells: Vec<usize>,
    /// `Some` for a zone that rotates rigidly (a rotor).
    pub rotation: Option<ZoneRotation>,
}

/// A pair of opposite boundaries joined periodically; its faces are internal faces.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct PeriodicPair {
    pub name: String,
    /// The internal faces that cross this periodic boundary.
    pub faces: Vec<usize>,
    /// Translation from the owner side to the neighbour side.
    pub shift: Vec3,
}

/// Face-addressed mesh with hexahedral cells.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Mesh {
    /// Current point positions.
    pub points: Vec<Vec3>,
    /// Cell → 8 point ids in VTK_HEXAHEDRON order (output, particle location).
    pub cell_points: Vec<[usize; 8]>,
    pub cell_centres: Vec<Vec3>,
    pub cell_volumes: Vec<f64>,
    /// Face → 4 point ids, ordered so the right-hand normal is `face_areas[f]`.
    pub face_points: Vec<[usize; 4]>,
    pub face_centres: Vec<Vec3>,
    pub face_areas: Vec<Vec3>,
    pub face_owner: Vec<usize>,
    /// Neighbour cell of each internal face (length `n_internal_faces`).
    pub face_neighbour: Vec<usize>,
    /// Owner centre → neighbour centre for internal faces (periodic shift included).
    pub face_delta: Vec<Vec3>,
    /// Linear interpolation weight of the owner value at each internal face:
    /// φ_f = w φ_P + (1 − w) φ_N.
    pub face_weight: Vec<f64>,
    pub n_internal_faces: usize,
    pub patches: Vec<Patch>,
    pub zones: Vec<CellZone>,
    pub periodic: Vec<PeriodicPair>,
    pub interfaces: Vec<crate::mesh::sliding_interface::SlidingInterface>,
}

pub mod sliding_interface;
