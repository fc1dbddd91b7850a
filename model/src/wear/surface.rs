//! The surface a wall wears on: its triangles over welded nodes, with the P1 operators of the
//! wear smoothing (lumped mass, Laplace–Beltrami stiffness) and the exact volume a moving
//! surface sweeps (wear-model.md §7.3–7.4).
//!
//! Generated walls repeat a vertex on every face that meets there (a box's corners), so the
//! nodes are the wall's vertices welded by position: a worn corner stays closed.

use crate::walls::state::Vec3;

/// Vertices closer than this fraction of the wall's size are one node.
const WELD_TOLERANCE: f64 = 1e-9;

/// One wall's surface for the wear model. The operators are built once, on the wall's initial
/// shape: wear depths are small against the triangles, and fixed operators keep the smoothing's
/// volume bookkeeping exact from step to step (§7.3, conservation identity).
#[derive(Clone, Debug, PartialEq)]
pub struct WearSurface {
    /// Node of each wall vertex.
    pub node_of_vertex: Vec<u32>,
    /// Number of nodes.
    pub n_nodes: usize,
    /// Triangles over nodes (the wall's winding).
    pub triangles: Vec<[u32; 3]>,
    /// Lumped mass: one third of the area of every triangle at the node [m²] (M of §7.3).
    pub node_area: Vec<f64>,
    /// Off-diagonal entries (i, j, L_ij) of the cotangent Laplace–Beltrami matrix, each edge
    /// once with i < j; L_ii = −Σ_j L_ij, so every row and column sums to zero (zero-flux edges).
    pub stiffness: Vec<(u32, u32, f64)>,
    /// Nodes on an edge used by one triangle only: the rim of an open wall. They stay put when
    /// the wall recedes (§7.4 [R] "pin them"), so the wall keeps its outline.
    pub rim: Vec<bool>,
    /// Whether the wall is closed (no rim): its triangles then enclose a volume.
    pub closed: bool,
}

impl WearSurface {
    /// The surface of a wall with `vertices` and `triangles` (body frame).
    pub fn new(vertices: &[Vec3], triangles: &[[u32; 3]]) -> WearSurface {
        let (node_of_vertex, n_nodes) = weld(vertices);
        let nodes = node_positions(vertices, &node_of_vertex, n_nodes);
        let tris: Vec<[u32; 3]> = triangles.iter().map(|t| t.map(|v| node_of_vertex[v as usize])).collect();
        let mut node_area = vec![0.0; n_nodes];
        let mut edges: std::collections::BTreeMap<(u32, u32), (f64, u32)> = std::collections::BTreeMap::new();
        for t in &tris {
            let [a, b, c] = t.map(|n| nodes[n as usize]);
            let area = 0.5 * (b - a).cross(&(c - a)).norm();
            for n in t {
                node_area[*n as usize] += area / 3.0;
            }
            // the cotangent of the angle at each corner weighs the opposite edge
            for k in 0..3 {
                let (i, j, o) = (t[(k + 1) % 3], t[(k + 2) % 3], t[k]);
                let (pi, pj, po) = (nodes[i as usize], nodes[j as usize], nodes[o as usize]);
                let (u, v) = (pi - po, pj - po);
                let sine = u.cross(&v).norm();
                let cot = if sine > 0.0 { u.dot(&v) / sine } else { 0.0 };
                let entry = edges.entry((i.min(j), i.max(j))).or_insert((0.0, 0));
                entry.0 += 0.5 * cot;
                entry.1 += 1;
            }
        }
        let mut rim = vec![false; n_nodes];
        let mut stiffness = Vec::with_capacity(edges.len());
        for (&(i, j), &(weight, uses)) in &edges {
            if uses == 1 {
                rim[i as usize] = true;
                rim[j as usize] = true;
            }
            stiffness.push((i, j, -weight));
        }
        let closed = !rim.iter().any(|r| *r);
        WearSurface { node_of_vertex, n_nodes, triangles: tris, node_area, stiffness, rim, closed }
    }

