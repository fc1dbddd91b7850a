//! Which cells have their centre (or any part) within a radius of a point: a hashed bucket grid
//! of the cell centres at their current position (the rotor zone moves, so it is rebuilt every
//! step).

use std::collections::HashMap;

use crate::mesh::{Mesh, Vec3};

/// Cell centres binned into cubes of side `bucket`.
pub struct CellSearch {
    bucket: f64,
    bins: HashMap<[i64; 3], Vec<usize>>,
    /// Per cell, the largest distance from its centre to a corner.
    reach: Vec<f64>,
    /// The largest of `reach`.
    largest_reach: f64,
}

impl CellSearch {
    /// Bins every cell centre of `mesh`; `bucket` is best set to the usual query radius.
    pub fn new(mesh: &Mesh, bucket: f64) -> Self {
        let bucket = if bucket.is_finite() && bucket > 0.0 { bucket } else { 1.0 };
        let mut bins: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for (c, x) in mesh.cell_centres.iter().enumerate() {
            bins.entry(Self::key(bucket, x)).or_default().push(c);
        }
        let reach: Vec<f64> =
            mesh.cell_points.iter().zip(&mesh.cell_centres).map(|(ids, x)| ids.iter().map(|&p| (mesh.points[p] - x).norm()).fold(0.0, f64::max)).collect();
        let largest_reach = reach.iter().copied().fold(0.0, f64::max);
        Self { bucket, bins, reach, largest_reach }
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

    /// Appends to `out` every cell that may have a part within `radius` of `point`: its centre
    /// lies within `radius` plus its reach (centre to farthest corner). Unsorted.
    pub fn reaching(&self, mesh: &Mesh, point: &Vec3, radius: f64, out: &mut Vec<usize>) {
        let start = out.len();
        self.within(mesh, point, radius + self.largest_reach, out);
        let mut kept = start;
        for i in start..out.len() {
            let c = out[i];
            let r = radius + self.reach[c];
            if (mesh.cell_centres[c] - point).norm_squared() <= r * r {
                out[kept] = c;
                kept += 1;
            }
        }
        out.truncate(kept);
    }
}
