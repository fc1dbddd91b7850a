//! Moving a mesh's points (a fluid mesh that follows a receding wall, wear-model.md §7.4: "mesh
//! movement driven by the wear velocity"), with the volumes and face mesh fluxes that keep the
//! discrete space-conservation law exact.
//!
//! [R, our construction] Under a deforming mesh the cells' volumes change, and the continuity
//! and momentum equations hold only if each cell's volume change equals the volume its faces
//! sweep (the geometric conservation law, GCL; Thomas & Lombard 1979). With the points moving
//! linearly in time from `old` to `new`, the volume of a cell bounded by the triangles
//! (pᵢ, pᵢ₊₁, p̄) of its faces (p̄ the face's point average, the triangulation
//! [`super::geometry::face_centre_and_area`] uses) is a cubic in time whose change is exactly
//! the faces' swept volume ∫₀¹ ∫_T(t) d·n dA dt, with d the displacement. On one triangle d is
//! linear, so ∫_T d·n dA = d̄·S(t) (d̄ the mean of its three vertices' displacements, S(t) its
//! area vector, quadratic in t), and Simpson's rule integrates S(t) exactly:
//!
//!   swept(T) = d̄ · (S(0) + 4 S(½) + S(1)) / 6.
//!
//! So the volumes of a deforming mesh are [`fan_volume`]s (the same triangulation), and
//! Σ_faces swept = V_new − V_old holds to round-off. On planar faces the fan volume equals the
//! pyramid volume [`super::geometry::hex_centre_and_volume`] computes, up to round-off.

use super::geometry::HEX_FACES;
use super::{Mesh, MeshError, Vec3};

/// Volume enclosed by the fan triangles (pᵢ, pᵢ₊₁, p̄) of a hexahedral cell's six faces: the sum
/// of the signed tetrahedra from the cell's first point (module doc).
pub fn fan_volume(points: &[Vec3], cell: &[usize; 8]) -> f64 {
    let apex = points[cell[0]];
    let mut six_volume = 0.0;
    for face in HEX_FACES {
        let corners = face.map(|i| points[cell[i]] - apex);
        let average = corners.iter().sum::<Vec3>() / 4.0;
        for i in 0..4 {
            six_volume += corners[i].dot(&corners[(i + 1) % 4].cross(&average));
        }
    }
    six_volume / 6.0
}

/// Volume swept by a quadrilateral face whose corners move linearly from `old` to `new`
/// (corner order as in `Mesh::face_points`, so it is positive when the face moves along its
/// area vector; module doc).
pub fn swept_volume(old: &[Vec3; 4], new: &[Vec3; 4]) -> f64 {
    let mid: [Vec3; 4] = std::array::from_fn(|i| (old[i] + new[i]) * 0.5);
    let average = |p: &[Vec3; 4]| p.iter().sum::<Vec3>() / 4.0;
    let (old_average, mid_average, new_average) = (average(old), average(&mid), average(new));
    let displacement_average = new_average - old_average;
    let area = |a: &Vec3, b: &Vec3, c: &Vec3| (b - a).cross(&(c - a)) * 0.5;
    let mut swept = 0.0;
    for i in 0..4 {
        let j = (i + 1) % 4;
        let simpson = (area(&old[i], &old[j], &old_average) + area(&mid[i], &mid[j], &mid_average) * 4.0 + area(&new[i], &new[j], &new_average)) / 6.0;
        let mean_displacement = (new[i] - old[i] + new[j] - old[j] + displacement_average) / 3.0;
        swept += mean_displacement.dot(&simpson);
    }
    swept
}

impl Mesh {
    /// Sets every cell's volume to its [`fan_volume`] (the volumes a deforming mesh keeps, so
    /// that its swept volumes balance them; module doc).
    pub fn use_fan_volumes(&mut self) {
        for c in 0..self.n_cells() {
            self.cell_volumes[c] = fan_volume(&self.points, &self.cell_points[c]);
        }
    }

