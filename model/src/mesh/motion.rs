//! Rigid rotation of cell zones and the mesh flux it induces (spec fluid-dem-model.md §4.1).
//!
//! The rotor moves by resetting its points to the reference points turned by the current angle
//! (never by incremental turns), so geometry carries no accumulated round-off. Under rigid
//! rotation with angular velocity ω about the unit axis â through x₀ the mesh flux of a planar
//! face is φ_mesh,f = (ω â × (c_f − x₀))·S_f: the velocity is linear in x, so its face integral
//! is its value at the centroid. Summed over a closed cell it vanishes, ω â·Σ_f c_f × S_f = 0,
//! the discrete space-conservation law (volumes are constant).

use super::{Mesh, MeshError, Vec3, ZoneGeometry, ZoneRotation};
use nalgebra::{Rotation3, Unit};

/// Velocity ω â × (x − x₀) of point `x` on a body rotating rigidly at `omega` (rad/s) about the
/// unit `axis` â through `origin` x₀: the one definition of a rotating wall's, rotor face's and
/// rotor zone's velocity (spec fluid-dem-model.md §4.1, §7.4). Computed as (â ω) × (x − x₀).
#[inline]
pub fn rigid_rotation_velocity(omega: f64, axis: &Vec3, origin: &Vec3, x: &Vec3) -> Vec3 {
    (axis * omega).cross(&(x - origin))
}

/// Velocity ω â × (x − x₀) of a point moving with a zone rotating at `omega` (rad/s).
pub fn rigid_velocity(rotation: &ZoneRotation, omega: f64, point: &Vec3) -> Vec3 {
    rigid_rotation_velocity(omega, &rotation.axis, &rotation.origin, point)
}

impl Mesh {
    /// Axis and origin of the first rotating zone (the frame of the sliding interfaces), if any.
    pub fn rotating_zone_axis(&self) -> Option<(Vec3, Vec3)> {
        self.zones.iter().find_map(|z| z.rotation.as_ref()).map(|r| (r.axis, r.origin))
    }

    fn rotation_of(&self, zone: usize) -> Result<&ZoneRotation, MeshError> {
        let z = self.zones.get(zone).ok_or(MeshError::UnknownZone { zone, n_zones: self.zones.len() })?;
        z.rotation.as_ref().ok_or_else(|| MeshError::ZoneNotRotating { name: z.name.clone() })
    }

    /// Turn rotating zone `zone` to `angle` (rad, counter-clockwise about its axis) relative to
    /// its reference geometry: its points, and the centres, area vectors and deltas of its cells
    /// and faces turned from the angle-0 copy ([`super::ZoneGeometry`]; volumes and weights
    /// are rotation invariants and stay as they are).
    pub fn set_zone_angle(&mut self, zone: usize, angle: f64) -> Result<(), MeshError> {
        if !angle.is_finite() {
            return Err(MeshError::input("zone angle", angle, "must be finite"));
        }
        let rotation = self.rotation_of(zone)?.clone();
        let turn = Rotation3::from_axis_angle(&Unit::new_normalize(rotation.axis), angle);
        let origin = rotation.origin;
        let zone_data = &self.zones[zone];
        for &p in &zone_data.points {
            self.points[p] = origin + turn * (self.reference_points[p] - origin);
        }
        let faces = std::mem::take(&mut self.zones[zone].faces);
        let cells = std::mem::take(&mut self.zones[zone].cells);
        match self.zones[zone].reference_geometry.take() {
            Some(reference) => {
                // angle 0 is the reference itself, bit for bit
                let place = |x: &Vec3| if angle == 0.0 { *x } else { origin + turn * (x - origin) };
                let orient = |v: &Vec3| if angle == 0.0 { *v } else { turn * v };
                for (k, &f) in faces.iter().enumerate() {
                    self.face_centres[f] = place(&reference.face_centres[k]);
                    self.face_areas[f] = orient(&reference.face_areas[k]);
                    if f < self.n_internal_faces && !reference.face_periodic[k] {
                        self.face_delta[f] = orient(&reference.face_delta[k]);
                    }
                }
                for (k, &c) in cells.iter().enumerate() {
                    self.cell_centres[c] = place(&reference.cell_centres[k]);
                }
                self.update_interpolation(faces.iter().zip(&reference.face_periodic).filter(|(_, &periodic)| periodic).map(|(&f, _)| f));
                self.zones[zone].reference_geometry = Some(reference);
            }
            None => {
                self.update_face_geometry(faces.iter().copied());
                self.update_cell_geometry(cells.iter().copied());
                self.update_interpolation(faces.iter().copied());
            }
        }
        let zone_data = &mut self.zones[zone];
        zone_data.faces = faces;
        zone_data.cells = cells;
        zone_data.rotation.as_mut().expect("checked above").angle = angle;
        Ok(())
    }

