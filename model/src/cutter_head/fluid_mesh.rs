//! The fluid mesh of a cutter head: a cylindrical rotor zone (shaft to the sliding interface)
//! inside a stator zone (interface to the tank wall), every rotor cell a solid touches removed
//! ([`CutterHead::touches_solid`]), its faces toward the fluid the rotating wall patch `head`.
//!
//! Layers follow the head: graded from `outer_cell_size` at the tank floor to `cell_size` at
//! the hub plate, then `cell_size` through hub plate, head, ring and pipe, so the ring's
//! underside (z = 0) and the hub (z = −H) are layer edges. Radially the rotor is uniform at
//! `cell_size`; the stator is graded to `outer_cell_size` at the tank wall.

use std::f64::consts::TAU;

use super::geometry::{CutterHead, Part};
use super::mouth::SuctionWindow;
use super::settings::{BladeCells, CutterHeadSection};
use crate::mesh::cartesian::graded_edges;
use crate::mesh::{BlockedRotorStator, Mesh, MeshError, BLOCKED_ROTOR_STATOR_PATCHES};

/// The patches of the head's mesh: `shaft` (the rotating shaft), `tank` (the tank wall),
/// `floor`, `top` (the water surface around the pipe), `head` (every face of the head's
/// solids), `suction` (the end of the pipe; with an eccentric mouth, every face of the back
/// plate and its housing at rest, [`super::mouth`]). The case gives conditions for all but
/// `floor` and `suction`, which [`crate::case::Case`] sets from `suction_discharge` (see
/// [`FLOW_PATCHES`]).
pub const PATCHES: [&str; 6] = ["shaft", "tank", "floor", "top", "head", "suction"];

/// The patches whose conditions carry the suction discharge: the water enters uniformly
/// through the tank floor (Q_m / floor area, upward) and leaves through the pipe's end at
/// fixed pressure with zero-gradient velocity, or through an eccentric mouth in the back plate
/// at the flux continuity leaves it, again at zero-gradient velocity ([`super::mouth`]). (The
/// thesis fed the tank through its side, §4.2; a fixed velocity at the pipe's end, which turns
/// with the rotor, blocks the swirl leaving the pipe and grew a 35 m/s azimuthal jet in the top
/// cells in our tests; a fixed velocity through the eccentric mouth grew one of 13 m/s.)
pub const FLOW_PATCHES: [&str; 2] = ["floor", "suction"];

fn cells_over(length: f64, size: f64) -> usize {
    ((length / size).round() as usize).max(1)
}

/// The z edges of the mesh, bottom to top.
pub fn z_edges(head: &CutterHead, section: &CutterHeadSection) -> Result<Vec<f64>, MeshError> {
    let (h, ho) = (section.mesh.cell_size, section.mesh.outer_cell_size);
    let floor = head.hub_bottom() - section.tank.below_hub;
    let below = section.tank.below_hub;
    let mut edges = graded_edges("tank.below_hub", floor, head.hub_bottom(), cells_over(below, 0.5 * (h + ho)), h / ho)?;
    for (start, end) in [(head.hub_bottom(), -head.height()), (-head.height(), 0.0), (0.0, head.ring_top()), (head.ring_top(), head.pipe_top())] {
        let segment = graded_edges("cutter_head.mesh.cell_size", start, end, cells_over(end - start, h), 1.0)?;
        edges.extend_from_slice(&segment[1..]);
    }
    Ok(edges)
}

