//! Contact detection and forces for one DEM sub-step (fluid-dem-model.md §7.8).

use std::collections::BTreeMap;

use spillage_model::closure::contact::{hertz_mindlin_force, ContactForce};
use spillage_model::particles::first_touch::{continued_wall_contact, impact, pair_record, wall_record};
use spillage_model::particles::guards::{pair_fault, wall_fault, Fault};
use spillage_model::particles::materials::MaterialTable;
use spillage_model::particles::state::Vec3;
use spillage_model::particles::{ContactRecord, ImpactRecord, Particle, Partner};
use spillage_model::walls::geometry::WallMesh;
use spillage_model::walls::state::Wall;
use spillage_model::wear::sliding::sliding_impact;

use super::neighbours::overlapping_pairs;

/// One active contact after a sub-step, for diagnostics and verification.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSample {
    pub particle: u64,
    pub partner: Partner,
    /// Radius of `particle` (to report overlap ratios).
    pub radius: f64,
    pub overlap: f64,
    /// Unit normal from `particle` to its partner.
    pub normal: Vec3,
    /// Forces on `particle` [N].
    pub force: ContactForce,
    /// Wall triangle (wall contacts).
    pub triangle: Option<u32>,
}

/// What the contact evaluation reads besides the particles.
pub struct Context<'a> {
    pub materials: &'a MaterialTable,
    pub walls: &'a [Wall],
    pub meshes: &'a [WallMesh],
    /// (ρ_f, ν) for the wet restitution law, if wet.
    pub wet_fluid: Option<(f64, f64)>,
    /// Per wall: whether its contacts book sliding wear (`spillage_model::wear::sliding`).
    pub sliding_walls: &'a [bool],
    /// Time at the end of the sub-step [s] (stamps new contacts and impacts).
    pub time: f64,
    pub dt: f64,
    /// Particles with this id or above were fed in this step (exempt from the overlap guard,
    /// their first touch counted as placed energy).
    pub fed_from: u64,
}

/// What [`evaluate`] measures besides the forces, for the run's guards (scalars: no allocation).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Watch {
    /// The first fault found ([`Fault`]).
    pub fault: Option<Fault>,
    /// Power the moving walls put into the particles, Σ F·v_wall [W], at this sub-step.
    pub wall_power: f64,
    /// Elastic energy stored in the normal springs, Σ (2/5)|F_n| δ [J] (exact for Hertz's
    /// F ∝ δ^{3/2} without damping; the damping part makes it an estimate).
    pub elastic_energy: f64,
    /// The part of it in contacts of particles fed in this step that began at this sub-step
    /// [J]: the energy of where the feed put them (against a moving blade).
    pub new_contact_energy: f64,
}

