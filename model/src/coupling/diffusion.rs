//! The diffusion method (spec fluid-dem-model.md §6.4, §6.5): a cell field is smoothed by one
//! backward-Euler step of ∂q/∂τ = D ∇²q over the pseudo-time T,
//!
//!   V_j q_j − T D Σ_f (|S_f|/|d_f|)(q_N − q_j) = V_j q⁰_j,
//!
//! with zero flux through every boundary face [R, §6.4: homogeneous Neumann at walls, the
//! continuum mirror ghost] — sliding-interface sides included, so nothing diffuses across the
//! interface (the kernel method's truncation, Table 4.2). With D = (γ d_p)²/(2Δt) and T = Δt
//! (T4.46) the discrete second moment grows by exactly 2DT = (γ d_p)² per axis on a uniform
//! grid (§12 U-20), the Gaussian of width σ = γ d_p (T3.81).
//!
//! The matrix is symmetric positive definite; it is solved by conjugate gradients with a
//! Jacobi preconditioner to a relative residual of 1e-13, and the final residual r_j is then
//! added back as r_j/V_j: Σ_j V_j q_j = Σ_j V_j q⁰_j holds to round-off (the Laplacian's
//! column sums vanish), whatever the iteration count.

use crate::mesh::Mesh;

/// The smoothing operator of one mesh position.
pub struct Diffusion {
    /// T·D·|S_f|/|d_f| per internal face.
    coefficient: Vec<f64>,
    owner: Vec<usize>,
    neighbour: Vec<usize>,
    volume: Vec<f64>,
    /// Diagonal of the matrix.
    diagonal: Vec<f64>,
}

/// Relative residual the conjugate gradients stop at (the residual is then folded back, so
/// this sets the smoothness of the result, not its conservation).
pub const TOLERANCE: f64 = 1e-13;

impl Diffusion {
    /// The operator for diffusion length² `spread` = T·D = (γ d_p)²/2 on `mesh`.
    pub fn new(mesh: &Mesh, spread: f64) -> Self {
        let n_internal = mesh.n_internal_faces;
        let owner = mesh.face_owner[..n_internal].to_vec();
        let neighbour = mesh.face_neighbour[..n_internal].to_vec();
        let coefficient: Vec<f64> = (0..n_internal).map(|f| spread * mesh.face_areas[f].norm() / mesh.face_delta[f].norm()).collect();
        let mut diagonal = mesh.cell_volumes.clone();
        for (f, a) in coefficient.iter().enumerate() {
            diagonal[owner[f]] += a;
            diagonal[neighbour[f]] += a;
        }
        Self { coefficient, owner, neighbour, volume: mesh.cell_volumes.clone(), diagonal }
    }

    /// The internal faces' owners, neighbours and coefficients T·D·|S_f|/|d_f| (for a solver
    /// that assembles the same matrix its own way).
    pub fn faces(&self) -> (&[usize], &[usize], &[f64]) {
        (&self.owner, &self.neighbour, &self.coefficient)
    }

    /// The cell volumes V_j (the matrix's mass term and the fold-back's divisor).
    pub fn volumes(&self) -> &[f64] {
        &self.volume
    }

    /// The matrix diagonal V_j + Σ_f T·D·|S_f|/|d_f|.
    pub fn diagonal(&self) -> &[f64] {
        &self.diagonal
    }

    fn apply(&self, q: &[f64], out: &mut [f64]) {
        for (o, (v, x)) in out.iter_mut().zip(self.volume.iter().zip(q)) {
            *o = v * x;
        }
        for (f, a) in self.coefficient.iter().enumerate() {
            let (p, n) = (self.owner[f], self.neighbour[f]);
            let flux = a * (q[n] - q[p]);
            out[p] -= flux;
            out[n] += flux;
        }
    }

    /// Smooths `field` in place (one backward-Euler step of the module doc). Returns the number
    /// of conjugate-gradient iterations.
    pub fn smooth(&self, field: &mut [f64]) -> usize {
        let n = field.len();
        let b: Vec<f64> = field.iter().zip(&self.volume).map(|(q, v)| q * v).collect();
        let b_norm = b.iter().map(|x| x * x).sum::<f64>().sqrt();
        if b_norm == 0.0 {
            return 0;
        }
        let mut x = field.to_vec();
        let mut ax = vec![0.0; n];
        self.apply(&x, &mut ax);
        let mut r: Vec<f64> = b.iter().zip(&ax).map(|(b, a)| b - a).collect();
        let mut z: Vec<f64> = r.iter().zip(&self.diagonal).map(|(r, d)| r / d).collect();
        let mut p = z.clone();
        let mut rz: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
        let mut iterations = 0;
        let mut ap = vec![0.0; n];
        while r.iter().map(|x| x * x).sum::<f64>().sqrt() > TOLERANCE * b_norm && iterations < 10 * n + 100 {
            self.apply(&p, &mut ap);
            let alpha = rz / p.iter().zip(&ap).map(|(a, b)| a * b).sum::<f64>();
            for i in 0..n {
                x[i] += alpha * p[i];
                r[i] -= alpha * ap[i];
            }
            for i in 0..n {
                z[i] = r[i] / self.diagonal[i];
            }
            let rz_new: f64 = r.iter().zip(&z).map(|(a, b)| a * b).sum();
            let beta = rz_new / rz;
            rz = rz_new;
            for i in 0..n {
                p[i] = z[i] + beta * p[i];
            }
            iterations += 1;
        }
        // fold the final residual back (module doc): Σ V q = Σ b to round-off
        self.apply(&x, &mut ax);
        for i in 0..n {
            field[i] = x[i] + (b[i] - ax[i]) / self.volume[i];
        }
        iterations
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::cartesian::BoxSpec;
    use crate::mesh::Vec3;

    /// §12 U-20: a unit point load at a cell centre of a large uniform grid, diffused over one
    /// implicit step with T·D = (γ d)²/2, keeps its integral to round-off and has the second
    /// moment 2TD per axis. Exact on an infinite grid (the discrete Laplacian of x² is 2); the
    /// 81 × 81 grid reaches 40 cells = 20σ from the load, where the implicit step's tail has
    /// decayed like exp(−r√2/σ) ≈ 5e-13, so the walls change the moment by less than 1e-9.
    #[test]
    fn point_load_spreads_to_the_gaussian_width() {
        let n = 81;
        let h = 1.0 / n as f64;
        let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(1.0, 1.0, h), [n, n, 1])).unwrap();
        let sigma = 2.0 * h;
        let diffusion = Diffusion::new(&mesh, 0.5 * sigma * sigma);
        let centre = n / 2 + n * (n / 2);
        let mut q = vec![0.0; mesh.n_cells()];
        q[centre] = 1.0 / mesh.cell_volumes[centre];
        diffusion.smooth(&mut q);
        let total: f64 = q.iter().zip(&mesh.cell_volumes).map(|(q, v)| q * v).sum();
        assert!((total - 1.0).abs() < 1e-14, "integral {total}");
        let x0 = mesh.cell_centres[centre];
        for axis in 0..2 {
            let moment: f64 = (0..mesh.n_cells()).map(|c| q[c] * mesh.cell_volumes[c] * (mesh.cell_centres[c][axis] - x0[axis]).powi(2)).sum();
            assert!((moment / (sigma * sigma) - 1.0).abs() < 1e-9, "axis {axis}: second moment / σ² = {}", moment / (sigma * sigma));
        }
        assert!(q.iter().all(|&x| x >= -1e-14), "diffusion kept the field non-negative");
    }
}
