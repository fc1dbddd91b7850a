//! The cell quadratures of a kernel width, tabulated once for a mesh that stands still: a
//! kernel narrower than the cells (the diffusion method's deposit, σ₀ = 0.22 d: 2 × 2 points on
//! each 5 mm cell of P3 fine) is integrated over each cell it touches, and each cell of a cloud
//! is touched by ~10 particles, each time mapping the same points through the cell's trilinear
//! map. The table holds the points, Jacobians and their sum per cell
//! ([`cell_quadrature::quadrature_points`]), which give [`cell_quadrature::integrate`] bit for bit.
//!
//! A table is valid for one width, one 2-D normal and the mesh's points and cells at its build
//! (all compared bit for bit before use). It is built only once three consecutive builds saw the
//! same geometry: a rotor zone that moves between a step's sample and its deposit would have it
//! rebuilt every step, for more than the quadratures it saves.

use rayon::prelude::*;

use spillage_model::coupling::cell_quadrature;
use spillage_model::mesh::{Mesh, Vec3};

/// Consecutive builds with the same geometry before a table is made.
const STILL_BUILDS: u32 = 3;

/// What a table depends on, bit for bit.
#[derive(Default)]
struct Geometry {
    width: u64,
    empty: Option<[u64; 3]>,
    points: Vec<Vec3>,
    cell_points: Vec<[usize; 8]>,
}

fn bits(v: &Vec3) -> [u64; 3] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
}

impl Geometry {
    fn matches(&self, mesh: &Mesh, width: f64, empty: Option<&Vec3>) -> bool {
        self.width == width.to_bits()
            && self.empty == empty.map(bits)
            && self.cell_points == mesh.cell_points
            && self.points.len() == mesh.points.len()
            && self.points.iter().zip(&mesh.points).all(|(a, b)| bits(a) == bits(b))
    }

    fn record(&mut self, mesh: &Mesh, width: f64, empty: Option<&Vec3>) {
        self.width = width.to_bits();
        self.empty = empty.map(bits);
        self.points.clone_from(&mesh.points);
        self.cell_points.clone_from(&mesh.cell_points);
    }
}

/// Per cell: its quadrature points with their Jacobians, and their sum (`None`: one point).
type CellRule = (Vec<(Vec3, f64)>, Option<f64>);

/// The tabulated quadratures (see the module doc) and the geometry of the last builds.
#[derive(Default)]
pub struct QuadratureTable {
    /// The geometry the last builds saw, and how many in a row.
    seen: Geometry,
    still: u32,
    /// The rules of `seen`, once made.
    rules: Option<Vec<CellRule>>,
}

impl QuadratureTable {
    /// Called once per build of the stencils of kernels of width `width`: the table, if it
    /// holds for this geometry (made on the build that makes the geometry's count
    /// [`STILL_BUILDS`]).
    pub fn prepare(&mut self, mesh: &Mesh, width: f64, empty: Option<&Vec3>) -> Option<&QuadratureTable> {
        if self.seen.matches(mesh, width, empty) {
            self.still += 1;
        } else {
            self.seen.record(mesh, width, empty);
            self.still = 1;
            self.rules = None;
        }
        if self.rules.is_none() && self.still >= STILL_BUILDS {
            self.rules = Some(
                (0..mesh.n_cells())
                    .into_par_iter()
                    .with_min_len(256)
                    .map(|c| {
                        let mut points = Vec::new();
                        let weights = cell_quadrature::quadrature_points(mesh, c, width, empty, &mut points);
                        (points, weights)
                    })
                    .collect(),
            );
        }
        self.rules.as_ref().map(|_| &*self)
    }

    /// The kernel width the table is for.
    pub fn width(&self) -> f64 {
        f64::from_bits(self.seen.width)
    }

    /// [`cell_quadrature::integrate`] of `f` over cell `c`, from the table.
    #[inline]
    pub fn integrate(&self, mesh: &Mesh, c: usize, mut f: impl FnMut(&Vec3) -> (f64, f64)) -> (f64, f64) {
        let (points, weights) = &self.rules.as_ref().expect("prepared")[c];
        let Some(weights) = weights else {
            let (a, b) = f(&mesh.cell_centres[c]);
            return (a * mesh.cell_volumes[c], b * mesh.cell_volumes[c]);
        };
        let (mut sum_a, mut sum_b) = (0.0, 0.0);
        for (x, jacobian) in points {
            let (a, b) = f(x);
            sum_a += jacobian * a;
            sum_b += jacobian * b;
        }
        let scale = mesh.cell_volumes[c] / weights;
        (sum_a * scale, sum_b * scale)
    }
}
