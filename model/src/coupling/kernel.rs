//! The kernel method (spec fluid-dem-model.md §6.3, §6.5, §6.7): a particle's volume and forces
//! are spread over the cells within R = 3σ of its centre with the Gaussian φ, and the fluid it
//! sees is the ψ-weighted average over the same cells, ψ ∝ r² (zero at the centre, so the fluid
//! the particle drags along hardly counts).
//!
//! - Width σ = γ d_p (T4.45), support r ≤ 3σ (T3.76).
//! - Volume-consistent renormalisation [R, §6.7]: deposit weights w_j = φ_j V_j / Σ_k φ_k V_k
//!   (Σ_j w_j = 1, so Σ_j α_p,j V_j = V_p exactly), sample weights s_j = ψ_j V_j / Σ_k ψ_k V_k
//!   (Σ_j s_j = 1, uniform fields are reproduced). The prefactors of φ (T3.74) and ψ (T3.84)
//!   cancel, so only the shapes are evaluated.
//! - Walls: a ghost mirrored in the nearest wall face within 3σ (T4.50, T4.51, mirror
//!   construction [R]); its kernel is evaluated on the domain cells and normalised with the
//!   particle's.
//! - Sliding interface: only cells of the zone holding the particle (Table 4.2, "evaluated only
//!   on one side"); the normalisation runs over those cells alone.
//! - Cells wider than 1.5σ [R, deviation]: φ and ψ are integrated over the cell
//!   ([`cell_quadrature`]) instead of read at its centre, so a kernel narrower than the cells
//!   still moves smoothly from cell to cell; narrower cells are read at the centre as in
//!   T3.75/T3.85.
//! - Fallback [R, §6.7]: if no cell carries weight (ψ of a particle at a cell centre with only
//!   the host cell inside R) the host cell takes all of it (the centroid method).

use super::cell_quadrature;
use super::cell_search::CellSearch;
use crate::mesh::{Mesh, PatchKind, Vec3};

/// The ghost of a particle at `x`: its mirror image in the nearest wall face whose centre is
/// within `support` (faces of walls and other physical boundaries; not the front and back of a
/// 2-D mesh, not sliding-interface sides). `None` when no such face is near.
pub fn ghost_position(mesh: &Mesh, wall_faces: &[usize], x: &Vec3, support: f64) -> Option<Vec3> {
    let mut best: Option<(f64, usize)> = None;
    for &f in wall_faces {
        let d = (mesh.face_centres[f] - x).norm_squared();
        if best.is_none_or(|(b, _)| d < b) {
            best = Some((d, f));
        }
    }
    let (d2, f) = best?;
    ghost_in_face(mesh, f, d2, x, support)
}

/// The ghost of a particle at `x` in wall face `f`, the nearest to it (squared distance `d2`
/// between their centres), if that face is near enough ([`ghost_position`]).
pub fn ghost_in_face(mesh: &Mesh, f: usize, d2: f64, x: &Vec3, support: f64) -> Option<Vec3> {
    let n = mesh.face_areas[f].normalize();
    let h = (x - mesh.face_centres[f]).dot(&n);
    // the plane, not the face centre, decides: a particle beside a large face is still near it
    if d2.sqrt() > support + mesh.face_areas[f].norm().sqrt() || h.abs() > support {
        return None;
    }
    Some(x - n * (2.0 * h))
}

/// Boundary faces that mirror ghosts: every boundary face except 2-D front/back and sliding
/// interfaces.
pub fn wall_faces(mesh: &Mesh) -> Vec<usize> {
    mesh.patches.iter().filter(|p| matches!(p.kind, PatchKind::Wall | PatchKind::Patch)).flat_map(|p| p.faces()).collect()
}

/// One particle's cells and weights.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stencil {
    pub cells: Vec<usize>,
    /// w_j: Σ = 1; cell j receives the fraction w_j of what the particle deposits.
    pub deposit: Vec<f64>,
    /// s_j: Σ = 1; the particle sees Σ_j s_j q_j.
    pub sample: Vec<f64>,
}

/// What a kernel stencil is built from.
pub struct KernelGeometry<'a> {
    pub mesh: &'a Mesh,
    pub search: &'a CellSearch,
    pub wall_faces: &'a [usize],
    /// Whether the mesh has sliding interfaces (then stencils stay in the particle's zone).
    pub truncate_at_interface: bool,
    /// The normal of a 2-D mesh's front and back ([`cell_quadrature::empty_normal`]).
    pub empty_normal: Option<Vec3>,
}

