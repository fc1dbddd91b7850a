//! The closest point of a wall triangle to a sphere centre, with the triangle's edge vectors
//! kept from the mesh's build: the same IEEE operations, in the same order, as parry's
//! `Triangle::project_local_point_and_get_location` (parry3d-f64 0.31, after Ericson's
//! Voronoi-region walk), so every contact keeps its bits, in about a fifth of the instructions
//! (parry recomputes the edges and their normal at every query, and tests the result for
//! being inside, which the contact query does not read).
//!
//! The sphere–mesh contact query ([`super::geometry::WallMesh::sphere_contacts_among`]) asks
//! for one projection per nearby triangle at every sub-step of every particle at a wall: in the
//! 10⁴ settling bed it was a sixth of the wall pass's instructions.
//!
//! The products are written out as glam writes them (`DVec3::dot` sums x, y, z left to right;
//! `DVec3::cross` takes `self.y * rhs.z - rhs.y * self.z`, …): a product of two factors does not
//! depend on their order, a sum does. A degenerate triangle (collinear vertices, whose face
//! normal is zero) is handed to parry itself, whose segment projection handles it.

use parry3d_f64::math::Vector as GlamVector;
use parry3d_f64::query::PointQueryWithLocation;
use parry3d_f64::shape::{Triangle, TrianglePointLocation};

type V = [f64; 3];

#[inline(always)]
fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
fn cross(a: V, b: V) -> V {
    [a[1] * b[2] - b[1] * a[2], a[2] * b[0] - b[2] * a[0], a[0] * b[1] - b[0] * a[1]]
}

/// `a + u t`, as glam's `a + u * t`.
#[inline(always)]
fn along(a: V, u: V, t: f64) -> V {
    [a[0] + u[0] * t, a[1] + u[1] * t, a[2] + u[2] * t]
}

/// One triangle, with what its projection reads besides the point.
#[derive(Clone, Copy, Debug)]
pub struct ProjectedTriangle {
    a: V,
    b: V,
    c: V,
    ab: V,
    ac: V,
    bc: V,
    /// ab × ac: the face normal, not normalised (zero for a degenerate triangle).
    n: V,
    ab_ab: f64,
    ac_ac: f64,
    bc_bc: f64,
}

/// Where the closest point lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feature {
    Vertex,
    Edge,
    Face,
}

impl ProjectedTriangle {
    pub fn new(triangle: &Triangle) -> Self {
        let v = |p: GlamVector| [p.x, p.y, p.z];
        let (a, b, c) = (v(triangle.a), v(triangle.b), v(triangle.c));
        let (ab, ac, bc) = (sub(b, a), sub(c, a), sub(c, b));
        ProjectedTriangle { a, b, c, ab, ac, bc, n: cross(ab, ac), ab_ab: dot(ab, ab), ac_ac: dot(ac, ac), bc_bc: dot(bc, bc) }
    }

    /// The closest point of the triangle to `p` and the feature it lies on: bit for bit parry's
    /// `project_local_point_and_get_location(p, false)` (its point, and its location's kind).
    #[inline]
    pub fn project(&self, p: V) -> (V, Feature) {
        let &ProjectedTriangle { a, b, c, ab, ac, bc, n, .. } = self;
        let ap = sub(p, a);
        let (ab_ap, ac_ap) = (dot(ab, ap), dot(ac, ap));
        if ab_ap <= 0.0 && ac_ap <= 0.0 {
            return (a, Feature::Vertex);
        }
        let bp = sub(p, b);
        let (ab_bp, ac_bp) = (dot(ab, bp), dot(ac, bp));
        if ab_bp >= 0.0 && ac_bp <= ab_bp {
            return (b, Feature::Vertex);
        }
        let cp = sub(p, c);
        let (ab_cp, ac_cp) = (dot(ab, cp), dot(ac, cp));
        if ac_cp >= 0.0 && ab_cp <= ac_cp {
            return (c, Feature::Vertex);
        }
        let vc = dot(n, cross(ab, ap));
        if vc < 0.0 && ab_ap >= 0.0 && ab_bp <= 0.0 {
            return (along(a, ab, ab_ap / self.ab_ab), Feature::Edge);
        }
        let vb = -dot(n, cross(ac, cp));
        if vb < 0.0 && ac_ap >= 0.0 && ac_cp <= 0.0 {
            return (along(a, ac, ac_ap / self.ac_ac), Feature::Edge);
        }
        let va = dot(n, cross(bc, bp));
        if va < 0.0 && ac_bp - ab_bp >= 0.0 && ab_cp - ac_cp >= 0.0 {
            return (along(b, bc, dot(bc, bp) / self.bc_bc), Feature::Edge);
        }
        let denom = va + vb + vc;
        if denom == 0.0 {
            return self.project_degenerate(p);
        }
        let (v, w) = (vb / denom, vc / denom);
        (along(along(a, ab, v), ac, w), Feature::Face)
    }

    /// A triangle with collinear vertices: parry projects on its longest edge.
    #[cold]
    fn project_degenerate(&self, p: V) -> (V, Feature) {
        let g = |v: V| GlamVector::new(v[0], v[1], v[2]);
        let (projection, location) = Triangle::new(g(self.a), g(self.b), g(self.c)).project_local_point_and_get_location(g(p), false);
        ([projection.point.x, projection.point.y, projection.point.z], Feature::of(location))
    }
}

