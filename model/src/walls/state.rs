//! Wall state: each wall's triangle mesh (in its own body frame) and its current rigid pose.

use nalgebra::{Rotation3, Unit, Vector3};
use serde::{Deserialize, Serialize};

use crate::mesh::motion::rigid_rotation_velocity;

pub type Vec3 = Vector3<f64>;

/// Rigid motion of a wall, resolved from `[walls.motion]` (and `[rotor]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum WallMotion {
    Static,
    /// Turns with the `[rotor]`: its pose comes from the rotor pose of the step
    /// ([`crate::step::RotorPose`], stored once in the state), never integrated on its own.
    Rotor,
    /// Its own rotation at `omega` about the unit `axis` through `origin` (body-frame point),
    /// turned ω t at time t.
    Rotate {
        omega: f64,
        axis: Vec3,
        origin: Vec3,
    },
    /// Translation by v t at time t.
    Translate {
        velocity: Vec3,
    },
}

/// Where a wall is at one instant: derived from the time and the rotor pose by [`Wall::place`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallPose {
    /// Angular velocity [rad/s], unit axis and a point on the axis of the rotation.
    pub omega: f64,
    pub axis: Vec3,
    pub origin: Vec3,
    /// Angle turned from the body frame [rad].
    pub angle: f64,
    /// Translation velocity [m/s] and displacement from the body frame [m].
    pub velocity: Vec3,
    pub displacement: Vec3,
}

impl Default for WallPose {
    /// The body frame itself, at rest.
    fn default() -> Self {
        WallPose { omega: 0.0, axis: Vec3::z(), origin: Vec3::zeros(), angle: 0.0, velocity: Vec3::zeros(), displacement: Vec3::zeros() }
    }
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
    /// Bumped whenever the vertices move (a receding wall): the particle phase rebuilds its
    /// collision structure for the wall when it sees a new revision.
    pub revision: u64,
    /// The pose set by the last [`Wall::place`] (not stored in checkpoints: it is a function of
    /// the time and the rotor pose, which are).
    #[serde(skip)]
    pub pose: WallPose,
}

impl Wall {
    /// Moves the wall to its pose at `time` with the rotor at `rotor` (needed by
    /// [`WallMotion::Rotor`] walls; without it they stay in the body frame).
    pub fn place(&mut self, time: f64, rotor: Option<&crate::step::RotorPose>) {
        self.pose = match (&self.motion, rotor) {
            (WallMotion::Rotor, Some(r)) => WallPose { omega: r.omega, axis: r.axis, origin: r.origin, angle: r.angle, ..WallPose::default() },
            (WallMotion::Rotate { omega, axis, origin }, _) => {
                WallPose { omega: *omega, axis: *axis, origin: *origin, angle: omega * time, ..WallPose::default() }
            }
            (WallMotion::Translate { velocity }, _) => WallPose { velocity: *velocity, displacement: velocity * time, ..WallPose::default() },
            (WallMotion::Static, _) | (WallMotion::Rotor, None) => WallPose::default(),
        };
    }
    /// The current pose resolved once, for transforming many points.
    pub fn frame(&self) -> WallFrame {
        let rotation =
            if self.pose.angle == 0.0 { Rotation3::identity() } else { Rotation3::from_axis_angle(&Unit::new_normalize(self.pose.axis), self.pose.angle) };
        WallFrame { pivot: self.pose.origin, inverse: rotation.inverse(), rotation, displacement: self.pose.displacement }
    }
    /// Body-frame point → world point at the current pose.
    pub fn to_world(&self, body: Vec3) -> Vec3 {
        self.frame().to_world(body)
    }
    /// World point → body-frame point at the current pose.
    pub fn to_body(&self, world: Vec3) -> Vec3 {
        self.frame().to_body(world)
    }
    /// Body-frame direction → world direction.
    pub fn direction_to_world(&self, body: Vec3) -> Vec3 {
        self.frame().rotation * body
    }
    /// Velocity of the wall material at world point `p` [m/s] (§7.4: ω × (x − x_axis) + v).
    pub fn surface_velocity(&self, p: Vec3) -> Vec3 {
        let pose = &self.pose;
        rigid_rotation_velocity(pose.omega, &pose.axis, &(pose.origin + pose.displacement), &p) + pose.velocity
    }
}

/// A wall's rigid pose with its rotation built: body frame ↔ world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallFrame {
    pub pivot: Vec3,
    pub rotation: Rotation3<f64>,
    pub inverse: Rotation3<f64>,
    pub displacement: Vec3,
}

impl WallFrame {
    pub fn to_world(&self, body: Vec3) -> Vec3 {
        self.pivot + self.rotation * (body - self.pivot) + self.displacement
    }
    pub fn to_body(&self, world: Vec3) -> Vec3 {
        self.pivot + self.inverse * (world - self.displacement - self.pivot)
    }
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WallState {
    pub walls: Vec<Wall>,
}

impl WallState {
    /// Moves every wall to its pose at `time` with the rotor at `rotor`.
    pub fn place(&mut self, time: f64, rotor: Option<&crate::step::RotorPose>) {
        for wall in &mut self.walls {
            wall.place(time, rotor);
        }
    }
}
