//! Cylindrical (r, θ, z) block generators about the z axis (origin 0): a plain annulus, and a
//! rotor annulus inside a stator annulus joined by a sliding interface (spec
//! fluid-dem-model.md §4; spillage-and-flow-verification.md §3.3, circular Couette flow).
//!
//! Cells span the full 2π in θ; the θ wrap is joined by internal faces (no seam patch). All
//! faces are planar quads: radial faces are chords, so a ring of `n` cells between radii
//! R_i < R_o and heights h is the difference of two regular n-gons, of exact area
//!
//!   V = (n/2) sin(2π/n) (R_o² − R_i²) h,
//!
//! which tends to π (R_o² − R_i²) h with relative error (2π/n)²/6 as n grows.
//!
//! Cell `(i, j, k)` (radial, azimuthal, axial index) of a block has index
//! `first_cell + i + n_r (j + n_θ k)` and spans θ ∈ [j, j+1]·2π/n_θ at zone angle 0. Local
//! hexahedron faces −x/+x/−y/+y/−z/+z are −r/+r/−θ/+θ/−z/+z.

use super::assemble::{assemble, HexCells, ZoneInput};
use super::cartesian::graded_edges;
use super::locate::CylinderBlock;
use super::{InterfaceSide, Locator, Mesh, MeshError, PatchKind, SlidingInterface, Vec3, ZoneRotation};
use std::f64::consts::TAU;

/// A single-zone annulus R_i ≤ r ≤ R_o, z_min ≤ z ≤ z_max.
///
/// Patches `inner`, `outer`, `z_min`, `z_max` (kind Patch); one non-rotating zone "fluid".
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AnnulusSpec {
    pub r_inner: f64,
    pub r_outer: f64,
    pub z_min: f64,
    pub z_max: f64,
    pub n_r: usize,
    pub n_theta: usize,
    pub n_z: usize,
    /// Ratio of the outermost to the innermost radial cell size (1 = uniform).
    pub radial_grading: f64,
}

/// A rotor annulus R_i ≤ r ≤ R_interface inside a stator annulus R_interface ≤ r ≤ R_o, sharing
/// the z layers, with independent radial and azimuthal resolutions.
///
/// Cells: zone 0 `rotor` (rotating about the z axis through the origin), cells
/// `0..n_r_rotor·n_theta_rotor·n_z`, then zone 1 `stator`. Patches, in this order:
/// `inner` (rotor side, moves with the rotor), `outer` (stator), `z_min`, `z_max` (each covering
/// both zones), `interface_rotor`, `interface_stator` (kind `Interface { interface: 0, side }`).
/// `Mesh::interfaces[0]` describes the sliding interface.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RotorStatorSpec {
    pub r_inner: f64,
    pub r_interface: f64,
    pub r_outer: f64,
    pub z_min: f64,
    pub z_max: f64,
    pub n_r_rotor: usize,
    pub n_r_stator: usize,
    pub n_theta_rotor: usize,
    pub n_theta_stator: usize,
    pub n_z: usize,
    /// Ratio of outermost to innermost radial cell size in the rotor (1 = uniform).
    pub radial_grading_rotor: f64,
    /// Same for the stator.
    pub radial_grading_stator: f64,
}

/// Appends one cylindrical block's points and cells; returns its locator entry.
pub(super) fn add_block(
    points: &mut Vec<Vec3>,
    cells: &mut Vec<[usize; 8]>,
    r_edges: Vec<f64>,
    n_theta: usize,
    z_edges: Vec<f64>,
    zone: usize,
) -> CylinderBlock {
    let (n_r, n_z) = (r_edges.len() - 1, z_edges.len() - 1);
    let first_point = points.len();
    let first_cell = cells.len();
    for &z in &z_edges {
        for j in 0..n_theta {
            let theta = TAU * j as f64 / n_theta as f64;
            let (sin, cos) = theta.sin_cos();
            for &r in &r_edges {
                points.push(Vec3::new(r * cos, r * sin, z));
            }
        }
    }
    // θ index n_theta is θ index 0: the wrap shares points, so its faces match as internal.
    let point_id = |i: usize, j: usize, k: usize| first_point + i + (n_r + 1) * (j % n_theta + n_theta * k);
    for k in 0..n_z {
        for j in 0..n_theta {
            for i in 0..n_r {
                cells.push([
                    point_id(i, j, k),
                    point_id(i + 1, j, k),
                    point_id(i + 1, j + 1, k),
                    point_id(i, j + 1, k),
                    point_id(i, j, k + 1),
                    point_id(i + 1, j, k + 1),
                    point_id(i + 1, j + 1, k + 1),
                    point_id(i, j + 1, k + 1),
                ]);
            }
        }
    }
    CylinderBlock { r_edges, n_theta, z_edges, first_cell, zone, cell_of_slot: Vec::new(), blocked: Vec::new() }
}