    /// Node positions of a wall whose vertices are `vertices` (the first vertex of each node).
    pub fn nodes(&self, vertices: &[Vec3]) -> Vec<Vec3> {
        node_positions(vertices, &self.node_of_vertex, self.n_nodes)
    }

    /// Area-weighted unit normals at the nodes, in the triangles' winding sense.
    pub fn node_normals(&self, nodes: &[Vec3]) -> Vec<Vec3> {
        let mut normals = vec![Vec3::zeros(); self.n_nodes];
        for t in &self.triangles {
            let [a, b, c] = t.map(|n| nodes[n as usize]);
            let twice_area_normal = (b - a).cross(&(c - a));
            for n in t {
                normals[*n as usize] += twice_area_normal;
            }
        }
        for n in &mut normals {
            let length = n.norm();
            if length > 0.0 {
                *n /= length;
            }
        }
        normals
    }

    /// y = L x with the stiffness matrix.
    pub fn apply_stiffness(&self, x: &[f64], y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        for &(i, j, l) in &self.stiffness {
            let (i, j) = (i as usize, j as usize);
            y[i] += l * (x[j] - x[i]);
            y[j] += l * (x[i] - x[j]);
        }
    }

    /// Signed volume of the cone from `origin` over the triangles at `nodes`: the enclosed
    /// volume of a closed wall (positive for outward winding). For an open wall whose rim stays
    /// put, its change is the volume the surface swept: an independent measure of the removed
    /// volume (the recession computes it triangle by triangle instead).
    pub fn cone_volume(&self, nodes: &[Vec3], origin: Vec3) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|n| nodes[n as usize] - origin);
                a.dot(&b.cross(&c))
            })
            .sum::<f64>()
            / 6.0
    }

    /// Coefficients (c₁, c₂, c₃) of the volume V(s) = c₁s + c₂s² + c₃s³ swept when every node
    /// moves from `nodes` by s·`displacement` (signed, positive along the winding normal).
    /// Exact for the ruled solid between the two positions of each triangle: its sides are
    /// bilinear patches shared by neighbours, so the sum over triangles is the swept volume of
    /// the whole surface (derivation: ∫ d·(x_u × x_v) over the triangle and s ∈ [0, 1]).
    pub fn swept_volume_coefficients(&self, nodes: &[Vec3], displacement: &[Vec3]) -> [f64; 3] {
        let mut c = [0.0; 3];
        for t in &self.triangles {
            let [a, b, cc] = t.map(|n| nodes[n as usize]);
            let [da, db, dc] = t.map(|n| displacement[n as usize]);
            let (e1, e2) = (b - a, cc - a);
            let (f1, f2) = (db - da, dc - da);
            let mean = (da + db + dc) / 3.0;
            c[0] += 0.5 * mean.dot(&e1.cross(&e2));
            c[1] += 0.25 * mean.dot(&(e1.cross(&f2) + f1.cross(&e2)));
            c[2] += mean.dot(&f1.cross(&f2)) / 6.0;
        }
        c
    }
}

/// Barycentric weights of the point of triangle `(a, b, c)` nearest to `p` (each ≥ 0, sum 1):
/// the P1 hat functions at an impact point (§7.3).
pub fn barycentric_weights(a: Vec3, b: Vec3, c: Vec3, p: Vec3) -> [f64; 3] {
    let (e1, e2, d) = (b - a, c - a, p - a);
    let (d11, d12, d22) = (e1.dot(&e1), e1.dot(&e2), e2.dot(&e2));
    let (d1, d2) = (d.dot(&e1), d.dot(&e2));
    let det = d11 * d22 - d12 * d12;
    if !(det > 0.0) {
        return [1.0 / 3.0; 3];
    }
    let v = (d22 * d1 - d12 * d2) / det;
    let w = (d11 * d2 - d12 * d1) / det;
    let weights = [1.0 - v - w, v, w].map(|x| x.max(0.0));
    let sum: f64 = weights.iter().sum();
    weights.map(|x| x / sum)
}

