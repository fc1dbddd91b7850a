//! Spillage bookkeeping of a cutter head, shared by every solver
//! (spillage-and-flow-verification.md §5.1, §5.4):
//!
//! - every particle is inside the head, **sucked** (its centre rose `capture_height` into the
//!   suction pipe) or **spilled** (its centre left the contour hull), with the time and place
//!   it left; production and spillage fractions are P = sucked/created and S = spilled/created
//!   (Eq. 8.6, with P_ini the particles created so far, which for a batch is the batch);
//! - the fluid flux through the contour hull: the out-flowing flux Q_out = Σ pos(φ) (Eq. 8.4)
//!   and the net flux Σ φ, which continuity makes equal to the flux through the mouth (Q_m).
//!
//! The thesis interpolated cell-centre velocities onto a hull surface (Eqs. 8.1–8.2), whose
//! net flux missed Q_m by −3 % to +10 %. We sum the solver's own face fluxes over the faces
//! that separate the cells inside the hull from the rest (the staircase of the contour), so
//! the net hull flux equals the mouth flux to the solver's continuity tolerance and Q_out
//! converges with the mesh.

use super::geometry::CutterHead;
use crate::mesh::Mesh;
use crate::particles::bookkeeping::{ExitRecord, ExitRoute};
use crate::particles::state::Vec3;

/// Width of the exit-height bins under the ring (Fig. 8.8: "0–3 cm under the ring") [m].
pub const EXIT_BIN: f64 = 0.03;

/// The faces of the hull and of the mouth with the sign that makes their flux outward.
#[derive(Clone, Debug)]
pub struct HullFaces {
    /// (face, +1 or −1, face centre height) of every face between a cell inside the hull and
    /// one outside, except the mouth.
    pub hull: Vec<(usize, f64, f64)>,
    /// (face, sign) of the faces through which the hull's cells feed the suction (up).
    pub mouth: Vec<(usize, f64)>,
    /// With an eccentric mouth: the back plate's boundary faces over the hull's cells (the
    /// mouth is their condition, and their flux points out of the domain).
    pub plate: Vec<usize>,
}

/// The fluxes of one step [m³/s].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HullFlux {
    /// Q_out = Σ pos(φ) over the hull (Eq. 8.4).
    pub outflow: f64,
    /// Σ φ over the hull, outward positive: −Q_m when the head only feeds the suction.
    pub net: f64,
    /// Σ φ through the mouth, up (out of the head) positive.
    pub suction: f64,
    /// Q_out through the top `EXIT_BIN` under the ring.
    pub outflow_top_bin: f64,
}

impl HullFaces {
    /// Sorts the mesh's internal faces: a cell is inside when its centre lies between the hub
    /// and the ring and its innermost point within the contour radius R(z) (rotation leaves r
    /// and z alone, so this holds at every angle). The cells the contour crosses are inside
    /// because the blades' staircase fills the cells they touch: the hull wraps the blocked
    /// blade tips, as the thesis' hull wraps the blade contour, and converges to R(z) with the
    /// mesh. (A hull through the cell centres cut through the staircase tips at 5 cm cells and
    /// saw a fifth of the outflow between them.)
    pub fn new(head: &CutterHead, mesh: &Mesh) -> HullFaces {
        let inside = inside_cells(head, mesh);
        let (mut hull, mut mouth) = (Vec::new(), Vec::new());
        for f in 0..mesh.n_internal_faces {
            let (o, n) = (mesh.face_owner[f], mesh.face_neighbour[f]);
            if inside[o] == inside[n] {
                continue;
            }
            let sign = if inside[o] { 1.0 } else { -1.0 };
            let c = mesh.face_centres[f];
            let upward = mesh.face_areas[f].z.abs() > 0.9 * mesh.face_areas[f].norm();
            if upward && c.z >= -1e-9 && c.x.hypot(c.y) < head.opening_radius {
                mouth.push((f, sign));
            } else {
                hull.push((f, sign, c.z));
            }
        }
        let plate = match (head.mouth, mesh.patch("suction")) {
            (Some(_), Ok(patch)) => patch.faces().filter(|&f| inside[mesh.face_owner[f]] && mesh.face_areas[f].z > 0.9 * mesh.face_areas[f].norm()).collect(),
            _ => Vec::new(),
        };
        HullFaces { hull, mouth, plate }
    }

