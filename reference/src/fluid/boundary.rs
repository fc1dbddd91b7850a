//! Boundary conditions of the case, resolved per patch (spec §8.8): the definition is
//! [`spillage_model::fluid::conditions`]; here the reference reads it per [`BoundaryFace`].

pub use spillage_model::fluid::conditions::{Condition, Conditions};
use spillage_model::mesh::Vec3;

use super::geometry::{BoundaryFace, RotorMotion};

/// The rotor's velocity field x ↦ ω â × (x − x₀) (`None` without a rotor).
fn rotor_velocity(rotor: Option<&RotorMotion>) -> Option<impl Fn(&Vec3) -> Vec3 + '_> {
    rotor.map(|r| move |x: &Vec3| r.velocity_at(x))
}

/// The fixed boundary velocity of a face, if its condition fixes one.
pub fn fixed_velocity(conditions: &Conditions, face: &BoundaryFace, rotor: Option<&RotorMotion>) -> Option<Vec3> {
    conditions.fixed_velocity(face.patch, &face.centre, rotor_velocity(rotor))
}

/// The prescribed absolute flux of a face (`None` where the pressure is fixed instead).
pub fn prescribed_flux(conditions: &Conditions, face: &BoundaryFace, rotor: Option<&RotorMotion>) -> Option<f64> {
    conditions.prescribed_flux(face.patch, &face.centre, &face.area, face.mesh_flux, rotor_velocity(rotor))
}