/// The generator input: edges, resolutions and the blocked rotor slots.
pub fn blocked_rotor_stator(section: &CutterHeadSection) -> Result<BlockedRotorStator, MeshError> {
    let head = CutterHead::new(section);
    let (h, ho) = (section.mesh.cell_size, section.mesh.outer_cell_size);
    let ri = section.mesh.interface_radius;
    let rotor_r = match section.mesh.blades {
        BladeCells::Blocked => graded_edges("cutter_head.mesh.cell_size", head.shaft_radius, ri, cells_over(ri - head.shaft_radius, h).max(2), 1.0)?,
        // an edge on the widest contour radius: the blade tips and the ring end at R on every
        // mesh, not up to a cell beyond it (the outflow is sensitive to the tip radius)
        BladeCells::Baffles => {
            let widest = head.contour().iter().map(|p| p.1).fold(0.0, f64::max);
            let mut edges = graded_edges("cutter_head.mesh.cell_size", head.shaft_radius, widest, cells_over(widest - head.shaft_radius, h), 1.0)?;
            edges.extend_from_slice(&graded_edges("cutter_head.mesh.cell_size", widest, ri, cells_over(ri - widest, h), 1.0)?[1..]);
            edges
        }
    };
    let stator_r = graded_edges("cutter_head.mesh.outer_cell_size", ri, section.tank.radius, cells_over(section.tank.radius - ri, 0.5 * (h + ho)), ho / h)?;
    let z = z_edges(&head, section)?;
    let n_theta_rotor = ((TAU * head.radius_at(0.0) / h).ceil() as usize).max(3);
    let n_theta_stator = ((TAU * ri / h).ceil() as usize).max(3);
    let n_r = rotor_r.len() - 1;
    let n_slots = n_r * n_theta_rotor * (z.len() - 1);
    let (mut blocked, mut stationary) = (Vec::with_capacity(n_slots), Vec::with_capacity(n_slots));
    for k in 0..z.len() - 1 {
        for j in 0..n_theta_rotor {
            let theta = [TAU * j as f64 / n_theta_rotor as f64, TAU * (j + 1) as f64 / n_theta_rotor as f64];
            for i in 0..n_r {
                let (r, z) = ([rotor_r[i], rotor_r[i + 1]], [z[k], z[k + 1]]);
                let solid = match section.mesh.blades {
                    BladeCells::Blocked => head.touches_solid(r, theta, z),
                    BladeCells::Baffles => head.touches_plate(r, z),
                };
                blocked.push(solid.is_some());
                stationary.push(solid == Some(Part::BackPlate));
            }
        }
    }
    let suction_radius = if head.mouth.is_some() { 0.0 } else { head.opening_radius };
    let mut spec =
        BlockedRotorStator { rotor_r, stator_r, z_edges: z, n_theta_rotor, n_theta_stator, blocked, baffles: Vec::new(), suction_radius, stationary };
    if section.mesh.blades == BladeCells::Baffles {
        spec.add_baffles_where(|a, b| head.blade_between(a, b).is_some());
    }
    spec.close_pockets();
    if let Some(mouth) = head.mouth {
        check_mouth_over_open_cells(&spec, mouth.radii)?;
        return Ok(spec);
    }
    let top = n_r * n_theta_rotor * (spec.z_edges.len() - 2);
    let pipe_open = (0..n_r).any(|i| !spec.blocked[top + i] && 0.5 * (spec.rotor_r[i] + spec.rotor_r[i + 1]) < head.opening_radius);
    if !pipe_open {
        return Err(MeshError::input(
            "cutter_head.mesh.cell_size",
            h,
            &format!(
                "cells small enough that the pipe keeps open cells between the shaft ({} m) and its wall ({} m): the staircase of the wall fills it",
                head.shaft_radius, head.opening_radius
            ),
        ));
    }
    Ok(spec)
}

/// An eccentric mouth must lie over rotor cells that are open under the back plate at every
/// angle (each ring's whole circle), so that the plate's faces tile it as they turn
/// ([`SuctionWindow::new`]); the error names the radii that do.
fn check_mouth_over_open_cells(spec: &BlockedRotorStator, radii: [f64; 2]) -> Result<(), MeshError> {
    let n_r = spec.rotor_r.len() - 1;
    let Some(under) = spec.z_edges.iter().position(|&z| z == 0.0).and_then(|k| k.checked_sub(1)) else {
        return Err(MeshError::input("cutter_head.suction", "(no cell layer under the back plate)", "a mesh with a layer edge at z = 0"));
    };
    let slot = |i: usize, j: usize, k: usize| i + n_r * (j + spec.n_theta_rotor * k);
    let clear = |i: usize| (0..spec.n_theta_rotor).all(|j| !spec.blocked[slot(i, j, under)] && spec.stationary[slot(i, j, under + 1)]);
    let covered = (0..n_r).filter(|&i| spec.rotor_r[i] < radii[1] && spec.rotor_r[i + 1] > radii[0]);
    if covered.clone().all(clear) {
        return Ok(());
    }
    let last_clear = (0..n_r).take_while(|&i| clear(i)).last();
    let allowed = match last_clear {
        Some(i) => format!(
            "radii within [{}, {}] m on this mesh (the cells beyond are blocked by the blades' or the ring's staircase; a finer mesh widens it)",
            spec.rotor_r[0],
            spec.rotor_r[i + 1]
        ),
        None => "a mesh with open cells under the back plate next to the shaft".to_string(),
    };
    Err(MeshError::input("cutter_head.suction.radii", format!("{radii:?}"), &allowed))
}

