//! The ghost of each particle ([`spillage_model::coupling::kernel::ghost_position`]) without a
//! pass over every wall face per particle: the wall-face centres binned in a bucket grid, and
//! only the faces that can decide the ghost looked at.
//!
//! The reference takes the wall face whose centre is nearest (the first in `wall_faces` order
//! of equally near ones) and mirrors the particle in it if the face is within its support plus
//! the face's own size, √|A_f|. So a face farther than 3σ + max_f √|A_f| never gives a ghost:
//! if no face lies within that radius the nearest does not either, and the answer is none; if
//! some do, the nearest is among them. The radius is widened by a relative 1e-9 so that no
//! rounding of the squared distances can leave the deciding face out; the same face, the same
//! squared distance and [`ghost_in_face`] then give the reference's ghost, bit for bit.

use spillage_model::coupling::bucket_grid::BucketGrid;
use spillage_model::coupling::kernel::ghost_in_face;
use spillage_model::mesh::{Mesh, Vec3};

/// Wall-face centres binned in cubes.
pub struct WallGrid {
    /// Bins the positions in `wall_faces`.
    grid: BucketGrid,
    wall_faces: Vec<usize>,
    /// max_f √|A_f| over the wall faces.
    largest_size: f64,
}

impl WallGrid {
    /// Bins `wall_faces` of `mesh` for queries of supports up to about `support`.
    pub fn new(mesh: &Mesh, wall_faces: &[usize], support: f64) -> Self {
        let largest_size = wall_faces.iter().map(|&f| mesh.face_areas[f].norm().sqrt()).fold(0.0, f64::max);
        let centres: Vec<Vec3> = wall_faces.iter().map(|&f| mesh.face_centres[f]).collect();
        Self { grid: BucketGrid::new(&centres, support + largest_size), wall_faces: wall_faces.to_vec(), largest_size }
    }

    /// [`spillage_model::coupling::kernel::ghost_position`] of a particle at `x` with support
    /// `support`, bit for bit.
    pub fn ghost(&self, mesh: &Mesh, x: &Vec3, support: f64) -> Option<Vec3> {
        if self.grid.is_empty() {
            return None;
        }
        let radius = (support + self.largest_size) * (1.0 + 1e-9);
        let r2 = radius * radius;
        // (squared distance, position in wall_faces) of the nearest, first on ties
        let mut best: Option<(f64, usize)> = None;
        self.grid.candidates(x, radius, |i| {
            let d = (mesh.face_centres[self.wall_faces[i]] - x).norm_squared();
            if d <= r2 && best.is_none_or(|(bd, bi)| d < bd || (d == bd && i < bi)) {
                best = Some((d, i));
            }
        });
        let (d2, i) = best?;
        ghost_in_face(mesh, self.wall_faces[i], d2, x, support)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use spillage_model::coupling::kernel::{ghost_position, wall_faces};
    use spillage_model::mesh::cartesian::BoxSpec;

    /// The reference's ghost, bit for bit (or none with it), for points inside, at and beyond
    /// the walls and corners of a graded box, for supports from below a cell to beyond the box.
    #[test]
    fn the_same_ghost_as_the_reference() {
        let mut spec = BoxSpec::uniform(Vec3::zeros(), Vec3::new(0.2, 0.3, 0.1), [8, 12, 4]);
        spec.grading = [2.0, 0.5, 1.0];
        let mesh = Mesh::cartesian_box(&spec).unwrap();
        let walls = wall_faces(&mesh);
        for support in [0.004, 0.03, 0.09, 1.0] {
            let grid = WallGrid::new(&mesh, &walls, 0.03);
            for i in 0..=20 {
                for j in 0..=15 {
                    let x = Vec3::new(-0.02 + 0.012 * i as f64, -0.03 + 0.024 * j as f64, 0.0123 + 0.004 * j as f64);
                    let (want, got) = (ghost_position(&mesh, &walls, &x, support), grid.ghost(&mesh, &x, support));
                    assert_eq!(want.map(|g| g.map(f64::to_bits)), got.map(|g| g.map(f64::to_bits)), "{x} with support {support}");
                }
            }
        }
    }
}
