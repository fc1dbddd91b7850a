//! Face-addressed finite-volume mesh (owner/neighbour faces, as OpenFOAM's polyMesh) and its
//! block-structured generators (spec fluid-dem-model.md §4, DESIGN.md "mesh").
//!
//! Conventions (every solver relies on these):
//! - Faces `0..n_internal_faces` are internal; boundary faces follow, grouped by patch
//!   (`patches[k].start .. patches[k].start + patches[k].len`).
//! - Internal faces satisfy `face_owner[f] < face_neighbour[f]` and are sorted by
//!   (owner, neighbour) (upper-triangular order); no two faces join the same pair of cells.
//! - `face_areas[f]` is the area vector S_f; for an internal face it points from
//!   `face_owner[f]` to `face_neighbour[f]`, for a boundary face out of the domain.
//! - Periodic faces are stored once, as internal faces whose neighbour lies across the periodic
//!   boundary. Their points, centre and area are the *owner's* copy of the face;
//!   `face_delta[f]` (owner centre → neighbour centre) already includes the shift, so
//!   solvers treat them like any internal face.
//! - Every cell belongs to exactly one zone (`cell_zone`). Cells of a rotating zone move
//!   rigidly; [`Mesh::set_zone_angle`] updates all geometry of that zone from its reference
//!   (angle 0) points, so rotation never accumulates round-off.
//! - `cell_faces[cell_face_offsets[c]..cell_face_offsets[c + 1]]` lists the faces of cell `c`
//!   (ascending face index).

use nalgebra::Vector3;

pub mod assemble;
pub mod blocked;
pub mod cartesian;
pub mod cylindrical;
pub mod deform;
pub mod from_case;
pub mod geometry;
pub mod locate;
pub mod motion;
pub mod sliding_interface;

pub use blocked::{BlockedRotorStator, BLOCKED_ROTOR_STATOR_PATCHES};
pub use cartesian::BoxSpec;
pub use cylindrical::{AnnulusSpec, RotorStatorSpec};
pub use from_case::{build, for_case};
pub use locate::Locator;
pub use sliding_interface::{overlap_1d, InterfaceFrame, Overlap, Overlap1d, OverlapLinkGeometry, SlidingInterface};

pub type Vec3 = Vector3<f64>;

/// Invalid generator input or an invalid request on a mesh. Every variant names the input,
/// the offending value and what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    #[error("invalid mesh input `{input}` = {value}: {allowed}")]
    InvalidInput { input: String, value: String, allowed: String },
    #[error("unknown patch `{name}`; the mesh has patches {available:?}")]
    UnknownPatch { name: String, available: Vec<String> },
    #[error("zone index {zone} out of range: the mesh has {n_zones} zones")]
    UnknownZone { zone: usize, n_zones: usize },
    #[error("zone `{name}` has no rotation; only rotating zones can be turned")]
    ZoneNotRotating { name: String },
    #[error("inconsistent mesh topology: {0}")]
    Topology(String),
    /// A point move ([`Mesh::move_points`]) that would fold the mesh.
    #[error("{0}")]
    Motion(String),
}

impl MeshError {
    pub(crate) fn input(input: &str, value: impl std::fmt::Display, allowed: &str) -> Self {
        MeshError::InvalidInput { input: input.to_string(), value: value.to_string(), allowed: allowed.to_string() }
    }
}

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
    /// Unit axis; positive angles turn counter-clockwise seen from the tip of the axis.
    pub axis: Vec3,
    /// A point on the axis.
    pub origin: Vec3,
    /// Current angle (rad) of the zone relative to its reference geometry.
    pub angle: f64,
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct CellZone {
    pub name: String,
    /// Cells of the zone, ascending.
    pub cells: Vec<usize>,
    /// `Some` for a zone that rotates rigidly (a rotor).
    pub rotation: Option<ZoneRotation>,
    /// Points used by the zone's cells, ascending. For a rotating zone no cell outside the
    /// zone uses them (the zone is detached from the rest of the mesh by an interface).
    pub points: Vec<usize>,
    /// Faces of the zone's cells, ascending (their geometry moves with the zone).
    pub faces: Vec<usize>,
    /// A rotating zone's geometry at angle 0, which [`Mesh::set_zone_angle`] turns.
    #[serde(skip)]
    pub reference_geometry: Option<ZoneGeometry>,
}

