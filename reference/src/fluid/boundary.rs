//! Boundary conditions of the case, resolved per patch (spec §8.8).

use spillage_model::case::Case;
use spillage_model::fluid::settings::BoundaryCondition;
use spillage_model::mesh::{Mesh, PatchKind, Vec3};
use spillage_model::solver::SolverError;

use super::geometry::{BoundaryFace, RotorMotion};

/// What a boundary patch imposes.
#[derive(Clone, Debug)]
pub enum Condition {
    /// Fixed velocity u_b(x) = `velocity` + Ω × (x − `origin`) (+ rotor motion if `rotating`);
    /// prescribed flux u_b·S. `inlet` only changes the name in messages.
    FixedVelocity { velocity: Vec3, spin: Vec3, origin: Vec3, rotating: bool },
    /// Fixed kinematic pressure, zero-gradient velocity.
    FixedPressure { pressure: f64 },
    /// No normal flux (relative to the mesh), zero-gradient tangential velocity.
    Symmetry,
}

/// Per-patch conditions: `patch_condition[k]` is the index into `conditions` of mesh patch k,
/// `None` for patches that carry no condition (empty, sliding interface).
#[derive(Clone, Debug)]
pub struct Conditions {
    pub conditions: Vec<Condition>,
    pub patch_condition: Vec<Option<usize>>,
    /// True when some boundary fixes the pressure level (otherwise a reference cell does).
    pub has_fixed_pressure: bool,
}

impl Conditions {
    pub fn from_case(case: &Case, mesh: &Mesh, density: f64) -> Result<Conditions, SolverError> {
        let mut conditions = Vec::new();
        let mut patch_condition = Vec::new();
        let mut has_fixed_pressure = false;
        for patch in &mesh.patches {
            match patch.kind {
                PatchKind::Empty | PatchKind::Interface { .. } => {
                    patch_condition.push(None);
                    continue;
                }
                PatchKind::Patch | PatchKind::Wall => {}
            }
            let Some(bc) = case.boundary.get(&patch.name) else {
                return Err(SolverError::Unsupported(format!(
                    "mesh patch `{}` has no [boundary.{}] condition in the case",
                    patch.name, patch.name
                )));
            };
            let condition = match bc {
                BoundaryCondition::Wall { velocity, rotating, angular_velocity, axis, origin } => {
                    let axis = Vec3::from(*axis).normalize();
                    Condition::FixedVelocity {
                        velocity: Vec3::from(*velocity),
                        spin: axis * *angular_velocity,
                        origin: Vec3::from(*origin),
                        rotating: *rotating,
                    }
                }
                BoundaryCondition::VelocityInlet { velocity } => Condition::FixedVelocity {
                    velocity: Vec3::from(*velocity),
                    spin: Vec3::zeros(),
                    origin: Vec3::zeros(),
                    rotating: false,
                },
                BoundaryCondition::PressureOutlet { pressure } => {
                    has_fixed_pressure = true;
                    Condition::FixedPressure { pressure: pressure / density }
                }
                BoundaryCondition::Symmetry => Condition::Symmetry,
            };
            patch_condition.push(Some(conditions.len()));
            conditions.push(condition);
        }
        Ok(Conditions { conditions, patch_condition, has_fixed_pressure })
    }

    /// The fixed boundary velocity of a face, if its condition fixes one.
    pub fn fixed_velocity(&self, face: &BoundaryFace, rotor: Option<&RotorMotion>) -> Option<Vec3> {
        match &self.conditions[face.patch] {
            Condition::FixedVelocity { velocity, spin, origin, rotating } => {
                let mut u = velocity + spin.cross(&(face.centre - origin));
                if *rotating {
                    if let Some(r) = rotor {
                        u += r.velocity_at(&face.centre);
                    }
                }
                Some(u)
            }
            _ => None,
        }
    }

    /// The prescribed absolute flux of a face (`None` where the pressure is fixed instead).
    pub fn prescribed_flux(&self, face: &BoundaryFace, rotor: Option<&RotorMotion>) -> Option<f64> {
        match &self.conditions[face.patch] {
            Condition::FixedVelocity { .. } => self.fixed_velocity(face, rotor).map(|u| u.dot(&face.area)),
            Condition::Symmetry => Some(face.mesh_flux),
            Condition::FixedPressure { .. } => None,
        }
    }
}
