//! Step 3 of wear: the eroding wall recedes (wear-model.md §7.4).
//!
//! Each node moves into the wall material along its area-weighted normal (§7.4 [R]); rim nodes
//! of an open wall stay put ([R] "pin them"). The depths from the smoothing are scaled by one
//! factor s so that the volume the surface sweeps, a cubic in s computed exactly per triangle
//! ([`WearSurface::swept_volume_coefficients`]), equals the volume this step removes: the wall
//! geometry loses exactly what the impacts deposited, however coarse the triangles.

use spillage_model::walls::state::{Vec3, Wall};
use spillage_model::wear::recession::{displacement_scale, inside_out};
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
    let Some(s) = displacement_scale(c, side, target, &w.name)? else {
        // only rim nodes were hit: the volume waits for a step that moves an inner node
        w.pending = target;
        return Ok(());
    };
    let moved: Vec<Vec3> = nodes.iter().zip(&displacement).map(|(p, d)| p + s * d).collect();
    // a node may move at most half its shortest edge in one step: deeper, its triangles fold
    let mut shortest = vec![f64::INFINITY; surface.n_nodes];
    for t in &surface.triangles {
        for k in 0..3 {
            let (i, j) = (t[k] as usize, t[(k + 1) % 3] as usize);
            let length = (nodes[i] - nodes[j]).norm();
            shortest[i] = shortest[i].min(length);
            shortest[j] = shortest[j].min(length);
        }
    }
    if let Some(j) = (0..surface.n_nodes).find(|&j| s * displacement[j].norm() > 0.5 * shortest[j]) {
        return Err(inside_out(&w.name, nodes[j]));
    }
    for t in &surface.triangles {
        let [a, b, cc] = t.map(|n| nodes[n as usize]);
        let [a2, b2, c2] = t.map(|n| moved[n as usize]);
        if (b - a).cross(&(cc - a)).dot(&(b2 - a2).cross(&(c2 - a2))) <= 0.0 {
            return Err(inside_out(&w.name, (a + b + cc) / 3.0));
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

#[cfg(test)]
mod tests {
    use super::*;
    use spillage_model::walls::geometry::box_faces;
    use spillage_model::walls::state::WallMotion;

    fn closed_box() -> (Wall, WearSurface, WallWear) {
        let mesh = box_faces(Vec3::zeros(), Vec3::new(0.1, 0.1, 0.1), 4, &[]);
        let surface = WearSurface::new(&mesh.vertices, &mesh.triangles);
        let wall = spillage_model::walls::wall("box".into(), 0, mesh, WallMotion::Static).unwrap();
        let nodes = surface.nodes(&wall.vertices);
        let mut w = WallWear::new(0, "box".into(), wall.triangles.len(), surface.node_of_vertex.clone(), surface.n_nodes);
        w.volume_origin = [0.05; 3];
        w.initial_volume = surface.cone_volume(&nodes, Vec3::from(w.volume_origin));
        w.material_side = -w.initial_volume.signum();
        (wall, surface, w)
    }

    #[test]
    fn a_closed_wall_loses_exactly_the_removed_volume_from_its_enclosed_volume() {
        let (mut wall, surface, mut w) = closed_box();
        assert!(surface.closed && (w.initial_volume.abs() - 1e-3).abs() < 1e-15);
        // uneven depths on the nodes of the top face, including its edges and corners
        let nodes = surface.nodes(&wall.vertices);
        let depth: Vec<f64> = nodes.iter().map(|p| if p.z > 0.0999 { 1e-4 * (1.0 + 3.0 * p.x + 5.0 * p.y) } else { 0.0 }).collect();
        let removed: f64 = depth.iter().zip(&surface.node_area).map(|(d, a)| d * a).sum();
        recede(&surface, &nodes, &depth, true, &mut wall, &mut w).unwrap();
        let after = surface.cone_volume(&surface.nodes(&wall.vertices), Vec3::from(w.volume_origin));
        // the enclosed volume is the box's less the removed volume, up to round-off
        assert!((w.initial_volume.abs() - after.abs() - removed).abs() <= 1e-12 * removed, "{} vs {removed}", w.initial_volume.abs() - after.abs());
        assert_eq!(wall.revision, 1);
        // the top moved down (into the box), the bottom stayed
        let moved = surface.nodes(&wall.vertices);
        assert!(moved.iter().zip(&nodes).all(|(a, b)| a.z <= b.z + 1e-18));
        assert!(moved.iter().zip(&nodes).filter(|(_, b)| b.z < 1e-9).all(|(a, b)| a == b));
    }

    #[test]
    fn wear_deeper_than_the_triangles_is_refused_and_leaves_the_wall_alone() {
        let (mut wall, surface, mut w) = closed_box();
        let before = wall.clone();
        let nodes = surface.nodes(&wall.vertices);
        let depth: Vec<f64> = nodes.iter().map(|p| if (p.x - 0.05).abs() < 1e-9 && (p.y - 0.05).abs() < 1e-9 && p.z > 0.0999 { 0.2 } else { 0.0 }).collect();
        let error = recede(&surface, &nodes, &depth, true, &mut wall, &mut w).unwrap_err();
        assert!(error.contains("wall `box` would turn inside out"), "{error}");
        assert_eq!(wall, before);
    }
}