/// Node of every vertex, welding vertices within [`WELD_TOLERANCE`] of the wall's size (sorted
/// sweep along x; deterministic: a node is numbered by its first vertex).
fn weld(vertices: &[Vec3]) -> (Vec<u32>, usize) {
    let n = vertices.len();
    if n == 0 {
        return (Vec::new(), 0);
    }
    let (lo, hi) = vertices.iter().fold((vertices[0], vertices[0]), |(lo, hi), v| (lo.inf(v), hi.sup(v)));
    let tolerance = WELD_TOLERANCE * (hi - lo).norm().max(f64::MIN_POSITIVE);
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| vertices[i].x.total_cmp(&vertices[j].x).then(i.cmp(&j)));
    // representative (smallest index) of each vertex's group
    let mut representative: Vec<usize> = (0..n).collect();
    for (k, &i) in order.iter().enumerate() {
        for &j in &order[k + 1..] {
            if vertices[j].x - vertices[i].x > tolerance {
                break;
            }
            if (vertices[j] - vertices[i]).norm() <= tolerance {
                let (ri, rj) = (find(&mut representative, i), find(&mut representative, j));
                let (keep, drop) = (ri.min(rj), ri.max(rj));
                representative[drop] = keep;
            }
        }
    }
    let mut node_of_vertex = vec![u32::MAX; n];
    let mut count = 0u32;
    for i in 0..n {
        let r = find(&mut representative, i);
        if node_of_vertex[r] == u32::MAX {
            node_of_vertex[r] = count;
            count += 1;
        }
        node_of_vertex[i] = node_of_vertex[r];
    }
    (node_of_vertex, count as usize)
}

fn find(representative: &mut [usize], mut i: usize) -> usize {
    while representative[i] != i {
        representative[i] = representative[representative[i]];
        i = representative[i];
    }
    i
}

