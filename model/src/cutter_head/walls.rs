//! The cutter head's solids as closed triangle meshes for the DEM walls, in the head's body
//! frame (spillage-and-flow-verification.md §2.11; the shapes are those of [`CutterHead`], the
//! same the fluid mesh blocks with [`CutterHead::touches_solid`]).
//!
//! * `blade_1` … `blade_N`: a thin closed solid per blade. Its two faces are the centre surface
//!   θ_k(r, z) turned by ± [`CutterHead::blade_half_angle`] along the circles (half the
//!   thickness normal to the blade in a horizontal section, as the fluid mesh blocks it; where
//!   the twist or the contour's slope tilts the blade, it is thinner normal to its surface, by
//!   up to 18 % in the shipped head), for r from the blade's inner radius to the contour R(z)
//!   and z from the hub (−H) to the ring (0); strips along the inner and outer edges, the top
//!   and the bottom close it.
//! * `ring`, `hub`, `pipe`: the plates of [`CutterHead::plates`], each a closed polygonal annulus.
//! * `shaft`: the side of the shaft cylinder from the tank floor to the top of the pipe.
//! * `back_plate` (an eccentric mouth's head, [`stationary_walls`]): the underside of the back
//!   plate at rest, an open annulus at z = 0 from the shaft to the ring with the mouth cut out;
//!   a particle that passes the mouth has been sucked.
//!
//! Every closed part has outward normals (counter-clockwise seen from outside).

use std::f64::consts::TAU;

use super::geometry::{CutterHead, Part};
use super::mouth::EccentricMouth;
use super::settings::CutterHeadSection;
use crate::walls::geometry::{cylinder, TriangleMesh};
use crate::walls::state::Vec3;

/// Fewest blade segments along z and along r, so that a coarse `triangle_size` still follows
/// the twist and the log spiral.
const MIN_BLADE_Z_SEGMENTS: usize = 8;
const MIN_BLADE_RADIAL_SEGMENTS: usize = 4;
/// Fewest segments around a circle: the polygon then lies within 1 − cos(π/16) ≈ 2 % of the
/// radius of the circle.
const MIN_CIRCLE_SEGMENTS: usize = 16;

/// The walls of the head, named as in [`wall_name`], with triangles of about `triangle_size`
/// (blades, plates and pipe closed, the shaft a side surface).
pub fn head_walls(section: &CutterHeadSection, triangle_size: f64) -> Vec<(String, TriangleMesh)> {
    let head = CutterHead::new(section);
    let grid = BladeGrid::new(&head, triangle_size);
    let mut walls: Vec<(String, TriangleMesh)> = (0..head.blades).map(|k| (wall_name(Part::Blade(k)), blade(&head, k, &grid))).collect();
    for (part, r, z) in head.plates() {
        if part != Part::BackPlate {
            walls.push((wall_name(part), revolved_rectangle(r, z, triangle_size)));
        }
    }
    let floor = head.hub_bottom() - section.tank.below_hub;
    let length = head.pipe_top() - floor;
    let shaft = cylinder(
        Vec3::new(0.0, 0.0, floor),
        Vec3::z(),
        head.shaft_radius,
        length,
        circle_segments(head.shaft_radius, triangle_size) as u32,
        pieces(length, triangle_size) as u32,
    );
    walls.push(("shaft".to_string(), shaft));
    walls
}

/// The walls of the head at rest (the back plate of an eccentric mouth), with triangles of about
/// `triangle_size`.
pub fn stationary_walls(section: &CutterHeadSection, triangle_size: f64) -> Vec<(String, TriangleMesh)> {
    let head = CutterHead::new(section);
    head.mouth.map(|mouth| (wall_name(Part::BackPlate), back_plate(&head, &mouth, triangle_size))).into_iter().collect()
}

/// The names [`head_walls`] and then [`stationary_walls`] give their walls, in their order,
/// without building them.
pub fn head_wall_names(section: &CutterHeadSection) -> Vec<String> {
    let head = CutterHead::new(section);
    let mut names: Vec<String> = (0..head.blades).map(|k| wall_name(Part::Blade(k))).collect();
    names.extend(head.plates().into_iter().filter(|(part, _, _)| *part != Part::BackPlate).map(|(part, _, _)| wall_name(part)));
    names.push("shaft".to_string());
    if head.mouth.is_some() {
        names.push(wall_name(Part::BackPlate));
    }
    names
}

