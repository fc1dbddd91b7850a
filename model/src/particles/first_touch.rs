//! What a contact records when it begins (fluid-dem-model.md §7.8 step 3, wear-model.md §7.1),
//! the same in both particle phases: its history record and, against a wall, the impact the
//! wear model consumes.

use super::materials::MaterialTable;
use super::state::{ContactRecord, ImpactRecord, Particle, Partner, Vec3};
use crate::closure::contact::damping_ratio;
use crate::walls::geometry::MeshContact;

/// The record of a pair contact at first touch, kept under `a` (the smaller id); `v_rel` is the
/// relative velocity of the contact point (a minus b), `normal` the unit vector from a to b.
/// `wet_fluid`: (ρ_f, ν) when the wet restitution law applies.
pub fn pair_record(
    materials: &MaterialTable,
    wet_fluid: Option<(f64, f64)>,
    a: &Particle,
    b: &Particle,
    normal: Vec3,
    v_rel: Vec3,
    time: f64,
) -> ContactRecord {
    let approach = v_rel.dot(&normal);
    // [R] St_AM of unequal particles (unspecified, §7.5): mean density and the harmonic-mean
    // diameter; both reduce to the particle's own for identical spheres.
    let density = 0.5 * (a.density + b.density);
    let diameter = 2.0 * a.diameter * b.diameter / (a.diameter + b.diameter);
    let restitution = materials.first_touch_restitution(a.material, b.material, wet_fluid, approach, density, diameter);
    ContactRecord {
        particle: a.id,
        partner: Partner::Particle(b.id),
        tangential_overlap: Vec3::zeros(),
        damping_ratio: damping_ratio(restitution),
        approach_speed: approach,
        normal,
        start_time: time,
        restitution,
        normal_impulse: 0.0,
    }
}

/// The record of a wall contact at first touch (wall index `wall` of material
/// `wall_material`).
pub fn wall_record(
    materials: &MaterialTable,
    wet_fluid: Option<(f64, f64)>,
    p: &Particle,
    wall: u32,
    wall_material: usize,
    normal: Vec3,
    v_rel: Vec3,
    time: f64,
) -> ContactRecord {
    let approach = v_rel.dot(&normal);
    let restitution = materials.first_touch_restitution(p.material, wall_material, wet_fluid, approach, p.density, p.diameter);
    ContactRecord {
        particle: p.id,
        partner: Partner::Wall(wall),
        tangential_overlap: Vec3::zeros(),
        damping_ratio: damping_ratio(restitution),
        approach_speed: approach,
        normal,
        start_time: time,
        restitution,
        normal_impulse: 0.0,
    }
}

/// The impact of a new wall contact: speeds of the particle centre relative to the wall
/// surface, split along `normal` (world frame, towards the wall), and the contact point and
/// normal in the wall's body frame (`body_centre`: the particle centre there).
pub fn impact(p: &Particle, wall: u32, contact: &MeshContact, body_centre: Vec3, wall_velocity: Vec3, normal: Vec3, time: f64) -> ImpactRecord {
    let centre_velocity = p.velocity - wall_velocity;
    let normal_speed = centre_velocity.dot(&normal);
    let tangential_speed = (centre_velocity - normal_speed * normal).norm();
    ImpactRecord {
        particle: p.id,
        wall,
        triangle: contact.triangle,
        time,
        normal_speed,
        tangential_speed,
        angle: normal_speed.atan2(tangential_speed),
        mass: p.mass(),
        diameter: p.diameter,
        density: p.density,
        point: contact.point,
        normal: (contact.point - body_centre) / contact.distance,
        sliding: false,
    }
}

/// Two wall contacts of one particle are the same contact when their normals differ by less
/// than 45° (a sphere rolling across a triangle edge keeps its tangential spring).
pub const SAME_WALL_CONTACT_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// Which of a particle's records with one wall (from the last sub-step, not yet continued, in
/// their order, each with its index) a contact with unit normal `normal` continues: the index
/// of the one whose normal is closest (the last of equals), within [`SAME_WALL_CONTACT_COS`];
/// `None` for a new contact.
pub fn continued_wall_contact<'a>(previous: impl Iterator<Item = (usize, &'a ContactRecord)>, normal: &Vec3) -> Option<usize> {
    previous.map(|(k, r)| (k, r.normal.dot(normal))).filter(|(_, cos)| *cos > SAME_WALL_CONTACT_COS).max_by(|x, y| x.1.total_cmp(&y.1)).map(|(k, _)| k)
}
