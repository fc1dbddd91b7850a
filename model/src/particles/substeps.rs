//! How many DEM sub-steps an outer step takes (fluid-dem-model.md §7.6, T3.105–T3.106), the
//! same for both particle phases.

use super::materials::MaterialTable;
use super::settings::ParticlesSection;
use super::state::Particle;
use crate::closure::collision_time::{collision_time, substeps};
use crate::walls::state::WallState;

/// Worst-case collision time (T3.105 as OpenFOAM evaluates it, §7.6): smallest radius,
/// largest density, stiffest pair, largest speed |u| + |ω| r (plus the fastest wall
/// surface), never below `collision_speed`; for pairs R = d_min/4 and the speed doubled.
pub fn worst_collision_time(section: &ParticlesSection, materials: &MaterialTable, particles: &[Particle], walls: &WallState) -> f64 {
    if particles.is_empty() {
        return f64::INFINITY;
    }
    let d_min = particles.iter().map(|p| p.diameter).fold(f64::INFINITY, f64::min);
    let rho_max = particles.iter().map(|p| p.density).fold(0.0, f64::max);
    let speed_max = particles.iter().map(|p| p.velocity.norm() + p.spin.norm() * p.radius()).fold(0.0, f64::max);
    let wall_speed = walls.walls.iter().flat_map(|w| w.vertices.iter().map(move |v| w.surface_velocity(w.to_world(*v)).norm())).fold(0.0, f64::max);
    let e_star = materials.stiffest();
    let wall_contact = collision_time(rho_max, e_star, 0.5 * d_min, (speed_max + wall_speed).max(section.collision_speed));
    let pair_contact = collision_time(rho_max, e_star, 0.25 * d_min, (2.0 * speed_max).max(section.collision_speed));
    wall_contact.min(pair_contact)
}

/// Number of sub-steps for an outer step `dt` (T3.106, or the fixed `particles.substep`).
pub fn substeps_for(section: &ParticlesSection, materials: &MaterialTable, dt: f64, particles: &[Particle], walls: &WallState) -> u64 {
    match section.substep {
        Some(fixed) => substeps(dt, fixed, 1.0),
        None => substeps(dt, worst_collision_time(section, materials, particles, walls), section.steps_per_collision),
    }
}
