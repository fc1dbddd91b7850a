//! Which cells have their centre within a radius of a point: a hashed bucket grid of the cell
//! centres at their current position (the rotor zone moves, so it is rebuilt every step).

use std::collections::HashMap;

use crate::mesh::{Mesh, Vec3};

/// Cell centres binned into cubes of side `bucket`.
pub struct CellSearch {
    bucket: f64,
    bins: HashMap<[i64; 3], Vec<usize>>,
}

impl CellSearch {
    /// Bins every cell centre of `mesh`; `bucket` is best set to the usual query radius.
    pub fn new(mesh: &Mesh, bucket: f64) -> Self {
        let bucket = if bucket.is_finite() && bucket > 0.0 { bucket } else { 1.0 };
        let mut bins: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for (c, x) in mesh.cell_centres.iter().enumerate() {
            bins.entry(Self::key(bucket, x)).or_default().push(c);
        }
        Self { bucket, bins }
    }

    fn key(bucket: f64, x: &Vec3) -> [i64; 3] {
        [(x.x / bucket).floor() as i64, (x.y / bucket).floor() as i64, (x.z / bucket).floor() as i64]
    }

    /// Appends to `out` every cell whose centre lies within `radius` of `point` (in no
    /// particular order: callers sort).
    pub fn within(&self, mesh: &Mesh, point: &Vec3, radius: f64, out: &mut Vec<usize>) {
        let lo = Self::key(self.bucket, &(point - Vec3::repeat(radius)));
        let hi = Self::key(self.bucket, &(point + Vec3::repeat(radius)));
        let r2 = radius * radius;
        for i in lo[0]..=hi[0] {
            for j in lo[1]..=hi[1] {
                for k in lo[2]..=hi[2] {
                    if let Some(cells) = self.bins.get(&[i, j, k]) {
                        out.extend(cells.iter().copied().filter(|&c| (mesh.cell_centres[c] - point).norm_squared() <= r2));
                    }
                }
            }
        }
    }
}