    /// The fluxes of the face flux field `flux` (absolute u·S per face).
    pub fn flux(&self, flux: &[f64]) -> HullFlux {
        let (mut outflow, mut net, mut top) = (0.0, 0.0, 0.0);
        for &(f, sign, z) in &self.hull {
            let phi = sign * flux[f];
            net += phi;
            if phi > 0.0 {
                outflow += phi;
                if z >= -EXIT_BIN {
                    top += phi;
                }
            }
        }
        let suction = self.mouth.iter().map(|&(f, sign)| sign * flux[f]).sum::<f64>() + self.plate.iter().map(|&f| flux[f]).sum::<f64>();
        HullFlux { outflow, net, suction, outflow_top_bin: top }
    }
}

/// Per cell: inside the contour hull ([`HullFaces::new`] says which and why).
pub fn inside_cells(head: &CutterHead, mesh: &Mesh) -> Vec<bool> {
    (0..mesh.n_cells())
        .map(|cell| {
            let c = mesh.cell_centres[cell];
            // the mesh at rest: a turned rotor's radii differ by round-off, and a cell edge on
            // the contour (`blades = "baffles"`) would flip sides with the rotor angle (and on a
            // restart); an edge within round-off of R(z) counts as on it
            let points = &mesh.reference_points;
            let r_min = mesh.cell_points[cell].iter().map(|&p| points[p].x.hypot(points[p].y)).fold(f64::INFINITY, f64::min);
            let radius = head.radius_at(c.z);
            c.z >= -head.height() && c.z <= 0.0 && r_min < radius - 1e-9 * radius
        })
        .collect()
}

/// Where a particle at a body-frame position has gone, if it left the head: sucked (in the
/// pipe, `capture_height` above its entrance) or spilled (outside the contour hull, below the
/// hub, or beside the pipe above the ring). A particle between the hull and the capture height
/// (in the mouth) is still inside.
pub fn exit_route(head: &CutterHead, position: &Vec3) -> Option<ExitRoute> {
    let (r, z) = (position.x.hypot(position.y), position.z);
    if head.sucked(r, z) {
        return Some(ExitRoute::Sucked);
    }
    let in_mouth = z > 0.0 && r < head.opening_radius;
    if head.inside_hull(r, z) || in_mouth {
        None
    } else {
        Some(ExitRoute::Spilled)
    }
}

/// Particle counts of a head: sucked, spilled and any other exit, from the exit log.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SpillageCounts {
    pub sucked: u64,
    pub spilled: u64,
    pub other: u64,
}

impl SpillageCounts {
    pub fn from_exits(exits: &[ExitRecord]) -> SpillageCounts {
        let mut counts = SpillageCounts::default();
        for e in exits {
            match e.route {
                ExitRoute::Sucked => counts.sucked += 1,
                ExitRoute::Spilled => counts.spilled += 1,
                _ => counts.other += 1,
            }
        }
        counts
    }
}

/// Spilled particles per exit-height bin under the ring: bin b holds exits with
/// −(b+1)·EXIT_BIN ≤ z < −b·EXIT_BIN (bin 0: 0–3 cm under the ring); exits above the ring
/// count in bin 0, exits below the hub in the last bin. Returns (bin top z, count) pairs.
pub fn exit_height_histogram(head: &CutterHead, exits: &[ExitRecord]) -> Vec<(f64, u64)> {
    let n_bins = (head.height() / EXIT_BIN).ceil() as usize;
    let mut counts = vec![0u64; n_bins];
    for e in exits.iter().filter(|e| e.route == ExitRoute::Spilled) {
        let depth = (-e.position[2]).max(0.0);
        counts[((depth / EXIT_BIN) as usize).min(n_bins - 1)] += 1;
    }
    counts.into_iter().enumerate().map(|(b, n)| (-(b as f64) * EXIT_BIN, n)).collect()
}

/// The spillage fraction of a continuous feed once it is steady: of the particles that left
/// the head at or after `from` [s], the share spilled, S = spilled / (spilled + sucked) (the
/// rate form of Eq. 4.55), with its 95 % Wilson score interval (each exit a Bernoulli trial).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SteadySpillage {
    pub fraction: f64,
    pub low: f64,
    pub high: f64,
    /// Exits counted.
    pub exits: u64,
}