/// Geometry of a rotating zone at angle 0, aligned with its `faces` and `cells` lists. Rigid
/// rotation carries centres, area vectors and deltas along and leaves volumes and interpolation
/// weights unchanged, so turning this copy gives what recomputing from the turned points gives,
/// without the per-face polygon and per-cell hexahedron decompositions and with volumes and
/// weights exactly constant.
#[derive(Clone, Debug, Default)]
pub struct ZoneGeometry {
    pub face_centres: Vec<Vec3>,
    pub face_areas: Vec<Vec3>,
    /// Delta of each internal face (zero for boundary faces).
    pub face_delta: Vec<Vec3>,
    /// Whether the face is periodic (its delta involves a shift, recomputed rather than turned).
    pub face_periodic: Vec<bool>,
    pub cell_centres: Vec<Vec3>,
}

/// A pair of opposite boundaries joined periodically; its faces are internal faces.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct PeriodicPair {
    pub name: String,
    /// The internal faces that cross this periodic boundary.
    pub faces: Vec<usize>,
    /// Translation from the owner's copy of each face to the neighbour's copy. The neighbour
    /// cell's periodic image next to the owner is at `C_N − shift`, so
    /// `face_delta = C_N − shift − C_P`. For the box generator the owner is the low-side cell,
    /// so `shift` is +L along the periodic direction.
    pub shift: Vec3,
}

/// Face-addressed mesh with hexahedral cells.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Mesh {
    /// Current point positions.
    pub points: Vec<Vec3>,
    /// Point positions at zone angle 0 (rotation is always applied to these).
    pub reference_points: Vec<Vec3>,
    /// Cell → 8 point ids in VTK_HEXAHEDRON order (output, particle location).
    pub cell_points: Vec<[usize; 8]>,
    pub cell_centres: Vec<Vec3>,
    pub cell_volumes: Vec<f64>,
    /// Zone index of each cell.
    pub cell_zone: Vec<usize>,
    /// CSR offsets into `cell_faces` (length n_cells + 1).
    pub cell_face_offsets: Vec<usize>,
    /// Faces of each cell, see `cell_face_offsets`.
    pub cell_faces: Vec<usize>,
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
    /// Index map of the generator, for O(1) point location.
    pub locator: Locator,
}

impl Mesh {
    pub fn n_cells(&self) -> usize {
        self.cell_points.len()
    }

    pub fn n_faces(&self) -> usize {
        self.face_points.len()
    }

    pub fn n_points(&self) -> usize {
        self.points.len()
    }

    pub fn is_internal_face(&self, face: usize) -> bool {
        face < self.n_internal_faces
    }

    /// Faces of a cell (ascending).
    pub fn faces_of_cell(&self, cell: usize) -> &[usize] {
        &self.cell_faces[self.cell_face_offsets[cell]..self.cell_face_offsets[cell + 1]]
    }

    /// Area vector of `face` pointing out of `cell` (which must be its owner or neighbour).
    pub fn outward_area(&self, face: usize, cell: usize) -> Vec3 {
        if self.face_owner[face] == cell {
            self.face_areas[face]
        } else {
            -self.face_areas[face]
        }
    }

    /// Index of the patch holding boundary face `face`; `None` for an internal face.
    pub fn boundary_patch_of(&self, face: usize) -> Option<usize> {
        if face < self.n_internal_faces {
            return None;
        }
        self.patches.iter().position(|p| p.faces().contains(&face))
    }

    pub fn patch_index(&self, name: &str) -> Result<usize, MeshError> {
        self.patches
            .iter()
            .position(|p| p.name == name)
            .ok_or_else(|| MeshError::UnknownPatch { name: name.to_string(), available: self.patches.iter().map(|p| p.name.clone()).collect() })
    }

    pub fn patch(&self, name: &str) -> Result<&Patch, MeshError> {
        Ok(&self.patches[self.patch_index(name)?])
    }

    /// Change the geometric kind of a patch (e.g. mark `z_min`/`z_max` of a one-cell-thick mesh
    /// `Empty`, or a patch `Wall`).
    pub fn set_patch_kind(&mut self, name: &str, kind: PatchKind) -> Result<(), MeshError> {
        let index = self.patch_index(name)?;
        self.patches[index].kind = kind;
        Ok(())
    }

    pub fn zone_index(&self, name: &str) -> Option<usize> {
        self.zones.iter().position(|z| z.name == name)
    }
}

#[cfg(test)]
pub(crate) mod test_support;