fn check_radii(names: &[&str], radii: &[f64]) -> Result<(), MeshError> {
    if !(radii[0].is_finite() && radii[0] > 0.0) {
        return Err(MeshError::input(names[0], radii[0], "must be finite and > 0 (a block cannot contain the axis)"));
    }
    for k in 1..radii.len() {
        if !(radii[k].is_finite() && radii[k] > radii[k - 1]) {
            return Err(MeshError::input(names[k], radii[k], &format!("must be finite and > {} = {}", names[k - 1], radii[k - 1])));
        }
    }
    Ok(())
}

fn check_count(name: &str, n: usize, least: usize) -> Result<(), MeshError> {
    if n < least {
        return Err(MeshError::input(name, n, &format!("need at least {least}")));
    }
    Ok(())
}

fn check_heights(z_min: f64, z_max: f64) -> Result<(), MeshError> {
    if !(z_min.is_finite() && z_max.is_finite() && z_min < z_max) {
        return Err(MeshError::input("z_min/z_max", format!("[{z_min}, {z_max}]"), "need finite z_min < z_max"));
    }
    Ok(())
}

/// Which cylindrical index direction and side a local hexahedron face is (see HEX_FACES).
pub(super) const LOCAL_INNER: usize = 0;
pub(super) const LOCAL_OUTER: usize = 1;
pub(super) const LOCAL_Z_MIN: usize = 4;
pub(super) const LOCAL_Z_MAX: usize = 5;

impl Mesh {
    /// Generate the annulus described by `spec`.
    pub fn annulus(spec: &AnnulusSpec) -> Result<Mesh, MeshError> {
        check_radii(&["r_inner", "r_outer"], &[spec.r_inner, spec.r_outer])?;
        check_heights(spec.z_min, spec.z_max)?;
        check_count("n_r", spec.n_r, 1)?;
        check_count("n_theta", spec.n_theta, 3)?;
        check_count("n_z", spec.n_z, 1)?;
        let r_edges = graded_edges("radial_grading", spec.r_inner, spec.r_outer, spec.n_r, spec.radial_grading)?;
        let z_edges = graded_edges("z", spec.z_min, spec.z_max, spec.n_z, 1.0)?;
        let (mut points, mut cells) = (Vec::new(), Vec::new());
        let block = add_block(&mut points, &mut cells, r_edges, spec.n_theta, z_edges, 0);
        let n_cells = cells.len();
        let input = HexCells {
            canonical: (0..points.len()).collect(),
            points,
            cells,
            patches: ["inner", "outer", "z_min", "z_max"].iter().map(|n| (n.to_string(), PatchKind::Patch)).collect(),
            periodic: Vec::new(),
            zones: vec![ZoneInput { name: "fluid".into(), cells: (0..n_cells).collect(), rotation: None }],
            locator: Locator::Cylindrical { blocks: vec![block] },
        };
        assemble(input, |cell, local| match local {
            LOCAL_INNER => Ok(0),
            LOCAL_OUTER => Ok(1),
            LOCAL_Z_MIN => Ok(2),
            LOCAL_Z_MAX => Ok(3),
            _ => Err(MeshError::Topology(format!("θ face {local} of cell {cell} is unmatched"))),
        })
    }

