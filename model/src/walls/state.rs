//! Wall state: each wall's triangle mesh (in its own body frame) and its current rigid pose.

use nalgebra::{Rotation3, Unit, Vector3};
use serde::{Deserialize, Serialize};

use crate::mesh::motion::rigid_rotation_velocity;

pub type Vec3 = Vector3<f64>;

/// Rigid motion of a wall, resolved from `[walls.motion]` (and `[rotor]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum WallMotion {
    Static,
    /// Rotation at `omega` about the unit `axis` through `origin` (body-frame point).
    Rotate { omega: f64, axis: Vec3, origin: Vec3 },
    Translate { velocity: Vec3 },
}

/// One wall.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Wall {
    pub name: String,
    /// Index into `[[particles.materials]]`.
    pub material: usize,
    /// Vertices in the body frame (the pose at t = 0).
    pub vertices: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
    pub motion: WallMotion,
    /// Rotation angle [rad] turned so far (rotating walls).
    pub angle: f64,
    /// Displacement [m] so far (translating walls).
    pub displacement: Vec3,
}

impl Wall {
    fn rotation(&self) -> Rotation3<f64> {
        match &self.motion {
            WallMotion::Rotate { axis, .. } => Rotation3::from_axis_angle(&Unit::new_normalize(*axis), self.angle),
            _ => Rotation3::identity(),
        }
    }
    fn pivot(&self) -> Vec3 {
        match &self.motion {
            WallMotion::Rotate { origin, .. } => *origin,
            _ => Vec3::zeros(),
        }
    }
    /// Body-frame point → world point at the current pose.
    pub fn to_world(&self, body: Vec3) -> Vec3 {
        let pivot = self.pivot();
        pivot + self.rotation() * (body - pivot) + self.displacement
    }
    /// World point → body-frame point at the current pose.
    pub fn to_body(&self, world: Vec3) -> Vec3 {
        let pivot = self.pivot();
        pivot + self.rotation().inverse() * (world - self.displacement - pivot)
    }
    /// Body-frame direction → world direction.
    pub fn direction_to_world(&self, body: Vec3) -> Vec3 {
        self.rotation() * body
    }
    /// Velocity of the wall material at world point `p` [m/s] (§7.4: ω × (x − x_axis) + v).
    pub fn surface_velocity(&self, p: Vec3) -> Vec3 {
        match &self.motion {
            WallMotion::Static => Vec3::zeros(),
            WallMotion::Rotate { omega, axis, origin } => rigid_rotation_velocity(*omega, &axis.normalize(), &(origin + self.displacement), &p),
            WallMotion::Translate { velocity } => *velocity,
        }
    }
    /// Advances the pose by `dt`.
    pub fn advance(&mut self, dt: f64) {
        match &self.motion {
            WallMotion::Static => {}
            WallMotion::Rotate { omega, .. } => self.angle += omega * dt,
            WallMotion::Translate { velocity } => self.displacement += velocity * dt,
        }
    }
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WallState {
    pub walls: Vec<Wall>,
}