/// The stencil of a particle at `x` of diameter `d` whose centre lies in `host`, with distance
/// factor `gamma`. `scratch` is reused between calls.
pub fn stencil(geo: &KernelGeometry, x: &Vec3, diameter: f64, gamma: f64, host: usize, scratch: &mut Vec<usize>) -> Stencil {
    let mesh = geo.mesh;
    let sigma = gamma * diameter;
    let support = 3.0 * sigma;
    let ghost = ghost_position(mesh, geo.wall_faces, x, support);
    scratch.clear();
    geo.search.reaching(mesh, x, support, scratch);
    if let Some(g) = &ghost {
        geo.search.reaching(mesh, g, support, scratch);
    }
    scratch.sort_unstable();
    scratch.dedup();
    let zone = mesh.cell_zone[host];
    let mut out = Stencil::default();
    let (mut phi_sum, mut psi_sum) = (0.0, 0.0);
    let shapes = KernelShapes::new(sigma);
    let kernels = |point: &Vec3| shapes.around(point, &x, ghost.as_ref());
    // the search's spans hold for this quadrature if they were taken with its 2-D normal
    let spans_apply = geo.search.empty_normal() == geo.empty_normal;
    for &c in scratch.iter() {
        if geo.truncate_at_interface && mesh.cell_zone[c] != zone {
            continue;
        }
        let (phi, psi) = if spans_apply && cell_quadrature::takes_one_point(geo.search.span(c), sigma) {
            // integrate's one-point rule without its edge lengths (the cell is narrower than the lattice)
            let (phi, psi) = kernels(&mesh.cell_centres[c]);
            (phi * mesh.cell_volumes[c], psi * mesh.cell_volumes[c])
        } else {
            cell_quadrature::integrate(mesh, c, sigma, geo.empty_normal.as_ref(), &kernels)
        };
        if phi == 0.0 && psi == 0.0 {
            continue;
        }
        out.cells.push(c);
        out.deposit.push(phi);
        out.sample.push(psi);
        phi_sum += phi;
        psi_sum += psi;
    }
    normalise_or_host(&mut out, phi_sum, psi_sum, host);
    out
}

/// Divides the weights by their sums; a weight set that sums to zero goes to the host cell.
fn normalise_or_host(s: &mut Stencil, phi_sum: f64, psi_sum: f64, host: usize) {
    let host_index = match s.cells.iter().position(|&c| c == host) {
        Some(i) => i,
        None => {
            s.cells.push(host);
            s.deposit.push(0.0);
            s.sample.push(0.0);
            s.cells.len() - 1
        }
    };
    for (weights, sum) in [(&mut s.deposit, phi_sum), (&mut s.sample, psi_sum)] {
        if sum > 0.0 {
            weights.iter_mut().for_each(|w| *w /= sum);
        } else {
            weights.iter_mut().for_each(|w| *w = 0.0);
            weights[host_index] = 1.0;
        }
    }
}

/// The two kernels' shapes: φ = exp(−r²/2σ²) within 3σ (T3.74, T3.76) and ψ = r² within
/// R = 3σ (T3.84), both without their prefactors, which the normalisation cancels; from r²
/// alone, no root per point. Shared with the fast solver's stencils, which must have these bits.
#[derive(Clone, Copy, Debug)]
pub struct KernelShapes {
    pub support2: f64,
    pub inverse_2s2: f64,
}

impl KernelShapes {
    pub fn new(sigma: f64) -> Self {
        let support = 3.0 * sigma;
        Self { support2: support * support, inverse_2s2: 1.0 / (2.0 * sigma * sigma) }
    }

    /// (φ, ψ) at squared distance `r2` from the centre.
    #[inline]
    pub fn at(&self, r2: f64) -> (f64, f64) {
        if r2 <= self.support2 {
            (self.phi(r2), if r2 < self.support2 { r2 } else { 0.0 })
        } else {
            (0.0, 0.0)
        }
    }

    /// φ = e^{−r²/2σ²} at squared distance `r2` (within the support or not). The exponential is
    /// the model's own ([`crate::closure::elementary::exp`], within one unit in the last place
    /// of the C library's), whose bits do not depend on the machine or on SIMD lanes: a solver
    /// may evaluate many cells' φ at once and still get this function's bits.
    #[inline(always)]
    pub fn phi(&self, r2: f64) -> f64 {
        crate::closure::elementary::exp(-r2 * self.inverse_2s2)
    }

