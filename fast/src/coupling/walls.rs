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

use spillage_model::coupling::kernel::ghost_in_face;
use spillage_model::mesh::{Mesh, Vec3};

/// Wall-face centres binned in cubes.
pub struct WallGrid {
    bucket: f64,
    origin: [i64; 3],
    dims: [i64; 3],
    /// Bucket b holds `faces[start[b]..start[b + 1]]`: (position in `wall_faces`, face).
    start: Vec<usize>,
    faces: Vec<(usize, usize)>,
    /// max_f √|A_f| over the wall faces.
    largest_size: f64,
}

fn key(bucket: f64, x: &Vec3) -> [i64; 3] {
    [(x.x / bucket).floor() as i64, (x.y / bucket).floor() as i64, (x.z / bucket).floor() as i64]
}

impl WallGrid {
    /// Bins `wall_faces` of `mesh` for queries of supports up to about `support`.
    pub fn new(mesh: &Mesh, wall_faces: &[usize], support: f64) -> Self {
        let n = wall_faces.len();
        let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
        for &f in wall_faces {
            lo = lo.inf(&mesh.face_centres[f]);
            hi = hi.sup(&mesh.face_centres[f]);
        }
        let largest_size = wall_faces.iter().map(|&f| mesh.face_areas[f].norm().sqrt()).fold(0.0, f64::max);
        let extent = if n > 0 { hi - lo } else { Vec3::zeros() };
        let reach = support + largest_size;
        let mut bucket = if reach.is_finite() && reach > 0.0 { reach } else { extent.max().max(1.0) };
        // at most ~4 buckets per face (as the cell search)
        let cap = 4.0 * n as f64 + 64.0;
        while (0..3).map(|d| (extent[d] / bucket).floor() + 1.0).product::<f64>() > cap {
            bucket *= 1.5;
        }
        let (origin, dims) = if n > 0 {
            let (a, b) = (key(bucket, &lo), key(bucket, &hi));
            (a, [b[0] - a[0] + 1, b[1] - a[1] + 1, b[2] - a[2] + 1])
        } else {
            ([0; 3], [0; 3])
        };
        let index = |k: [i64; 3]| ((k[0] - origin[0]) + dims[0] * ((k[1] - origin[1]) + dims[1] * (k[2] - origin[2]))) as usize;
        let n_buckets = (dims[0] * dims[1] * dims[2]) as usize;
        let mut start = vec![0usize; n_buckets + 1];
        for &f in wall_faces {
            start[index(key(bucket, &mesh.face_centres[f])) + 1] += 1;
        }
        for b in 0..n_buckets {
            start[b + 1] += start[b];
        }
        let mut fill = start.clone();
        let mut faces = vec![(0, 0); n];
        for (i, &f) in wall_faces.iter().enumerate() {
            let b = index(key(bucket, &mesh.face_centres[f]));
            faces[fill[b]] = (i, f);
            fill[b] += 1;
        }
        Self { bucket, origin, dims, start, faces, largest_size }
    }

    /// [`spillage_model::coupling::kernel::ghost_position`] of a particle at `x` with support
    /// `support`, bit for bit.
    pub fn ghost(&self, mesh: &Mesh, x: &Vec3, support: f64) -> Option<Vec3> {
        if self.faces.is_empty() {
            return None;
        }
        let radius = (support + self.largest_size) * (1.0 + 1e-9);
        let r2 = radius * radius;
        let (lo, hi) = (key(self.bucket, &(x - Vec3::repeat(radius))), key(self.bucket, &(x + Vec3::repeat(radius))));
        let range = |d: usize| (lo[d].max(self.origin[d]), hi[d].min(self.origin[d] + self.dims[d] - 1));
        let ((i0, i1), (j0, j1), (k0, k1)) = (range(0), range(1), range(2));
        // (squared distance, position in wall_faces, face) of the nearest, first on ties
        let mut best: Option<(f64, usize, usize)> = None;
        for k in k0..=k1 {
            for j in j0..=j1 {
                if i0 > i1 {
                    continue;
                }
                let row = self.dims[0] * ((j - self.origin[1]) + self.dims[1] * (k - self.origin[2]));
                let (a, b) = ((row + i0 - self.origin[0]) as usize, (row + i1 - self.origin[0]) as usize);
                for &(i, f) in &self.faces[self.start[a]..self.start[b + 1]] {
                    let d = (mesh.face_centres[f] - x).norm_squared();
                    if d <= r2 && best.is_none_or(|(bd, bi, _)| d < bd || (d == bd && i < bi)) {
                        best = Some((d, i, f));
                    }
                }
            }
        }
        let (d2, _, f) = best?;
        ghost_in_face(mesh, f, d2, x, support)
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