/// `blade_1` … `blade_N`, `ring`, `hub`, `pipe`.
pub fn wall_name(part: Part) -> String {
    match part {
        Part::Blade(k) => format!("blade_{}", k + 1),
        Part::Ring => "ring".to_string(),
        Part::Hub => "hub".to_string(),
        Part::Pipe => "pipe".to_string(),
        Part::BackPlate => "back_plate".to_string(),
    }
}

/// Pieces of at most `size` along `length` (at least one).
fn pieces(length: f64, size: f64) -> usize {
    ((length / size).ceil() as usize).max(1)
}

fn circle_segments(radius: f64, triangle_size: f64) -> usize {
    pieces(TAU * radius, triangle_size).max(MIN_CIRCLE_SEGMENTS)
}

fn cylindrical(r: f64, theta: f64, z: f64) -> Vec3 {
    Vec3::new(r * theta.cos(), r * theta.sin(), z)
}

/// Where a blade's grid lines lie: heights from the hub to the ring, and a number of equal
/// steps from the inner radius to the contour at each height (the same for every blade).
struct BladeGrid {
    z: Vec<f64>,
    radial_segments: usize,
}

impl BladeGrid {
    /// The contour points, and the height where the inner radius R − depth meets the shaft, are
    /// grid heights (R, φ and the inner radius have kinks only there). Between them, steps of
    /// at most `triangle_size` along the outer edge (a chord that includes the twist); radially,
    /// steps of at most `triangle_size` along the spiral, whose length from r₀ to r₁ is
    /// (r₁ − r₀) / sin φ since it crosses every circle at φ.
    fn new(head: &CutterHead, triangle_size: f64) -> BladeGrid {
        let height = head.height();
        let contour = head.contour();
        let mut kinks: Vec<f64> = contour.iter().map(|p| -p.0).collect();
        let reach = head.shaft_radius + head.blade_depth;
        for pair in contour.windows(2) {
            let ((s0, r0, _), (s1, r1, _)) = (pair[0], pair[1]);
            if (r0 - reach) * (r1 - reach) < 0.0 {
                kinks.push(-(s0 + (s1 - s0) * (reach - r0) / (r1 - r0)));
            }
        }
        kinks.sort_by(f64::total_cmp);
        let outer_edge = |z: f64| {
            let r = head.radius_at(z);
            cylindrical(r, head.blade_azimuth(0, r, z), z)
        };
        let mut z = vec![kinks[0]];
        for pair in kinks.windows(2) {
            let (z0, z1) = (pair[0], pair[1]);
            let steps = pieces((outer_edge(z1) - outer_edge(z0)).norm(), triangle_size).max((MIN_BLADE_Z_SEGMENTS as f64 * (z1 - z0) / height).ceil() as usize);
            z.extend((1..=steps).map(|i| z0 + (z1 - z0) * i as f64 / steps as f64));
        }
        let longest_spiral = z.iter().map(|&z| (head.radius_at(z) - head.blade_inner_radius(z)) / head.blade_angle_at(z).sin()).fold(0.0, f64::max);
        BladeGrid { z, radial_segments: pieces(longest_spiral, triangle_size).max(MIN_BLADE_RADIAL_SEGMENTS) }
    }

    fn radius(&self, head: &CutterHead, i: usize, z: f64) -> f64 {
        let (inner, outer) = (head.blade_inner_radius(z), head.radius_at(z));
        inner + (outer - inner) * i as f64 / self.radial_segments as f64
    }
}

