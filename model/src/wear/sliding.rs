//! Sliding wear: the wear of a particle held against a wall while it slides along it
//! (wear-model.md §14 item 12, "sliding/abrasive wear for fine particles that stay at the
//! wall"; §6.3.1: the thesis' fine sand wears the coupon "by sliding", deepest ≈ 3 cm after
//! the step).
//!
//! **Why an impact law on soft spheres needs it.** The thesis' particles are points that rebound
//! with e = 0.99 (§5.2): one pressed onto a wall by a force F_n (Coriolis, drag) re-collides
//! at every time step with a normal speed of about (F_n/m)·Δt, and each re-collision is an
//! impact at a grazing angle that the law turns into volume. A soft sphere pressed onto a wall
//! stays in one contact, which the DEM logs as one impact at first touch; its later normal
//! impulse wears nothing.
//!
//! **The limit we take [R].** A rebound at normal speed v_n transfers the normal impulse
//! (1 + e)·m·v_n. At a grazing angle θ = v_n/U every law's volume is linear in θ (Arabnejad's
//! f(θ) → θ/K, §6.2), so the re-collisions' wear per unit of normal impulse tends to
//!
//!   dW/dJ = lim_{θ→0} W(U, θ) / ((1 + e)·m·U·sin θ),
//!
//! whatever the step: for Arabnejad's cutting term F_s·C·U^1.41 / (2·K·(1 + e)·√Hv), and the
//! deformation term vanishes below its threshold normal speed. A sustained contact delivers
//! J = ∫|F_n| dt. Its first (1 + e)·m·v_n,in is the collision the first-touch impact already
//! wore for; what it delivers beyond that is booked, sub-step by sub-step, as one equivalent
//! grazing impact per sub-step: normal speed ΔJ / ((1 + e)·m), the particle centre's
//! tangential speed relative to the wall (§5.3's U, as for impacts), on the triangle touched.
//! Its angle is ΔJ/((1 + e)·m·U), small at any sub-step (3e-5 rad for sand pressed at
//! 7·10³ m/s² and sliding at 10 m/s in the Coriolis case's 8·10⁻⁸ s sub-steps), so the law
//! stays on its linear branch: the wear per
//! impulse is the limit above to O(θ²) for every law whose angle function has a finite slope
//! at 0 (all but Oka with an exponent n₁ < 1, whose booked wear then depends on the sub-step).
//! A particle at rest on a wall books head-on "impacts" far below any threshold speed: no wear.

use crate::particles::first_touch::impact;
use crate::particles::state::{ContactRecord, ImpactRecord, Particle, Vec3};
use crate::walls::geometry::MeshContact;

/// One sub-step of a wall contact on a wall whose sliding wear is on: adds the compressive
/// normal impulse of `normal_force` (the force on the particle, [N]) over `dt` to `record`, and
/// returns the equivalent grazing impact of the impulse beyond the collision's own, if any.
/// `normal` is the unit vector from the particle centre to the wall (world frame);
/// `body_centre` the particle centre in the wall's body frame.
#[allow(clippy::too_many_arguments)]
pub fn sliding_impact(
    record: &mut ContactRecord,
    p: &Particle,
    wall: u32,
    contact: &MeshContact,
    body_centre: Vec3,
    wall_velocity: Vec3,
    normal: Vec3,
    normal_force: Vec3,
    dt: f64,
    time: f64,
) -> Option<ImpactRecord> {
    let rebound = 1.0 + record.restitution;
    let collision = rebound * p.mass() * record.approach_speed.max(0.0);
    let before = record.normal_impulse;
    record.normal_impulse += (-normal_force.dot(&normal)).max(0.0) * dt;
    let beyond = (record.normal_impulse - collision).max(0.0) - (before - collision).max(0.0);
    if beyond <= 0.0 {
        return None;
    }
    let mut sliding = impact(p, wall, contact, body_centre, wall_velocity, normal, time);
    sliding.normal_speed = beyond / (rebound * p.mass());
    sliding.angle = sliding.normal_speed.atan2(sliding.tangential_speed);
    sliding.sliding = true;
    Some(sliding)
}