    /// Keep the current (angle-0) geometry of every rotating zone as the reference that
    /// [`Mesh::set_zone_angle`] turns.
    pub(crate) fn capture_zone_geometry(&mut self) {
        for z in 0..self.zones.len() {
            if self.zones[z].rotation.is_none() {
                continue;
            }
            let zone = &self.zones[z];
            let face_periodic: Vec<bool> = zone.faces.iter().map(|&f| f < self.n_internal_faces && self.periodic_shift_of(f) != Vec3::zeros()).collect();
            let reference = ZoneGeometry {
                face_centres: zone.faces.iter().map(|&f| self.face_centres[f]).collect(),
                face_areas: zone.faces.iter().map(|&f| self.face_areas[f]).collect(),
                face_delta: zone.faces.iter().map(|&f| if f < self.n_internal_faces { self.face_delta[f] } else { Vec3::zeros() }).collect(),
                face_periodic,
                cell_centres: zone.cells.iter().map(|&c| self.cell_centres[c]).collect(),
            };
            self.zones[z].reference_geometry = Some(reference);
        }
    }

    /// Velocity of a point moving with rotating zone `zone` at angular velocity `omega`
    /// (e.g. a rotor wall's velocity, spec fluid-dem-model.md §4.1).
    pub fn zone_velocity(&self, zone: usize, omega: f64, point: &Vec3) -> Result<Vec3, MeshError> {
        Ok(rigid_velocity(self.rotation_of(zone)?, omega, point))
    }

    /// Mesh flux φ_mesh,f = (ω â × (c_f − x₀))·S_f of `face` moving with rotating zone `zone`.
    pub fn zone_face_mesh_flux(&self, zone: usize, omega: f64, face: usize) -> Result<f64, MeshError> {
        let velocity = rigid_velocity(self.rotation_of(zone)?, omega, &self.face_centres[face]);
        Ok(velocity.dot(&self.face_areas[face]))
    }

