//! Sliding-interface overlaps in O(faces): both sides share the z layers, so in each layer the
//! overlaps are a merge sweep of two periodic θ partitions (the rotor one turned by the zone
//! angle), `spillage_model::mesh::SlidingInterface::overlaps_into`, which also gives each
//! overlap's θ bounds. Each overlap becomes one link whose area is the chord of the true
//! circle over the overlap (the reference's construction, `spillage_reference::fluid::interface`), so the
//! rotor and stator cells stay closed and the interface balances by construction.

use spillage_model::mesh::{Mesh, Overlap, SlidingInterface, Vec3};

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

/// Appends the overlap links of `interface` at rotor-zone angle `angle` to `links`.
pub fn push_overlaps(mesh: &Mesh, interface: &SlidingInterface, frame: &Frame, angle: f64, rotor: Option<&Rotor>, overlaps: &mut Vec<Overlap>, links: &mut Links) {
    let radius = interface.radius;
    interface.overlaps_into(angle, overlaps);
    for o in overlaps.iter() {
        // touching end points are not overlaps (the reference's threshold: 1e-13 of the face span)
        if o.rotor_fraction <= 1e-13 {
            continue;
        }
        let (z_lo, z_hi) = (interface.z_edges[o.layer], interface.z_edges[o.layer + 1]);
        let (rotor_face, stator_face) = (o.rotor_face, o.stator_face);
        let a = frame.circle_point(radius, o.theta_lo);
        let b = frame.circle_point(radius, o.theta_hi);
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
    }
}
