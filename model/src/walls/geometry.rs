//! Wall triangle meshes: generated shapes, and the sphere–mesh contact query on a parry3d
//! `TriMesh` (parry uses glam vectors; conversion to/from nalgebra happens only in this file).

use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Vector as GlamVector;
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::TriMesh;

use super::projection::{Feature, ProjectedTriangle};
use super::state::Vec3;

/// A plain triangle mesh: vertices and counter-clockwise vertex triples.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    pub vertices: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    fn push_quad_grid(&mut self, corner: Vec3, u: Vec3, v: Vec3, nu: u32, nv: u32) {
        let base = self.vertices.len() as u32;
        for j in 0..=nv {
            for i in 0..=nu {
                self.vertices.push(corner + u * (i as f64 / nu as f64) + v * (j as f64 / nv as f64));
            }
        }
        let index = |i: u32, j: u32| base + j * (nu + 1) + i;
        for j in 0..nv {
            for i in 0..nu {
                let (a, b, c, d) = (index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
                // Alternate the diagonal so vertices with 4 and with 8 triangles both occur.
                if (i + j) % 2 == 0 {
                    self.triangles.push([a, b, c]);
                    self.triangles.push([a, c, d]);
                } else {
                    self.triangles.push([a, b, d]);
                    self.triangles.push([b, c, d]);
                }
            }
        }
    }
}

/// Two unit vectors spanning the plane with normal `n` (the first along `u_hint` if given).
pub fn plane_axes(n: Vec3, u_hint: Option<Vec3>) -> (Vec3, Vec3) {
    let n = n.normalize();
    let u = match u_hint {
        Some(h) => (h - n * h.dot(&n)).normalize(),
        None => {
            let least = if n.x.abs() <= n.y.abs() && n.x.abs() <= n.z.abs() {
                Vec3::x()
            } else if n.y.abs() <= n.z.abs() {
                Vec3::y()
            } else {
                Vec3::z()
            };
            (least - n * least.dot(&n)).normalize()
        }
    };
    (u, n.cross(&u))
}

/// Rectangle centred at `centre`, sides `size` along the plane axes, `divisions` cells.
pub fn plane(centre: Vec3, normal: Vec3, size: [f64; 2], divisions: [u32; 2], u_hint: Option<Vec3>) -> TriangleMesh {
    let (u, v) = plane_axes(normal, u_hint);
    let mut mesh = TriangleMesh::default();
    let corner = centre - u * (0.5 * size[0]) - v * (0.5 * size[1]);
    mesh.push_quad_grid(corner, u * size[0], v * size[1], divisions[0], divisions[1]);
    mesh
}

/// The faces of an axis-aligned box, without those named in `open` ("-x" … "+z").
pub fn box_faces(min: Vec3, max: Vec3, divisions: u32, open: &[String]) -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    let e = max - min;
    let (ex, ey, ez) = (Vec3::new(e.x, 0.0, 0.0), Vec3::new(0.0, e.y, 0.0), Vec3::new(0.0, 0.0, e.z));
    let faces = [("-x", min, ey, ez), ("+x", min + ex, ez, ey), ("-y", min, ez, ex), ("+y", min + ey, ex, ez), ("-z", min, ex, ey), ("+z", min + ez, ey, ex)];
    for (name, corner, u, v) in faces {
        if !open.iter().any(|o| o == name) {
            mesh.push_quad_grid(corner, u, v, divisions, divisions);
        }
    }
    mesh
}

