//! Points binned in cubes: a dense grid over their bounding box, each bucket a slice of one
//! array (counting sort by bucket, points in their given order within a bucket), so a query
//! visits a few contiguous slices and no hash. Used for the cell centres
//! ([`super::cell_search::CellSearch`]) and, by the fast solver, for the wall-face centres.

use crate::mesh::Vec3;

/// The indices 0..n of n points binned into cubes of side `bucket`.
pub struct BucketGrid {
    bucket: f64,
    /// Integer coordinates of the first bucket and the grid's size in buckets.
    origin: [i64; 3],
    dims: [i64; 3],
    /// Bucket b holds `items[start[b]..start[b + 1]]` (x fastest).
    start: Vec<usize>,
    items: Vec<usize>,
}

impl BucketGrid {
    /// Bins `points` in cubes of side `bucket`, widened (×1.5 at a time) until the grid has at
    /// most ~4 buckets per point: a bucket far below the points' spacing would make a huge grid
    /// of empty buckets. A bucket that is not a positive number takes the points' extent.
    pub fn new(points: &[Vec3], bucket: f64) -> Self {
        let n = points.len();
        let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
        for x in points {
            lo = lo.inf(x);
            hi = hi.sup(x);
        }
        let extent = if n > 0 { hi - lo } else { Vec3::zeros() };
        let mut bucket = if bucket.is_finite() && bucket > 0.0 { bucket } else { extent.max().max(1.0) };
        let cap = 4.0 * n as f64 + 64.0;
        let buckets = |b: f64| (0..3).map(|d| (extent[d] / b).floor() + 1.0).product::<f64>();
        while buckets(bucket) > cap {
            bucket *= 1.5;
        }
        let (origin, dims) = if n > 0 {
            let (a, b) = (key(bucket, &lo), key(bucket, &hi));
            (a, [b[0] - a[0] + 1, b[1] - a[1] + 1, b[2] - a[2] + 1])
        } else {
            ([0; 3], [0; 3])
        };
        let n_buckets = (dims[0] * dims[1] * dims[2]) as usize;
        let index = |k: [i64; 3]| ((k[0] - origin[0]) + dims[0] * ((k[1] - origin[1]) + dims[1] * (k[2] - origin[2]))) as usize;
        let bucket_of: Vec<usize> = points.iter().map(|x| index(key(bucket, x))).collect();
        let mut start = vec![0usize; n_buckets + 1];
        for &b in &bucket_of {
            start[b + 1] += 1;
        }
        for b in 0..n_buckets {
            start[b + 1] += start[b];
        }
        let mut fill = start.clone();
        let mut items = vec![0; n];
        for (i, &b) in bucket_of.iter().enumerate() {
            items[fill[b]] = i;
            fill[b] += 1;
        }
        Self { bucket, origin, dims, start, items }
    }

    /// Whether no point was binned.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Calls `visit` with every point whose bucket meets the box of half-width `radius` about
    /// `point` (a superset of the points within `radius`).
    #[inline]
    pub fn candidates(&self, point: &Vec3, radius: f64, mut visit: impl FnMut(usize)) {
        let lo = key(self.bucket, &(point - Vec3::repeat(radius)));
        let hi = key(self.bucket, &(point + Vec3::repeat(radius)));
        let range = |d: usize| (lo[d].max(self.origin[d]), hi[d].min(self.origin[d] + self.dims[d] - 1));
        let ((i0, i1), (j0, j1), (k0, k1)) = (range(0), range(1), range(2));
        for k in k0..=k1 {
            for j in j0..=j1 {
                if i0 > i1 {
                    continue;
                }
                // the buckets i0..=i1 of row (j, k) are contiguous
                let row = self.dims[0] * ((j - self.origin[1]) + self.dims[1] * (k - self.origin[2]));
                let (a, b) = ((row + i0 - self.origin[0]) as usize, (row + i1 - self.origin[0]) as usize);
                for &i in &self.items[self.start[a]..self.start[b + 1]] {
                    visit(i);
                }
            }
        }
    }
}

fn key(bucket: f64, x: &Vec3) -> [i64; 3] {
    [(x.x / bucket).floor() as i64, (x.y / bucket).floor() as i64, (x.z / bucket).floor() as i64]
}