    /// Write the mesh flux of every face of rotating zone `zone` (its `faces` list) into
    /// `flux` (length `n_faces`); other entries are left unchanged.
    pub fn zone_mesh_fluxes(&self, zone: usize, omega: f64, flux: &mut [f64]) -> Result<(), MeshError> {
        let rotation = self.rotation_of(zone)?;
        if flux.len() != self.n_faces() {
            return Err(MeshError::input("mesh flux length", flux.len(), &format!("must equal the number of faces, {}", self.n_faces())));
        }
        for &f in &self.zones[zone].faces {
            flux[f] = rigid_velocity(rotation, omega, &self.face_centres[f]).dot(&self.face_areas[f]);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::cylindrical::tests::rotor_stator;
    use crate::mesh::test_support::*;
    use std::f64::consts::TAU;

    #[test]
    fn rotation_keeps_volumes_and_closes_cells() {
        let mut mesh = Mesh::rotor_stator(&rotor_stator()).unwrap();
        let volumes = mesh.cell_volumes.clone();
        let stator_centres = mesh.cell_centres[mesh.zones[1].cells[0]..].to_vec();
        for angle in [0.3, -2.0, 17.0 * TAU + 1.1] {
            mesh.set_zone_angle(0, angle).unwrap();
            for (c, (v, v0)) in mesh.cell_volumes.iter().zip(&volumes).enumerate() {
                // volumes are rotation invariants, kept from the reference geometry
                assert_eq!(v, v0, "cell {c}");
            }
            assert_cells_closed(&mesh);
            assert_internal_faces_oriented(&mesh);
            assert_boundary_faces_outward(&mesh);
            assert_eq!(&mesh.cell_centres[mesh.zones[1].cells[0]..], &stator_centres[..]);
            // The rotor centre of cell 0 turned by the angle.
            let reference = Mesh::rotor_stator(&rotor_stator()).unwrap().cell_centres[0];
            let expected = Rotation3::from_axis_angle(&Vec3::z_axis(), angle) * reference;
            assert!((mesh.cell_centres[0] - expected).norm() < 1e-14);
        }
    }

    #[test]
    fn turned_reference_geometry_is_the_geometry_of_the_turned_points() {
        let mut mesh = Mesh::rotor_stator(&rotor_stator()).unwrap();
        for angle in [0.3, -2.0, 17.0 * TAU + 1.1] {
            mesh.set_zone_angle(0, angle).unwrap();
            let mut recomputed = mesh.clone();
            recomputed.update_all_geometry();
            // O(1) coordinates: the two routes differ by the round-off of a few operations
            let close = |a: &[Vec3], b: &[Vec3], what: &str| {
                for (k, (x, y)) in a.iter().zip(b).enumerate() {
                    assert!((x - y).norm() <= 1e-14 * (1.0 + y.norm()), "{what} {k}: {x} vs {y}");
                }
            };
            close(&mesh.face_centres, &recomputed.face_centres, "face centre");
            close(&mesh.face_areas, &recomputed.face_areas, "face area");
            close(&mesh.face_delta, &recomputed.face_delta, "face delta");
            close(&mesh.cell_centres, &recomputed.cell_centres, "cell centre");
            for (k, (w, v)) in mesh.face_weight.iter().zip(&recomputed.face_weight).enumerate() {
                assert!((w - v).abs() < 1e-13, "face weight {k}: {w} vs {v}");
            }
            for (k, (w, v)) in mesh.cell_volumes.iter().zip(&recomputed.cell_volumes).enumerate() {
                assert!((w - v).abs() < 1e-14 * v, "cell volume {k}: {w} vs {v}");
            }
        }
        mesh.set_zone_angle(0, 0.0).unwrap();
        let fresh = Mesh::rotor_stator(&rotor_stator()).unwrap();
        assert_eq!(mesh.face_centres, fresh.face_centres);
        assert_eq!(mesh.cell_centres, fresh.cell_centres);
        assert_eq!(mesh.face_delta, fresh.face_delta);
    }

    #[test]
    fn rotation_does_not_accumulate() {
        let mut turned = Mesh::rotor_stator(&rotor_stator()).unwrap();
        let mut direct = turned.clone();
        let mut random = Lcg::new(3);
        for _ in 0..500 {
            turned.set_zone_angle(0, TAU * (4.0 * random.next() - 2.0)).unwrap();
        }
        turned.set_zone_angle(0, 1.25).unwrap();
        direct.set_zone_angle(0, 1.25).unwrap();
        assert_eq!(turned.points, direct.points);
        assert_eq!(turned.face_areas, direct.face_areas);
        turned.set_zone_angle(0, 0.0).unwrap();
        assert_eq!(turned.points, turned.reference_points);
    }

    #[test]
    fn interface_faces_follow_the_overlap_convention() {
        // After turning the rotor by a, rotor face j's centre sits at θ = (j + ½)Δθ + a,
        // the angle `SlidingInterface::overlaps(a)` assumes.
        let mut mesh = Mesh::rotor_stator(&rotor_stator()).unwrap();
        let angle = 0.7;
        mesh.set_zone_angle(0, angle).unwrap();
        let interface = &mesh.interfaces[0];
        let n = interface.n_theta_rotor;
        for (index, &f) in interface.rotor_faces.iter().enumerate() {
            let c = mesh.face_centres[f];
            let expected = (TAU * ((index % n) as f64 + 0.5) / n as f64 + angle).rem_euclid(TAU);
            assert!((c.y.atan2(c.x).rem_euclid(TAU) - expected).abs() < 1e-13);
        }
    }

    #[test]
    fn interface_weights_sum_to_one_on_the_generated_mesh() {
        let mut mesh = Mesh::rotor_stator(&rotor_stator()).unwrap();
        let n_faces = mesh.n_faces();
        let mut out = Vec::new();
        let mut worst: f64 = 0.0;
        for k in 0..1000 {
            let angle = -2.0 * TAU + 5.0 * TAU * k as f64 / 999.0;
            mesh.set_zone_angle(0, angle).unwrap();
            let interface = &mesh.interfaces[0];
            interface.overlaps_into(angle, &mut out);
            let mut rotor_sum = vec![0.0; n_faces];
            let mut stator_sum = vec![0.0; n_faces];
            let mut covered = vec![0.0; interface.n_layers()];
            for o in &out {
                rotor_sum[o.rotor_face] += o.rotor_fraction;
                stator_sum[o.stator_face] += o.stator_fraction;
                let layer = interface.rotor_faces.iter().position(|&f| f == o.rotor_face).unwrap() / interface.n_theta_rotor;
                covered[layer] += o.rotor_fraction * TAU / interface.n_theta_rotor as f64;
                // The faces really overlap: their centre angles differ by at most the sum of
                // their half widths.
                let theta = |f: usize| mesh.face_centres[f].y.atan2(mesh.face_centres[f].x);
                let gap = (theta(o.rotor_face) - theta(o.stator_face) + TAU / 2.0).rem_euclid(TAU) - TAU / 2.0;
                let reach = TAU / 2.0 / interface.n_theta_rotor as f64 + TAU / 2.0 / interface.n_theta_stator as f64;
                assert!(gap.abs() <= reach + 1e-12, "angle {angle}: {o:?}");
            }
            for &f in &interface.rotor_faces {
                worst = worst.max((rotor_sum[f] - 1.0).abs());
            }
            for &f in &interface.stator_faces {
                worst = worst.max((stator_sum[f] - 1.0).abs());
            }
            for c in covered {
                worst = worst.max((c - TAU).abs());
            }
        }
        // Round-off of breakpoints ≤ 4π relative to face widths 2π/24: ~50ε.
        assert!(worst < 1e-13, "worst deviation {worst:e}");
    }

    #[test]
    fn mesh_flux_conserves_space_on_every_rotor_cell() {
        let mut mesh = Mesh::rotor_stator(&rotor_stator()).unwrap();
        let omega = 2.5;
        let mut flux = vec![f64::NAN; mesh.n_faces()];
        for angle in [0.0, 0.4, -5.0] {
            mesh.set_zone_angle(0, angle).unwrap();
            mesh.zone_mesh_fluxes(0, omega, &mut flux).unwrap();
            for &c in &mesh.zones[0].cells {
                let mut sum = 0.0;
                let mut scale = 0.0;
                for &f in mesh.faces_of_cell(c) {
                    let outward = if mesh.face_owner[f] == c { flux[f] } else { -flux[f] };
                    sum += outward;
                    scale += flux[f].abs();
                }
                // Six terms of size ≤ scale, each with ~1e-16 relative round-off.
                assert!(sum.abs() <= 1e-14 * scale, "cell {c}: Σφ = {sum} (scale {scale})");
                assert!(scale > 0.0);
            }
            // Stator faces untouched.
            let stator_face = mesh.zones[1].faces.iter().find(|f| mesh.zones[0].faces.binary_search(f).is_err());
            assert!(flux[*stator_face.unwrap()].is_nan());
        }
    }

    #[test]
    fn mesh_flux_of_a_radial_face_is_its_swept_volume_rate() {
        // A +θ face between radii r_a, r_b sweeps the volume ½(r_b² − r_a²) h dθ per dθ:
        // φ = ω (r_a + r_b)/2 (r_b − r_a) h.
        let mut mesh = Mesh::rotor_stator(&rotor_stator()).unwrap();
        mesh.set_zone_angle(0, 0.9).unwrap();
        let omega = -1.5;
        let height = 0.15;
        for &c in &mesh.zones[0].cells {
            let ids = mesh.cell_points[c];
            let r_a = mesh.points[ids[0]].xy().norm();
            let r_b = mesh.points[ids[1]].xy().norm();
            let theta_face = mesh
                .faces_of_cell(c)
                .iter()
                .copied()
                .find(|&f| {
                    let quad = mesh.face_points[f];
                    [ids[2], ids[3], ids[6], ids[7]].iter().all(|p| quad.contains(p))
                })
                .unwrap();
            let outward = mesh.outward_area(theta_face, c);
            let sign = outward.dot(&mesh.face_areas[theta_face]).signum();
            let flux = sign * mesh.zone_face_mesh_flux(0, omega, theta_face).unwrap();
            let expected = omega * 0.5 * (r_a + r_b) * (r_b - r_a) * height;
            assert!((flux - expected).abs() < 1e-14 * expected.abs(), "cell {c}: {flux} vs {expected}");
        }
    }

    #[test]
    fn locate_after_rotation_agrees_with_brute_force() {
        let mut mesh = Mesh::rotor_stator(&rotor_stator()).unwrap();
        mesh.set_zone_angle(0, 2.2).unwrap();
        let mut random = Lcg::new(5);
        let mut found = 0;
        for _ in 0..2000 {
            let p = Vec3::new(4.2 * random.next() - 2.1, 4.2 * random.next() - 2.1, 0.4 * random.next() - 0.05);
            let brute = (0..mesh.n_cells()).find(|&c| mesh.contains(c, &p));
            match (mesh.locate(&p), brute) {
                (Some(c), Some(_)) => {
                    assert!(mesh.contains(c, &p));
                    found += 1;
                }
                (None, None) => {}
                (located, brute) => panic!("{p:?}: locate {located:?}, brute force {brute:?}"),
            }
        }
        assert!(found > 500);
    }

    #[test]
    fn rotating_a_static_zone_is_an_error() {
        let mut mesh = Mesh::rotor_stator(&rotor_stator()).unwrap();
        assert!(matches!(mesh.set_zone_angle(1, 0.1), Err(MeshError::ZoneNotRotating { .. })));
        assert!(matches!(mesh.set_zone_angle(5, 0.1), Err(MeshError::UnknownZone { .. })));
        assert!(mesh.set_zone_angle(0, f64::NAN).is_err());
    }
}