/// Blade `k` as a closed thin solid. Vertices: two faces (behind and ahead of the centre surface
/// in θ), each a grid of `radial_segments + 1` radii by the grid heights. On the face behind, the
/// grid's (r, z) order gives normals toward −θ, out of the blade; the face ahead takes the
/// reverse order. The strips joining the faces' boundaries follow the face behind's boundary
/// backward, so every directed edge occurs once.
fn blade(head: &CutterHead, k: usize, grid: &BladeGrid) -> TriangleMesh {
    let (nr, nz) = (grid.radial_segments, grid.z.len() - 1);
    let mut mesh = TriangleMesh::default();
    for side in [-1.0, 1.0] {
        for &z in &grid.z {
            for i in 0..=nr {
                let r = grid.radius(head, i, z);
                mesh.vertices.push(cylindrical(r, head.blade_azimuth(k, r, z) + side * head.blade_half_angle(r, z), z));
            }
        }
    }
    let index = |ahead: bool, i: usize, j: usize| (usize::from(ahead) * (nz + 1) * (nr + 1) + j * (nr + 1) + i) as u32;
    for j in 0..nz {
        for i in 0..nr {
            let corners = |ahead| (index(ahead, i, j), index(ahead, i + 1, j), index(ahead, i + 1, j + 1), index(ahead, i, j + 1));
            let (a, b, c, d) = corners(false);
            mesh.triangles.extend([[a, b, c], [a, c, d]]);
            let (a, b, c, d) = corners(true);
            mesh.triangles.extend([[a, c, b], [a, d, c]]);
        }
    }
    // the boundary of the (i, j) grid, counter-clockwise: bottom (hub), outer edge, top (ring),
    // inner edge
    let boundary: Vec<(usize, usize)> =
        (0..nr).map(|i| (i, 0)).chain((0..nz).map(|j| (nr, j))).chain((1..=nr).rev().map(|i| (i, nz))).chain((1..=nz).rev().map(|j| (0, j))).collect();
    for (n, &(i0, j0)) in boundary.iter().enumerate() {
        let (i1, j1) = boundary[(n + 1) % boundary.len()];
        let (a, b) = (index(false, i0, j0), index(false, i1, j1));
        let (a_ahead, b_ahead) = (index(true, i0, j0), index(true, i1, j1));
        mesh.triangles.extend([[b, a, a_ahead], [b, a_ahead, b_ahead]]);
    }
    mesh
}

