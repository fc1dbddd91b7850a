//! The rotor pose: the one place where the rotor's angle is known (spec fluid-dem-model.md §4.1;
//! DESIGN.md "One step, one pipeline").
//!
//! The angle itself is stored once, in [`crate::state::State::rotor_angle`]; a [`RotorPose`] is
//! that angle together with the constant axis, origin and angular velocity of `[rotor]`. The
//! mesh's rotor zone, the walls that turn with the rotor and every ω×r velocity are derived
//! from a pose handed to them by the driver, never integrated on their own, so the blades of the
//! DEM and the blocked cells of the fluid cannot drift apart.

use crate::case::Case;
use crate::mesh::Vec3;

/// Rigid rotation of the rotor at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotorPose {
    /// Unit axis; positive angles turn counter-clockwise seen from the tip of the axis.
    pub axis: Vec3,
    /// A point on the axis.
    pub origin: Vec3,
    /// Angular velocity about `axis` [rad/s].
    pub omega: f64,
    /// Angle turned from the reference geometry [rad].
    pub angle: f64,
}

impl RotorPose {
    /// The pose of the case's `[rotor]` at `angle`; `None` without a rotor.
    pub fn from_case(case: &Case, angle: f64) -> Option<RotorPose> {
        case.rotor.as_ref().map(|r| RotorPose { axis: Vec3::from(r.axis).normalize(), origin: Vec3::from(r.origin), omega: r.angular_velocity(), angle })
    }

    /// The pose `dt` seconds later (constant ω).
    pub fn advanced(&self, dt: f64) -> RotorPose {
        RotorPose { angle: self.angle + self.omega * dt, ..*self }
    }

    /// Velocity of a point turning with the rotor, ω â × (x − x₀) [m/s].
    pub fn velocity_at(&self, x: &Vec3) -> Vec3 {
        rigid_rotation_velocity(self.omega, &self.axis, &self.origin, x)
    }
}

pub use crate::mesh::motion::rigid_rotation_velocity;

/// The fluid mesh's rotor zone and the rotor's pose at the current step: what both fluid
/// phases turn and take their rotor-face and rotating-wall velocities from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RotorZone {
    /// Index of the mesh zone named by `[rotor] zone`.
    pub zone: usize,
    pub pose: RotorPose,
}

impl RotorZone {
    /// The zone of `[rotor]` in `mesh` at angle 0 (`None` without `[rotor]`), or why it cannot
    /// turn.
    pub fn from_case(case: &Case, mesh: &crate::mesh::Mesh) -> Result<Option<RotorZone>, String> {
        let (Some(section), Some(pose)) = (&case.rotor, RotorPose::from_case(case, 0.0)) else { return Ok(None) };
        let zone =
            mesh.zones.iter().position(|z| z.name == section.zone).ok_or_else(|| format!("rotor.zone = {:?} is not a zone of the mesh", section.zone))?;
        if mesh.zones[zone].rotation.is_none() {
            return Err(format!("mesh zone {:?} cannot rotate", section.zone));
        }
        Ok(Some(RotorZone { zone, pose }))
    }

    /// Velocity of a point turning with the rotor.
    #[inline]
    pub fn velocity_at(&self, x: &Vec3) -> Vec3 {
        self.pose.velocity_at(x)
    }

    /// Takes `pose` and turns the zone of `mesh` to its angle (from the zone's reference
    /// geometry, so no round-off accumulates).
    pub fn place(&mut self, mesh: &mut crate::mesh::Mesh, pose: &RotorPose) -> Result<(), String> {
        self.pose = *pose;
        mesh.set_zone_angle(self.zone, pose.angle).map_err(|e| format!("cannot rotate the rotor zone: {e}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn velocity_is_omega_cross_r_and_advancing_adds_omega_dt() {
        let pose = RotorPose { axis: Vec3::z(), origin: Vec3::new(1.0, 0.0, 0.0), omega: 2.0, angle: 0.5 };
        let v = pose.velocity_at(&Vec3::new(1.0, 3.0, 7.0));
        // ω ẑ × (0, 3, 7) = (−6, 0, 0)
        assert_eq!(v, Vec3::new(-6.0, 0.0, 0.0));
        assert_eq!(pose.advanced(0.25).angle, 1.0);
        assert_eq!(pose.advanced(0.25).omega, 2.0);
    }
}
