//! Mesh invariants shared by the generator tests.

use super::{Mesh, Vec3};

/// Σ outward S_f over each cell's faces vanishes (closed cell). Tolerance 1e-14 of Σ|S_f|:
/// each component is a sum of six O(|S|) terms computed to ~1e-16 relative.
pub fn assert_cells_closed(mesh: &Mesh) {
    for c in 0..mesh.n_cells() {
        let mut sum = Vec3::zeros();
        let mut scale = 0.0;
        for &f in mesh.faces_of_cell(c) {
            sum += mesh.outward_area(f, c);
            scale += mesh.face_areas[f].norm();
        }
        assert!(sum.norm() <= 1e-14 * scale, "cell {c}: Σ S = {sum:?} (scale {scale})");
    }
}

/// S_f·(C_N − C_P) > 0 for every internal face (C_N the periodic image where needed) and
/// owner < neighbour.
pub fn assert_internal_faces_oriented(mesh: &Mesh) {
    for f in 0..mesh.n_internal_faces {
        let (owner, neighbour) = (mesh.face_owner[f], mesh.face_neighbour[f]);
        assert!(owner < neighbour, "face {f}: owner {owner} ≥ neighbour {neighbour}");
        let image = mesh.cell_centres[neighbour] - mesh.periodic_shift_of(f);
        let delta = image - mesh.cell_centres[owner];
        assert!((delta - mesh.face_delta[f]).norm() <= 1e-14 * delta.norm(), "face {f}");
        assert!(mesh.face_areas[f].dot(&delta) > 0.0, "face {f} points backwards");
        let w = mesh.face_weight[f];
        assert!(w > 0.0 && w < 1.0, "face {f}: weight {w}");
    }
}

/// Boundary faces point out of their owner: S_f·(c_f − C_P) > 0.
pub fn assert_boundary_faces_outward(mesh: &Mesh) {
    for f in mesh.n_internal_faces..mesh.n_faces() {
        let out = mesh.face_centres[f] - mesh.cell_centres[mesh.face_owner[f]];
        assert!(mesh.face_areas[f].dot(&out) > 0.0, "boundary face {f} points inwards");
        assert!(mesh.boundary_patch_of(f).is_some(), "boundary face {f} in no patch");
    }
}

/// Small deterministic generator of uniform numbers in [0, 1) (Knuth's MMIX LCG).
pub struct Lcg(u64);

impl Lcg {
    pub fn new(seed: u64) -> Self {
        Lcg(seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407))
    }

    pub fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}