/// The back plate's underside: the annulus from the shaft to the ring's inner radius at z = 0
/// on a polar grid whose lines include the mouth's edges, without the grid cells of the mouth,
/// normals down into the head.
fn back_plate(head: &CutterHead, mouth: &EccentricMouth, triangle_size: f64) -> TriangleMesh {
    let split = |from: f64, to: f64, length: f64| {
        let n = pieces(length, triangle_size);
        (0..n).map(move |i| from + (to - from) * i as f64 / n as f64)
    };
    let [r1, r2] = mouth.radii;
    let rim = head.opening_radius;
    let mut radii: Vec<f64> = split(head.shaft_radius, r1, r1 - head.shaft_radius).chain(split(r1, r2, r2 - r1)).chain(split(r2, rim, rim - r2)).collect();
    radii.push(rim);
    let (start, width) = (mouth.angle - mouth.half_width, 2.0 * mouth.half_width);
    let open = pieces(width * r2, triangle_size).max(2);
    let closed = pieces((TAU - width) * rim, triangle_size).max(MIN_CIRCLE_SEGMENTS.saturating_sub(open));
    let angles: Vec<f64> = (0..open)
        .map(|j| start + width * j as f64 / open as f64)
        .chain((0..closed).map(|j| start + width + (TAU - width) * j as f64 / closed as f64))
        .collect();
    let n = angles.len();
    let mut mesh = TriangleMesh::default();
    for &theta in &angles {
        mesh.vertices.extend(radii.iter().map(|&r| cylindrical(r, theta, 0.0)));
    }
    let index = |i: usize, j: usize| ((j % n) * radii.len() + i) as u32;
    for j in 0..n {
        for i in 0..radii.len() - 1 {
            let in_mouth = j < open && radii[i] >= r1 && radii[i + 1] <= r2;
            if !in_mouth {
                let (a, b, c, d) = (index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
                mesh.triangles.extend([[a, c, b], [a, d, c]]);
            }
        }
    }
    mesh
}

/// The closed solid swept by the rectangle r ∈ `r`, z ∈ `z` of a meridian plane turned about
/// the z axis in flat steps: a polygonal annulus (its volume is exactly
/// ½ n sin(2π/n) (r₁² − r₀²) (z₁ − z₀) with n steps). The rectangle's sides are divided into
/// pieces of at most `triangle_size`, walked counter-clockwise in the (r, z) plane so that the
/// normals point out.
fn revolved_rectangle(r: [f64; 2], z: [f64; 2], triangle_size: f64) -> TriangleMesh {
    let segments = circle_segments(r[1], triangle_size);
    let corners = [(r[0], z[0]), (r[1], z[0]), (r[1], z[1]), (r[0], z[1])];
    let mut profile = Vec::new();
    for (n, &(r0, z0)) in corners.iter().enumerate() {
        let (r1, z1) = corners[(n + 1) % corners.len()];
        let steps = pieces((r1 - r0).hypot(z1 - z0), triangle_size);
        profile.extend((0..steps).map(|s| (r0 + (r1 - r0) * s as f64 / steps as f64, z0 + (z1 - z0) * s as f64 / steps as f64)));
    }
    let mut mesh = TriangleMesh::default();
    for &(radius, height) in &profile {
        mesh.vertices.extend((0..segments).map(|i| cylindrical(radius, TAU * i as f64 / segments as f64, height)));
    }
    let index = |p: usize, i: usize| ((p % profile.len()) * segments + i % segments) as u32;
    for p in 0..profile.len() {
        for i in 0..segments {
            let (a, b, c, d) = (index(p, i), index(p, i + 1), index(p + 1, i + 1), index(p + 1, i));
            mesh.triangles.extend([[a, b, c], [a, c, d]]);
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;
    use std::f64::consts::PI;

    use super::*;
    use crate::walls::geometry::WallMesh;
    use crate::walls::state::WallMotion;

    /// The target triangle size of the tests: a fine fluid cell.
    const SIZE: f64 = 0.02;

    fn case_text() -> String {
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../cases/cutter_head.toml")).unwrap()
    }

    fn section() -> CutterHeadSection {
        let case = crate::case::Case::from_toml(&case_text(), std::path::Path::new("cutter_head.toml")).unwrap();
        case.cutter_head.unwrap()
    }

    fn corners(mesh: &TriangleMesh, t: &[u32; 3]) -> [Vec3; 3] {
        t.map(|v| mesh.vertices[v as usize])
    }

    /// ∮ (x/3)·n dA by the divergence theorem: the sum of the tetrahedra origin–triangle.
    fn signed_volume(mesh: &TriangleMesh) -> f64 {
        mesh.triangles.iter().map(|t| corners(mesh, t)).map(|[a, b, c]| a.dot(&b.cross(&c)) / 6.0).sum()
    }

    /// The winding number of the closed mesh around `p`: the triangles' signed solid angles
    /// (Van Oosterom & Strackee) over 4π; 1 inside, 0 outside.
    fn winding_number(mesh: &TriangleMesh, p: Vec3) -> f64 {
        let solid_angle = |[a, b, c]: [Vec3; 3]| {
            let (a, b, c) = (a - p, b - p, c - p);
            let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
            2.0 * a.dot(&b.cross(&c)).atan2(la * lb * lc + a.dot(&b) * lc + a.dot(&c) * lb + b.dot(&c) * la)
        };
        mesh.triangles.iter().map(|t| solid_angle(corners(mesh, t))).sum::<f64>() / (4.0 * PI)
    }

    #[test]
    fn every_part_is_closed_oriented_outward_and_a_valid_wall_mesh() {
        let mut forward = section();
        forward.blade_sweep = crate::cutter_head::BladeSweep::Forward;
        let mut walls: Vec<(String, TriangleMesh)> = Vec::new();
        for (sweep, head) in [("backward", section()), ("forward", forward)] {
            walls.extend(head_walls(&head, SIZE).into_iter().map(|(name, mesh)| (format!("{name} ({sweep})"), mesh)));
        }
        for (name, mesh) in &walls {
            WallMesh::new(&mesh.vertices, &mesh.triangles).unwrap_or_else(|e| panic!("{name}: {e}"));
            if name.starts_with("shaft ") {
                continue;
            }
            let mut directed = HashMap::new();
            let mut undirected = HashMap::new();
            for t in &mesh.triangles {
                for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                    *directed.entry((a, b)).or_insert(0) += 1;
                    *undirected.entry((a.min(b), a.max(b))).or_insert(0) += 1;
                }
            }
            assert!(undirected.values().all(|&n| n == 2), "{name}: an edge not shared by exactly two triangles");
            assert!(directed.values().all(|&n| n == 1), "{name}: a directed edge twice (inconsistent orientation)");
            assert!(signed_volume(mesh) > 0.0, "{name}: normals point inward");
        }
    }

    #[test]
    fn the_plates_enclose_their_polygonal_annuli() {
        let section = section();
        let head = CutterHead::new(&section);
        let walls = head_walls(&section, SIZE);
        for (part, r, z) in head.plates() {
            let mesh = &walls.iter().find(|(name, _)| *name == wall_name(part)).unwrap().1;
            let n = circle_segments(r[1], SIZE) as f64;
            let polygon = 0.5 * n * (TAU / n).sin() * (r[1] * r[1] - r[0] * r[0]) * (z[1] - z[0]);
            let volume = signed_volume(mesh);
            // the annulus is bounded by flat faces: exact to round-off (1e-12 relative, sums of
            // ~10⁴ terms with coordinates from sin/cos)
            assert!((volume - polygon).abs() < 1e-12 * polygon, "{part:?}: {volume} vs {polygon}");
            // and the polygon falls short of the circle by 1 − sin(2π/n)/(2π/n) < (2π/n)²/6
            let circle = PI * (r[1] * r[1] - r[0] * r[0]) * (z[1] - z[0]);
            assert!(volume < circle && circle - volume < (TAU / n).powi(2) / 6.0 * circle, "{part:?}: {volume} vs {circle}");
        }
    }

    #[test]
    fn a_blade_holds_its_thickness_times_its_area() {
        let section = section();
        let head = CutterHead::new(&section);
        let walls = head_walls(&section, SIZE);
        let (t, h) = (head.blade_thickness, head.height());
        // Midpoint quadrature over (z, r) of the centre surface x(r, z) = (r cos θ, r sin θ, z),
        // θ = θ_k(r, z). Its area element is |x_r × x_z| = √(1 + (r θ_r)² + (r θ_z)²) dr dz. The
        // faces are ± t / (2 r sin φ) away in θ, so the volume between them is t / sin φ dr dz
        // (exact), and the blade is t_n = t / (sin φ √(1 + (r θ_r)² + (r θ_z)²)) thick normal
        // to the surface: t where the surface is vertical (θ_z = 0, as r θ_r = −cot φ), thinner where
        // the twist or the contour's slope tilts it.
        let (nz, nr) = (880, 200);
        let (mut area, mut volume) = (0.0, 0.0);
        let (mut thinnest, mut thickest) = (f64::INFINITY, 0.0_f64);
        for j in 0..nz {
            let z = -h + h * (j as f64 + 0.5) / nz as f64;
            let (inner, outer) = (head.blade_inner_radius(z), head.radius_at(z));
            let (dz, dr) = (h / nz as f64, (outer - inner) / nr as f64);
            for i in 0..nr {
                let r = inner + dr * (i as f64 + 0.5);
                let e = 1e-6;
                let theta_r = (head.blade_azimuth(0, r + e, z) - head.blade_azimuth(0, r - e, z)) / (2.0 * e);
                let theta_z = (head.blade_azimuth(0, r, z + e) - head.blade_azimuth(0, r, z - e)) / (2.0 * e);
                let stretch = (1.0 + (r * theta_r).powi(2) + (r * theta_z).powi(2)).sqrt();
                let sin_phi = head.blade_angle_at(z).sin();
                area += stretch * dr * dz;
                volume += t / sin_phi * dr * dz;
                thinnest = thinnest.min(1.0 / (sin_phi * stretch));
                thickest = thickest.max(1.0 / (sin_phi * stretch));
            }
        }
        for (k, (_, mesh)) in walls.iter().enumerate().take(head.blades) {
            let enclosed = signed_volume(mesh);
            // The flat triangles are chords of the curved faces (an O(h²) error, −0.2 % at 2 cm),
            // and the flat inner and outer edge strips cut across the arcs of r = r_in and R
            // (+0.1 %, independent of h): within 0.5 %.
            assert!((enclosed - volume).abs() < 5e-3 * volume, "blade {k}: {enclosed} vs {volume} m³");
            // Thickness × area: the volume is ∫ t_n dA, so volume / (t A) is an area-weighted
            // mean of t_n / t, between its least and greatest value (0.5 % for the mesh as above).
            let ratio = enclosed / (t * area);
            assert!(ratio > thinnest - 5e-3 && ratio < thickest + 5e-3, "blade {k}: volume / (t A) = {ratio}, t_n / t in [{thinnest}, {thickest}]");
        }
        // the tilt thins the shipped blades by ≈ 5 % on average, by up to 18 % at the outer edge
        // where R(z) narrows toward the hub
        assert!(thickest < 1.0 && thinnest > 0.8, "t_n / t in [{thinnest}, {thickest}]");
    }

    #[test]
    fn the_blade_meshes_match_the_cells_the_fluid_mesh_blocks() {
        let section = section();
        let head = CutterHead::new(&section);
        let walls = head_walls(&section, SIZE);
        let grid = BladeGrid::new(&head, SIZE);
        let per_face = grid.z.len() * (grid.radial_segments + 1);
        let (t, h) = (head.blade_thickness, head.height());
        for (k, (_, mesh)) in walls.iter().enumerate().take(head.blades) {
            for (n, (behind, ahead)) in mesh.vertices[..per_face].iter().zip(&mesh.vertices[per_face..]).enumerate() {
                // the point of the centre surface between the two faces: same r and z, the
                // bisecting azimuth
                let (r, z) = (behind.xy().norm(), behind.z);
                let mid = behind + ahead;
                let theta = mid.y.atan2(mid.x);
                // a 1 mm cell around it, kept inside the blade's extent (the plates start at the
                // blade's top and bottom)
                let e = 1e-3;
                let cell_r = [(r - e).max(head.blade_inner_radius(z)), (r + e).min(head.radius_at(z))];
                let cell_z = [(z - e).max(-h), (z + e).min(0.0)];
                assert_eq!(head.touches_solid(cell_r, [theta - e / r, theta + e / r], cell_z), Some(Part::Blade(k)), "blade {k}, vertex {n}");
                // the unit normal of the centre surface θ = θ_k(r, z): ∇(θ − θ_k) ∝ (−r θ_r, 1, −r θ_z)
                // in (e_r, e_θ, e_z)
                let d = 1e-6;
                let theta_r = (head.blade_azimuth(k, r + d, z) - head.blade_azimuth(k, r - d, z)) / (2.0 * d);
                let theta_z = (head.blade_azimuth(k, r, z + d) - head.blade_azimuth(k, r, z - d)) / (2.0 * d);
                let (e_r, e_theta) = (Vec3::new(theta.cos(), theta.sin(), 0.0), Vec3::new(-theta.sin(), theta.cos(), 0.0));
                let normal = (-r * theta_r * e_r + e_theta - r * theta_z * Vec3::z()).normalize();
                let centre = cylindrical(r, theta, z);
                for side in [-1.5, 1.5] {
                    let off = centre + side * t * normal;
                    assert!(winding_number(mesh, off).abs() < 0.5, "blade {k}, vertex {n}: 1.5 t off the surface is inside");
                }
                // away from the blade's edges, the centre surface and points 0.3 t off it are inside:
                // the blade is at least 0.8 t thick normal to the surface (the tilt thins it, see
                // a_blade_holds_its_thickness_times_its_area), which leaves 0.1 t = 1.5 mm for the
                // sag of the faces' chords (< 0.5 mm at 2 cm triangles)
                let (i, j) = (n % (grid.radial_segments + 1), n / (grid.radial_segments + 1));
                if i > 0 && i < grid.radial_segments && j > 0 && j < grid.z.len() - 1 {
                    for side in [-0.3, 0.0, 0.3] {
                        let p = centre + side * t * normal;
                        assert!((winding_number(mesh, p) - 1.0).abs() < 0.5, "blade {k}, vertex {n}: {side} t off the centre surface is outside");
                    }
                }
            }
        }
    }

    #[test]
    fn a_particle_case_gets_the_head_walls_turning_with_the_rotor() {
        // the shipped case: rock (material 0) between the blades, the head of steel (material 1)
        let text = case_text();
        let case = crate::case::Case::from_toml(&text, std::path::Path::new("cutter_head.toml")).unwrap();
        let state = crate::walls::build(&case, std::path::Path::new(".")).unwrap();
        let names: Vec<&str> = state.walls.iter().map(|w| w.name.as_str()).collect();
        assert_eq!(names, ["blade_1", "blade_2", "blade_3", "blade_4", "blade_5", "blade_6", "hub", "ring", "pipe", "shaft"]);
        assert!(state.walls.iter().all(|w| w.motion == WallMotion::Rotor && w.material == 1));
        // without [particles] (a fluid-only run of the same head) there are no walls
        let fluid_only = text[..text.find("[coupling]").unwrap()].to_string();
        let fluid_only = crate::case::Case::from_toml(&fluid_only, std::path::Path::new("cutter_head.toml")).unwrap();
        assert!(crate::walls::build(&fluid_only, std::path::Path::new(".")).unwrap().walls.is_empty());
        // a material that is not a [[particles.materials]] entry is an error naming the key
        let wrong = text.replace("material = \"steel\"", "material = \"brass\"");
        let case = crate::case::Case::from_toml(&wrong, std::path::Path::new("cutter_head.toml")).unwrap();
        let error = crate::walls::build(&case, std::path::Path::new(".")).unwrap_err().to_string();
        assert!(error.contains("cutter_head.material") && error.contains("brass"), "{error}");
    }

    /// An eccentric mouth's head: the back plate is a wall at rest after the turning parts
    /// (the ring reaches in to the plate, no pipe turns with the head), it covers the inner
    /// ring area at z = 0 except the mouth, and a sphere under the mouth can rise through it
    /// while one under the plate touches it.
    #[test]
    fn the_back_plate_stands_still_with_the_mouth_cut_out() {
        let text = case_text()
            .replace("suction = { type = \"mouth\", radius = 0.12 }", "suction = { type = \"eccentric\", angle = 180.0, width = 103.0, radii = [0.07, 0.2] }");
        let case = crate::case::Case::from_toml(&text, std::path::Path::new("cutter_head.toml")).unwrap();
        let state = crate::walls::build(&case, std::path::Path::new(".")).unwrap();
        let names: Vec<&str> = state.walls.iter().map(|w| w.name.as_str()).collect();
        assert_eq!(names, ["blade_1", "blade_2", "blade_3", "blade_4", "blade_5", "blade_6", "hub", "ring", "shaft", "back_plate"]);
        assert_eq!(names, head_wall_names(case.cutter_head.as_ref().unwrap()));
        let plate = state.walls.last().unwrap();
        assert!(state.walls[..9].iter().all(|w| w.motion == WallMotion::Rotor) && plate.motion == WallMotion::Static);
        let section = case.cutter_head.unwrap();
        let head = CutterHead::new(&section);
        let mouth = head.mouth.unwrap();
        let mesh = TriangleMesh { vertices: plate.vertices.clone(), triangles: plate.triangles.clone() };
        // flat at z = 0, facing down into the head; its area is the polygonal annulus less the
        // mouth's polygonal sector (the grid has the mouth's edges as lines). Chords fall short
        // of arcs by (Δθ)²/6 of the area: 0.8 % for the mouth's 8 segments of 0.225 rad (so more
        // than 0.95 of its area is cut out) and 0.5 % for the plate's 26 of 0.17 rad elsewhere
        // (within 2 % of the circular annulus)
        assert!(mesh.vertices.iter().all(|v| v.z == 0.0));
        let areas: Vec<f64> = mesh.triangles.iter().map(|t| corners(&mesh, t)).map(|[a, b, c]| 0.5 * (b - a).cross(&(c - a)).z).collect();
        assert!(areas.iter().all(|&a| a < 0.0), "a triangle faces up");
        let area = -areas.iter().sum::<f64>();
        let annulus = PI * (head.opening_radius.powi(2) - head.shaft_radius.powi(2));
        assert!(area < annulus - 0.95 * mouth.area() && area > annulus - mouth.area() - 0.02 * annulus, "{area} vs {annulus} − {}", mouth.area());
        let geometry = WallMesh::new(&mesh.vertices, &mesh.triangles).unwrap();
        // a 2 cm sphere half a radius under the plate: under the mouth's middle (r 0.135 m,
        // θ 180°, 6.5 cm from its edges) nothing touches; under the plate (θ 0°) the plate does
        let a = 0.01;
        assert!(geometry.sphere_contacts(Vec3::new(-0.135, 0.0, -0.5 * a), a).is_empty(), "the mouth is closed");
        let contacts = geometry.sphere_contacts(Vec3::new(0.135, 0.0, -0.5 * a), a);
        assert!(contacts.len() == 1 && (contacts[0].distance - 0.5 * a).abs() < 1e-15, "{contacts:?}");
    }
}
