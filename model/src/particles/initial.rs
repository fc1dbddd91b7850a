//! Builds the initial particle state from `[particles]`.

use super::random::SplitMix64;
use super::settings::{BoxRegion, Diameter, GroupSection, ParticlesSection};
use super::state::{Particle, ParticleCounts, ParticleState, Vec3};
use crate::case::{Case, FieldError};

/// Attempts per particle before random placement gives up.
const PLACEMENT_ATTEMPTS: usize = 10_000;

/// The particles at t = 0, ids 0, 1, 2… in group order.
pub fn initial_state(case: &Case) -> Result<ParticleState, FieldError> {
    initial_state_by_group(case).map(|(state, _)| state)
}

/// [`initial_state`] and, per group, the end of its particles in the list (group g made
/// particles `ends[g - 1]..ends[g]`).
pub fn initial_state_by_group(case: &Case) -> Result<(ParticleState, Vec<usize>), FieldError> {
    let mut ends = Vec::new();
    let Some(section) = &case.particles else {
        return Err(FieldError::new("particles", "(missing)", "a [particles] section"));
    };
    let mut state = ParticleState {
        feed_debt: vec![0.0; section.feed.len()],
        feed_random: section.feed.iter().map(|f| SplitMix64::new(f.seed)).collect(),
        ..Default::default()
    };
    // batches placed later are checked here, placed by the step driver
    let later = super::batch::later_batches(case)?;
    super::batch::check_later_batches(case, &later)?;
    for (g, group) in section.groups.iter().enumerate() {
        let key = format!("particles.groups.{g}");
        if later.iter().any(|b| b.group == g) {
            ends.push(state.particles.len());
            continue;
        }
        if let GroupSection::HeadLattice { .. } = group {
            let head =
                case.cutter_head.as_ref().ok_or_else(|| FieldError::new(format!("{key}.placement"), "\"head_lattice\"", "a case with a [cutter_head]"))?;
            let omega = case.rotor.as_ref().map_or(0.0, |r| r.angular_velocity());
            add_head_lattice(section, group, &key, &crate::cutter_head::CutterHead::new(head), omega, HeadPose::AT_START, &mut state)?;
        } else {
            add_group(section, group, &key, &mut state)?;
        }
        ends.push(state.particles.len());
    }
    state.counts = ParticleCounts { created: state.particles.len() as u64, impacts: 0 };
    Ok((state, ends))
}

fn draw_diameter(diameter: &Diameter, random: &mut SplitMix64) -> f64 {
    match diameter {
        Diameter::Fixed(d) => *d,
        Diameter::Uniform { min, max } => random.uniform(*min, *max),
    }
}

/// A particle at rest with the given material, diameter and position (id from the state).
pub fn new_particle(section: &ParticlesSection, state: &mut ParticleState, material: usize, diameter: f64, position: Vec3, velocity: Vec3) -> Particle {
    let id = state.next_id;
    state.next_id += 1;
    Particle {
        id,
        material,
        diameter,
        density: section.materials[material].density,
        position,
        velocity,
        spin: Vec3::zeros(),
        contact_force: Vec3::zeros(),
        contact_torque: Vec3::zeros(),
        contacts: 0,
    }
}

/// A random centre in `region` for a sphere of `diameter` lying fully inside it, overlapping
/// none of `existing` and accepted by `clear(centre, radius)`, or `None` after
/// [`PLACEMENT_ATTEMPTS`] tries.
pub fn place_without_overlap(
    region: &BoxRegion,
    diameter: f64,
    existing: &[Particle],
    random: &mut SplitMix64,
    clear: impl Fn(&Vec3, f64) -> bool,
) -> Option<Vec3> {
    let r = 0.5 * diameter;
    if (0..3).any(|k| region.max[k] - region.min[k] < diameter) {
        return None;
    }
    for _ in 0..PLACEMENT_ATTEMPTS {
        let p = Vec3::new(
            random.uniform(region.min[0] + r, region.max[0] - r),
            random.uniform(region.min[1] + r, region.max[1] - r),
            random.uniform(region.min[2] + r, region.max[2] - r),
        );
        if existing.iter().all(|q| (q.position - p).norm() >= r + q.radius()) && clear(&p, r) {
            return Some(p);
        }
    }
    None
}

/// Where a head's blades stand when a `head_lattice` batch is placed, and what else is there.
#[derive(Clone, Copy, Debug)]
pub struct HeadPose {
    /// The rotor angle [rad] (0 at t = 0).
    pub angle: f64,
    /// Whether sites overlapping particles already in the state are left out (a batch placed
    /// into a running head); at the start an overlap between groups is the case's error, which
    /// `spillage check` names.
    pub skip_occupied: bool,
}

impl HeadPose {
    /// A batch at t = 0: the blades at their reference angle, nothing else placed yet.
    pub const AT_START: HeadPose = HeadPose { angle: 0.0, skip_occupied: false };
}

