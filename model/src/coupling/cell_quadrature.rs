//! A kernel's share of one cell, integrated over the cell rather than read at its centre
//! [R, deviation from T3.75/T3.85, fluid-dem-model.md §6.7].
//!
//! The thesis evaluates φ and ψ at the cell centres. That is a one-point quadrature of the
//! kernel over the cell, and it breaks down once the kernel is narrower than the cell: at
//! d_p/Δx = 0.1 (P1, particle-verification.md §2) the support 3σ = 3 cm of a 10 mm particle
//! reaches no centre of the 10 cm cells, the weights fall back to the host cell, and the
//! particle's whole volume jumps to the next cell in the step its centre crosses a face. The
//! pressure equation turns that jump into a one-step return flow (Eq. 6.6), which the
//! particle's fluid-acceleration force feeds straight back: P1's settling velocity dipped by
//! 6.5 % of u_t at each crossing (kernel γ = 1; the diffusion method, whose deposit starts from
//! the host cell, 5.3 %).
//!
//! Here a cell's weight is the kernel integrated over the cell: the cell is cut into
//! n_ξ × n_η × n_ζ parametric sub-cells of its trilinear hexahedron, no wider than
//! [`LATTICE_SPACING`] σ along each edge direction, and the kernel is summed at their centres
//! with their volumes. A Gaussian summed on a lattice of spacing h matches its integral up to a
//! ripple 2 exp(−2π²σ²/h²) (Poisson summation): 3e-4 at h = 1.5σ, so the footprint moves smoothly
//! with the particle whatever the cell size. Cells no wider than 1.5σ take one point, the centre
//! with the cell's volume: exactly the thesis' evaluation, so every case whose kernel spans its
//! cells (d_p/Δx ≥ 1/(1.5γ)) is unchanged.

use crate::mesh::{Mesh, PatchKind, Vec3};

/// The widest sub-cell, in kernel widths σ: the ripple of the lattice sum is 3e-4 (module doc),
/// at 3.4× fewer points than a spacing of σ (ripple 5e-9) on the cutter head's 5 cm cells.
pub const LATTICE_SPACING: f64 = 1.5;

/// Sub-cells per edge direction at most: 32³ points bound the cost of a cell hundreds of kernel
/// widths across. At the cap the lattice is coarser than σ and the sum is no longer smooth to
/// round-off, but still far smoother than the host-cell jump.
pub const MAX_SUBDIVISIONS: usize = 32;

/// Parametric (ξ, η, ζ) ∈ {0, 1}³ of the VTK_HEXAHEDRON corners.
const CORNERS: [[f64; 3]; 8] =
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0], [0.0, 1.0, 1.0]];

/// Corner pairs of the four edges along each parametric direction.
const EDGES: [[(usize, usize); 4]; 3] = [[(0, 1), (3, 2), (4, 5), (7, 6)], [(0, 3), (1, 2), (4, 7), (5, 6)], [(0, 4), (1, 5), (2, 6), (3, 7)]];

/// The longest edge along each parametric direction, `None` for a direction through a 2-D
/// mesh's thickness (`empty` = the normal of its front and back: nothing varies across it).
fn longest_edges(corners: &[Vec3; 8], empty: Option<&Vec3>) -> [Option<f64>; 3] {
    std::array::from_fn(|d| {
        let (a, b) = EDGES[d][0];
        let edge = corners[b] - corners[a];
        if empty.is_some_and(|n| edge.dot(n).abs() > 0.5 * edge.norm() * n.norm()) {
            return None;
        }
        Some(EDGES[d].iter().map(|&(a, b)| (corners[b] - corners[a]).norm()).fold(0.0, f64::max))
    })
}

/// Sub-cells along a direction whose longest edge is `longest`, for a kernel of width `width`
/// (`ceil` of its ratio to the lattice spacing, not clamped).
#[inline]
fn raw_count(longest: f64, width: f64) -> f64 {
    // a cell exactly as wide as the spacing up to round-off takes one point
    (longest / (LATTICE_SPACING * width) * (1.0 - 1e-9)).ceil()
}

/// Sub-cells per parametric direction for a kernel of width `width`: the longest edge along the
/// direction over [`LATTICE_SPACING`] `width`, rounded up, between 1 and [`MAX_SUBDIVISIONS`]. A 2-D mesh (`empty`
/// = the normal of its front and back) is not cut through its thickness: nothing varies across
/// it, and its cells are read on the mid-plane as the thesis' centres are.
pub fn subdivisions(corners: &[Vec3; 8], width: f64, empty: Option<&Vec3>) -> [usize; 3] {
    let longest = longest_edges(corners, empty);
    std::array::from_fn(|d| {
        let Some(longest) = longest[d] else { return 1 };
        let n = raw_count(longest, width);
        if n.is_finite() && n >= 1.0 {
            (n as usize).min(MAX_SUBDIVISIONS)
        } else {
            1
        }
    })
}