    /// (φ, ψ) at `point` of a particle at `x`, plus its mirror `ghost` beyond a wall.
    #[inline]
    pub fn around(&self, point: &Vec3, x: &Vec3, ghost: Option<&Vec3>) -> (f64, f64) {
        let (mut phi, mut psi) = self.at((point - x).norm_squared());
        if let Some(g) = ghost {
            let (a, b) = self.at((point - g).norm_squared());
            phi += a;
            psi += b;
        }
        (phi, psi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::cartesian::BoxSpec;

    fn geometry(mesh: &Mesh, support: f64) -> (CellSearch, Vec<usize>) {
        (CellSearch::new(mesh, support), wall_faces(mesh))
    }

    /// U-19/U-23 (§12): Σ_j w_j V_p = V_p to round-off in the interior, at a wall (with the
    /// ghost) and in a corner; the sample weights sum to 1 and reproduce a uniform field.
    #[test]
    fn deposit_and_sample_weights_sum_to_one_everywhere() {
        let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::repeat(0.1), [10, 10, 10])).unwrap();
        let (d, gamma) = (0.01, 1.0);
        let (search, walls) = geometry(&mesh, 3.0 * gamma * d);
        let geo = KernelGeometry { mesh: &mesh, search: &search, wall_faces: &walls, truncate_at_interface: false, empty_normal: None };
        let mut scratch = Vec::new();
        for x in [Vec3::new(0.05, 0.05, 0.05), Vec3::new(0.004, 0.05, 0.05), Vec3::new(0.003, 0.002, 0.097)] {
            let host = mesh.locate(&x).unwrap();
            let s = stencil(&geo, &x, d, gamma, host, &mut scratch);
            let deposit: f64 = s.deposit.iter().sum();
            let sample: f64 = s.sample.iter().sum();
            assert!((deposit - 1.0).abs() < 1e-14 && (sample - 1.0).abs() < 1e-14, "{x}: {deposit} {sample}");
            assert!(s.cells.len() > 8, "{x}: the kernel spans {} cells", s.cells.len());
        }
    }

    /// U-23: a particle at distance h from a plane wall gets a ghost at distance h behind it.
    #[test]
    fn ghost_is_the_mirror_image_in_the_nearest_wall() {
        let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::repeat(1.0), [4, 4, 4])).unwrap();
        let walls = wall_faces(&mesh);
        let g = ghost_position(&mesh, &walls, &Vec3::new(0.3, 0.5, 0.1), 0.2).unwrap();
        assert!((g - Vec3::new(0.3, 0.5, -0.1)).norm() < 1e-15, "{g}");
        assert!(ghost_position(&mesh, &walls, &Vec3::new(0.5, 0.5, 0.5), 0.2).is_none());
    }

    /// U-21: with the particle at a cell centre of a uniform grid the ψ stencil is symmetric,
    /// so a linear field is reproduced exactly; ψ(0) = 0, so the host cell gets no weight.
    /// (R = 3.3 cells: with R a whole number of cells the cells at exactly R fall inside on one
    /// side and outside on the other by round-off, and ψ is largest there.)
    #[test]
    fn quadratic_sample_reproduces_a_linear_field_at_a_cell_centre() {
        let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::repeat(1.0), [20, 20, 20])).unwrap();
        let (d, gamma) = (0.055, 1.0);
        let (search, walls) = geometry(&mesh, 3.0 * gamma * d);
        let geo = KernelGeometry { mesh: &mesh, search: &search, wall_faces: &walls, truncate_at_interface: false, empty_normal: None };
        let x = Vec3::new(0.475, 0.525, 0.475);
        let host = mesh.locate(&x).unwrap();
        let s = stencil(&geo, &x, d, gamma, host, &mut Vec::new());
        let field = |c: usize| 2.0 * mesh.cell_centres[c].x - 3.0 * mesh.cell_centres[c].y + 0.5 * mesh.cell_centres[c].z + 1.0;
        let sampled: f64 = s.cells.iter().zip(&s.sample).map(|(&c, w)| w * field(c)).sum();
        let exact = 2.0 * x.x - 3.0 * x.y + 0.5 * x.z + 1.0;
        assert!((sampled - exact).abs() < 1e-13, "{sampled} vs {exact}");
        let host_weight = s.cells.iter().position(|&c| c == host).map_or(0.0, |i| s.sample[i]);
        // ψ(r) = r² with r the round-off offset of the given point from the computed centre
        assert!(host_weight < 1e-25, "host weight {host_weight}");
    }

    /// A kernel wholly inside its host cell puts all its weight there.
    #[test]
    fn a_kernel_inside_one_cell_stays_in_it() {
        let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::repeat(1.0), [2, 2, 2])).unwrap();
        let (search, walls) = geometry(&mesh, 0.03);
        let geo = KernelGeometry { mesh: &mesh, search: &search, wall_faces: &walls, truncate_at_interface: false, empty_normal: None };
        let x = Vec3::new(0.3, 0.3, 0.3);
        let host = mesh.locate(&x).unwrap();
        let s = stencil(&geo, &x, 0.01, 1.0, host, &mut Vec::new());
        assert_eq!((s.cells.as_slice(), s.deposit.as_slice(), s.sample.as_slice()), ([host].as_slice(), [1.0].as_slice(), [1.0].as_slice()));
    }
}