    /// Moves the points to `new_points` (linearly in time, as far as the swept volumes are
    /// concerned), recomputes faces, cells (centres by pyramids, volumes by fans) and
    /// interpolation, and puts each face's swept volume along its area vector [m³] in `swept`
    /// (its storage reused). A cell whose volume would not stay positive is an error naming it,
    /// and leaves the mesh as it was.
    pub fn move_points(&mut self, new_points: &[Vec3], swept: &mut Vec<f64>) -> Result<(), MeshError> {
        if new_points.len() != self.n_points() {
            return Err(MeshError::input("moved points", new_points.len() as f64, "must be one per mesh point"));
        }
        if let Some(p) = new_points.iter().position(|p| !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite())) {
            return Err(MeshError::input("moved point", p as f64, "has a non-finite coordinate"));
        }
        for (c, ids) in self.cell_points.iter().enumerate() {
            let volume = fan_volume(new_points, ids);
            if !(volume > 0.0) {
                let centre = ids.iter().map(|&i| new_points[i]).sum::<Vec3>() / 8.0;
                return Err(MeshError::Motion(format!(
                    "cell {c} near ({:.4}, {:.4}, {:.4}) m would turn inside out (volume {volume:e} m³): the moved points cross one another",
                    centre.x, centre.y, centre.z
                )));
            }
        }
        swept.clear();
        swept.extend(self.face_points.iter().map(|ids| swept_volume(&ids.map(|i| self.points[i]), &ids.map(|i| new_points[i]))));
        self.points.copy_from_slice(new_points);
        self.update_face_geometry(0..self.n_faces());
        self.update_cell_geometry(0..self.n_cells());
        self.use_fan_volumes();
        self.update_interpolation(0..self.n_internal_faces);
        if let super::Locator::Box { deformed, moved_bounds, .. } = &mut self.locator {
            *deformed = true;
            *moved_bounds = self
                .points
                .iter()
                .fold([[f64::MAX; 3], [f64::MIN; 3]], |[lo, hi], p| [std::array::from_fn(|k| lo[k].min(p[k])), std::array::from_fn(|k| hi[k].max(p[k]))]);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::BoxSpec;

    fn graded_box() -> Mesh {
        let spec = BoxSpec { grading: [0.2, 1.5, 1.0], ..BoxSpec::uniform(Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.5, 0.1), [6, 4, 2]) };
        Mesh::cartesian_box(&spec).unwrap()
    }

    /// A wavy recession of the +x side, fading linearly to the −x side (as a followed wall
    /// bends the mesh), with a smaller sideways wobble so that every face family moves.
    fn wavy(points: &[Vec3], amplitude: f64) -> Vec<Vec3> {
        points
            .iter()
            .map(|p| {
                p + Vec3::new(amplitude * p.x * (1.0 + (7.0 * p.y).sin() * (11.0 * p.z).cos()), 0.1 * amplitude * (3.0 * p.x).sin() * p.y * (0.5 - p.y), 0.0)
            })
            .collect()
    }

    /// On the unmoved box, with planar faces, fans and pyramids give the same volumes (to
    /// round-off of sums of order 1e-2 m³: 1e-15 relative).
    #[test]
    fn fan_volumes_equal_pyramid_volumes_on_planar_faces() {
        let mesh = graded_box();
        for c in 0..mesh.n_cells() {
            let fan = fan_volume(&mesh.points, &mesh.cell_points[c]);
            assert!((fan - mesh.cell_volumes[c]).abs() <= 1e-15 * mesh.cell_volumes[c].max(1e-3), "cell {c}: {fan} vs {}", mesh.cell_volumes[c]);
        }
    }

    /// The GCL: each cell's volume change equals the volume its faces sweep (out of it), to
    /// round-off (1e-13 of the cell volume: sums of a few dozen products of order V), over a
    /// move that bends the faces out of plane.
    #[test]
    fn swept_volumes_balance_the_volume_change_of_every_cell() {
        let mut mesh = graded_box();
        mesh.use_fan_volumes();
        let before = mesh.cell_volumes.clone();
        let target = wavy(&mesh.points, 0.05);
        let mut swept = Vec::new();
        mesh.move_points(&target, &mut swept).unwrap();
        let mut net = vec![0.0; mesh.n_cells()];
        for (f, s) in swept.iter().enumerate() {
            net[mesh.face_owner[f]] += s;
            if f < mesh.n_internal_faces {
                net[mesh.face_neighbour[f]] -= s;
            }
        }
        let mut largest_change = 0.0f64;
        for c in 0..mesh.n_cells() {
            let change = mesh.cell_volumes[c] - before[c];
            largest_change = largest_change.max(change.abs() / before[c]);
            assert!((net[c] - change).abs() <= 1e-13 * before[c], "cell {c}: swept {} against ΔV {change}", net[c]);
        }
        // the move must change volumes for the check to mean anything
        assert!(largest_change > 1e-2, "largest relative volume change {largest_change}");
        // a rigid translation sweeps nothing net through any cell but moves every face
        let shifted: Vec<Vec3> = mesh.points.iter().map(|p| p + Vec3::new(0.01, 0.0, 0.0)).collect();
        mesh.move_points(&shifted, &mut swept).unwrap();
        // (a face across x sweeps 0.01 m × its area, 1e-5 m³ and more here)
        assert!(swept.iter().any(|s| s.abs() > 1e-6));
    }

    /// A move that folds a cell is refused with the cell named, and the mesh is untouched.
    #[test]
    fn a_move_that_inverts_a_cell_is_refused() {
        let mut mesh = graded_box();
        let before = mesh.points.clone();
        let mut target = mesh.points.clone();
        let far = target.iter().position(|p| p.x == 1.0).unwrap();
        target[far].x = -0.5;
        let error = mesh.move_points(&target, &mut Vec::new()).unwrap_err().to_string();
        assert!(error.contains("would turn inside out"), "{error}");
        assert_eq!(mesh.points, before);
    }
}