/// The longest edge of cell `c` over the directions [`subdivisions`] may cut (0 if none): what
/// [`takes_one_point`] needs, computed once per cell instead of once per cell and particle.
pub fn widest_span(mesh: &Mesh, c: usize, empty: Option<&Vec3>) -> f64 {
    let corners: [Vec3; 8] = std::array::from_fn(|k| mesh.points[mesh.cell_points[c][k]]);
    longest_edges(&corners, empty).iter().flatten().fold(0.0, |a, &b| a.max(b))
}

/// Whether a cell of [`widest_span`] `span` takes one point for a kernel of width `width`,
/// without [`subdivisions`]: every cut direction's edge count is at most that of the widest
/// (the count is monotone in the length, the same float operations on a larger number), so
/// when it rounds up to 1 all do. A cheap test on the stencil's hot path: the same weights,
/// bit for bit. (A non-finite count, which `subdivisions` also maps to 1, answers false: the
/// caller then integrates, which is only slower.)
#[inline]
pub fn takes_one_point(span: f64, width: f64) -> bool {
    raw_count(span, width) <= 1.0
}

/// The normal of a 2-D mesh's front and back (its `Empty` patches), `None` for a 3-D mesh.
pub fn empty_normal(mesh: &Mesh) -> Option<Vec3> {
    let patch = mesh.patches.iter().find(|p| p.kind == PatchKind::Empty)?;
    patch.faces().next().map(|f| mesh.face_areas[f])
}

/// Σ_q w_q f(x_q) over the quadrature points of cell `c` for a kernel of width `width`, with
/// Σ_q w_q = the cell's volume (`empty`: see [`subdivisions`]). Returns the sums of the two kernels `f` gives at each point
/// (φ and ψ), so both are integrated at the same points.
pub fn integrate(mesh: &Mesh, c: usize, width: f64, empty: Option<&Vec3>, mut f: impl FnMut(&Vec3) -> (f64, f64)) -> (f64, f64) {
    let corners: [Vec3; 8] = std::array::from_fn(|k| mesh.points[mesh.cell_points[c][k]]);
    let n = subdivisions(&corners, width, empty);
    if n == [1, 1, 1] {
        let (a, b) = f(&mesh.cell_centres[c]);
        return (a * mesh.cell_volumes[c], b * mesh.cell_volumes[c]);
    }
    let (mut sum_a, mut sum_b, mut weights) = (0.0, 0.0, 0.0);
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let xi = [(i as f64 + 0.5) / n[0] as f64, (j as f64 + 0.5) / n[1] as f64, (k as f64 + 0.5) / n[2] as f64];
                let (x, jacobian) = trilinear(&corners, xi);
                let (a, b) = f(&x);
                sum_a += jacobian * a;
                sum_b += jacobian * b;
                weights += jacobian;
            }
        }
    }
    // the midpoint rule misses the volume of a distorted hexahedron by a little; scaling to the
    // mesh's own volume keeps a uniform kernel's weights exactly proportional to V_j
    let scale = mesh.cell_volumes[c] / weights;
    (sum_a * scale, sum_b * scale)
}

/// The quadrature [`integrate`] takes on cell `c` for width `width`, for callers that integrate
/// many kernels over the same cell: `None` when it is the one-point rule (the centre with the
/// cell's volume); else its points and Jacobians, in [`integrate`]'s order, appended to `out`,
/// and their sum in that order. Σ_q J_q f(x_q) · V / Σ_q J_q over these, in this order, is
/// [`integrate`] bit for bit.
pub fn quadrature_points(mesh: &Mesh, c: usize, width: f64, empty: Option<&Vec3>, out: &mut Vec<(Vec3, f64)>) -> Option<f64> {
    let corners: [Vec3; 8] = std::array::from_fn(|k| mesh.points[mesh.cell_points[c][k]]);
    let n = subdivisions(&corners, width, empty);
    if n == [1, 1, 1] {
        return None;
    }
    let mut weights = 0.0;
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                let xi = [(i as f64 + 0.5) / n[0] as f64, (j as f64 + 0.5) / n[1] as f64, (k as f64 + 0.5) / n[2] as f64];
                let (x, jacobian) = trilinear(&corners, xi);
                out.push((x, jacobian));
                weights += jacobian;
            }
        }
    }
    Some(weights)
}

