//! Boundary conditions of the case per patch (spec §8.8), as the reference resolves them.

use spillage_model::case::Case;
use spillage_model::fluid::settings::BoundaryCondition;
use spillage_model::mesh::{Mesh, PatchKind, Vec3};
use spillage_model::solver::SolverError;

use super::layout::Rotor;

#[derive(Clone, Debug)]
pub enum Condition {
    /// u_b(x) = velocity + spin × (x − origin) (+ rotor motion if `rotating`).
    FixedVelocity { velocity: Vec3, spin: Vec3, origin: Vec3, rotating: bool },
    /// Fixed kinematic pressure, zero-gradient velocity.
    FixedPressure { pressure: f64 },
    /// No normal flux relative to the mesh, zero-gradient tangential velocity.
    Symmetry,
}

#[derive(Clone, Debug)]
pub struct Conditions {
    pub conditions: Vec<Condition>,
    pub patch_condition: Vec<Option<usize>>,
    pub has_fixed_pressure: bool,
}

impl Conditions {
    pub fn from_case(case: &Case, mesh: &Mesh, density: f64) -> Result<Conditions, SolverError> {
        let mut conditions = Vec::new();
        let mut patch_condition = Vec::new();
        let mut has_fixed_pressure = false;
        for patch in &mesh.patches {
            if matches!(patch.kind, PatchKind::Empty | PatchKind::Interface { .. }) {
                patch_condition.push(None);
                continue;
            }
            let Some(bc) = case.boundary.get(&patch.name) else {
                return Err(SolverError::Unsupported(format!(
                    "mesh patch `{}` has no [boundary.{}] condition in the case",
                    patch.name, patch.name
                )));
            };
            let condition = match bc {
                BoundaryCondition::Wall { velocity, rotating, angular_velocity, axis, origin } => Condition::FixedVelocity {
                    velocity: Vec3::from(*velocity),
                    spin: Vec3::from(*axis).normalize() * *angular_velocity,
                    origin: Vec3::from(*origin),
                    rotating: *rotating,
                },
                BoundaryCondition::VelocityInlet { velocity } => {
                    Condition::FixedVelocity { velocity: Vec3::from(*velocity), spin: Vec3::zeros(), origin: Vec3::zeros(), rotating: false }
                }
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

    /// Fixed velocity at a face centre, if the condition fixes one.
    pub fn fixed_velocity(&self, condition: usize, centre: &Vec3, rotor: Option<&Rotor>) -> Option<Vec3> {
        match &self.conditions[condition] {
            Condition::FixedVelocity { velocity, spin, origin, rotating } => {
                let mut u = velocity + spin.cross(&(centre - origin));
                if *rotating {
                    if let Some(r) = rotor {
                        u += r.velocity_at(centre);
                    }
                }
                Some(u)
            }
            _ => None,
        }
    }

    /// Prescribed absolute flux (`None` where the pressure is fixed instead).
    pub fn prescribed_flux(&self, condition: usize, centre: &Vec3, area: &Vec3, mesh_flux: f64, rotor: Option<&Rotor>) -> Option<f64> {
        match &self.conditions[condition] {
            Condition::FixedVelocity { .. } => self.fixed_velocity(condition, centre, rotor).map(|u| u.dot(area)),
            Condition::Symmetry => Some(mesh_flux),
            Condition::FixedPressure { .. } => None,
        }
    }
}
