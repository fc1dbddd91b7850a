//! Step 3 of wear: the eroding wall recedes (wear-model.md §7.4), as the reference phase: each
//! node moves into the wall material along its area-weighted normal, rim nodes of an open wall
//! stay put, and one factor s scales the depths so that the exactly swept volume equals the
//! volume removed this step.
//!
//! Per-node quantities are gathered over the node's triangle corners in triangle order (the
//! order of the reference's triangle-by-triangle scatter: the same bits); per-triangle terms
//! are computed in parallel into a buffer and summed in triangle order (again the reference's
//! bits). Only the sum of depth × area uses fixed chunks, which equals the reference's
//! sequential sum up to [`crate::linear::reduce::CHUNK`] nodes and its round-off beyond.

use rayon::prelude::*;
use spillage_model::walls::state::{Vec3, Wall};
use spillage_model::wear::recession::{displacement_scale, inside_out};
use spillage_model::wear::state::WallWear;
use spillage_model::wear::surface::WearSurface;

use super::topology::Topology;
use crate::linear::par_update;
use crate::linear::reduce::{Reducer, CHUNK};

/// Work arrays of the recession (sized once).
pub struct RecessionWork {
    /// Per triangle: (b − a) × (c − a) at the start of the step.
    twice_area_normal: Vec<Vec3>,
    /// Per triangle: its terms of the swept-volume cubic, or of the cone volume.
    terms: Vec<[f64; 3]>,
    /// Per node: unit normal, displacement per unit s, moved position, shortest edge.
    normals: Vec<Vec3>,
    displacement: Vec<Vec3>,
    moved: Vec<Vec3>,
    shortest: Vec<f64>,
    red: Reducer,
}

impl RecessionWork {
    pub fn new(surface: &WearSurface) -> Self {
        let (n, m) = (surface.n_nodes, surface.triangles.len());
        RecessionWork {
            twice_area_normal: vec![Vec3::zeros(); m],
            terms: vec![[0.0; 3]; m],
            normals: vec![Vec3::zeros(); n],
            displacement: vec![Vec3::zeros(); n],
            moved: vec![Vec3::zeros(); n],
            shortest: vec![0.0; n],
            red: Reducer::default(),
        }
    }

    /// The volume the wall has lost, measured on its geometry `nodes`: the change of its cone
    /// volume about the fixed origin, signed so that removed material counts positive (the
    /// reference's `geometric_removed_volume`, same summation order).
    pub fn geometric_removed_volume(&mut self, surface: &WearSurface, nodes: &[Vec3], w: &WallWear) -> f64 {
        let origin = Vec3::from(w.volume_origin);
        par_update(&mut self.terms, |t, term| {
            let [a, b, c] = surface.triangles[t].map(|n| nodes[n as usize] - origin);
            term[0] = a.dot(&b.cross(&c));
        });
        let cone = self.terms.iter().map(|t| t[0]).sum::<f64>() / 6.0;
        w.material_side * (cone - w.initial_volume)
    }
}

/// The first index below `n` where `bad` holds (the lowest, whatever the number of threads).
fn first(n: usize, bad: impl Fn(usize) -> bool + Sync + Send) -> Option<usize> {
    if n <= CHUNK {
        (0..n).find(|&i| bad(i))
    } else {
        (0..n).into_par_iter().with_min_len(CHUNK).find_first(|&i| bad(i))
    }
}

