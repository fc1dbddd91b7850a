//! Adjacency of a wear surface for loops that gather instead of scatter: each node's triangle
//! corners in the order a triangle-by-triangle scatter would visit them, so a gathered sum has
//! the bits of the sequential scatter, whatever the number of threads.

use spillage_model::walls::state::Vec3;
use spillage_model::wear::surface::WearSurface;

use crate::linear::par_update;

pub struct Topology {
    /// The first wall vertex of each node: a node sits where that vertex is
    /// ([`WearSurface::nodes`]).
    vertex_of_node: Vec<u32>,
    /// Node n's corners are `corners[corner_start[n]..corner_start[n + 1]]`, each 3t + k for
    /// corner k of triangle t, in ascending order (triangle order, then corner order).
    corner_start: Vec<u32>,
    corners: Vec<u32>,
}

impl Topology {
    pub fn new(surface: &WearSurface) -> Self {
        let n = surface.n_nodes;
        let mut vertex_of_node = vec![u32::MAX; n];
        for (v, &node) in surface.node_of_vertex.iter().enumerate() {
            let first = &mut vertex_of_node[node as usize];
            if *first == u32::MAX {
                *first = v as u32;
            }
        }
        let mut corner_start = vec![0u32; n + 1];
        for t in &surface.triangles {
            for &node in t {
                corner_start[node as usize + 1] += 1;
            }
        }
        for j in 0..n {
            corner_start[j + 1] += corner_start[j];
        }
        let mut fill: Vec<u32> = corner_start[..n].to_vec();
        let mut corners = vec![0u32; 3 * surface.triangles.len()];
        for (t, tri) in surface.triangles.iter().enumerate() {
            for (k, &node) in tri.iter().enumerate() {
                let slot = &mut fill[node as usize];
                corners[*slot as usize] = (3 * t + k) as u32;
                *slot += 1;
            }
        }
        Topology { vertex_of_node, corner_start, corners }
    }

    /// Node positions of a wall whose vertices are `vertices` into `nodes` (the same values as
    /// [`WearSurface::nodes`], without allocating). A node without a vertex (none in a welded
    /// mesh) sits at the origin, as there.
    pub fn nodes(&self, vertices: &[Vec3], nodes: &mut [Vec3]) {
        par_update(nodes, |j, p| {
            let v = self.vertex_of_node[j];
            *p = if v == u32::MAX { Vec3::zeros() } else { vertices[v as usize] };
        });
    }

    /// The corners at node `j` (3t + k), in triangle order.
    #[inline]
    pub fn corners(&self, j: usize) -> &[u32] {
        &self.corners[self.corner_start[j] as usize..self.corner_start[j + 1] as usize]
    }
}