/// The boundary condition of an eccentric mouth on the back plate's faces of the mesh `spec` of
/// `section` (`None` for the other suctions).
pub fn suction_window(section: &CutterHeadSection, spec: &BlockedRotorStator) -> Option<SuctionWindow> {
    let mouth = section.eccentric_mouth()?;
    Some(SuctionWindow::new(mouth, 0.0, spec.rotor_r.clone(), spec.n_theta_rotor, section.suction_discharge))
}

/// Area of the `floor` patch: every bottom-layer cell's face, planar annular sectors of area
/// ½ sin(2π/n_θ)(r_o² − r_i²) in both zones.
pub fn floor_area(section: &CutterHeadSection, spec: &BlockedRotorStator) -> Result<f64, MeshError> {
    let n_r = spec.rotor_r.len() - 1;
    if spec.blocked[..n_r * spec.n_theta_rotor].iter().any(|&b| b) {
        return Err(MeshError::input("cutter_head.tank.below_hub", section.tank.below_hub, "water under the hub plate (a solid touches the floor)"));
    }
    let ring = |n: usize, r0: f64, r1: f64| 0.5 * n as f64 * (TAU / n as f64).sin() * (r1 * r1 - r0 * r0);
    let ri = *spec.rotor_r.last().expect("≥ 2 edges");
    Ok(ring(spec.n_theta_rotor, spec.rotor_r[0], ri) + ring(spec.n_theta_stator, ri, section.tank.radius))
}