/// The sites of a `head_lattice` group that lie inside the hull, in the sector (lab frame) and
/// clear of the head's solids with the blades at `pose.angle`, in z, y, x order; returns how
/// many were placed.
pub fn add_head_lattice(
    section: &ParticlesSection,
    group: &GroupSection,
    key: &str,
    head: &crate::cutter_head::CutterHead,
    omega: f64,
    pose: HeadPose,
    state: &mut ParticleState,
) -> Result<usize, FieldError> {
    let GroupSection::HeadLattice { material, diameter, spacing, sector, z, co_rotating, seed, .. } = group else { unreachable!("called for head lattices") };
    let material = section.material_index(material).ok_or_else(|| FieldError::new(format!("{key}.material"), material, "a known material"))?;
    let mut random = SplitMix64::new(*seed);
    let a = 0.5 * diameter.largest();
    let reach = head.contour().iter().map(|p| p.1).fold(0.0, f64::max);
    let n_xy = (reach / spacing).ceil() as i64;
    let (k0, k1) = ((z[0] / spacing).ceil() as i64, (z[1] / spacing).floor() as i64);
    let from = sector[0].to_radians();
    let width = (sector[1] - sector[0]).to_radians();
    let before = state.particles.len();
    for k in k0..=k1 {
        for iy in -n_xy..=n_xy {
            for ix in -n_xy..=n_xy {
                let p = Vec3::new(ix as f64 * spacing, iy as f64 * spacing, k as f64 * spacing);
                let (r, theta) = (p.x.hypot(p.y), p.y.atan2(p.x));
                let in_sector = (theta - from).rem_euclid(std::f64::consts::TAU) <= width;
                let inside = head.inside_hull(r + a, p.z) && head.inside_hull(r, p.z - a) && p.z + a <= 0.0;
                let free = || !pose.skip_occupied || state.particles.iter().all(|q| (q.position - p).norm() >= a + q.radius());
                if in_sector && inside && head.sphere_is_clear(r, theta - pose.angle, p.z, a) && free() {
                    let d = draw_diameter(diameter, &mut random);
                    let v = if *co_rotating { Vec3::new(-omega * p.y, omega * p.x, 0.0) } else { Vec3::zeros() };
                    let particle = new_particle(section, state, material, d, p, v);
                    state.particles.push(particle);
                }
            }
        }
    }
    if state.particles.len() == before {
        return Err(FieldError::new(format!("{key}.sector"), format!("{sector:?} with z = {z:?}"), "a region of the head with room for at least one particle"));
    }
    Ok(state.particles.len() - before)
}

fn add_group(section: &ParticlesSection, group: &GroupSection, key: &str, state: &mut ParticleState) -> Result<(), FieldError> {
    let material = section.material_index(group.material()).ok_or_else(|| FieldError::new(format!("{key}.material"), group.material(), "a known material"))?;
    match group {
        GroupSection::List { diameter, positions, velocities, spins, seed, .. } => {
            let mut random = SplitMix64::new(*seed);
            for (i, p) in positions.iter().enumerate() {
                let d = draw_diameter(diameter, &mut random);
                let v = velocities.get(i).map(|v| Vec3::from(*v)).unwrap_or_else(Vec3::zeros);
                let mut particle = new_particle(section, state, material, d, Vec3::from(*p), v);
                if let Some(w) = spins.get(i) {
                    particle.spin = Vec3::from(*w);
                }
                state.particles.push(particle);
            }
        }
        GroupSection::Lattice { diameter, region, spacing, velocity, seed, .. } => {
            let mut random = SplitMix64::new(*seed);
            let count = |k: usize| ((region.max[k] - region.min[k]) / spacing + 1e-9).floor() as usize;
            for iz in 0..count(2) {
                for iy in 0..count(1) {
                    for ix in 0..count(0) {
                        let p = Vec3::new(
                            region.min[0] + (ix as f64 + 0.5) * spacing,
                            region.min[1] + (iy as f64 + 0.5) * spacing,
                            region.min[2] + (iz as f64 + 0.5) * spacing,
                        );
                        let d = draw_diameter(diameter, &mut random);
                        let particle = new_particle(section, state, material, d, p, Vec3::from(*velocity));
                        state.particles.push(particle);
                    }
                }
            }
        }
        GroupSection::HeadLattice { .. } => unreachable!("placed by add_head_lattice"),
        GroupSection::Random { diameter, region, count, velocity, seed, .. } => {
            let mut random = SplitMix64::new(*seed);
            for placed in 0..*count {
                let d = draw_diameter(diameter, &mut random);
                let p = place_without_overlap(region, d, &state.particles, &mut random, |_, _| true).ok_or_else(|| {
                    FieldError::new(format!("{key}.count"), count, format!("a count that fits the region without overlap (only {placed} could be placed)"))
                })?;
                let particle = new_particle(section, state, material, d, p, Vec3::from(*velocity));
                state.particles.push(particle);
            }
        }
    }
    Ok(())
}
