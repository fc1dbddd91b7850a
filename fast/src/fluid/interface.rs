//! Sliding-interface overlaps in O(faces): both sides share the z layers, so in each layer the
//! overlaps are a merge sweep of two periodic θ partitions (the rotor one turned by the zone
//! angle), `spillage_model::mesh::SlidingInterface::overlaps_into`, which also gives each
//! overlap's θ bounds. Each overlap becomes one link whose geometry is the construction shared
//! with the reference, `spillage_model::mesh::InterfaceFrame::overlap_link` (area = chord of the
//! true circle over the overlap, so the rotor and stator cells stay closed and the interface
//! balances by construction; d, w and the skewness vector k that the predicted flux's
//! correction (k·∇u)_f uses, issue 12).

use spillage_model::mesh::{Mesh, Overlap, SlidingInterface};

use super::layout::{Links, Rotor};

/// Cylindrical frame of the interface: the one construction both solvers use.
pub use spillage_model::mesh::InterfaceFrame as Frame;

/// Appends the overlap links of `interface` at rotor-zone angle `angle` to `links`; each
/// link's geometry is [`Frame::overlap_link`] (chord of the true circle, centre, d, w, skewness
/// vector k), its mesh flux the rotor velocity at the overlap centre.
pub fn push_overlaps(
    mesh: &Mesh,
    interface: &SlidingInterface,
    frame: &Frame,
    angle: f64,
    rotor: Option<&Rotor>,
    overlaps: &mut Vec<Overlap>,
    links: &mut Links,
) {
    let radius = interface.radius;
    interface.overlaps_into(angle, overlaps);
    for o in overlaps.iter() {
        // touching end points are not overlaps (the reference's threshold: 1e-13 of the face span)
        if o.rotor_fraction <= 1e-13 {
            continue;
        }
        let (z_lo, z_hi) = (interface.z_edges[o.layer], interface.z_edges[o.layer + 1]);
        let (rotor_face, stator_face) = (o.rotor_face, o.stator_face);
        let owner = mesh.face_owner[rotor_face];
        let neighbour = mesh.face_owner[stator_face];
        let g = frame.overlap_link(
            radius,
            o.theta_lo,
            o.theta_hi,
            z_lo,
            z_hi,
            &mesh.face_areas[rotor_face],
            &mesh.cell_centres[owner],
            &mesh.cell_centres[neighbour],
        );
        let mesh_flux = rotor.map_or(0.0, |r| r.velocity_at(&g.centre).dot(&g.area));
        links.push_overlap(owner, neighbour, g.area, g.delta, g.weight, g.skew, mesh_flux, rotor_face, stator_face);
    }
}