/// The cutter head's fluid mesh, with the patch names of [`PATCHES`].
pub fn build(section: &CutterHeadSection) -> Result<Mesh, MeshError> {
    debug_assert!(BLOCKED_ROTOR_STATOR_PATCHES.iter().filter(|p| !p.starts_with("interface")).eq(PATCHES.iter()));
    Mesh::rotor_stator_blocked(&blocked_rotor_stator(section)?)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mesh::test_support::*;

    pub(crate) fn section(cell_size: f64) -> CutterHeadSection {
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../cases/cutter_head.toml")).unwrap();
        let case = crate::case::Case::from_toml(&text, std::path::Path::new("cutter_head.toml")).unwrap();
        let mut head = case.cutter_head.unwrap();
        head.mesh.cell_size = cell_size;
        head
    }

    fn polygon_ring(n: usize, r0: f64, r1: f64) -> f64 {
        0.5 * n as f64 * (TAU / n as f64).sin() * (r1 * r1 - r0 * r0)
    }

    #[test]
    fn the_head_mesh_is_closed_and_its_cells_plus_solids_fill_the_tank() {
        let section = section(0.04);
        let spec = blocked_rotor_stator(&section).unwrap();
        let mesh = build(&section).unwrap();
        assert_cells_closed(&mesh);
        assert_internal_faces_oriented(&mesh);
        assert_boundary_faces_outward(&mesh);
        let n_blocked = spec.blocked.iter().filter(|&&b| b).count();
        assert!(n_blocked > 0 && mesh.patch("head").unwrap().len > 0);
        // open cells + blocked slots = the two polygonal annuli, to round-off (1e-12: sums of
        // ~1e4 volumes with coordinates from sin/cos)
        let (n_r, n_t) = (spec.rotor_r.len() - 1, spec.n_theta_rotor);
        let mut blocked_volume = 0.0;
        for (slot, _) in spec.blocked.iter().enumerate().filter(|(_, b)| **b) {
            let (i, k) = (slot % n_r, slot / (n_r * n_t));
            blocked_volume += polygon_ring(n_t, spec.rotor_r[i], spec.rotor_r[i + 1]) / n_t as f64 * (spec.z_edges[k + 1] - spec.z_edges[k]);
        }
        let height = spec.z_edges.last().unwrap() - spec.z_edges[0];
        let ri = *spec.rotor_r.last().unwrap();
        let whole = (polygon_ring(n_t, spec.rotor_r[0], ri) + polygon_ring(spec.n_theta_stator, ri, section.tank.radius)) * height;
        let open: f64 = mesh.cell_volumes.iter().sum();
        assert!((open + blocked_volume - whole).abs() < 1e-12 * whole, "{open} + {blocked_volume} vs {whole}");
        // the floor's exact area is what the case's inflow velocity was computed from
        let floor: f64 = mesh.patch("floor").unwrap().faces().map(|f| -mesh.face_areas[f].z).sum();
        assert!((floor - floor_area(&section, &spec).unwrap()).abs() < 1e-13, "{floor}");
        assert!(mesh.patch("suction").unwrap().len > 0);
    }

    #[test]
    fn a_small_hub_opens_the_bottom_of_the_head_to_the_water_below() {
        let mut section = section(0.05);
        let head = CutterHead::new(&section);
        // internal faces in the plane of the hub's underside, within the contour: the water
        // under the hub meets the water in the head only where the hub plate is not
        let through_the_bottom = |mesh: &Mesh| {
            (0..mesh.n_internal_faces)
                .filter(|&f| {
                    let c = mesh.face_centres[f];
                    (c.z - head.hub_bottom()).abs() < 1e-9 && c.x.hypot(c.y) < head.radius_at(-head.height())
                })
                .count()
        };
        assert_eq!(through_the_bottom(&build(&section).unwrap()), 0);
        section.hub_radius = Some(0.13);
        let mesh = build(&section).unwrap();
        assert_cells_closed(&mesh);
        assert_internal_faces_oriented(&mesh);
        assert!(through_the_bottom(&mesh) > 0);
    }

    #[test]
    fn the_blocked_cells_are_the_solids_and_converge_to_their_volume() {
        // the staircase over-covers thin solids by up to a cell on each side, so its volume
        // falls toward the true one as the cells shrink
        let mut previous = f64::INFINITY;
        for h in [0.06, 0.04, 0.03] {
            let section = section(h);
            let mesh = build(&section).unwrap();
            let spec = blocked_rotor_stator(&section).unwrap();
            let height = spec.z_edges.last().unwrap() - spec.z_edges[0];
            let ri = *spec.rotor_r.last().unwrap();
            let whole = (polygon_ring(spec.n_theta_rotor, spec.rotor_r[0], ri) + polygon_ring(spec.n_theta_stator, ri, section.tank.radius)) * height;
            let solid = whole - mesh.cell_volumes.iter().sum::<f64>();
            assert!(solid < previous, "h = {h}: solid volume {solid} m³ did not shrink");
            previous = solid;
        }
    }

    /// The passages (between blade k and k + 1, by the cell centre's azimuth) met by each
    /// connected group of the open cells whose centres lie well inside the blades' annulus (half
    /// a cell from the blades' inner edge and the contour, a cell from the ring and the hub),
    /// linked by the internal faces between two of them.
    fn passages_of_connected_groups(section: &CutterHeadSection, mesh: &Mesh) -> Vec<Vec<usize>> {
        let head = CutterHead::new(section);
        let h = section.mesh.cell_size;
        let inner = |cell: usize| {
            let c = mesh.cell_centres[cell];
            let (r, z) = (c.x.hypot(c.y), c.z);
            z > -head.height() + h && z < -h && r > head.blade_inner_radius(z) + 0.5 * h && r < head.radius_at(z) - 0.25 * h
        };
        let passage = |cell: usize| {
            let c = mesh.cell_centres[cell];
            let (r, theta) = (c.x.hypot(c.y), c.y.atan2(c.x));
            (0..section.blades).min_by(|&a, &b| {
                let past = |k: usize| (theta - head.blade_azimuth(k, r, c.z)).rem_euclid(TAU);
                past(a).total_cmp(&past(b))
            })
        };
        let mut group: Vec<usize> = (0..mesh.n_cells()).map(|c| if inner(c) { c } else { usize::MAX }).collect();
        fn root(group: &mut [usize], mut c: usize) -> usize {
            while group[c] != c {
                group[c] = group[group[c]];
                c = group[c];
            }
            c
        }
        for f in 0..mesh.n_internal_faces {
            let (a, b) = (mesh.face_owner[f], mesh.face_neighbour[f]);
            if group[a] != usize::MAX && group[b] != usize::MAX {
                let (ra, rb) = (root(&mut group, a), root(&mut group, b));
                group[ra.max(rb)] = ra.min(rb);
            }
        }
        let mut passages: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
        for cell in 0..mesh.n_cells() {
            if group[cell] == usize::MAX {
                continue;
            }
            let g = root(&mut group, cell);
            passages.entry(g).or_default().extend(passage(cell));
        }
        passages
            .into_values()
            .map(|mut p| {
                p.sort_unstable();
                p.dedup();
                p
            })
            .collect()
    }

    #[test]
    fn baffle_blades_keep_the_passages_apart_and_take_no_volume() {
        use crate::cutter_head::BladeSweep;
        for (h, sweep) in [(0.05, BladeSweep::Backward), (0.04, BladeSweep::Backward), (0.04, BladeSweep::Forward)] {
            let mut section = section(h);
            section.mesh.blades = BladeCells::Baffles;
            section.blade_sweep = sweep;
            let spec = blocked_rotor_stator(&section).unwrap();
            let mesh = build(&section).unwrap();
            assert_cells_closed(&mesh);
            assert_internal_faces_oriented(&mesh);
            assert_boundary_faces_outward(&mesh);
            // only the plates are blocked: the same slots as a head without blades
            let mut bladeless = section.clone();
            bladeless.blades = 0;
            assert_eq!(spec.blocked, blocked_rotor_stator(&bladeless).unwrap().blocked, "h = {h}, {sweep:?}");
            // each baffle is two faces of the head patch, back to back
            let head = mesh.patch("head").unwrap();
            let n_baffle_sides: u32 = spec.baffles.iter().map(|b| b.count_ones()).sum();
            assert!(n_baffle_sides > 0);
            let mut centres: Vec<[i64; 3]> = head.faces().map(|f| mesh.face_centres[f].map(|x| (x * 1e9).round() as i64).into()).collect();
            let n = centres.len();
            centres.sort_unstable();
            centres.dedup();
            assert_eq!(n - centres.len(), n_baffle_sides as usize / 2, "h = {h}, {sweep:?}: baffles as pairs of coincident head faces");
            // the blades part the annulus: no connected group of cells reaches two passages, and
            // every passage has cells; without blades the annulus is one group
            let groups = passages_of_connected_groups(&section, &mesh);
            assert!(groups.iter().all(|g| g.len() == 1), "h = {h}, {sweep:?}: a group spans passages {groups:?}");
            let mut seen: Vec<usize> = groups.concat();
            seen.sort_unstable();
            seen.dedup();
            assert_eq!(seen, (0..section.blades).collect::<Vec<_>>(), "h = {h}, {sweep:?}");
            let open = passages_of_connected_groups(&bladeless, &build(&bladeless).unwrap());
            assert_eq!(open.len(), 1, "h = {h}, {sweep:?}: {open:?}");
        }
    }

    pub(crate) fn eccentric(cell_size: f64, radii: [f64; 2]) -> CutterHeadSection {
        let mut section = section(cell_size);
        section.suction = crate::cutter_head::Suction::Eccentric { angle: 180.0, width: 103.0, radii };
        section
    }

    /// The back plate at rest: every face toward it is in `suction` (none in `head`, which
    /// turns), it closes the inner ring area at z = 0 except the shaft, and the rest of it is
    /// the housing's side above the ring; the mouth's faces at unit shares are the plate's.
    #[test]
    fn an_eccentric_mouth_lies_in_a_back_plate_at_rest() {
        let section = eccentric(0.04, [0.07, 0.2]);
        let mesh = build(&section).unwrap();
        assert_cells_closed(&mesh);
        assert_boundary_faces_outward(&mesh);
        let suction = mesh.patch("suction").unwrap();
        let spec = blocked_rotor_stator(&section).unwrap();
        let n_t = spec.n_theta_rotor;
        // the plate: the tops of the open cells under z = 0 inside the ring (up to the edge
        // below its inner radius), planar annular sectors
        let plate: f64 = suction.faces().filter(|&f| mesh.face_centres[f].z.abs() < 1e-12).map(|f| mesh.face_areas[f].z).sum();
        let rim = spec.rotor_r.iter().copied().filter(|&r| r <= section.ring_inner_radius).fold(0.0, f64::max);
        let expected = polygon_ring(n_t, spec.rotor_r[0], rim);
        assert!((plate - expected).abs() < 1e-12 * expected, "plate {plate} vs {expected}");
        // the rest faces the axis from outside the housing, above the ring
        for f in suction.faces().filter(|&f| mesh.face_centres[f].z.abs() >= 1e-12) {
            let (c, s) = (mesh.face_centres[f], mesh.face_areas[f]);
            assert!(c.z > section.ring_thickness && s.z.abs() < 1e-12 * s.norm() && s.x * c.x + s.y * c.y < 0.0, "face {f} at {c:?}");
        }
        // no face of the head's rotating walls lies on the plate
        assert!(mesh
            .patch("head")
            .unwrap()
            .faces()
            .all(|f| mesh.face_centres[f].z.abs() > 1e-12 || mesh.face_centres[f].x.hypot(mesh.face_centres[f].y) > rim));
        // the window carries Q_m through these faces at the mesh's rest angle
        let window = suction_window(&section, &spec).unwrap();
        let q: f64 = suction.faces().map(|f| window.velocity(&mesh.face_centres[f]).dot(&mesh.face_areas[f])).sum();
        assert!((q - section.suction_discharge).abs() < 1e-14, "{q}");
    }

    #[test]
    fn a_mouth_over_the_blades_staircase_is_refused_with_the_radii_that_fit() {
        let err = blocked_rotor_stator(&eccentric(0.05, [0.07, 0.27])).unwrap_err().to_string();
        assert!(err.contains("cutter_head.suction.radii") && err.contains("radii within [0.06, "), "{err}");
    }

    #[test]
    fn an_axial_head_sucks_through_the_whole_inner_ring_area() {
        // the axial head of §4.1 (a): no back plate, the pipe as wide as the ring's inner radius
        let mut section = section(0.04);
        section.suction = crate::cutter_head::Suction::Axial;
        let mesh = build(&section).unwrap();
        let suction = mesh.patch("suction").unwrap();
        let widest = suction.faces().map(|f| mesh.face_centres[f].x.hypot(mesh.face_centres[f].y)).fold(0.0, f64::max);
        // the outlet reaches into the last open cell inside the pipe wall: within a cell of R_i
        assert!(widest < section.ring_inner_radius && widest > section.ring_inner_radius - 2.0 * section.mesh.cell_size, "{widest}");
        let mouth = build(&super::tests::section(0.04)).unwrap();
        assert!(suction.len > 2 * mouth.patch("suction").unwrap().len, "the axial outlet is much wider than the mouth");
    }

    #[test]
    fn a_point_in_a_blocked_cell_belongs_to_a_nearby_open_cell() {
        let section = section(0.04);
        let mesh = build(&section).unwrap();
        let head = CutterHead::new(&section);
        let (r, z) = (0.3, -0.2);
        let theta = head.blade_azimuth(1, r, z);
        let p = crate::mesh::Vec3::new(r * theta.cos(), r * theta.sin(), z);
        let cell = mesh.locate(&p).expect("on the blade: the nearest open cell");
        assert!((mesh.cell_centres[cell] - p).norm() < 3.0 * section.mesh.cell_size);
    }
}
