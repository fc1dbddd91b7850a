//! Particle state: the particles (stable ids), the contact history, the wall impact log and the
//! counts. Everything needed to continue a DEM run bit-for-bit from a checkpoint.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use super::random::SplitMix64;

pub type Vec3 = Vector3<f64>;

/// One sphere.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Particle {
    /// Stable identifier, never reused.
    pub id: u64,
    /// Index into `[[particles.materials]]`.
    pub material: usize,
    pub diameter: f64,
    /// ρ_p [kg/m³] (copied from the material).
    pub density: f64,
    pub position: Vec3,
    pub velocity: Vec3,
    /// Angular velocity ω_p [rad/s].
    pub spin: Vec3,
    /// Contact force and torque at the end of the last sub-step (needed by the first half-kick
    /// of the next, §5.10).
    pub contact_force: Vec3,
    pub contact_torque: Vec3,
    /// Number of contacts at the end of the last sub-step.
    pub contacts: u32,
}

impl Particle {
    pub fn radius(&self) -> f64 {
        0.5 * self.diameter
    }
    pub fn volume(&self) -> f64 {
        std::f64::consts::PI * self.diameter.powi(3) / 6.0
    }
    pub fn mass(&self) -> f64 {
        self.density * self.volume()
    }
    /// I_0 = K_0 m r², K_0 = 2/5 (§5.8).
    pub fn moment_of_inertia(&self) -> f64 {
        0.4 * self.mass() * self.radius() * self.radius()
    }
    /// Translational plus rotational kinetic energy [J].
    pub fn kinetic_energy(&self) -> f64 {
        0.5 * self.mass() * self.velocity.norm_squared() + 0.5 * self.moment_of_inertia() * self.spin.norm_squared()
    }
}

/// The other side of a contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Partner {
    /// Another particle, by id (pair records are stored once, under the smaller id).
    Particle(u64),
    /// A wall, by its index in `[[walls]]`.
    Wall(u32),
}

/// The history of one contact: what persists from sub-step to sub-step (§7.8).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactRecord {
    pub particle: u64,
    pub partner: Partner,
    /// Accumulated tangential overlap δ_t [m] (T3.96), on `particle`.
    pub tangential_overlap: Vec3,
    /// α_η fixed at first touch from ε_wet (§7.5 [R]).
    pub damping_ratio: f64,
    /// Normal relative approach speed at first touch [m/s].
    pub approach_speed: f64,
    /// Unit normal from the particle to its partner at the last sub-step (matches wall contacts
    /// across triangle edges).
    pub normal: Vec3,
    /// Time of first touch [s].
    pub start_time: f64,
    /// Restitution of the contact, fixed at first touch (ε_dry, or ε_wet of the approach).
    #[serde(default)]
    pub restitution: f64,
    /// Compressive normal impulse ∫|F_n| dt since first touch [N s], kept on the walls whose
    /// sliding wear is on (`crate::wear::sliding`), else 0.
    #[serde(default)]
    pub normal_impulse: f64,
}

/// One particle–wall impact (first touch of a contact), for the wear model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ImpactRecord {
    pub particle: u64,
    pub wall: u32,
    /// Triangle of the wall mesh that was hit.
    pub triangle: u32,
    pub time: f64,
    /// Normal approach speed of the particle centre relative to the wall surface [m/s].
    pub normal_speed: f64,
    /// Tangential speed of the particle centre relative to the wall surface [m/s].
    pub tangential_speed: f64,
    /// Impact angle between the relative velocity and the wall surface [rad] (π/2 = head-on).
    pub angle: f64,
    /// Particle mass, diameter and density (the wear laws need them).
    pub mass: f64,
    pub diameter: f64,
    pub density: f64,
    /// Contact point on the wall and unit normal from the particle into the wall, both in the
    /// wall's body frame (where wear is deposited and the wall recedes).
    pub point: Vec3,
    pub normal: Vec3,
    /// Not an impact but a sustained contact's normal impulse beyond its collision's, as the
    /// equivalent grazing impact (`crate::wear::sliding`): not counted as an impact.
    #[serde(default)]
    pub sliding: bool,
}

/// Particle bookkeeping: created = particles.len() + exits.len(), always.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ParticleCounts {
    /// Created in total (initial + fed).
    pub created: u64,
    /// Particle–wall impacts so far (the impacts themselves are consumed every step).
    pub impacts: u64,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ParticleState {
    /// Particles sorted by id.
    pub particles: Vec<Particle>,
    /// Contact history, sorted by (particle, partner).
    pub contacts: Vec<ContactRecord>,
    /// The particle–wall impacts of the current step, in time order: the wear phase consumes
    /// them at the end of the step (the log never grows beyond one step).
    pub impacts: Vec<ImpactRecord>,
    pub counts: ParticleCounts,
    /// Every particle that left, in the order it left.
    pub exits: Vec<super::bookkeeping::ExitRecord>,
    /// Next id to hand out.
    pub next_id: u64,
    /// Per feed: particles owed but not yet placed (fractional), and its random stream.
    pub feed_debt: Vec<f64>,
    pub feed_random: Vec<SplitMix64>,
}

impl ParticleState {
    /// Particles that left the domain so far.
    pub fn escaped(&self) -> u64 {
        self.exits.len() as u64
    }
}
