//! Initial placements that overlap a wall or another particle are refused before a run (issue
//! 14 item 4: a sphere started with its centre on a wall took the kinetic energy from 6.6e-4 J
//! to 2 111 J in one step; two spheres at one position ran with no contact at all).

use std::collections::HashMap;
use std::path::Path;

use super::initial::initial_state_by_group;
use super::settings::GroupSection;
use crate::case::{Case, FieldError};
use crate::walls::geometry::WallMesh;

/// Overlap allowed at t = 0, as a fraction of the smaller radius: round-off of spheres placed
/// exactly touching (a lattice at spacing = diameter, a sphere at z = r on a plane) is ~1e-16
/// of the coordinates; a millionth leaves room for coordinates written with 7 digits.
pub const TOUCHING: f64 = 1e-6;
/// Most particles whose placement is examined: random groups place in O(n²) (a check of a case
/// with more is skipped and says so).
pub const CHECKED_MAX: f64 = 5000.0;

/// Particles a case's groups will place, estimated from their sizes (without placing them).
pub fn estimated_count(case: &Case) -> f64 {
    let Some(p) = &case.particles else { return 0.0 };
    p.groups
        .iter()
        .map(|g| match g {
            GroupSection::List { positions, .. } => positions.len() as f64,
            GroupSection::Lattice { region, spacing, .. } => (0..3).map(|k| ((region.max[k] - region.min[k]) / spacing).floor().max(0.0) + 1.0).product(),
            GroupSection::Random { count, .. } => *count as f64,
            GroupSection::HeadLattice { spacing, sector, z, .. } => {
                let reach = case.cutter_head.as_ref().map_or(0.0, |h| h.contour.iter().map(|c| c[1]).fold(0.0, f64::max));
                std::f64::consts::PI * reach * reach * (z[1] - z[0]).abs() * ((sector[1] - sector[0]) / 360.0) / spacing.powi(3)
            }
        })
        .sum()
}

/// Where particle `index` of the initial list came from, as a key.
fn key_of(case: &Case, ends: &[usize], index: usize) -> String {
    let g = ends.iter().position(|&end| index < end).unwrap_or(0);
    let start = if g == 0 { 0 } else { ends[g - 1] };
    match case.particles.as_ref().map(|p| &p.groups[g]) {
        Some(GroupSection::List { .. }) => format!("particles.groups.{g}.positions.{}", index - start),
        _ => format!("particles.groups.{g}"),
    }
}

/// Refuses initial particles that overlap a wall or each other by more than [`TOUCHING`];
/// returns how many were examined, `None` when more than [`CHECKED_MAX`] would be placed.
/// Walls are built from `case_dir` (STL files) at their t = 0 pose.
pub fn check_initial_placement(case: &Case, case_dir: &Path) -> Result<Option<usize>, FieldError> {
    if case.particles.is_none() {
        return Ok(Some(0));
    }
    if estimated_count(case) > CHECKED_MAX {
        return Ok(None);
    }
    let (state, ends) = initial_state_by_group(case)?;
    let particles = &state.particles;
    let at = |i: usize| {
        let p = &particles[i].position;
        format!("[{:.6e}, {:.6e}, {:.6e}]", p.x, p.y, p.z)
    };
    // particle pairs, through a grid of cells one largest diameter wide
    let size = particles.iter().map(|p| p.diameter).fold(0.0, f64::max);
    let cell = |i: usize| {
        let p = &particles[i].position;
        [(p.x / size).floor() as i64, (p.y / size).floor() as i64, (p.z / size).floor() as i64]
    };
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for i in 0..particles.len() {
        grid.entry(cell(i)).or_default().push(i);
    }
    for i in 0..particles.len() {
        let c = cell(i);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    for &j in grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]).map_or(&[][..], |v| v.as_slice()) {
                        if j <= i {
                            continue;
                        }
                        let (a, b) = (&particles[i], &particles[j]);
                        let distance = (a.position - b.position).norm();
                        let overlap = a.radius() + b.radius() - distance;
                        if overlap > TOUCHING * a.radius().min(b.radius()) {
                            let what = if distance == 0.0 { "at the same position as".to_string() } else { format!("overlapping by {overlap:.3e} m") };
                            return Err(FieldError::new(
                                key_of(case, &ends, i),
                                format!("(particle {} at {} m {what} particle {} at {} m, `{}`)", a.id, at(i), b.id, at(j), key_of(case, &ends, j)),
                                "initial particles that do not overlap each other",
                            ));
                        }
                    }
                }
            }
        }
    }
    let walls = crate::walls::build(case, case_dir).map_err(|e| match e {
        crate::walls::WallError::Field(f) => f,
        crate::walls::WallError::Geometry { wall, message } => {
            let i = case.walls.iter().position(|w| w.name == wall).unwrap_or(0);
            FieldError::new(format!("walls.{i}.shape"), format!("({message})"), "a wall shape that can be built")
        }
    })?;
    for (w, wall) in walls.walls.iter().enumerate() {
        let mesh =
            WallMesh::new(&wall.vertices, &wall.triangles).map_err(|m| FieldError::new(format!("walls.{w}.shape"), format!("({m})"), "a valid wall mesh"))?;
        for (i, p) in particles.iter().enumerate() {
            let r = p.radius();
            if let Some(c) = mesh.sphere_contacts(wall.to_body(p.position), r).iter().find(|c| r - c.distance > TOUCHING * r) {
                return Err(FieldError::new(
                    key_of(case, &ends, i),
                    format!("(particle {} at {} m, radius {r:e} m, its centre {:.3e} m from wall `{}`)", p.id, at(i), c.distance, wall.name),
                    "initial particles clear of the walls (centre at least one radius from every wall)",
                ));
            }
        }
    }
    Ok(Some(particles.len()))
}