    /// Generate the rotor/stator annulus pair described by `spec`.
    pub fn rotor_stator(spec: &RotorStatorSpec) -> Result<Mesh, MeshError> {
        check_radii(&["r_inner", "r_interface", "r_outer"], &[spec.r_inner, spec.r_interface, spec.r_outer])?;
        check_heights(spec.z_min, spec.z_max)?;
        check_count("n_r_rotor", spec.n_r_rotor, 1)?;
        check_count("n_r_stator", spec.n_r_stator, 1)?;
        check_count("n_theta_rotor", spec.n_theta_rotor, 3)?;
        check_count("n_theta_stator", spec.n_theta_stator, 3)?;
        check_count("n_z", spec.n_z, 1)?;
        let rotor_r = graded_edges("radial_grading_rotor", spec.r_inner, spec.r_interface, spec.n_r_rotor, spec.radial_grading_rotor)?;
        let stator_r = graded_edges("radial_grading_stator", spec.r_interface, spec.r_outer, spec.n_r_stator, spec.radial_grading_stator)?;
        let z_edges = graded_edges("z", spec.z_min, spec.z_max, spec.n_z, 1.0)?;
        let (mut points, mut cells) = (Vec::new(), Vec::new());
        let rotor = add_block(&mut points, &mut cells, rotor_r, spec.n_theta_rotor, z_edges.clone(), 0);
        let n_rotor_cells = cells.len();
        let stator = add_block(&mut points, &mut cells, stator_r, spec.n_theta_stator, z_edges.clone(), 1);
        let n_cells = cells.len();
        let interface_kind = |side| PatchKind::Interface { interface: 0, side };
        let patches = vec![
            ("inner".to_string(), PatchKind::Patch),
            ("outer".to_string(), PatchKind::Patch),
            ("z_min".to_string(), PatchKind::Patch),
            ("z_max".to_string(), PatchKind::Patch),
            ("interface_rotor".to_string(), interface_kind(InterfaceSide::Rotor)),
            ("interface_stator".to_string(), interface_kind(InterfaceSide::Stator)),
        ];
        let input = HexCells {
            canonical: (0..points.len()).collect(),
            points,
            cells,
            patches,
            periodic: Vec::new(),
            zones: rotor_stator_zones(n_rotor_cells, n_cells),
            locator: Locator::Cylindrical { blocks: vec![rotor, stator] },
        };
        let mut mesh = assemble(input, |cell, local| {
            let in_rotor = cell < n_rotor_cells;
            match (local, in_rotor) {
                (LOCAL_INNER, true) => Ok(0),
                (LOCAL_OUTER, false) => Ok(1),
                (LOCAL_Z_MIN, _) => Ok(2),
                (LOCAL_Z_MAX, _) => Ok(3),
                (LOCAL_OUTER, true) => Ok(4),
                (LOCAL_INNER, false) => Ok(5),
                _ => Err(MeshError::Topology(format!("θ face {local} of cell {cell} is unmatched"))),
            }
        })?;
        let rotor_faces = interface_faces(&mesh, "interface_rotor", 0, spec.n_r_rotor, spec.n_theta_rotor)?;
        let stator_faces = interface_faces(&mesh, "interface_stator", n_rotor_cells, spec.n_r_stator, spec.n_theta_stator)?;
        mesh.interfaces.push(cylinder_interface(spec.r_interface, z_edges, [spec.n_theta_rotor, spec.n_theta_stator], rotor_faces, stator_faces));
        Ok(mesh)
    }
}

/// The sliding interface between zone 0 (rotor) and zone 1 (stator) on the cylinder of `radius`,
/// with `n_theta` = [rotor, stator] uniform θ divisions and faces ordered by (z layer, θ index).
pub(super) fn cylinder_interface(radius: f64, z_edges: Vec<f64>, n_theta: [usize; 2], rotor_faces: Vec<usize>, stator_faces: Vec<usize>) -> SlidingInterface {
    let theta_edges = |n: usize| (0..=n).map(|j| TAU * j as f64 / n as f64).collect();
    SlidingInterface {
        name: "interface".into(),
        rotor_zone: 0,
        stator_zone: 1,
        radius,
        z_edges,
        n_theta_rotor: n_theta[0],
        n_theta_stator: n_theta[1],
        rotor_theta_edges: theta_edges(n_theta[0]),
        stator_theta_edges: theta_edges(n_theta[1]),
        rotor_faces,
        stator_faces,
    }
}

/// Zone 0 `rotor` (cells below `n_rotor_cells`, turning about z through the origin) and zone 1
/// `stator` (the rest).
pub(super) fn rotor_stator_zones(n_rotor_cells: usize, n_cells: usize) -> Vec<ZoneInput> {
    vec![
        ZoneInput {
            name: "rotor".into(),
            cells: (0..n_rotor_cells).collect(),
            rotation: Some(ZoneRotation { axis: Vec3::z(), origin: Vec3::zeros(), angle: 0.0 }),
        },
        ZoneInput { name: "stator".into(), cells: (n_rotor_cells..n_cells).collect(), rotation: None },
    ]
}

/// Faces of an interface patch ordered by (z layer, θ index), from their owners' indices.
fn interface_faces(mesh: &Mesh, patch: &str, first_cell: usize, n_r: usize, n_theta: usize) -> Result<Vec<usize>, MeshError> {
    interface_faces_by(mesh, patch, n_theta, |cell| {
        let local = cell - first_cell;
        ((local / n_r) % n_theta, local / (n_r * n_theta))
    })
}