/// The side of a cylinder (no caps).
pub fn cylinder(origin: Vec3, axis: Vec3, radius: f64, length: f64, segments: u32, layers: u32) -> TriangleMesh {
    let a = axis.normalize();
    let (u, v) = plane_axes(a, None);
    let mut mesh = TriangleMesh::default();
    for j in 0..=layers {
        for i in 0..segments {
            let phi = 2.0 * std::f64::consts::PI * i as f64 / segments as f64;
            mesh.vertices.push(origin + a * (length * j as f64 / layers as f64) + radius * (u * phi.cos() + v * phi.sin()));
        }
    }
    let index = |i: u32, j: u32| j * segments + i % segments;
    for j in 0..layers {
        for i in 0..segments {
            let (p, q, r, s) = (index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
            mesh.triangles.push([p, q, r]);
            mesh.triangles.push([p, r, s]);
        }
    }
    mesh
}

/// A flat disc: a centre fan plus `rings − 1` annuli.
pub fn disc(centre: Vec3, normal: Vec3, radius: f64, segments: u32, rings: u32) -> TriangleMesh {
    let (u, v) = plane_axes(normal, None);
    let mut mesh = TriangleMesh { vertices: vec![centre], triangles: vec![] };
    for k in 1..=rings {
        let rho = radius * k as f64 / rings as f64;
        for i in 0..segments {
            let phi = 2.0 * std::f64::consts::PI * i as f64 / segments as f64;
            mesh.vertices.push(centre + rho * (u * phi.cos() + v * phi.sin()));
        }
    }
    let ring = |k: u32, i: u32| 1 + (k - 1) * segments + i % segments;
    for i in 0..segments {
        mesh.triangles.push([0, ring(1, i), ring(1, i + 1)]);
    }
    for k in 1..rings {
        for i in 0..segments {
            let (p, q, r, s) = (ring(k, i), ring(k, i + 1), ring(k + 1, i + 1), ring(k + 1, i));
            mesh.triangles.push([p, s, r]);
            mesh.triangles.push([p, r, q]);
        }
    }
    mesh
}

fn to_glam(v: Vec3) -> GlamVector {
    GlamVector::new(v.x, v.y, v.z)
}

fn from_glam(v: GlamVector) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

/// One contact between a sphere and a mesh, in the mesh's body frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshContact {
    pub triangle: u32,
    /// Closest point of the mesh to the sphere centre.
    pub point: Vec3,
    /// Distance from the sphere centre to `point`.
    pub distance: f64,
    /// Unit normal of the triangle (used only when the centre lies on the mesh).
    pub triangle_normal: Vec3,
}

/// A wall mesh ready for contact queries.
pub struct WallMesh {
    trimesh: TriMesh,
    /// Each triangle's first vertex and unit normal (+z for a degenerate triangle), for the
    /// plane test that spares most far triangles their projection.
    planes: Vec<(Vec3, Vec3)>,
    /// Each triangle with its edges, for the projection of a sphere centre.
    projections: Vec<ProjectedTriangle>,
}

impl WallMesh {
    /// Builds the parry mesh; fails on an empty or degenerate mesh.
    pub fn new(vertices: &[Vec3], triangles: &[[u32; 3]]) -> Result<WallMesh, String> {
        let trimesh = TriMesh::new(vertices.iter().map(|v| to_glam(*v)).collect(), triangles.to_vec()).map_err(|e| format!("{e:?}"))?;
        let planes = (0..trimesh.num_triangles() as u32)
            .map(|id| {
                let triangle = trimesh.triangle(id);
                (from_glam(triangle.a), triangle.normal().map(from_glam).unwrap_or_else(Vec3::z))
            })
            .collect();
        let projections = (0..trimesh.num_triangles() as u32).map(|id| ProjectedTriangle::new(&trimesh.triangle(id))).collect();
        Ok(WallMesh { trimesh, planes, projections })
    }

    /// The contacts of a sphere (centre, radius) with the mesh, each surface feature counted
    /// once (issue #5: a sphere on a flat tessellated plane feels one contact, whichever
    /// triangles, edges or vertices it overlaps).
    ///
    /// Every triangle within `radius` gives a candidate closest point. Candidates are taken in
    /// order of distance and one is dropped when
    /// * an accepted candidate has the same closest point (a shared edge or vertex hit from both
    ///   sides, e.g. a convex box edge), or
    /// * its closest point lies on an edge or vertex that also belongs to a nearer (or equally
    ///   near, earlier) candidate triangle: then the distance keeps decreasing across that edge and the point is not a
    ///   local minimum of the distance to the surface (a flat or convex continuation).
    ///
    /// What remains are the local minima of the distance: one per flat region, and one per face
    /// in a concave corner.
    pub fn sphere_contacts(&self, centre: Vec3, radius: f64) -> Vec<MeshContact> {
        let mut ids = Vec::new();
        self.triangles_near(centre, radius, &mut ids);
        let mut scratch = ContactScratch::default();
        self.sphere_contacts_among(&ids, centre, radius, &mut scratch);
        scratch.accepted
    }

