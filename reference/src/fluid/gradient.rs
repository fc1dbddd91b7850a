//! Cell gradients by the Gauss theorem with linearly interpolated face values (spec §8.1,
//! T4.8/T4.10): ∇φ_P = (1/V_P) Σ_f φ_f S_f.

use spillage_model::mesh::Vec3;

use super::geometry::Geometry;

/// Gradient of a cell scalar; `boundary_values[b]` is the value on `geo.boundary[b]`.
pub fn scalar_gradient(geo: &Geometry, volumes: &[f64], cell: &[f64], boundary_values: &[f64]) -> Vec<Vec3> {
    let mut grad = vec![Vec3::zeros(); cell.len()];
    for link in &geo.links {
        let face = link.interpolate(cell[link.owner], cell[link.neighbour]);
        grad[link.owner] += link.area * face;
        grad[link.neighbour] -= link.area * face;
    }
    for (b, face) in geo.boundary.iter().enumerate() {
        grad[face.cell] += face.area * boundary_values[b];
    }
    for (g, v) in grad.iter_mut().zip(volumes) {
        *g /= *v;
    }
    grad
}

/// Gradient tensor of a cell vector, g[i][j] = ∂u_j/∂x_i (OpenFOAM's convention).
pub fn vector_gradient(geo: &Geometry, volumes: &[f64], cell: &[Vec3], boundary_values: &[Vec3]) -> Vec<[Vec3; 3]> {
    let mut grad = vec![[Vec3::zeros(); 3]; cell.len()];
    for j in 0..3 {
        let component: Vec<f64> = cell.iter().map(|u| u[j]).collect();
        let boundary: Vec<f64> = boundary_values.iter().map(|u| u[j]).collect();
        let g = scalar_gradient(geo, volumes, &component, &boundary);
        for (c, gc) in g.iter().enumerate() {
            for i in 0..3 {
                grad[c][i][j] = gc[i];
            }
        }
    }
    grad
}

/// (d·∇)u for a gradient tensor g[i][j] = ∂u_j/∂x_i.
pub fn directional(g: &[Vec3; 3], d: &Vec3) -> Vec3 {
    g[0] * d[0] + g[1] * d[1] + g[2] * d[2]
}
