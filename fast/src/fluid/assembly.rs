//! Kernels shared by the stages of a step: Gauss gradients, tensor interpolation, the explicit
//! stress, the convection weight, and the parallel-loop helpers. Every per-cell quantity is a gather over the cell's links in ascending link order (the
//! reference's accumulation order), so each cell's value is computed by one thread in a fixed
//! order and the result is independent of the thread count.

use spillage_model::fluid::settings::ConvectionScheme;
use spillage_model::mesh::Vec3;

use super::layout::{Adjacency, Boundary, Links};

pub use crate::linear::Out;

/// Runs `f(c)` for every index in parallel (as [`crate::linear::par_range`]).
#[inline]
pub fn par_for(n: usize, f: impl Fn(usize) + Sync + Send) {
    crate::linear::par_range(n, f);
}

#[inline]
pub fn vec_of(u: &[Vec<f64>; 3], c: usize) -> Vec3 {
    Vec3::new(u[0][c], u[1][c], u[2][c])
}

/// Gauss gradient of a cell scalar with boundary values `phi_b` (per boundary face).
pub fn scalar_gradient(links: &Links, adj: &Adjacency, bnd: &Boundary, vol: &[f64], phi: &[f64], phi_b: &[f64], out: &mut [Vec3]) {
    let o = Out::of(out);
    par_for(vol.len(), |c| {
        let mut g = Vec3::zeros();
        for k in adj.row_start[c] as usize..adj.row_start[c + 1] as usize {
            let e = adj.entry[k] as usize;
            let l = e >> 1;
            let face = links.interpolate(l, phi[links.owner[l] as usize], phi[links.neighbour[l] as usize]);
            if e & 1 == 1 {
                g += links.area[l] * face;
            } else {
                g -= links.area[l] * face;
            }
        }
        for &b in &bnd.faces_of_cell[bnd.cell_start[c] as usize..bnd.cell_start[c + 1] as usize] {
            g += bnd.area[b as usize] * phi_b[b as usize];
        }
        unsafe { o.set(c, g / vol[c]) };
    });
}

/// Gradient tensor g[i][j] = ∂u_j/∂x_i of the cell velocity with boundary values `u_b`.
pub fn vector_gradient(links: &Links, adj: &Adjacency, bnd: &Boundary, vol: &[f64], u: &[Vec<f64>; 3], u_b: &[Vec3], out: &mut [[Vec3; 3]]) {
    let o = Out::of(out);
    par_for(vol.len(), |c| {
        let mut g = [Vec3::zeros(); 3]; // g_j = gradient of component j
        for k in adj.row_start[c] as usize..adj.row_start[c + 1] as usize {
            let e = adj.entry[k] as usize;
            let l = e >> 1;
            let (p, n) = (links.owner[l] as usize, links.neighbour[l] as usize);
            for j in 0..3 {
                let face = links.interpolate(l, u[j][p], u[j][n]);
                if e & 1 == 1 {
                    g[j] += links.area[l] * face;
                } else {
                    g[j] -= links.area[l] * face;
                }
            }
        }
        for &b in &bnd.faces_of_cell[bnd.cell_start[c] as usize..bnd.cell_start[c + 1] as usize] {
            for (j, gj) in g.iter_mut().enumerate() {
                *gj += bnd.area[b as usize] * u_b[b as usize][j];
            }
        }
        let v = vol[c];
        let mut t = [Vec3::zeros(); 3];
        for j in 0..3 {
            let gj = g[j] / v;
            for i in 0..3 {
                t[i][j] = gj[i];
            }
        }
        unsafe { o.set(c, t) };
    });
}

/// (d·∇)u for g[i][j] = ∂u_j/∂x_i.
#[inline]
pub fn directional(g: &[Vec3; 3], d: &Vec3) -> Vec3 {
    g[0] * d[0] + g[1] * d[1] + g[2] * d[2]
}

#[inline]
pub fn interpolate_tensor(w: f64, a: &[Vec3; 3], b: &[Vec3; 3]) -> [Vec3; 3] {
    [a[0] * w + b[0] * (1.0 - w), a[1] * w + b[1] * (1.0 - w), a[2] * w + b[2] * (1.0 - w)]
}

/// [(∇u)ᵀ − ⅔ tr(∇u) I]·S.
#[inline]
pub fn explicit_stress(g: &[Vec3; 3], s: &Vec3) -> Vec3 {
    let trace = g[0][0] + g[1][1] + g[2][2];
    Vec3::new(g[0].dot(s), g[1].dot(s), g[2].dot(s)) - s * (2.0 / 3.0 * trace)
}

/// Owner weight λ of the convected face value (spec §8.10), as the reference's `schemes`.
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn convection_weight(
    scheme: ConvectionScheme,
    linear_fraction: f64,
    weight: f64,
    delta: &Vec3,
    flux: f64,
    u_p: Vec3,
    u_n: Vec3,
    grad_upwind: impl Fn(bool) -> [Vec3; 3],
) -> f64 {
    let upwind = if flux >= 0.0 { 1.0 } else { 0.0 };
    match scheme {
        ConvectionScheme::Linear => weight,
        ConvectionScheme::Upwind => upwind,
        ConvectionScheme::Blended => linear_fraction * weight + (1.0 - linear_fraction) * upwind,
        ConvectionScheme::LimitedLinear => {
            let limiter = spillage_model::fluid::limiter::limited_linear_v(&u_p, &u_n, &directional(&grad_upwind(flux >= 0.0), delta));
            limiter * weight + (1.0 - limiter) * upwind
        }
    }
}
