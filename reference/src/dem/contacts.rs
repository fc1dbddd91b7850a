//! Contact detection and forces for one DEM sub-step (fluid-dem-model.md §7.8).

use std::collections::BTreeMap;

use spillage_model::closure::contact::{damping_ratio, hertz_mindlin_force, ContactForce};
use spillage_model::closure::restitution::{stokes_number, wet_restitution};
use spillage_model::particles::state::Vec3;
use spillage_model::particles::{ContactRecord, ImpactRecord, Particle, Partner};
use spillage_model::walls::geometry::WallMesh;
use spillage_model::walls::state::Wall;

use super::materials::MaterialTable;
use super::neighbours::overlapping_pairs;

/// Two wall contacts of one particle are the same contact when their normals differ by less
/// than 45° (a sphere rolling across a triangle edge keeps its tangential spring).
const SAME_WALL_CONTACT_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;

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
    /// Time at the end of the sub-step [s] (stamps new contacts and impacts).
    pub time: f64,
    pub dt: f64,
}

impl Context<'_> {
    /// α_η of a new contact (§7.8 step 3): ε_wet from St_AM at first touch when wet (T3.103–104),
    /// else ε_dry; then (T3.101).
    fn damping_ratio(&self, dry_restitution: f64, approach_speed: f64, density: f64, diameter: f64) -> f64 {
        let restitution = match self.wet_fluid {
            Some((rho_f, nu)) => wet_restitution(dry_restitution, stokes_number(density, rho_f, approach_speed.max(0.0), diameter, nu)),
            None => dry_restitution,
        };
        damping_ratio(restitution)
    }
}

/// Evaluates every contact: sets each particle's contact force, torque and count, updates the
/// history (new records at first touch, records of ended contacts dropped) and appends the
/// impacts of new wall contacts. Returns the contact samples.
pub fn evaluate(
    context: &Context,
    particles: &mut [Particle],
    history: &mut BTreeMap<(u64, Partner), Vec<ContactRecord>>,
    impacts: &mut Vec<ImpactRecord>,
) -> Vec<ContactSample> {
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
        if distance == 0.0 {
            continue; // coincident centres: no normal direction
        }
        let normal = offset / distance;
        let overlap = a.radius() + b.radius() - distance;
        // §7.8 step 2: relative velocity of the contact point.
        let v_rel = a.velocity + a.spin.cross(&(a.radius() * normal)) - (b.velocity + b.spin.cross(&(-b.radius() * normal)));
        let key = (a.id, Partner::Particle(b.id));
        let mut record = match old.remove(&key).and_then(|mut v| v.pop()) {
            Some(r) => r,
            None => {
                let approach = v_rel.dot(&normal);
                let pair = &context.materials.pairs[a.material][b.material];
                // [R] St_AM of unequal particles (unspecified, §7.5): mean density and the
                // harmonic-mean diameter; both reduce to the particle's own for identical spheres.
                let density = 0.5 * (a.density + b.density);
                let diameter = 2.0 * a.diameter * b.diameter / (a.diameter + b.diameter);
                ContactRecord {
                    particle: a.id,
                    partner: key.1,
                    tangential_overlap: Vec3::zeros(),
                    damping_ratio: context.damping_ratio(pair.dry_restitution, approach, density, diameter),
                    approach_speed: approach,
                    normal,
                    start_time: context.time,
                }
            }
        };
        let constants = context.materials.constants(a.material, b.material, a.radius(), b.radius(), a.mass(), b.mass());
        let force = hertz_mindlin_force(&constants, record.damping_ratio, normal, overlap, v_rel, &mut record.tangential_overlap, context.dt);
        record.normal = normal;
        let (ra, rb) = (a.radius(), b.radius());
        let total = force.normal + force.tangential;
        // §7.8 steps 6–7.
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
            let found = mesh.sphere_contacts(wall.to_body(p.position), p.radius());
            for contact in found {
                let point = wall.to_world(contact.point);
                if contact.distance <= 1e-12 * p.radius() {
                    continue; // centre on the wall surface: no normal direction
                }
                let normal = (point - p.position) / contact.distance;
                let overlap = p.radius() - contact.distance;
                let wall_velocity = wall.surface_velocity(point);
                let v_rel = p.velocity + p.spin.cross(&(p.radius() * normal)) - wall_velocity;
                let matched = previous
                    .iter()
                    .enumerate()
                    .map(|(k, r)| (k, r.normal.dot(&normal)))
                    .filter(|(_, cos)| *cos > SAME_WALL_CONTACT_COS)
                    .max_by(|x, y| x.1.total_cmp(&y.1))
                    .map(|(k, _)| k);
                let mut record = match matched {
                    Some(k) => previous.remove(k),
                    None => {
                        let approach = v_rel.dot(&normal);
                        let pair = &context.materials.pairs[p.material][wall.material];
                        let centre_velocity = p.velocity - wall_velocity;
                        let normal_speed = centre_velocity.dot(&normal);
                        let tangential_speed = (centre_velocity - normal_speed * normal).norm();
                        impacts.push(ImpactRecord {
                            particle: p.id,
                            wall: w as u32,
                            triangle: contact.triangle,
                            time: context.time,
                            normal_speed,
                            tangential_speed,
                            angle: normal_speed.atan2(tangential_speed),
                            mass: p.mass(),
                            diameter: p.diameter,
                            density: p.density,
                            point: contact.point,
                            normal: (contact.point - wall.to_body(p.position)) / contact.distance,
                        });
                        ContactRecord {
                            particle: p.id,
                            partner: key.1,
                            tangential_overlap: Vec3::zeros(),
                            damping_ratio: context.damping_ratio(pair.dry_restitution, approach, p.density, p.diameter),
                            approach_speed: approach,
                            normal,
                            start_time: context.time,
                        }
                    }
                };
                let constants = context.materials.constants(p.material, wall.material, p.radius(), f64::INFINITY, p.mass(), f64::INFINITY);
                let force = hertz_mindlin_force(&constants, record.damping_ratio, normal, overlap, v_rel, &mut record.tangential_overlap, context.dt);
                record.normal = normal;
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