/// [`SteadySpillage`] of the exits at or after `from`; `None` when none left.
pub fn steady_spillage(exits: &[ExitRecord], from: f64) -> Option<SteadySpillage> {
    let (mut spilled, mut sucked) = (0u64, 0u64);
    for e in exits.iter().filter(|e| e.time >= from) {
        match e.route {
            ExitRoute::Spilled => spilled += 1,
            ExitRoute::Sucked => sucked += 1,
            _ => {}
        }
    }
    let n = spilled + sucked;
    if n == 0 {
        return None;
    }
    let (nf, p) = (n as f64, spilled as f64 / n as f64);
    // z = 1.96 for 95 %; the Wilson interval stays inside [0, 1] and is sound for small n
    let z2 = 1.96f64 * 1.96;
    let centre = (p + z2 / (2.0 * nf)) / (1.0 + z2 / nf);
    let half = 1.96 * (p * (1.0 - p) / nf + z2 / (4.0 * nf * nf)).sqrt() / (1.0 + z2 / nf);
    Some(SteadySpillage { fraction: p, low: centre - half, high: centre + half, exits: n })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn head() -> CutterHead {
        super::super::geometry::tests::head()
    }

    #[test]
    fn particles_are_sucked_in_the_pipe_and_spilled_outside_the_contour() {
        let head = head();
        let at = |r: f64, z: f64| exit_route(&head, &Vec3::new(r, 0.0, z));
        assert_eq!(at(0.2, -0.2), None);
        assert_eq!(at(0.05, head.ring_top() + 0.5 * head.capture_height), None, "in the mouth, not yet captured");
        assert_eq!(at(0.05, head.ring_top() + 1.01 * head.capture_height), Some(ExitRoute::Sucked));
        assert_eq!(at(1.01 * head.radius_at(-0.1), -0.1), Some(ExitRoute::Spilled));
        assert_eq!(at(0.1, -head.height() - 0.01), Some(ExitRoute::Spilled));
        assert_eq!(at(0.3, 0.05), Some(ExitRoute::Spilled), "beside the pipe above the ring");
    }

    /// With an eccentric mouth the pipe is not meshed: a particle is sucked once its centre has
    /// passed the back plate, which only the mouth lets it do.
    #[test]
    fn behind_an_eccentric_mouth_a_particle_is_sucked_at_the_plate() {
        let mut section = crate::cutter_head::fluid_mesh::tests::eccentric(0.05, [0.07, 0.2]);
        section.capture_height = 0.05;
        let head = CutterHead::new(&section);
        let at = |r: f64, z: f64| exit_route(&head, &Vec3::new(-r, 0.0, z));
        assert_eq!(at(0.15, -0.001), None);
        assert_eq!(at(0.15, 0.001), Some(ExitRoute::Sucked));
        assert_eq!(at(0.3, 0.001), Some(ExitRoute::Spilled), "above the ring, outside the plate");
    }

    #[test]
    fn steady_spillage_counts_the_window_and_brackets_the_fraction() {
        let exit = |t: f64, route: ExitRoute| ExitRecord { particle: 0, time: t, position: [0.4, 0.0, -0.1], velocity: [0.0; 3], diameter: 0.02, route };
        // before the window: ignored; in it: 30 spilled, 70 sucked, one domain exit not counted
        let mut exits: Vec<ExitRecord> = (0..50).map(|_| exit(0.5, ExitRoute::Spilled)).collect();
        exits.extend((0..30).map(|_| exit(1.5, ExitRoute::Spilled)));
        exits.extend((0..70).map(|_| exit(1.6, ExitRoute::Sucked)));
        exits.push(exit(1.7, ExitRoute::Domain));
        let s = steady_spillage(&exits, 1.0).unwrap();
        assert_eq!((s.fraction, s.exits), (0.3, 100));
        // the Wilson 95 % interval of 30/100, to its printed 4 digits: [0.2189, 0.3959] (computed independently)
        assert!((s.low - 0.2189).abs() < 1e-4 && (s.high - 0.3959).abs() < 1e-4, "{s:?}");
        assert_eq!(steady_spillage(&exits, 2.0), None);
    }

    #[test]
    fn exit_heights_are_binned_under_the_ring() {
        let head = head();
        let exit = |z: f64, route: ExitRoute| ExitRecord { particle: 0, time: 0.0, position: [0.4, 0.0, z], velocity: [0.0; 3], diameter: 0.02, route };
        let exits = [
            exit(-0.01, ExitRoute::Spilled),
            exit(-0.029, ExitRoute::Spilled),
            exit(-0.031, ExitRoute::Spilled),
            exit(-0.01, ExitRoute::Sucked),
            exit(-1.0, ExitRoute::Spilled),
        ];
        let bins = exit_height_histogram(&head, &exits);
        assert_eq!(bins[0], (0.0, 2));
        assert_eq!(bins[1].1, 1);
        assert_eq!(bins.last().unwrap().1, 1, "below the hub: the last bin");
        assert_eq!(bins.iter().map(|b| b.1).sum::<u64>(), 4, "the sucked one is not spillage");
        assert_eq!(SpillageCounts::from_exits(&exits), SpillageCounts { sucked: 1, spilled: 4, other: 0 });
    }
}
