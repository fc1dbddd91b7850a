//! Sliding-interface overlaps in O(faces): both sides share the z layers, so in each layer the
//! overlaps are a merge sweep of two periodic θ partitions (the rotor one turned by the zone
//! angle). Each overlap becomes one link whose area is the chord of the true circle over the
//! overlap (the reference's construction, `spillage_reference::fluid::interface`), so the
//! rotor and stator cells stay closed and the interface balances by construction.

use std::f64::consts::TAU;

use spillage_model::mesh::{Mesh, SlidingInterface, Vec3};

use super::layout::{Links, Rotor};

/// Cylindrical frame of the interface (same construction as the reference's).
#[derive(Clone, Debug)]
pub struct Frame {
    pub origin: Vec3,
    pub axis: Vec3,
    e1: Vec3,
    e2: Vec3,
}

impl Frame {
    pub fn new(origin: Vec3, axis: Vec3) -> Frame {
        let axis = axis.normalize();
        let trial = if axis.x.abs() < 0.9 { Vec3::x() } else { Vec3::y() };
        let e1 = (trial - axis * trial.dot(&axis)).normalize();
        let e2 = axis.cross(&e1);
        Frame { origin, axis, e1, e2 }
    }

    fn circle_point(&self, radius: f64, theta: f64) -> Vec3 {
        self.origin + (self.e1 * theta.cos() + self.e2 * theta.sin()) * radius
    }
}

/// Merge sweep of the rotor θ partition turned by `angle` against the stator partition;
/// `emit(i, j, θ_lo, θ_hi)` for every overlap wider than 10⁻¹³ of its rotor face (the
/// reference's threshold for "touching end points").
fn periodic_sweep(rotor_edges: &[f64], stator_edges: &[f64], angle: f64, mut emit: impl FnMut(usize, usize, f64, f64)) {
    let (n_r, n_s) = (rotor_edges.len() - 1, stator_edges.len() - 1);
    let shift = angle.rem_euclid(TAU);
    let rotor = |i: usize| rotor_edges[i] + shift;
    let stator = |m: i64| {
        let n = n_s as i64;
        stator_edges[m.rem_euclid(n) as usize] + TAU * m.div_euclid(n) as f64
    };
    let start = rotor(0);
    let mut m = ((start - stator_edges[0]) / TAU).floor() as i64 * n_s as i64;
    while stator(m) > start {
        m -= 1;
    }
    while stator(m + 1) <= start {
        m += 1;
    }
    let mut i = 0;
    let mut current = start;
    loop {
        let (rotor_end, stator_end) = (rotor(i + 1), stator(m + 1));
        let end = rotor_end.min(stator_end);
        if end - current > 1e-13 * (rotor_end - rotor(i)) {
            emit(i, m.rem_euclid(n_s as i64) as usize, current, end);
        }
        current = current.max(end);
        if stator_end <= rotor_end {
            m += 1;
        }
        if rotor_end <= stator_end {
            i += 1;
            if i == n_r {
                break;
            }
        }
    }
}

/// Appends the overlap links of `interface` at rotor-zone angle `angle` to `links`.
pub fn push_overlaps(mesh: &Mesh, interface: &SlidingInterface, frame: &Frame, angle: f64, rotor: Option<&Rotor>, links: &mut Links) {
    let radius = interface.radius;
    for layer in 0..interface.n_layers() {
        let (z_lo, z_hi) = (interface.z_edges[layer], interface.z_edges[layer + 1]);
        let rotor_faces = &interface.rotor_faces[layer * interface.n_theta_rotor..][..interface.n_theta_rotor];
        let stator_faces = &interface.stator_faces[layer * interface.n_theta_stator..][..interface.n_theta_stator];
        periodic_sweep(&interface.rotor_theta_edges, &interface.stator_theta_edges, angle, |i, j, lo, hi| {
            let (rotor_face, stator_face) = (rotor_faces[i], stator_faces[j]);
            let a = frame.circle_point(radius, lo);
            let b = frame.circle_point(radius, hi);
            let mut area = (b - a).cross(&frame.axis) * (z_hi - z_lo);
            if area.dot(&mesh.face_areas[rotor_face]) < 0.0 {
                area = -area;
            }
            let centre = (a + b) * 0.5 + frame.axis * (0.5 * (z_lo + z_hi));
            let owner = mesh.face_owner[rotor_face];
            let neighbour = mesh.face_owner[stator_face];
            let (xp, xn) = (mesh.cell_centres[owner], mesh.cell_centres[neighbour]);
            let n = area.normalize();
            let dp = (centre - xp).dot(&n).abs();
            let dn = (xn - centre).dot(&n).abs();
            let mesh_flux = rotor.map_or(0.0, |r| r.velocity_at(&centre).dot(&area));
            links.push_overlap(owner, neighbour, area, xn - xp, dn / (dp + dn), mesh_flux, rotor_face, stator_face);
        });
    }
}