impl Feature {
    /// The kind of parry's location.
    fn of(location: TrianglePointLocation) -> Feature {
        match location {
            TrianglePointLocation::OnVertex(_) => Feature::Vertex,
            TrianglePointLocation::OnEdge(..) => Feature::Edge,
            TrianglePointLocation::OnFace(..) | TrianglePointLocation::OnSolid => Feature::Face,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (the test needs no statistics, only many varied points).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
        fn point(&mut self, scale: f64) -> GlamVector {
            GlamVector::new(scale * (2.0 * self.next() - 1.0), scale * (2.0 * self.next() - 1.0), scale * (2.0 * self.next() - 1.0))
        }
    }

    fn assert_same_as_parry(triangle: &Triangle, p: GlamVector, seen: &mut [usize; 3]) {
        let (projection, location) = triangle.project_local_point_and_get_location(p, false);
        let (point, feature) = ProjectedTriangle::new(triangle).project([p.x, p.y, p.z]);
        let bits = |v: [f64; 3]| v.map(f64::to_bits);
        assert_eq!(bits(point), bits([projection.point.x, projection.point.y, projection.point.z]), "{triangle:?} at {p:?}");
        assert_eq!(feature, Feature::of(location), "{triangle:?} at {p:?}");
        seen[feature as usize] += 1;
    }

    /// Every region (three vertices, three edges, both sides of the face) of random triangles,
    /// of points near their plane, near their edges' lines and on them, of slivers and of a
    /// degenerate triangle: the same bits as parry, and every feature kind met many times.
    #[test]
    fn the_same_bits_as_parry_in_every_region() {
        let mut rng = Lcg(7);
        let mut seen = [0usize; 3];
        for _ in 0..2000 {
            let scale = [1e-3, 1.0, 40.0][(rng.next() * 3.0) as usize];
            let (a, b, c) = (rng.point(scale), rng.point(scale), rng.point(scale));
            let triangle = Triangle::new(a, b, c);
            for _ in 0..20 {
                assert_same_as_parry(&triangle, rng.point(1.5 * scale), &mut seen);
            }
            // near the plane, inside and out
            let (u, v) = (3.0 * rng.next() - 1.0, 3.0 * rng.next() - 1.0);
            let n = (b - a).cross(c - a);
            let on_plane = a + (b - a) * u + (c - a) * v;
            for h in [0.0, 1e-12, -1e-9] {
                assert_same_as_parry(&triangle, on_plane + n * h, &mut seen);
            }
            // on an edge's line, and exactly on a vertex
            assert_same_as_parry(&triangle, a + (b - a) * u, &mut seen);
            assert_same_as_parry(&triangle, c, &mut seen);
        }
        // a sliver, and collinear vertices (parry's own segment projection)
        let sliver = Triangle::new(GlamVector::new(0.0, 0.0, 0.0), GlamVector::new(1.0, 0.0, 0.0), GlamVector::new(0.5, 1e-12, 0.0));
        let line = Triangle::new(GlamVector::new(0.0, 0.0, 0.0), GlamVector::new(1.0, 1.0, 0.0), GlamVector::new(2.0, 2.0, 0.0));
        for _ in 0..500 {
            let p = rng.point(2.0);
            assert_same_as_parry(&sliver, p, &mut seen);
            assert_same_as_parry(&line, p, &mut seen);
        }
        assert!(seen.iter().all(|&k| k > 1000), "every feature kind met often: {seen:?}");
    }

    /// Ties, as a lattice bed meets a box's faces: axis-aligned triangles with whole-number
    /// corners, points exactly at each vertex, on the planes through the vertices at right
    /// angles to the edges (where a Voronoi test compares a zero), on the edges and on the face.
    #[test]
    fn the_same_bits_as_parry_on_the_ties_of_a_box() {
        let v = |x: f64, y: f64, z: f64| GlamVector::new(x, y, z);
        let mut seen = [0usize; 3];
        let triangles = [
            Triangle::new(v(0.0, 0.0, 0.0), v(4.0, 0.0, 0.0), v(0.0, 4.0, 0.0)),
            Triangle::new(v(4.0, 0.0, 0.0), v(4.0, 4.0, 0.0), v(0.0, 4.0, 0.0)),
            Triangle::new(v(0.0, 0.0, 2.0), v(0.0, 3.0, 2.0), v(0.0, 0.0, 5.0)),
            Triangle::new(v(1.0, 1.0, 1.0), v(1.0, 1.0, 3.0), v(3.0, 1.0, 1.0)),
        ];
        for triangle in &triangles {
            for x in -2..=6 {
                for y in -2..=6 {
                    for z in -2..=6 {
                        assert_same_as_parry(triangle, v(x as f64, y as f64, z as f64), &mut seen);
                        assert_same_as_parry(triangle, v(x as f64 * 0.5, y as f64 * 0.5, z as f64 * 0.5), &mut seen);
                    }
                }
            }
        }
        assert!(seen.iter().all(|&k| k > 100), "every feature kind met often: {seen:?}");
    }
}