    /// The triangles whose bounding boxes meet the cube of half-width `reach` around `centre`,
    /// in ascending order, into `out` (cleared first). With `reach` = radius + skin the list
    /// holds every triangle a sphere of `radius` can touch while its centre stays within the
    /// skin of `centre` (in every coordinate).
    pub fn triangles_near(&self, centre: Vec3, reach: f64, out: &mut Vec<u32>) {
        let c = to_glam(centre);
        let half = GlamVector::splat(reach);
        let aabb = Aabb::new(c - half, c + half);
        out.clear();
        out.extend(self.trimesh.bvh().intersect_aabb(&aabb));
        out.sort_unstable();
    }

    /// The triangles closer than `reach` to `centre`, in ascending order, into `out` (cleared
    /// first): with `reach` = radius + skin, every triangle a sphere of `radius` can touch while
    /// its centre stays within the (Euclidean) skin of `centre`. A margin of 1e-9 `reach` keeps
    /// triangles at the limit whatever the projection's round-off.
    pub fn triangles_within(&self, centre: Vec3, reach: f64, out: &mut Vec<u32>) {
        self.triangles_near(centre, reach, out);
        let c = to_glam(centre);
        let limit = reach * (1.0 + 1e-9);
        out.retain(|&id| self.trimesh.triangle(id).distance_to_local_point(c, false) < limit);
    }

    /// [`Self::sphere_contacts`] among the triangles `ids` (ascending, a superset of those
    /// within `radius`), into `scratch.accepted`; the buffers are reused, nothing is allocated
    /// once they have grown.
    pub fn sphere_contacts_among(&self, ids: &[u32], centre: Vec3, radius: f64, scratch: &mut ContactScratch) {
        let c = [centre.x, centre.y, centre.z];
        let candidates = &mut scratch.candidates;
        candidates.clear();
        scratch.accepted.clear();
        // a triangle is never nearer than its plane: farther than the radius from the plane (with
        // a margin far above round-off), it cannot be within the radius
        let plane_limit = radius * (1.0 + 1e-9);
        for &id in ids {
            let (corner, normal) = self.planes[id as usize];
            if (centre - corner).dot(&normal).abs() > plane_limit {
                continue;
            }
            let (projection, feature) = self.projections[id as usize].project(c);
            let point = Vec3::from(projection);
            let distance = (point - centre).norm();
            if distance < radius {
                let on_face = feature == Feature::Face;
                candidates.push(Candidate { contact: MeshContact { triangle: id, point, distance, triangle_normal: normal }, on_face });
            }
        }
        candidates.sort_by(|a, b| a.contact.distance.total_cmp(&b.contact.distance).then(a.contact.triangle.cmp(&b.contact.triangle)));
        // Tolerances relative to the sphere size: far above round-off, far below any geometry.
        let same_point = 1e-9 * radius;
        for (k, candidate) in candidates.iter().enumerate() {
            let p = candidate.contact.point;
            if scratch.accepted.iter().any(|a| (a.point - p).norm() <= same_point) {
                continue;
            }
            if !candidate.on_face {
                // A triangle that contains p is never farther than p, so its own closest point is
                // nearer or, beside an edge, equally near to round-off: the distance differs
                // only to second order in the offset from the edge, which at 1e-12 of the radius
                // is below the distances' last bit. So any other candidate triangle through p,
                // whatever the sort put first, continues the surface, unless its own closest
                // point is p itself (both sides of a convex edge, kept once above).
                let continues = candidates.iter().enumerate().any(|(j, other)| {
                    j != k && other.contact.triangle != candidate.contact.triangle && (other.contact.point - p).norm() > same_point && {
                        let (projection, _) = self.projections[other.contact.triangle as usize].project([p.x, p.y, p.z]);
                        (Vec3::from(projection) - p).norm() <= same_point
                    }
                });
                if continues {
                    continue;
                }
            }
            scratch.accepted.push(candidate.contact);
        }
    }
}

/// A triangle within the radius, before the local-minimum filter of
/// [`WallMesh::sphere_contacts`].
#[derive(Clone, Copy, Debug)]
struct Candidate {
    contact: MeshContact,
    on_face: bool,
}

