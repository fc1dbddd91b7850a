//! Step 3 of wear: the eroding wall recedes (wear-model.md §7.4).
//!
//! Each node moves into the wall material along its area-weighted normal (§7.4 [R]); rim nodes
//! of an open wall stay put ([R] "pin them"). The depths from the smoothing are scaled by one
//! factor s so that the volume the surface sweeps, a cubic in s computed exactly per triangle
//! ([`WearSurface::swept_volume_coefficients`]), equals the volume this step removes: the wall
//! geometry loses exactly what the impacts deposited, however coarse the triangles.

use spillage_model::walls::state::{Vec3, Wall};
use spillage_model::wear::state::WallWear;
use spillage_model::wear::surface::WearSurface;

/// Moves `wall` by the node depths `depth` (or, static, only books them). Errors name the wall
/// and where it would turn inside out.
pub fn recede(surface: &WearSurface, nodes: &[Vec3], depth: &[f64], receding: bool, wall: &mut Wall, w: &mut WallWear) -> Result<(), String> {
    let step_volume: f64 = depth.iter().zip(&surface.node_area).map(|(d, a)| d * a).sum();
    if !receding {
        // static-boundary mode (§7.4): the depths are booked, the geometry stays
        for (total, d) in w.node_depth.iter_mut().zip(depth) {
            *total += d;
        }
        w.receded += step_volume;
        return Ok(());
    }
    let target = step_volume + w.pending;
    if !(target > 0.0) {
        return Ok(());
    }
    let normals = surface.node_normals(nodes);
    let side = w.material_side;
    let movable = |j: usize| !surface.rim[j] && depth[j] > 0.0;
    let displacement: Vec<Vec3> = (0..surface.n_nodes).map(|j| if movable(j) { side * depth[j] * normals[j] } else { Vec3::zeros() }).collect();
    let c = surface.swept_volume_coefficients(nodes, &displacement);
    let removed = |s: f64| side * (c[0] * s + c[1] * s * s + c[2] * s * s * s);
    let slope = |s: f64| side * (c[0] + 2.0 * c[1] * s + 3.0 * c[2] * s * s);
    if !(side != 0.0 && slope(0.0) > 0.0) {
        // only rim nodes were hit: the volume waits for a step that moves an inner node
        w.pending = target;
        return Ok(());
    }
    let mut s = target / slope(0.0);
    for _ in 0..50 {
        let step = (removed(s) - target) / slope(s);
        s -= step;
        if step.abs() <= 1e-15 * s.abs() {
            break;
        }
    }
    if !(s.is_finite() && s > 0.0 && (removed(s) - target).abs() <= 1e-12 * target) {
        return Err(format!("wall `{}`: the receding wall's volume equation has no solution (removed volume {target:e} m³)", w.name));
    }
    let moved: Vec<Vec3> = nodes.iter().zip(&displacement).map(|(p, d)| p + s * d).collect();
    for t in &surface.triangles {
        let [a, b, cc] = t.map(|n| nodes[n as usize]);
        let [a2, b2, c2] = t.map(|n| moved[n as usize]);
        if (b - a).cross(&(cc - a)).dot(&(b2 - a2).cross(&(c2 - a2))) <= 0.0 {
            let centre = (a + b + cc) / 3.0;
            return Err(format!(
                "wall `{}` would turn inside out near ({:.4}, {:.4}, {:.4}) m (body frame): the wear of one step is deeper than its triangles are wide; lower [wear] acceleration or modifier, or widen [wear.smoothing]",
                w.name, centre.x, centre.y, centre.z
            ));
        }
    }
    for (v, &node) in wall.vertices.iter_mut().zip(&surface.node_of_vertex) {
        let node = node as usize;
        if displacement[node] != Vec3::zeros() {
            *v = moved[node];
        }
    }
    for j in 0..surface.n_nodes {
        if movable(j) {
            w.node_depth[j] += s * depth[j];
        }
    }
    w.receded += target;
    w.pending = 0.0;
    wall.revision += 1;
    Ok(())
}

/// The volume the wall has lost, measured on its geometry: the change of its cone volume about
/// the fixed origin (for a closed wall its enclosed volume; for an open one, with its rim fixed,
/// the volume swept), signed so that removed material counts positive.
pub fn geometric_removed_volume(surface: &WearSurface, w: &WallWear, vertices: &[Vec3]) -> f64 {
    let nodes = surface.nodes(vertices);
    w.material_side * (surface.cone_volume(&nodes, Vec3::from(w.volume_origin)) - w.initial_volume)
}
