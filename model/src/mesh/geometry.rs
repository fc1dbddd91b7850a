//! Face and cell geometry, computed as OpenFOAM's primitiveMesh does: faces by triangle
//! decomposition about the point average, cells by pyramid decomposition about the face-centre
//! average (divergence theorem). Both are exact for planar faces, which is all the block
//! generators produce (spec fluid-dem-model.md §4.1: cell volumes constant under rotation).

use super::{Mesh, Vec3};

/// Local faces of a VTK_HEXAHEDRON, each ordered so its right-hand normal points out of the
/// cell. VTK order: points 0–3 are the bottom face counter-clockwise seen from above (+z),
/// 4–7 the top face above them; in index space point 0 = (0,0,0), 1 = (1,0,0), 2 = (1,1,0),
/// 3 = (0,1,0). Local face order: −x, +x, −y, +y, −z, +z (first, second, third index
/// direction; for cylindrical blocks r, θ, z).
pub const HEX_FACES: [[usize; 4]; 6] = [
    [3, 0, 4, 7], // −x
    [1, 2, 6, 5], // +x
    [0, 1, 5, 4], // −y
    [2, 3, 7, 6], // +y
    [0, 3, 2, 1], // −z
    [4, 5, 6, 7], // +z
];

/// Centre and area vector of a polygonal face (right-hand normal).
///
/// Triangles (p_i, p_{i+1}, p̄) about the point average p̄; the centre is the area-weighted
/// mean of triangle centroids with the areas projected on the face normal, so a planar face
/// gets its exact centroid and S_f = ½ Σ (p_{i+1} − p_i) × (p̄ − p_i).
pub fn face_centre_and_area(points: &[Vec3]) -> (Vec3, Vec3) {
    let n = points.len();
    let average = points.iter().sum::<Vec3>() / n as f64;
    let mut sum_normal = Vec3::zeros();
    for i in 0..n {
        let next = points[(i + 1) % n];
        sum_normal += (next - points[i]).cross(&(average - points[i]));
    }
    let magnitude = sum_normal.norm();
    if magnitude == 0.0 {
        return (average, Vec3::zeros());
    }
    let unit_normal = sum_normal / magnitude;
    let mut sum_area = 0.0;
    let mut sum_area_centre = Vec3::zeros();
    for i in 0..n {
        let next = points[(i + 1) % n];
        let triangle_normal = (next - points[i]).cross(&(average - points[i]));
        let signed_area = triangle_normal.dot(&unit_normal);
        sum_area += signed_area;
        sum_area_centre += signed_area * (points[i] + next + average);
    }
    (sum_area_centre / (3.0 * sum_area), 0.5 * sum_normal)
}

/// Centre and area vector of one local face of a hexahedral cell.
pub fn hex_face(points: &[Vec3], cell: &[usize; 8], local_face: usize) -> (Vec3, Vec3) {
    let ids = HEX_FACES[local_face];
    face_centre_and_area(&ids.map(|i| points[cell[i]]))
}

/// Centre and volume of a hexahedral cell from its six own faces.
///
/// Pyramids with base = face and apex = mean of the face centres: V = Σ S_f·(c_f − c̄)/3, centre
/// = Σ V_pyr (¾ c_f + ¼ c̄) / V (divergence theorem; exact for planar faces).
pub fn hex_centre_and_volume(points: &[Vec3], cell: &[usize; 8]) -> (Vec3, f64) {
    let faces: [(Vec3, Vec3); 6] = std::array::from_fn(|k| hex_face(points, cell, k));
    let estimate = faces.iter().map(|(c, _)| *c).sum::<Vec3>() / 6.0;
    let mut three_volume = 0.0;
    let mut sum_volume_centre = Vec3::zeros();
    for (centre, area) in &faces {
        let pyramid = area.dot(&(centre - estimate));
        three_volume += pyramid;
        sum_volume_centre += pyramid * (0.75 * centre + 0.25 * estimate);
    }
    if three_volume == 0.0 {
        return (estimate, 0.0);
    }
    (sum_volume_centre / three_volume, three_volume / 3.0)
}