/// The point of the trilinear map at parametric `xi` and the map's Jacobian determinant there.
fn trilinear(corners: &[Vec3; 8], xi: [f64; 3]) -> (Vec3, f64) {
    let mut x = Vec3::zeros();
    let mut d = [Vec3::zeros(); 3];
    for (p, c) in corners.iter().zip(&CORNERS) {
        let s: [f64; 3] = std::array::from_fn(|a| if c[a] == 1.0 { xi[a] } else { 1.0 - xi[a] });
        let ds: [f64; 3] = std::array::from_fn(|a| if c[a] == 1.0 { 1.0 } else { -1.0 });
        x += p * (s[0] * s[1] * s[2]);
        d[0] += p * (ds[0] * s[1] * s[2]);
        d[1] += p * (s[0] * ds[1] * s[2]);
        d[2] += p * (s[0] * s[1] * ds[2]);
    }
    (x, d[0].dot(&d[1].cross(&d[2])).abs())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::cartesian::BoxSpec;

    /// On a box cell the sub-cells tile it: a constant integrates to the volume, a linear
    /// function to volume × its centre value, x² to its exact moment (midpoint rule: error
    /// h²/(12 n²) per axis, compared against that closed form).
    #[test]
    fn box_cell_moments_are_exact() {
        let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(0.3, 0.2, 0.02), [3, 2, 1])).unwrap();
        let c = 4; // [0.1, 0.2] × [0.1, 0.2] × [0, 0.02]
        let width = 0.01;
        let corners: [Vec3; 8] = std::array::from_fn(|k| mesh.points[mesh.cell_points[c][k]]);
        assert_eq!(subdivisions(&corners, width, None), [7, 7, 2]);
        assert_eq!(subdivisions(&corners, width, Some(&Vec3::z())), [7, 7, 1]);
        let (volume, linear) = integrate(&mesh, c, width, None, |x| (1.0, 2.0 * x.x - x.y + 3.0 * x.z));
        assert!((volume - 2e-4).abs() < 1e-18, "{volume}");
        assert!((linear - 2e-4 * (0.3 - 0.15 + 0.03)).abs() < 1e-17, "{linear}");
        let (second, _) = integrate(&mesh, c, width, None, |x| ((x.x - 0.15).powi(2), 0.0));
        // midpoint rule over 7 sub-cells: Σ = ∫ − V h_s²/12 with h_s = 0.1/7
        let exact = 2e-4 * (0.1f64.powi(2) / 12.0 - (0.1f64 / 7.0).powi(2) / 12.0);
        assert!((second - exact).abs() < 1e-18, "{second} vs {exact}");
    }

    /// The tabulated quadrature gives [`integrate`]'s bits (a box cell and a sheared one).
    #[test]
    fn tabulated_points_integrate_to_the_same_bits() {
        let mut mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(0.3, 0.2, 0.02), [3, 2, 1])).unwrap();
        for p in mesh.points.iter_mut() {
            p.x += 0.13 * p.y * p.y;
        }
        let f = |x: &Vec3| ((-(x - Vec3::new(0.14, 0.12, 0.01)).norm_squared() / 2e-4).exp(), (x.x - 0.1) * (x.x - 0.1));
        for c in 0..mesh.n_cells() {
            for width in [0.004, 0.01, 0.5] {
                let mut points = Vec::new();
                let got = match quadrature_points(&mesh, c, width, None, &mut points) {
                    None => {
                        let (a, b) = f(&mesh.cell_centres[c]);
                        (a * mesh.cell_volumes[c], b * mesh.cell_volumes[c])
                    }
                    Some(weights) => {
                        let (mut a, mut b) = (0.0, 0.0);
                        for (x, j) in &points {
                            let (fa, fb) = f(x);
                            a += j * fa;
                            b += j * fb;
                        }
                        let scale = mesh.cell_volumes[c] / weights;
                        (a * scale, b * scale)
                    }
                };
                let want = integrate(&mesh, c, width, None, f);
                assert_eq!((got.0.to_bits(), got.1.to_bits()), (want.0.to_bits(), want.1.to_bits()), "cell {c}, width {width}");
            }
        }
    }

    /// A cell no wider than the lattice spacing takes the thesis' one point: its centre, its
    /// volume.
    #[test]
    fn a_cell_narrower_than_the_kernel_is_read_at_its_centre() {
        let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::repeat(0.1), [10, 10, 10])).unwrap();
        let (a, b) = integrate(&mesh, 123, 0.01, None, |x| (x.x, x.y * x.y));
        let (v, x) = (mesh.cell_volumes[123], mesh.cell_centres[123]);
        assert_eq!((a, b), (x.x * v, x.y * x.y * v));
    }

    /// The shortcut [`takes_one_point`] never claims one point for a cell that
    /// [`subdivisions`] would cut: on 2-D box cells 36 mm thick (P3 fine's: the thickness is not
    /// cut) and on the distorted hexahedra of a two-layer rotor–stator mesh, over widths from far below to far above the cells (and it does claim
    /// it for the cells well inside the lattice spacing, or it would save nothing).
    #[test]
    fn the_one_point_shortcut_agrees_with_the_subdivisions() {
        use crate::mesh::cylindrical::RotorStatorSpec;
        let mut boxes = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(0.2, 0.3, 0.036), [41, 60, 1])).unwrap();
        boxes.set_patch_kind("z_min", PatchKind::Empty).unwrap();
        boxes.set_patch_kind("z_max", PatchKind::Empty).unwrap();
        let spec = RotorStatorSpec {
            r_inner: 0.05,
            r_interface: 0.2,
            r_outer: 0.4,
            z_min: 0.0,
            z_max: 0.02,
            n_r_rotor: 15,
            n_r_stator: 20,
            n_theta_rotor: 126,
            n_theta_stator: 137,
            n_z: 2,
            radial_grading_rotor: 1.0,
            radial_grading_stator: 1.0,
        };
        let rings = Mesh::rotor_stator(&spec).unwrap();
        let mut claimed = 0;
        for mesh in [&boxes, &rings] {
            let search = crate::coupling::cell_search::CellSearch::new(mesh, 0.03);
            for width in [1e-4, 2e-3, 3.3e-3, 5e-3, 1e-2, 0.1] {
                for c in 0..mesh.n_cells() {
                    if takes_one_point(search.span(c), width) {
                        claimed += 1;
                        let corners: [Vec3; 8] = std::array::from_fn(|k| mesh.points[mesh.cell_points[c][k]]);
                        for empty in [search.empty_normal()] {
                            assert_eq!(subdivisions(&corners, width, empty.as_ref()), [1, 1, 1], "cell {c}, width {width}");
                        }
                    }
                }
            }
        }
        assert!(claimed > boxes.n_cells() + rings.n_cells(), "the shortcut took {claimed} cells");
        // the 2-D boxes (4.9 × 5 mm, 36 mm thick) take it at σ = 5 mm: the thickness is not cut
        let search = crate::coupling::cell_search::CellSearch::new(&boxes, 0.03);
        assert!(search.empty_normal().is_some() && (0..boxes.n_cells()).all(|c| takes_one_point(search.span(c), 5e-3)));
    }

    /// A narrow Gaussian summed over a cell's sub-cells: its share of the cell is near the
    /// exact integral (erf) wherever it sits, and it changes smoothly as the particle moves
    /// across the face, where the centre-point kernel jumped from one cell to the other.
    #[test]
    fn a_narrow_gaussian_moves_smoothly_across_a_face() {
        let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(0.2, 0.1, 0.1), [2, 1, 1])).unwrap();
        let sigma = 0.01;
        let erf_share =
            |lo: f64, hi: f64, centre: f64| 0.5 * (libm::erf((hi - centre) / (sigma * 2f64.sqrt())) - libm::erf((lo - centre) / (sigma * 2f64.sqrt())));
        let norm = (2.0 * std::f64::consts::PI * sigma * sigma).powf(1.5);
        let left_share = |x0: f64| {
            let p = Vec3::new(x0, 0.05, 0.05);
            let (left, _) = integrate(&mesh, 0, sigma, None, |x| ((-(x - p).norm_squared() / (2.0 * sigma * sigma)).exp() / norm, 0.0));
            let (right, _) = integrate(&mesh, 1, sigma, None, |x| ((-(x - p).norm_squared() / (2.0 * sigma * sigma)).exp() / norm, 0.0));
            (left, left + right)
        };
        let step = sigma / 20.0;
        let mut previous = left_share(0.08).0;
        for k in 1..=80 {
            let x0 = 0.08 + k as f64 * step;
            let (left, total) = left_share(x0);
            let exact = erf_share(0.0, 0.1, x0) * erf_share(0.0, 0.1, 0.05).powi(2);
            // the midpoint rule's boundary error at a face: h²/24 · max|G'| = 0.021 for the
            // 7 sub-cells of h = 1.43σ here, 0.0237 with the higher terms (measured in 1-D)
            assert!((left - exact).abs() < 0.025, "x = {x0}: {left} vs {exact}");
            // the two cells hold the whole kernel (it lies 5σ inside the y and z faces: tails
            // 2 erfc(5/√2) ≈ 1.2e-6) up to the lattice ripple, 1.3e-4 per axis at h = 1.43σ
            assert!((total - 1.0).abs() < 5e-4, "x = {x0}: total {total}");
            // no jump: the share moves at most at the exact integral's steepest slope
            // step/(σ√2π), plus 15 % for the lattice sum's own slope error (10.8 % measured in
            // 1-D at h = 1.43σ)
            let slope_bound = 1.15 * step / (sigma * (2.0 * std::f64::consts::PI).sqrt());
            assert!((left - previous).abs() <= slope_bound, "x = {x0}: share jumped by {}", left - previous);
            previous = left;
        }
    }
}