fn node_positions(vertices: &[Vec3], node_of_vertex: &[u32], n_nodes: usize) -> Vec<Vec3> {
    let mut nodes = vec![None; n_nodes];
    for (v, &n) in vertices.iter().zip(node_of_vertex) {
        nodes[n as usize].get_or_insert(*v);
    }
    nodes.into_iter().map(|n| n.unwrap_or_else(Vec3::zeros)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::walls::geometry::{box_faces, plane};

    #[test]
    fn a_box_welds_into_a_closed_surface_whose_volume_is_the_box() {
        let mesh = box_faces(Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 3.0), 3, &[]);
        let s = WearSurface::new(&mesh.vertices, &mesh.triangles);
        assert!(s.closed);
        // 6 faces of a 3×3 grid share their edges: V − E + F = 2 with 6·18 triangles
        assert_eq!(s.n_nodes, 2 + 6 * 18 / 2);
        let nodes = s.nodes(&mesh.vertices);
        // exact up to round-off of a sum of 108 terms of size 1
        assert!((s.cone_volume(&nodes, Vec3::new(0.3, 0.1, 0.2)).abs() - 6.0).abs() < 1e-12);
        let area: f64 = s.node_area.iter().sum();
        assert!((area - 22.0).abs() < 1e-12, "surface area {area}");
    }

    #[test]
    fn the_laplacian_of_a_linear_field_vanishes_inside_a_flat_plate() {
        let mesh = plane(Vec3::zeros(), Vec3::z(), [1.0, 1.0], [4, 4], None);
        let s = WearSurface::new(&mesh.vertices, &mesh.triangles);
        assert!(!s.closed);
        let nodes = s.nodes(&mesh.vertices);
        let field: Vec<f64> = nodes.iter().map(|p| 2.0 * p.x - 3.0 * p.y + 1.0).collect();
        let mut y = vec![0.0; s.n_nodes];
        s.apply_stiffness(&field, &mut y);
        for (j, v) in y.iter().enumerate() {
            if !s.rim[j] {
                // the cotangent Laplacian is exact for linear fields on a flat mesh
                assert!(v.abs() < 1e-12, "node {j}: {v}");
            }
        }
        // rows sum to zero: a constant field has no Laplacian anywhere
        s.apply_stiffness(&vec![1.0; s.n_nodes], &mut y);
        assert!(y.iter().all(|v| v.abs() < 1e-14));
    }

    #[test]
    fn the_swept_volume_is_exact_for_a_tilted_uneven_displacement() {
        // one triangle moved by different amounts at its corners: the ruled solid's volume by
        // quadrature of the tetrahedra of its subdivision converges to the closed form
        let mesh = plane(Vec3::zeros(), Vec3::z(), [1.0, 1.0], [1, 1], None);
        let s = WearSurface::new(&mesh.vertices, &mesh.triangles);
        let nodes = s.nodes(&mesh.vertices);
        let d: Vec<Vec3> = nodes.iter().enumerate().map(|(i, _)| Vec3::new(0.01 * i as f64, -0.02, 0.1 + 0.05 * i as f64)).collect();
        let c = s.swept_volume_coefficients(&nodes, &d);
        let closed_form = c[0] + c[1] + c[2];
        // the same solid closed by its bottom, top and (unmoved-rim) sides, measured as the
        // cone volume difference: top minus bottom plus the four ruled sides
        let moved: Vec<Vec3> = nodes.iter().zip(&d).map(|(p, d)| p + d).collect();
        let top_minus_bottom = s.cone_volume(&moved, Vec3::zeros()) - s.cone_volume(&nodes, Vec3::zeros());
        let mut sides = 0.0;
        let n = 400;
        for t in &s.triangles {
            for k in 0..3 {
                let (i, j) = (t[k] as usize, t[(k + 1) % 3] as usize);
                // rim edges only (each used once): the bilinear side patch, finely triangulated
                let shared = s.triangles.iter().filter(|u| u.contains(&(i as u32)) && u.contains(&(j as u32))).count();
                if shared != 1 {
                    continue;
                }
                for m in 0..n {
                    let (s0, s1) = (m as f64 / n as f64, (m + 1) as f64 / n as f64);
                    let p = |u: f64, s: f64| nodes[i] * (1.0 - u) + nodes[j] * u + (d[i] * (1.0 - u) + d[j] * u) * s;
                    for q in 0..n {
                        let (u0, u1) = (q as f64 / n as f64, (q + 1) as f64 / n as f64);
                        let (a, b, c2, e) = (p(u0, s0), p(u1, s0), p(u1, s1), p(u0, s1));
                        sides += a.dot(&b.cross(&c2)) / 6.0 + a.dot(&c2.cross(&e)) / 6.0;
                    }
                }
            }
        }
        let measured = top_minus_bottom + sides;
        // the triangulated side patches converge at O(1/n²) to the bilinear ones
        assert!((closed_form - measured).abs() < 1e-5 * closed_form.abs(), "{closed_form} vs {measured}");
    }

    #[test]
    fn barycentric_weights_locate_points_and_clamp_outside() {
        let (a, b, c) = (Vec3::zeros(), Vec3::x(), Vec3::y());
        let w = barycentric_weights(a, b, c, Vec3::new(0.25, 0.5, 0.3));
        assert!((w[0] - 0.25).abs() < 1e-15 && (w[1] - 0.25).abs() < 1e-15 && (w[2] - 0.5).abs() < 1e-15);
        let outside = barycentric_weights(a, b, c, Vec3::new(2.0, -1.0, 0.0));
        assert!(outside.iter().all(|x| *x >= 0.0) && (outside.iter().sum::<f64>() - 1.0).abs() < 1e-15);
    }
}