/// Moves `wall` by the node depths `depth` (or, static, only books them); `nodes` are the
/// node positions at the start of the step and become the moved ones. Errors name the wall and
/// where it would turn inside out (the reference's messages); the wall is then left alone.
#[allow(clippy::too_many_arguments)]
pub fn recede(
    surface: &WearSurface,
    topology: &Topology,
    nodes: &mut [Vec3],
    depth: &[f64],
    receding: bool,
    wall: &mut Wall,
    w: &mut WallWear,
    work: &mut RecessionWork,
) -> Result<(), String> {
    let n = surface.n_nodes;
    let area = &surface.node_area;
    let step_volume = work.red.sum(n, |j| depth[j] * area[j]);
    if !receding {
        // static-boundary mode (§7.4): the depths are booked, the geometry stays
        par_update(&mut w.node_depth, |j, total| *total += depth[j]);
        w.receded += step_volume;
        return Ok(());
    }
    let target = step_volume + w.pending;
    if !(target > 0.0) {
        return Ok(());
    }
    let RecessionWork { twice_area_normal, terms, normals, displacement, moved, shortest, .. } = work;
    let nodes_now = &*nodes;
    par_update(twice_area_normal, |t, normal| {
        let [a, b, c] = surface.triangles[t].map(|n| nodes_now[n as usize]);
        *normal = (b - a).cross(&(c - a));
    });
    let side = w.material_side;
    let movable = |j: usize| !surface.rim[j] && depth[j] > 0.0;
    let tan = &*twice_area_normal;
    par_update(normals, |j, normal| {
        let mut sum = Vec3::zeros();
        for &c in topology.corners(j) {
            sum += tan[c as usize / 3];
        }
        let length = sum.norm();
        *normal = if length > 0.0 { sum / length } else { sum };
    });
    let normals = &*normals;
    par_update(displacement, |j, d| *d = if movable(j) { side * depth[j] * normals[j] } else { Vec3::zeros() });
    let displacement = &*displacement;
    par_update(terms, |t, term| {
        // the terms of WearSurface::swept_volume_coefficients, per triangle
        let [a, b, cc] = surface.triangles[t].map(|n| nodes_now[n as usize]);
        let [da, db, dc] = surface.triangles[t].map(|n| displacement[n as usize]);
        let (e1, e2) = (b - a, cc - a);
        let (f1, f2) = (db - da, dc - da);
        let mean = (da + db + dc) / 3.0;
        *term = [0.5 * mean.dot(&e1.cross(&e2)), 0.25 * mean.dot(&(e1.cross(&f2) + f1.cross(&e2))), mean.dot(&f1.cross(&f2)) / 6.0];
    });
    let mut c = [0.0; 3];
    for term in terms.iter() {
        for k in 0..3 {
            c[k] += term[k];
        }
    }
    let Some(s) = displacement_scale(c, side, target, &w.name)? else {
        // only rim nodes were hit: the volume waits for a step that moves an inner node
        w.pending = target;
        return Ok(());
    };
    par_update(moved, |j, p| *p = nodes_now[j] + s * displacement[j]);
    // a node may move at most half its shortest edge in one step: deeper, its triangles fold
    par_update(shortest, |j, shortest| {
        let mut m = f64::INFINITY;
        for &corner in topology.corners(j) {
            let t = &surface.triangles[corner as usize / 3];
            let k = corner as usize % 3;
            for other in [t[(k + 1) % 3], t[(k + 2) % 3]] {
                m = m.min((nodes_now[j] - nodes_now[other as usize]).norm());
            }
        }
        *shortest = m;
    });
    let shortest = &*shortest;
    if let Some(j) = first(n, |j| s * displacement[j].norm() > 0.5 * shortest[j]) {
        return Err(inside_out(&w.name, nodes_now[j]));
    }
    let moved = &*moved;
    let folds = |t: usize| {
        let tri = &surface.triangles[t];
        let [a2, b2, c2] = tri.map(|n| moved[n as usize]);
        tan[t].dot(&(b2 - a2).cross(&(c2 - a2))) <= 0.0
    };
    if let Some(t) = first(surface.triangles.len(), folds) {
        let [a, b, cc] = surface.triangles[t].map(|n| nodes_now[n as usize]);
        return Err(inside_out(&w.name, (a + b + cc) / 3.0));
    }
    let node_of_vertex = &surface.node_of_vertex;
    par_update(&mut wall.vertices, |v, p| {
        let node = node_of_vertex[v] as usize;
        if displacement[node] != Vec3::zeros() {
            *p = moved[node];
        }
    });
    par_update(&mut w.node_depth, |j, total| {
        if movable(j) {
            *total += s * depth[j];
        }
    });
    // the node positions after the move (what WearSurface::nodes gives on the new vertices)
    par_update(nodes, |j, p| {
        if displacement[j] != Vec3::zeros() {
            *p = moved[j];
        }
    });
    w.receded += target;
    w.pending = 0.0;
    wall.revision += 1;
    Ok(())
}
