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
//! rebuilt every step, for more than the quadratures it saves. A build on a mesh that moves makes
//! each cell's quadrature instead the first time a particle needs it, and its other particles
//! reuse it ([`BuildQuadratures`]): the cutter head's 2 cm rocks on a 3 cm lattice reach each of
//! its 5 cm cells from dozens of particles.

use std::sync::OnceLock;

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
    pub fn integrate(&self, mesh: &Mesh, c: usize, f: impl FnMut(&Vec3) -> (f64, f64)) -> (f64, f64) {
        integrate_by_rule(mesh, c, &self.rules.as_ref().expect("prepared")[c], f)
    }
}

/// The cell quadratures of one build of the stencils of kernels of one width on a mesh that
/// moves between builds, each made when a particle first needs it (module doc). Each build
/// allocates the points of the cells it reaches (a few hundred short vectors on the cutter
/// head) and the next build's [`BuildQuadratures::start`] frees them: far less than the
/// trilinear maps they save.
#[derive(Default)]
pub struct BuildQuadratures {
    width: f64,
    empty: Option<Vec3>,
    rules: Vec<OnceLock<CellRule>>,
}

impl BuildQuadratures {
    /// Forgets the last build's quadratures: this build's are for width `width` on `mesh` as it
    /// stands now.
    pub fn start(&mut self, mesh: &Mesh, width: f64, empty: Option<&Vec3>) -> &BuildQuadratures {
        (self.width, self.empty) = (width, empty.copied());
        self.rules.resize_with(mesh.n_cells(), OnceLock::new);
        self.rules.iter_mut().for_each(|rule| drop(rule.take()));
        self
    }

    /// The kernel width of this build.
    pub fn width(&self) -> f64 {
        self.width
    }

    /// [`cell_quadrature::integrate`] of `f` over cell `c`, its quadrature made on first use.
    #[inline]
    pub fn integrate(&self, mesh: &Mesh, c: usize, f: impl FnMut(&Vec3) -> (f64, f64)) -> (f64, f64) {
        let rule = self.rules[c].get_or_init(|| {
            let mut points = Vec::new();
            let weights = cell_quadrature::quadrature_points(mesh, c, self.width, self.empty.as_ref(), &mut points);
            (points, weights)
        });
        integrate_by_rule(mesh, c, rule, f)
    }
}

/// Σ_q J_q f(x_q) · V / Σ_q J_q over a cell's tabulated rule, or f at the centre times V for the
/// one-point rule: [`cell_quadrature::integrate`] bit for bit.
#[inline]
fn integrate_by_rule(mesh: &Mesh, c: usize, (points, weights): &CellRule, mut f: impl FnMut(&Vec3) -> (f64, f64)) -> (f64, f64) {
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