/// Evaluates every contact: sets each particle's contact force, torque and count, updates the
/// history (new records at first touch, records of ended contacts dropped) and appends the
/// impacts of new wall contacts (and, on sliding-wear walls, the equivalent impacts of sustained
/// contacts). Returns the contact samples.
pub fn evaluate(
    context: &Context,
    particles: &mut [Particle],
    history: &mut BTreeMap<(u64, Partner), Vec<ContactRecord>>,
    impacts: &mut Vec<ImpactRecord>,
    watch: &mut Watch,
) -> Vec<ContactSample> {
    watch.wall_power = 0.0;
    watch.elastic_energy = 0.0;
    watch.new_contact_energy = 0.0;
    for p in particles.iter_mut() {
        p.contact_force = Vec3::zeros();
        p.contact_torque = Vec3::zeros();
        p.contacts = 0;
    }
    let mut old = std::mem::take(history);
    let mut samples = Vec::new();

    // Particle pairs: the record is kept under the smaller id (particles are sorted by id).
    for (i, j) in overlapping_pairs(particles) {
        let (a, b) = (&particles[i], &particles[j]);
        let offset = b.position - a.position;
        let distance = offset.norm();
        let overlap = a.radius() + b.radius() - distance;
        let fed = a.id >= context.fed_from || b.id >= context.fed_from;
        if let Some(fault) = pair_fault(a, b, distance, overlap, fed) {
            let coincident = matches!(fault, Fault::Coincident { .. });
            watch.fault.get_or_insert(fault);
            if coincident {
                continue;
            }
        }
        let normal = offset / distance;
        // §7.8 step 2: relative velocity of the contact point.
        let v_rel = a.velocity + a.spin.cross(&(a.radius() * normal)) - (b.velocity + b.spin.cross(&(-b.radius() * normal)));
        let key = (a.id, Partner::Particle(b.id));
        let existing = old.remove(&key).and_then(|mut v| v.pop());
        let new_contact = existing.is_none();
        let mut record = existing.unwrap_or_else(|| pair_record(context.materials, context.wet_fluid, a, b, normal, v_rel, context.time));
        let constants = context.materials.constants(a.material, b.material, a.radius(), b.radius(), a.mass(), b.mass());
        let force = hertz_mindlin_force(&constants, record.damping_ratio, normal, overlap, v_rel, &mut record.tangential_overlap, context.dt);
        record.normal = normal;
        let (ra, rb) = (a.radius(), b.radius());
        let total = force.normal + force.tangential;
        // §7.8 steps 6–7.
        let elastic = 0.4 * force.normal.norm() * overlap;
        watch.elastic_energy += elastic;
        if new_contact && fed {
            watch.new_contact_energy += elastic;
        }
        particles[i].contact_force += total;
        particles[i].contact_torque += (ra * normal).cross(&force.tangential);
        particles[i].contacts += 1;
        particles[j].contact_force -= total;
        particles[j].contact_torque += (-rb * normal).cross(&(-force.tangential));
        particles[j].contacts += 1;
        samples.push(ContactSample { particle: particles[i].id, partner: key.1, radius: ra, overlap, normal, force, triangle: None });
        history.entry(key).or_default().push(record);
    }

    // Walls: a wall has infinite radius and mass (§7.4); the partner velocity is the wall's
    // surface velocity at the contact point.
    for p in particles.iter_mut() {
        for (w, (wall, mesh)) in context.walls.iter().zip(context.meshes).enumerate() {
            let key = (p.id, Partner::Wall(w as u32));
            let mut previous = old.remove(&key).unwrap_or_default();
            let body = wall.to_body(p.position);
            let found = mesh.sphere_contacts(body, p.radius());
            for contact in found {
                let point = wall.to_world(contact.point);
                let overlap = p.radius() - contact.distance;
                let fed = p.id >= context.fed_from;
                if let Some(fault) = wall_fault(p, w as u32, contact.distance, overlap, fed) {
                    let on_wall = matches!(fault, Fault::CentreOnWall { .. });
                    watch.fault.get_or_insert(fault);
                    if on_wall {
                        continue;
                    }
                }
                let normal = (point - p.position) / contact.distance;
                let wall_velocity = wall.surface_velocity(point);
                let v_rel = p.velocity + p.spin.cross(&(p.radius() * normal)) - wall_velocity;
                let matched = continued_wall_contact(previous.iter().enumerate(), &normal);
                let new_contact = matched.is_none();
                let mut record = match matched {
                    Some(k) => previous.remove(k),
                    None => {
                        impacts.push(impact(p, w as u32, &contact, body, wall_velocity, normal, context.time));
                        wall_record(context.materials, context.wet_fluid, p, w as u32, wall.material, normal, v_rel, context.time)
                    }
                };
                let constants = context.materials.constants(p.material, wall.material, p.radius(), f64::INFINITY, p.mass(), f64::INFINITY);
                let force = hertz_mindlin_force(&constants, record.damping_ratio, normal, overlap, v_rel, &mut record.tangential_overlap, context.dt);
                record.normal = normal;
                if context.sliding_walls[w] {
                    impacts.extend(sliding_impact(&mut record, p, w as u32, &contact, body, wall_velocity, normal, force.normal, context.dt, context.time));
                }
                let elastic = 0.4 * force.normal.norm() * overlap;
                watch.elastic_energy += elastic;
                if new_contact && fed {
                    watch.new_contact_energy += elastic;
                }
                watch.wall_power += (force.normal + force.tangential).dot(&wall_velocity);
                p.contact_force += force.normal + force.tangential;
                p.contact_torque += (p.radius() * normal).cross(&force.tangential);
                p.contacts += 1;
                samples.push(ContactSample { particle: p.id, partner: key.1, radius: p.radius(), overlap, normal, force, triangle: Some(contact.triangle) });
                history.entry(key).or_default().push(record);
            }
        }
    }
    samples
}
