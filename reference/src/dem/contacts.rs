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

/// Largest overlap of a contact as a fraction of the particle's radius (of the smaller one for
/// a pair). Hertz's law assumes overlaps far below the radius (≲ 1 %); the softened rock of the
/// thesis' cutter runs (E = 10 MPa) reaches ≈ 30 % in a 5 m/s impact (measured: 9 % at the
/// end of steps of the fed cutter head). At half the radius the contact circle is 70 % of the
/// sphere's and the model means nothing: a particle started inside a wall or tunnelling
/// through another, which a run must not finish as `completed` (issue 14 item 4). Particles
/// fed in the step are exempt for that step: a feed outside a cutter head does not avoid the
/// walls, and places a particle up to its radius into a turning blade (one_way_rotor.toml puts
/// one 60 % in at step 17); its push out is the feed's doing.
pub const MAX_OVERLAP_RATIO: f64 = 0.5;

/// What makes a sub-step's contacts meaningless: the first one found stops the run.
#[derive(Clone, Debug, PartialEq)]
pub enum Fault {
    /// Two particle centres at one point: no contact normal exists.
    Coincident { particle: u64, other: u64, position: Vec3 },
    /// A particle's centre on a wall's surface: no contact normal exists.
    CentreOnWall { particle: u64, wall: u32, position: Vec3 },
    /// An overlap beyond [`MAX_OVERLAP_RATIO`] of the radius.
    Overlap { particle: u64, partner: Partner, ratio: f64, position: Vec3 },
}

impl Fault {
    /// In words, the walls by their names.
    pub fn describe(&self, walls: &[Wall]) -> String {
        let at = |p: &Vec3| format!("[{:e}, {:e}, {:e}] m", p.x, p.y, p.z);
        let wall = |w: &u32| walls.get(*w as usize).map_or(format!("wall {w}"), |x| format!("wall `{}`", x.name));
        match self {
            Fault::Coincident { particle, other, position } => {
                format!("particles {particle} and {other} have their centres at the same point {} (no contact direction)", at(position))
            }
            Fault::CentreOnWall { particle, wall: w, position } => format!("particle {particle} at {} has its centre on {} (no contact direction)", at(position), wall(w)),
            Fault::Overlap { particle, partner, ratio, position } => format!(
                "particle {particle} at {} overlaps {} by {ratio:.3} of its radius (at most {MAX_OVERLAP_RATIO}: started inside it, or a step too long for the collision)",
                at(position),
                match partner {
                    Partner::Particle(id) => format!("particle {id}"),
                    Partner::Wall(w) => wall(w),
                }
            ),
        }
    }
}

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
        if distance == 0.0 {
            // coincident centres: no normal direction
            watch.fault.get_or_insert(Fault::Coincident { particle: a.id, other: b.id, position: a.position });
            continue;
        }
        let normal = offset / distance;
        let overlap = a.radius() + b.radius() - distance;
        let fed = a.id >= context.fed_from || b.id >= context.fed_from;
        if overlap > MAX_OVERLAP_RATIO * a.radius().min(b.radius()) && watch.fault.is_none() && !fed {
            let (small, other) = if a.radius() <= b.radius() { (a, b) } else { (b, a) };
            watch.fault =
                Some(Fault::Overlap { particle: small.id, partner: Partner::Particle(other.id), ratio: overlap / small.radius(), position: small.position });
        }
        // §7.8 step 2: relative velocity of the contact point.
        let v_rel = a.velocity + a.spin.cross(&(a.radius() * normal)) - (b.velocity + b.spin.cross(&(-b.radius() * normal)));
        let key = (a.id, Partner::Particle(b.id));
        let existing = old.remove(&key).and_then(|mut v| v.pop());
        let new_contact = existing.is_none();
        let mut record = match existing {
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
            let found = mesh.sphere_contacts(wall.to_body(p.position), p.radius());
            for contact in found {
                let point = wall.to_world(contact.point);
                if contact.distance <= 1e-12 * p.radius() {
                    // centre on the wall surface: no normal direction
                    watch.fault.get_or_insert(Fault::CentreOnWall { particle: p.id, wall: w as u32, position: p.position });
                    continue;
                }
                let normal = (point - p.position) / contact.distance;
                let overlap = p.radius() - contact.distance;
                let fed = p.id >= context.fed_from;
                if overlap > MAX_OVERLAP_RATIO * p.radius() && watch.fault.is_none() && !fed {
                    watch.fault = Some(Fault::Overlap { particle: p.id, partner: key.1, ratio: overlap / p.radius(), position: p.position });
                }
                let wall_velocity = wall.surface_velocity(point);
                let v_rel = p.velocity + p.spin.cross(&(p.radius() * normal)) - wall_velocity;
                let matched = previous
                    .iter()
                    .enumerate()
                    .map(|(k, r)| (k, r.normal.dot(&normal)))
                    .filter(|(_, cos)| *cos > SAME_WALL_CONTACT_COS)
                    .max_by(|x, y| x.1.total_cmp(&y.1))
                    .map(|(k, _)| k);
                let new_contact = matched.is_none();
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
