//! Wall geometry: triangle meshes (generated shapes or STL) with rigid motion.
//!
//! Cutter head walls: in a particle run, a `[cutter_head]` with a `material` adds its blades,
//! ring, hub, pipe and shaft as walls turning with the `[rotor]` ([`crate::cutter_head::walls`],
//! spillage-and-flow-verification.md §2.11).

pub mod geometry;
pub mod projection;
pub mod settings;
pub mod state;
pub mod stl;

use std::path::Path;

use crate::case::{Case, FieldError};
use geometry::TriangleMesh;
use settings::{MotionSection, ShapeSection};
use state::{Vec3, Wall, WallMotion, WallState};

/// Why the walls could not be built.
#[derive(Debug, thiserror::Error)]
pub enum WallError {
    #[error("key `{}` = {} is not allowed; expected {}", .0.key, .0.value, .0.allowed)]
    Field(FieldError),
    #[error("wall `{wall}`: {message}")]
    Geometry { wall: String, message: String },
}

/// Builds every `[[walls]]` entry, then the cutter head's walls, at their t = 0 pose; STL paths
/// are relative to `case_dir`.
pub fn build(case: &Case, case_dir: &Path) -> Result<WallState, WallError> {
    let mut walls = Vec::new();
    for (i, section) in case.walls.iter().enumerate() {
        let key = format!("walls.{i}");
        let material = case.particles.as_ref().and_then(|p| p.material_index(&section.material)).ok_or_else(|| {
            WallError::Field(FieldError::new(format!("{key}.material"), format!("{:?}", section.material), "the name of a [[particles.materials]] entry"))
        })?;
        let mesh = match &section.shape {
            ShapeSection::Plane { centre, normal, size, divisions, u_axis } => {
                geometry::plane(Vec3::from(*centre), Vec3::from(*normal), *size, *divisions, u_axis.map(Vec3::from))
            }
            ShapeSection::Box { min, max, divisions, open } => geometry::box_faces(Vec3::from(*min), Vec3::from(*max), *divisions, open),
            ShapeSection::Cylinder { origin, axis, radius, length, segments, layers } => {
                geometry::cylinder(Vec3::from(*origin), Vec3::from(*axis), *radius, *length, *segments, *layers)
            }
            ShapeSection::Disc { centre, normal, radius, segments, rings } => {
                geometry::disc(Vec3::from(*centre), Vec3::from(*normal), *radius, *segments, *rings)
            }
            ShapeSection::Stl { file, scale } => {
                stl::read_stl(&case_dir.join(file), *scale).map_err(|message| WallError::Geometry { wall: section.name.clone(), message })?
            }
        };
        let motion = match &section.motion {
            MotionSection::Static => WallMotion::Static,
            MotionSection::Rotor => {
                case.rotor
                    .as_ref()
                    .ok_or_else(|| WallError::Field(FieldError::new(format!("{key}.motion.type"), "\"rotor\"", "a [rotor] section to turn with")))?;
                WallMotion::Rotor
            }
            MotionSection::Rotate { omega, axis, origin } => {
                WallMotion::Rotate { omega: *omega, axis: Vec3::from(*axis).normalize(), origin: Vec3::from(*origin) }
            }
            MotionSection::Translate { velocity } => WallMotion::Translate { velocity: Vec3::from(*velocity) },
        };
        walls.push(wall(section.name.clone(), material, mesh, motion)?);
    }
    if let (Some(head), Some(particles)) = (&case.cutter_head, &case.particles) {
        if let Some(name) = &head.material {
            let material = particles
                .material_index(name)
                .ok_or_else(|| WallError::Field(FieldError::new("cutter_head.material", format!("{name:?}"), "the name of a [[particles.materials]] entry")))?;
            // triangles the size of the fluid cells
            for (name, mesh) in crate::cutter_head::walls::head_walls(head, head.mesh.cell_size) {
                walls.push(wall(name, material, mesh, WallMotion::Rotor)?);
            }
            for (name, mesh) in crate::cutter_head::walls::stationary_walls(head, head.mesh.cell_size) {
                walls.push(wall(name, material, mesh, WallMotion::Static)?);
            }
        }
    }
    Ok(WallState { walls })
}

/// A wall at its body-frame pose, once its mesh is known to be valid.
pub fn wall(name: String, material: usize, mesh: TriangleMesh, motion: WallMotion) -> Result<Wall, WallError> {
    let TriangleMesh { vertices, triangles } = mesh;
    match geometry::WallMesh::new(&vertices, &triangles) {
        Ok(_) => Ok(Wall { name, material, vertices, triangles, motion, revision: 0, pose: Default::default() }),
        Err(message) => Err(WallError::Geometry { wall: name, message }),
    }
}