/// Faces of an interface patch ordered by (z layer, θ index); `jk` gives an owner cell's
/// (θ index, z layer).
pub(super) fn interface_faces_by(mesh: &Mesh, patch: &str, n_theta: usize, jk: impl Fn(usize) -> (usize, usize)) -> Result<Vec<usize>, MeshError> {
    let range = mesh.patch(patch)?.faces();
    let mut faces = vec![usize::MAX; range.len()];
    for f in range {
        let (j, k) = jk(mesh.face_owner[f]);
        if k * n_theta + j >= faces.len() {
            return Err(MeshError::Topology(format!("patch {patch}: face {f} outside the interface grid")));
        }
        faces[k * n_theta + j] = f;
    }
    if faces.contains(&usize::MAX) {
        return Err(MeshError::Topology(format!("patch {patch} misses interface faces")));
    }
    Ok(faces)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mesh::test_support::*;
    use std::f64::consts::PI;

    fn annulus(n_theta: usize) -> AnnulusSpec {
        AnnulusSpec { r_inner: 1.0, r_outer: 2.0, z_min: -0.25, z_max: 0.5, n_r: 4, n_theta, n_z: 3, radial_grading: 2.0 }
    }

    pub(crate) fn rotor_stator() -> RotorStatorSpec {
        RotorStatorSpec {
            r_inner: 1.0,
            r_interface: 1.4,
            r_outer: 2.0,
            z_min: 0.0,
            z_max: 0.3,
            n_r_rotor: 3,
            n_r_stator: 4,
            n_theta_rotor: 24,
            n_theta_stator: 17,
            n_z: 2,
            radial_grading_rotor: 1.5,
            radial_grading_stator: 0.5,
        }
    }

    fn polygon_annulus_volume(n: usize, r_inner: f64, r_outer: f64, height: f64) -> f64 {
        0.5 * n as f64 * (TAU / n as f64).sin() * (r_outer * r_outer - r_inner * r_inner) * height
    }

    #[test]
    fn annulus_volume_is_the_polygon_formula() {
        for n in [3, 7, 32, 256] {
            let mesh = Mesh::annulus(&annulus(n)).unwrap();
            assert_eq!(mesh.n_cells(), 4 * n * 3);
            let total: f64 = mesh.cell_volumes.iter().sum();
            let exact = polygon_annulus_volume(n, 1.0, 2.0, 0.75);
            // Round-off of point coordinates (cos, sin) and of summing ~1e3 cell volumes.
            assert!((total - exact).abs() < 1e-13 * exact, "n = {n}: {total} vs {exact}");
        }
    }

    #[test]
    fn annulus_volume_converges_to_circle_at_second_order() {
        let circle = PI * 3.0 * 0.75;
        let mut previous = f64::NAN;
        for n in [16, 32, 64, 128] {
            let mesh = Mesh::annulus(&annulus(n)).unwrap();
            let error = (circle - mesh.cell_volumes.iter().sum::<f64>()) / circle;
            let leading = (TAU / n as f64).powi(2) / 6.0;
            // Next term of 1 − sin(x)/x is x⁴/120: relative to x²/6 that is x²/20 ≤ 0.008.
            assert!((error / leading - 1.0).abs() < 0.01, "n = {n}: error {error}");
            if previous.is_finite() {
                let order = (previous / error).log2();
                assert!((order - 2.0).abs() < 0.01, "n = {n}: order {order}");
            }
            previous = error;
        }
    }

    #[test]
    fn annulus_cells_closed_and_oriented() {
        let mesh = Mesh::annulus(&annulus(7)).unwrap();
        assert_cells_closed(&mesh);
        assert_internal_faces_oriented(&mesh);
        assert_boundary_faces_outward(&mesh);
        let names: Vec<&str> = mesh.patches.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["inner", "outer", "z_min", "z_max"]);
        assert_eq!(mesh.patch("inner").unwrap().len, 7 * 3);
        assert_eq!(mesh.patch("z_max").unwrap().len, 4 * 7);
        // Every vertex of the inner patch lies on the inner circle.
        for f in mesh.patch("inner").unwrap().faces() {
            for p in mesh.face_points[f] {
                assert!((mesh.points[p].xy().norm() - 1.0).abs() < 1e-15);
            }
        }
        // Wrap joined: each cell has 6 faces, internal faces = 3 n_r n_θ n_z − boundary/2 …
        assert!((0..mesh.n_cells()).all(|c| mesh.faces_of_cell(c).len() == 6));
        let (n_r, n_t, n_z) = (4, 7, 3);
        let expected_internal = (n_r - 1) * n_t * n_z + n_r * n_t * n_z + n_r * n_t * (n_z - 1);
        assert_eq!(mesh.n_internal_faces, expected_internal);
    }

    #[test]
    fn bad_cylinder_input_is_rejected() {
        let mut spec = annulus(8);
        spec.r_inner = 0.0;
        assert!(Mesh::annulus(&spec).unwrap_err().to_string().contains("r_inner"));
        let mut spec = annulus(8);
        spec.r_outer = 0.5;
        assert!(Mesh::annulus(&spec).unwrap_err().to_string().contains("r_outer"));
        let mut spec = annulus(2);
        spec.n_theta = 2;
        assert!(Mesh::annulus(&spec).unwrap_err().to_string().contains("n_theta"));
        let mut spec = rotor_stator();
        spec.r_interface = 2.5;
        assert!(Mesh::rotor_stator(&spec).unwrap_err().to_string().contains("r_outer"));
        let mut spec = rotor_stator();
        spec.radial_grading_stator = f64::NAN;
        assert!(Mesh::rotor_stator(&spec).unwrap_err().to_string().contains("radial_grading_stator"));
    }

    #[test]
    fn rotor_stator_zones_patches_and_interface() {
        let spec = rotor_stator();
        let mesh = Mesh::rotor_stator(&spec).unwrap();
        assert_cells_closed(&mesh);
        assert_internal_faces_oriented(&mesh);
        assert_boundary_faces_outward(&mesh);
        let n_rotor = 3 * 24 * 2;
        assert_eq!(mesh.zones[0].name, "rotor");
        assert_eq!(mesh.zones[0].cells, (0..n_rotor).collect::<Vec<_>>());
        assert!(mesh.zones[0].rotation.is_some() && mesh.zones[1].rotation.is_none());
        assert_eq!(mesh.zones[1].cells.len(), 4 * 17 * 2);
        // No internal face joins rotor and stator.
        for f in 0..mesh.n_internal_faces {
            assert_eq!(mesh.cell_zone[mesh.face_owner[f]], mesh.cell_zone[mesh.face_neighbour[f]]);
        }
        let total: f64 = mesh.cell_volumes.iter().sum();
        let exact = polygon_annulus_volume(24, 1.0, 1.4, 0.3) + polygon_annulus_volume(17, 1.4, 2.0, 0.3);
        assert!((total - exact).abs() < 1e-13 * exact);

        let interface = &mesh.interfaces[0];
        assert_eq!(interface.rotor_faces.len(), 24 * 2);
        assert_eq!(interface.stator_faces.len(), 17 * 2);
        let rotor_patch = mesh.patch("interface_rotor").unwrap();
        assert_eq!(rotor_patch.kind, PatchKind::Interface { interface: 0, side: InterfaceSide::Rotor });
        for (side, faces, n, patch) in [(1.0, &interface.rotor_faces, 24, "interface_rotor"), (-1.0, &interface.stator_faces, 17, "interface_stator")] {
            let range = mesh.patch(patch).unwrap().faces();
            for (index, &f) in faces.iter().enumerate() {
                assert!(range.contains(&f));
                let (layer, j) = (index / n, index % n);
                let centre = mesh.face_centres[f];
                let theta = centre.y.atan2(centre.x).rem_euclid(TAU);
                assert!((theta - TAU * (j as f64 + 0.5) / n as f64).abs() < 1e-13, "{patch} {index}");
                assert!((centre.z - 0.15 * (layer as f64 + 0.5)).abs() < 1e-15);
                // Rotor faces point outwards (+r), stator faces inwards.
                assert!(side * mesh.face_areas[f].dot(&centre) > 0.0);
                for p in mesh.face_points[f] {
                    assert!((mesh.points[p].xy().norm() - 1.4).abs() < 1e-15);
                }
            }
        }
    }

    #[test]
    fn locate_in_annulus_agrees_with_brute_force() {
        let mesh = Mesh::annulus(&annulus(7)).unwrap();
        let mut random = Lcg::new(11);
        let mut found = 0;
        for _ in 0..3000 {
            // Sample a box around the annulus: points outside and between chord and arc too.
            let p = Vec3::new(4.4 * random.next() - 2.2, 4.4 * random.next() - 2.2, random.next() - 0.4);
            let brute = (0..mesh.n_cells()).find(|&c| mesh.contains(c, &p));
            let located = mesh.locate(&p);
            match (located, brute) {
                (Some(c), Some(_)) => {
                    assert!(mesh.contains(c, &p));
                    found += 1
                }
                (None, None) => {}
                _ => panic!("{p:?}: locate {located:?}, brute force {brute:?}"),
            }
        }
        // Expected fraction inside: 7-gon annulus area 8.2 of the 19.4 box, 0.75 of the height
        // → ~32 %, about 950 points.
        assert!(found > 800, "only {found} points inside");
    }
}
