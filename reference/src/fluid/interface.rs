//! Sliding-interface coupling (spec §4.2): each overlap of a rotor-side and a stator-side
//! interface face becomes one link between the two cells, carrying one flux, so the interface
//! balances by construction.
//!
//! Geometry of an overlap [R, our construction]: the rotor and stator faces are flat chords of
//! the interface cylinder between their θ end points. The overlap [θ₁, θ₂] × [z₁, z₂] gets the
//! area vector of the chord of the *true* circle between θ₁ and θ₂,
//! S = (c(θ₂) − c(θ₁)) × axis · (z₂ − z₁). Because the overlaps of a face tile its θ range, their
//! chords telescope to the face's own chord: both the rotor and the stator cells stay exactly
//! closed (Σ S = 0), so a uniform flow crosses the interface unchanged (free-stream
//! preservation), and a rigid rotation of the rotor sweeps no volume through the overlaps
//! (the chord midpoint velocity ω×r is parallel to the chord).
//!
//! The construction is shared with the fast solver: `spillage_model::mesh::InterfaceFrame::
//! overlap_link` gives the area, centre, d = x_N − x_P, the weight w from the normal distances
//! and the skewness vector k = x_f − (w x_P + (1 − w) x_N). Rotor and stator cell centres lie at
//! different θ, so d is not parallel to S (the schemes' over-relaxed split handles that) and the
//! linear interpolation point lies O(h) beside the overlap centre; the predicted flux corrects
//! (A⁻¹H)_f by (k·∇u)_f there (`pressure`, issue 12), without which a swirling flow gets a
//! first-order spurious radial velocity at the interface.
//!
//! The area fractions of spec (T3.33), A_s∩A_t / A_t, are |S_overlap| / |S_face| of this
//! construction; they are not needed separately because the flux, not a face value, is what
//! crosses the interface.

use std::f64::consts::PI;

use spillage_model::mesh::{InterfaceFrame, InterfaceSide, Mesh, PatchKind, Vec3};

use super::geometry::{Link, LinkOrigin, RotorMotion};

/// Angular and axial extent of one interface face.
#[derive(Clone, Copy, Debug)]
struct FaceExtent {
    face: usize,
    theta_lo: f64,
    theta_hi: f64,
    z_lo: f64,
    z_hi: f64,
}

fn face_extent(mesh: &Mesh, frame: &InterfaceFrame, face: usize, radius_sum: &mut f64, count: &mut usize) -> FaceExtent {
    let pts = mesh.face_points[face];
    let (t0, _, _) = frame.theta_z_r(&mesh.points[pts[0]]);
    let (mut theta_lo, mut theta_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut z_lo, mut z_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &p in &pts {
        let (mut t, z, r) = frame.theta_z_r(&mesh.points[p]);
        // unwrap relative to the first point so a face across θ = ±π stays contiguous
        while t - t0 > PI {
            t -= 2.0 * PI;
        }
        while t - t0 < -PI {
            t += 2.0 * PI;
        }
        theta_lo = theta_lo.min(t);
        theta_hi = theta_hi.max(t);
        z_lo = z_lo.min(z);
        z_hi = z_hi.max(z);
        *radius_sum += r;
        *count += 1;
    }
    FaceExtent { face, theta_lo, theta_hi, z_lo, z_hi }
}

/// Overlap links of every sliding interface of the mesh in its current position.
/// `axis`/`origin` come from the rotor zone; `rotor` gives the mesh velocity of the rotor side.
pub fn interface_links(mesh: &Mesh, axis: Vec3, origin: Vec3, rotor: Option<&RotorMotion>) -> Vec<Link> {
    let frame = InterfaceFrame::new(origin, axis);
    let mut links = Vec::new();
    let n_interfaces = mesh
        .patches
        .iter()
        .filter_map(|p| match p.kind {
            PatchKind::Interface { interface, .. } => Some(interface + 1),
            _ => None,
        })
        .max()
        .unwrap_or(0);
    for which in 0..n_interfaces {
        let (mut radius_sum, mut count) = (0.0, 0usize);
        let mut rotor_faces = Vec::new();
        let mut stator_faces = Vec::new();
        for patch in &mesh.patches {
            if let PatchKind::Interface { interface, side } = patch.kind {
                if interface != which {
                    continue;
                }
                for f in patch.faces() {
                    let e = face_extent(mesh, &frame, f, &mut radius_sum, &mut count);
                    match side {
                        InterfaceSide::Rotor => rotor_faces.push(e),
                        InterfaceSide::Stator => stator_faces.push(e),
                    }
                }
            }
        }
        if count == 0 {
            continue;
        }
        let radius = radius_sum / count as f64;
        for r in &rotor_faces {
            for s in &stator_faces {
                let z_lo = r.z_lo.max(s.z_lo);
                let z_hi = r.z_hi.min(s.z_hi);
                if z_hi - z_lo <= 1e-12 * (r.z_hi - r.z_lo) {
                    continue;
                }
                for k in [-1.0, 0.0, 1.0] {
                    let shift = 2.0 * PI * k;
                    let lo = r.theta_lo.max(s.theta_lo + shift);
                    let hi = r.theta_hi.min(s.theta_hi + shift);
                    // touching end points are not overlaps; 1e-13 of the face span is far
                    // below any mesh spacing and far above the round-off of atan2
                    if hi - lo <= 1e-13 * (r.theta_hi - r.theta_lo) {
                        continue;
                    }
                    links.push(overlap_link(mesh, &frame, radius, r.face, s.face, lo, hi, z_lo, z_hi, rotor));
                }
            }
        }
    }
    links
}

/// The link of one overlap: geometry from the shared construction
/// [`InterfaceFrame::overlap_link`] (chord of the true circle, centre, d, w and the skewness
/// vector k), the rotor's mesh flux at the overlap centre.
#[allow(clippy::too_many_arguments)]
fn overlap_link(
    mesh: &Mesh,
    frame: &InterfaceFrame,
    radius: f64,
    rotor_face: usize,
    stator_face: usize,
    theta_lo: f64,
    theta_hi: f64,
    z_lo: f64,
    z_hi: f64,
    rotor: Option<&RotorMotion>,
) -> Link {
    let owner = mesh.face_owner[rotor_face];
    let neighbour = mesh.face_owner[stator_face];
    let g = frame.overlap_link(radius, theta_lo, theta_hi, z_lo, z_hi, &mesh.face_areas[rotor_face], &mesh.cell_centres[owner], &mesh.cell_centres[neighbour]);
    let mesh_flux = match rotor {
        Some(r) => r.velocity_at(&g.centre).dot(&g.area),
        None => 0.0,
    };
    Link {
        owner,
        neighbour,
        area: g.area,
        centre: g.centre,
        delta: g.delta,
        weight: g.weight,
        mesh_flux,
        origin: LinkOrigin::Interface { rotor_face, stator_face },
        skew: g.skew,
    }
}