impl Mesh {
    /// Recompute centre and area of the given faces from `points`.
    pub fn update_face_geometry(&mut self, faces: impl IntoIterator<Item = usize>) {
        for f in faces {
            let ids = self.face_points[f];
            let (centre, area) = face_centre_and_area(&ids.map(|i| self.points[i]));
            self.face_centres[f] = centre;
            self.face_areas[f] = area;
        }
    }

    /// Recompute centre and volume of the given cells from `points`.
    pub fn update_cell_geometry(&mut self, cells: impl IntoIterator<Item = usize>) {
        for c in cells {
            let (centre, volume) = hex_centre_and_volume(&self.points, &self.cell_points[c]);
            self.cell_centres[c] = centre;
            self.cell_volumes[c] = volume;
        }
    }

    /// Periodic shift of an internal face (zero for an ordinary face).
    pub fn periodic_shift_of(&self, face: usize) -> Vec3 {
        for pair in &self.periodic {
            if pair.faces.binary_search(&face).is_ok() {
                return pair.shift;
            }
        }
        Vec3::zeros()
    }

    /// Recompute `face_delta` and `face_weight` of the given internal faces (others skipped).
    ///
    /// w = |S·(C_N − c_f)| / (|S·(c_f − C_P)| + |S·(C_N − c_f)|) with C_N the neighbour centre
    /// (its periodic image for periodic faces), as OpenFOAM's surfaceInterpolation.
    pub fn update_interpolation(&mut self, faces: impl IntoIterator<Item = usize>) {
        for f in faces {
            if f >= self.n_internal_faces {
                continue;
            }
            let owner_centre = self.cell_centres[self.face_owner[f]];
            let neighbour_image = self.cell_centres[self.face_neighbour[f]] - self.periodic_shift_of(f);
            let area = self.face_areas[f];
            let owner_distance = area.dot(&(self.face_centres[f] - owner_centre)).abs();
            let neighbour_distance = area.dot(&(neighbour_image - self.face_centres[f])).abs();
            self.face_delta[f] = neighbour_image - owner_centre;
            self.face_weight[f] = neighbour_distance / (owner_distance + neighbour_distance);
        }
    }

    /// Recompute all derived geometry from `points`.
    pub fn update_all_geometry(&mut self) {
        self.update_face_geometry(0..self.n_faces());
        self.update_cell_geometry(0..self.n_cells());
        self.update_interpolation(0..self.n_internal_faces);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_cube_is_exact_and_faces_point_outward() {
        let points: Vec<Vec3> = [(0., 0., 0.), (1., 0., 0.), (1., 1., 0.), (0., 1., 0.), (0., 0., 1.), (1., 0., 1.), (1., 1., 1.), (0., 1., 1.)]
            .iter()
            .map(|&(x, y, z)| Vec3::new(x, y, z))
            .collect();
        let cell = [0, 1, 2, 3, 4, 5, 6, 7];
        let (centre, volume) = hex_centre_and_volume(&points, &cell);
        assert_eq!(volume, 1.0);
        assert!((centre - Vec3::new(0.5, 0.5, 0.5)).norm() < 1e-15);
        let expected_normals =
            [Vec3::new(-1., 0., 0.), Vec3::new(1., 0., 0.), Vec3::new(0., -1., 0.), Vec3::new(0., 1., 0.), Vec3::new(0., 0., -1.), Vec3::new(0., 0., 1.)];
        for (k, expected) in expected_normals.iter().enumerate() {
            let (_, area) = hex_face(&points, &cell, k);
            assert_eq!(area, *expected, "local face {k}");
        }
    }

    #[test]
    fn trapezoid_face_centroid_is_exact() {
        // Trapezoid with parallel sides 2 (y = 0) and 1 (y = 1): area 1.5, centroid
        // y = h(2a + b)/(3(a + b)) with a = 1 (top), b = 2 (bottom) → 4/9.
        let quad = [Vec3::new(0., 0., 0.), Vec3::new(2., 0., 0.), Vec3::new(1.5, 1., 0.), Vec3::new(0.5, 1., 0.)];
        let (centre, area) = face_centre_and_area(&quad);
        assert!((area - Vec3::new(0., 0., 1.5)).norm() < 1e-15);
        assert!((centre - Vec3::new(1.0, 4.0 / 9.0, 0.0)).norm() < 1e-15);
    }
}