/// Work buffers of [`WallMesh::sphere_contacts_among`]; `accepted` holds its answer.
#[derive(Clone, Debug, Default)]
pub struct ContactScratch {
    candidates: Vec<Candidate>,
    pub accepted: Vec<MeshContact>,
}

impl ContactScratch {
    /// Buffers with room for `n` candidate triangles (a query among more grows them).
    pub fn with_capacity(n: usize) -> Self {
        Self { candidates: Vec::with_capacity(n), accepted: Vec::with_capacity(n) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh(m: &TriangleMesh) -> WallMesh {
        WallMesh::new(&m.vertices, &m.triangles).unwrap()
    }

    #[test]
    fn one_contact_on_a_tessellated_plane_everywhere() {
        let plane = mesh(&plane(Vec3::zeros(), Vec3::z(), [1.0, 1.0], [10, 10], None));
        // Centres over face interiors, edges, diagonals and vertices (the grid has 0.1 spacing).
        // Including points 1e-9 and 1e-7 beside an edge, where the neighbour's edge point is
        // farther only by a second-order amount.
        for (x, y) in [
            (0.0, 0.0),
            (0.05, 0.0),
            (0.05, 0.05),
            (0.01, 0.03),
            (0.1, 0.1),
            (0.13, 0.1),
            (-0.2, 0.37),
            (0.1 + 1e-9, 0.03),
            (0.03, 0.1 - 1e-7),
            (0.05 + 1e-8, 0.05),
        ] {
            let contacts = plane.sphere_contacts(Vec3::new(x, y, 0.04), 0.05);
            assert_eq!(contacts.len(), 1, "at ({x}, {y})");
            assert!((contacts[0].distance - 0.04).abs() < 1e-14);
        }
    }

    /// A small sphere sliding along the line where two rows of triangles meet, 1e-12 of its
    /// radius off it (drift of round-off): the edge point of the row it is not over and the face
    /// point of the row it is over are equally far to the distances' last bit, and the edge
    /// point sorted first (lower triangle id) was kept as a second contact, doubling the force.
    #[test]
    fn one_contact_a_hair_beside_an_edge_whatever_the_sort() {
        let plane = mesh(&plane(Vec3::zeros(), Vec3::z(), [0.2, 0.02], [20, 2], None));
        for y in [-1.7e-12, -1e-13, 0.0, 1e-13, 1.7e-12, 1e-9] {
            for x in [0.004, 0.0041, 0.006, 0.0087] {
                let contacts = plane.sphere_contacts(Vec3::new(x, y, 9.978e-4), 1e-3);
                assert_eq!(contacts.len(), 1, "at ({x}, {y}): {contacts:?}");
            }
        }
    }

    #[test]
    fn convex_box_edge_is_one_contact_and_concave_corner_is_three() {
        let b = mesh(&box_faces(Vec3::zeros(), Vec3::new(1.0, 1.0, 1.0), 2, &[]));
        // Outside, over the edge x = 1, z = 1.
        assert_eq!(b.sphere_contacts(Vec3::new(1.02, 0.3, 1.02), 0.05).len(), 1);
        // Inside, in the corner at the origin: floor and two side walls.
        let inside = b.sphere_contacts(Vec3::new(0.04, 0.04, 0.04), 0.05);
        assert_eq!(inside.len(), 3);
    }

    #[test]
    fn generated_shapes_are_closed_where_expected() {
        let c = cylinder(Vec3::zeros(), Vec3::z(), 0.5, 1.0, 16, 2);
        assert_eq!(c.triangles.len(), 64);
        let d = disc(Vec3::zeros(), Vec3::z(), 0.5, 16, 3);
        assert_eq!(d.triangles.len(), 16 + 2 * 32);
        let area: f64 = d
            .triangles
            .iter()
            .map(|t| 0.5 * (d.vertices[t[1] as usize] - d.vertices[t[0] as usize]).cross(&(d.vertices[t[2] as usize] - d.vertices[t[0] as usize])).norm())
            .sum();
        let polygon = 0.5 * 16.0 * 0.25 * (2.0 * std::f64::consts::PI / 16.0).sin();
        assert!((area - polygon).abs() < 1e-12);
    }
}
