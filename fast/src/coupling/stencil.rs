//! The kernel stencils of all particles, built in parallel into reused storage, with only the
//! weights the mapping asks for ([`Weights`]): the same cells and, for each weight computed, the
//! same bits as [`spillage_model::coupling::kernel::stencil`], whose steps this follows one
//! for one (the ghost, the cells reaching the support, one side of an interface, the one-point
//! rule or the cell quadrature, the skip of cells with neither weight, the normalisation or the
//! host-cell fallback).
//!
//! What it saves: a sample-only stencil evaluates no exponential on the cells read at their
//! centre (ψ = r² alone; whether φ would be non-zero is r ≤ 3σ, since φ ≥ e^{−4.5} there), which
//! on the diffusion method's wide sampling kernel (γ = 3: ~1 200 cells a particle at P3 fine) is
//! most of the work; the candidate cells are put in order by marking them in a bitmap and
//! reading it back over their index range, in place of a sort; the one-point test is taken once
//! for the mesh's widest cell rather than per cell when that cell takes one point already; a
//! mesh that stands still has its cell quadratures tabulated ([`QuadratureTable`]), one that
//! moves makes each once per build ([`BuildQuadratures`]); and no
//! stencil allocates once its storage has grown. The ghost's wall face is found among the faces
//! near the particle ([`WallGrid`]) rather than all of them.

use std::cell::RefCell;

use rayon::prelude::*;

use spillage_model::coupling::cell_quadrature;
use spillage_model::coupling::kernel::{KernelGeometry, KernelShapes, Stencil};
use spillage_model::coupling::mapping::host_cell;
use spillage_model::coupling::{BuilderMemory, Weights};

use super::quadrature::{BuildQuadratures, QuadratureTable};
use super::walls::WallGrid;
use spillage_model::mesh::Vec3;
use spillage_model::particles::Particle;

/// Per thread: the candidate cells and the bitmap that orders them; per cell, the kernels summed
/// so far (one-point builds; zero outside a build).
#[derive(Default)]
struct Scratch {
    cells: Vec<usize>,
    marked: Vec<bool>,
    phi: Vec<f64>,
    psi: Vec<f64>,
}

/// Cells whose φ waits to be evaluated, [`PhiBatch::LEN`] at most, in the order they were
/// visited: evaluated together in SIMD lanes, then added to their cells in that order.
struct PhiBatch {
    cells: [usize; PhiBatch::LEN],
    r2: [f64; PhiBatch::LEN],
    len: usize,
}

impl PhiBatch {
    const LEN: usize = 64;

    fn new() -> Self {
        PhiBatch { cells: [0; Self::LEN], r2: [0.0; Self::LEN], len: 0 }
    }

    #[inline(always)]
    fn push(&mut self, c: usize, r2: f64, shapes: KernelShapes, phi: &mut [f64]) {
        self.cells[self.len] = c;
        self.r2[self.len] = r2;
        self.len += 1;
        if self.len == Self::LEN {
            self.flush(shapes, phi);
        }
    }

    /// Adds the waiting cells' φ to `phi`, in their order.
    fn flush(&mut self, shapes: KernelShapes, phi: &mut [f64]) {
        let mut values = [0.0; Self::LEN];
        let len = self.len;
        phi_in_lanes(shapes, &self.r2[..len], &mut values[..len]);
        for (&c, &f) in self.cells[..len].iter().zip(&values[..len]) {
            phi[c] += f;
        }
        self.len = 0;
    }
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// What the builder keeps between builds (in the mapping's [`BuilderMemory`]).
#[derive(Default)]
struct Memory {
    quadrature: QuadratureTable,
    this_build: BuildQuadratures,
}

/// How a build integrates the kernels over the cells.
struct Rules<'a> {
    /// The mesh's widest span, if every cell's is finite: a kernel for which it takes one point
    /// has every cell take one point (the count is monotone in the span,
    /// [`cell_quadrature::takes_one_point`]).
    widest_span: Option<f64>,
    /// The tabulated quadratures of this build's width, if any.
    table: Option<&'a QuadratureTable>,
    /// Else, on a mesh that moves, the quadratures made in this build.
    this_build: Option<&'a BuildQuadratures>,
    /// The wall faces that mirror ghosts, binned.
    walls: WallGrid,
}

/// The kernel stencils of `particles` (σ = γ d) into `out`, one per particle in particle order,
/// built in parallel (a [`spillage_model::coupling::StencilBuilder`]). A weight not in
/// `weights` is left empty.
pub fn stencils_in_parallel(geo: &KernelGeometry, particles: &[Particle], gamma: f64, weights: Weights, out: &mut Vec<Stencil>, memory: &mut BuilderMemory) {
    out.resize_with(particles.len(), Stencil::default);
    let spans_apply = geo.search.empty_normal() == geo.empty_normal;
    let widest_span = (0..geo.mesh.n_cells()).map(|c| geo.search.span(c)).try_fold(0.0f64, |a, s| s.is_finite().then(|| a.max(s))).filter(|_| spans_apply);
    // one width for all (the usual monodisperse cloud) that some cell integrates: the table
    let width = particles.first().map(|p| gamma * p.diameter).filter(|&w| particles.iter().all(|p| gamma * p.diameter == w));
    let (table, this_build) = match width.filter(|&w| !widest_span.is_some_and(|s| cell_quadrature::takes_one_point(s, w))) {
        Some(w) => {
            let memory = memory.get_or_insert_with(|| Box::new(Memory::default()));
            let Memory { quadrature, this_build } = memory.downcast_mut::<Memory>().expect("the fast builder's memory");
            match quadrature.prepare(geo.mesh, w, geo.empty_normal.as_ref()) {
                Some(table) => (Some(table), None),
                None => (None, Some(&*this_build.start(geo.mesh, w, geo.empty_normal.as_ref()))),
            }
        }
        None => (None, None),
    };
    let largest_support = particles.iter().map(|p| 3.0 * gamma * p.diameter).fold(0.0, f64::max);
    let rules = Rules { widest_span, table, this_build, walls: WallGrid::new(geo.mesh, geo.wall_faces, largest_support) };
    out.par_iter_mut().zip(particles.par_iter()).with_min_len(32).for_each(|(s, p)| {
        let host = host_cell(geo.mesh, &p.position);
        SCRATCH.with_borrow_mut(|scratch| build(geo, &rules, &p.position, p.diameter, gamma, host, weights, scratch, s));
    });
}

/// The cells whose part may lie within `support` of `x` or of its ghost, in increasing order
/// without repeats, into `scratch.cells` (the reference sorts and dedups; this marks).
fn ordered_candidates(geo: &KernelGeometry, x: &Vec3, ghost: Option<&Vec3>, support: f64, scratch: &mut Scratch) {
    let cells = &mut scratch.cells;
    cells.clear();
    geo.search.reaching(geo.mesh, x, support, cells);
    if let Some(g) = ghost {
        geo.search.reaching(geo.mesh, g, support, cells);
    }
    let (lo, hi) = cells.iter().fold((usize::MAX, 0), |(lo, hi), &c| (lo.min(c), hi.max(c)));
    if cells.is_empty() || hi - lo > 8 * cells.len() + 64 {
        // scattered numbering: the range would cost more to read than a sort
        cells.sort_unstable();
        cells.dedup();
        return;
    }
    let marked = &mut scratch.marked;
    if marked.len() <= hi {
        marked.resize(geo.mesh.n_cells().max(hi + 1), false);
    }
    for &c in cells.iter() {
        marked[c] = true;
    }
    cells.clear();
    for (c, m) in marked[lo..=hi].iter_mut().enumerate() {
        if *m {
            cells.push(lo + c);
            *m = false;
        }
    }
}

/// [`build`] when every cell takes one point. The reference evaluates both kernels on every
/// cell that reaches the support of the particle or its ghost and drops the cells where both
/// vanish; those that remain are the cells whose centre lies within 3σ of the particle or of
/// the ghost (a kernel read at the centre vanishes beyond 3σ, and a centre within 3σ of a point
/// reaches it), which one pass per point finds with the squared distances the kernels need.
/// Each point's shapes are summed into the cell's entry in the order the reference adds them
/// (the particle's, then the ghost's; a term missing is the reference's 0 + term).
#[allow(clippy::too_many_arguments)]
fn build_one_point(geo: &KernelGeometry, x: &Vec3, ghost: Option<&Vec3>, sigma: f64, host: usize, weights: Weights, scratch: &mut Scratch, out: &mut Stencil) {
    let mesh = geo.mesh;
    let support = 3.0 * sigma;
    let (want_phi, want_psi) = (weights != Weights::Sample, weights != Weights::Deposit);
    let shapes = KernelShapes::new(sigma);
    let support2 = shapes.support2;
    let n = mesh.n_cells();
    if scratch.marked.len() < n {
        scratch.marked.resize(n, false);
    }
    if scratch.phi.len() < n {
        scratch.phi.resize(n, 0.0);
        scratch.psi.resize(n, 0.0);
    }
    let Scratch { cells, marked, phi, psi } = scratch;
    cells.clear();
    let (mut lo, mut hi) = (usize::MAX, 0);
    // the φ of many cells at once (in SIMD lanes), added in the order the cells were visited:
    // each cell's sum is still the particle's term, then the ghost's
    let mut batch = PhiBatch::new();
    for point in std::iter::once(x).chain(ghost) {
        geo.search.within_each(mesh, point, support, |c, r2| {
            if !marked[c] {
                marked[c] = true;
                cells.push(c);
                lo = lo.min(c);
                hi = hi.max(c);
            }
            if want_phi {
                batch.push(c, r2, shapes, phi);
            }
            if want_psi {
                psi[c] += if r2 < support2 { r2 } else { 0.0 };
            }
        });
    }
    batch.flush(shapes, phi);
    if !cells.is_empty() && hi - lo > 8 * cells.len() + 64 {
        // scattered numbering: the range would cost more to read than a sort
        cells.sort_unstable();
    } else if !cells.is_empty() {
        marked_in_order(marked, lo..=hi, cells);
    }
    let zone = geo.truncate_at_interface.then(|| mesh.cell_zone[host]);
    // every cell found is within 3σ of the particle or the ghost, so its φ is at least e^{−4.5}:
    // none has both weights zero, the reference's reason to drop a cell
    let sums = match (want_phi, want_psi) {
        (true, true) => gather::<true, true>(mesh, zone, cells, marked, phi, psi, out),
        (true, false) => gather::<true, false>(mesh, zone, cells, marked, phi, psi, out),
        _ => gather::<false, true>(mesh, zone, cells, marked, phi, psi, out),
    };
    normalise_or_host(out, (want_phi, want_psi), sums.0, sums.1, host);
}

/// φ at each squared distance of `r2` into `out` ([`KernelShapes::phi`], the same bits), on the
/// widest SIMD this CPU has.
fn phi_in_lanes(shapes: KernelShapes, r2: &[f64], out: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU has AVX-512 F (checked just above)
            return unsafe { phi_avx512(shapes, r2, out) };
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above)
            return unsafe { phi_avx2(shapes, r2, out) };
        }
    }
    phi_each(shapes, r2, out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn phi_avx512(shapes: KernelShapes, r2: &[f64], out: &mut [f64]) {
    phi_each(shapes, r2, out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn phi_avx2(shapes: KernelShapes, r2: &[f64], out: &mut [f64]) {
    phi_each(shapes, r2, out)
}

#[inline(always)]
fn phi_each(shapes: KernelShapes, r2: &[f64], out: &mut [f64]) {
    for (f, &r2) in out.iter_mut().zip(r2) {
        *f = shapes.phi(r2);
    }
}

/// The cells of `range` marked in `marked`, in increasing order, into `cells` (without
/// branching on the marks: every cell is written and the count moves on only past a marked one).
fn marked_in_order(marked: &[bool], range: std::ops::RangeInclusive<usize>, cells: &mut Vec<usize>) {
    let lo = *range.start();
    let marks = &marked[range];
    cells.clear();
    cells.reserve(marks.len());
    let spare = cells.spare_capacity_mut();
    let mut k = 0;
    for (c, &m) in marks.iter().enumerate() {
        // k ≤ c < marks.len() ≤ the capacity
        spare[k].write(lo + c);
        k += usize::from(m);
    }
    // SAFETY: entries 0..k were written above
    unsafe { cells.set_len(k) };
}

/// The one-point stencil's cells `cells` (in order) into `out` with their φ and ψ summed so far
/// times the cell volume (the wanted ones, `PHI` and `PSI`), skipping the cells outside `zone`
/// when it is given, and the running sums of the weights in the reference's order; clears the
/// cells' entries of `marked`, `phi` and `psi` for the next particle. Writes into reserved
/// storage rather than pushing: a push stores each vector's length back to memory, which took
/// most of this loop's time.
fn gather<const PHI: bool, const PSI: bool>(
    mesh: &spillage_model::mesh::Mesh,
    zone: Option<usize>,
    cells: &[usize],
    marked: &mut [bool],
    phi: &mut [f64],
    psi: &mut [f64],
    out: &mut Stencil,
) -> (f64, f64) {
    for v in [&mut out.deposit, &mut out.sample] {
        v.clear();
    }
    out.cells.clear();
    out.cells.reserve(cells.len());
    if PHI {
        out.deposit.reserve(cells.len());
    }
    if PSI {
        out.sample.reserve(cells.len());
    }
    let (to_cells, to_phi, to_psi) = (out.cells.spare_capacity_mut(), out.deposit.spare_capacity_mut(), out.sample.spare_capacity_mut());
    let (mut sums, mut k) = ((0.0, 0.0), 0);
    for &c in cells {
        let volume = mesh.cell_volumes[c];
        let (f, s) = (phi[c] * volume, psi[c] * volume);
        marked[c] = false;
        phi[c] = 0.0;
        psi[c] = 0.0;
        if zone.is_some_and(|z| mesh.cell_zone[c] != z) {
            continue;
        }
        to_cells[k].write(c);
        if PHI {
            to_phi[k].write(f);
            sums.0 += f;
        }
        if PSI {
            to_psi[k].write(s);
            sums.1 += s;
        }
        k += 1;
    }
    // SAFETY: the first k entries of each vector written are initialised just above (the
    // capacity was reserved for every cell)
    unsafe {
        out.cells.set_len(k);
        if PHI {
            out.deposit.set_len(k);
        }
        if PSI {
            out.sample.set_len(k);
        }
    }
    sums
}

/// Adds cell `c` with its (φ, ψ) integrals to the stencil, the wanted weights only, and to
/// their running sums (in the reference's order of addition).
#[inline]
fn push_cell(out: &mut Stencil, (want_phi, want_psi): (bool, bool), c: usize, (phi, psi): (f64, f64), sums: &mut (f64, f64)) {
    out.cells.push(c);
    if want_phi {
        out.deposit.push(phi);
        sums.0 += phi;
    }
    if want_psi {
        out.sample.push(psi);
        sums.1 += psi;
    }
}

/// Divides the computed weights by their sums; a weight set that sums to zero goes to the host
/// cell (the reference's `normalise_or_host`).
fn normalise_or_host(out: &mut Stencil, (want_phi, want_psi): (bool, bool), phi_sum: f64, psi_sum: f64, host: usize) {
    let host_index = match out.cells.iter().position(|&c| c == host) {
        Some(i) => i,
        None => {
            out.cells.push(host);
            if want_phi {
                out.deposit.push(0.0);
            }
            if want_psi {
                out.sample.push(0.0);
            }
            out.cells.len() - 1
        }
    };
    for (wanted, weights, sum) in [(want_phi, &mut out.deposit, phi_sum), (want_psi, &mut out.sample, psi_sum)] {
        if !wanted {
            continue;
        }
        if sum > 0.0 {
            weights.iter_mut().for_each(|w| *w /= sum);
        } else {
            weights.iter_mut().for_each(|w| *w = 0.0);
            weights[host_index] = 1.0;
        }
    }
}

/// One particle's stencil into `out` (its storage reused): [`spillage_model::coupling::kernel::stencil`]
/// with only `weights` computed.
#[allow(clippy::too_many_arguments)]
fn build(geo: &KernelGeometry, rules: &Rules, x: &Vec3, diameter: f64, gamma: f64, host: usize, weights: Weights, scratch: &mut Scratch, out: &mut Stencil) {
    let mesh = geo.mesh;
    let sigma = gamma * diameter;
    let support = 3.0 * sigma;
    let ghost = rules.walls.ghost(mesh, x, support);
    if rules.widest_span.is_some_and(|s| cell_quadrature::takes_one_point(s, sigma)) {
        return build_one_point(geo, x, ghost.as_ref(), sigma, host, weights, scratch, out);
    }
    ordered_candidates(geo, x, ghost.as_ref(), support, scratch);
    let zone = mesh.cell_zone[host];
    let (want_phi, want_psi) = (weights != Weights::Sample, weights != Weights::Deposit);
    out.cells.clear();
    out.deposit.clear();
    out.sample.clear();
    let mut sums = (0.0, 0.0);
    // the reference's shapes, term for term; without φ wanted, φ becomes the indicator of
    // r ≤ 3σ (φ itself is at least e^{−4.5} there), which is all the skip below reads of it
    let exact_shapes = KernelShapes::new(sigma);
    let KernelShapes { support2, .. } = exact_shapes;
    let shapes = |r2: f64| {
        if r2 <= support2 {
            (if want_phi { exact_shapes.phi(r2) } else { 1.0 }, if r2 < support2 { r2 } else { 0.0 })
        } else {
            (0.0, 0.0)
        }
    };
    let kernels = |point: &Vec3| {
        let (mut phi, mut psi) = shapes((point - x).norm_squared());
        if let Some(g) = &ghost {
            let (a, b) = shapes((point - g).norm_squared());
            phi += a;
            psi += b;
        }
        (phi, psi)
    };
    // the quadrature's points may lie beyond 3σ where the centre does not: it takes the
    // reference's kernels whole
    let exact_kernels = |point: &Vec3| exact_shapes.around(point, &x, ghost.as_ref());
    let spans_apply = geo.search.empty_normal() == geo.empty_normal;
    let table = rules.table.filter(|t| t.width() == sigma);
    let this_build = rules.this_build.filter(|t| t.width() == sigma);
    for &c in &scratch.cells {
        if geo.truncate_at_interface && mesh.cell_zone[c] != zone {
            continue;
        }
        let (phi, psi) = if spans_apply && cell_quadrature::takes_one_point(geo.search.span(c), sigma) {
            let (phi, psi) = kernels(&mesh.cell_centres[c]);
            (phi * mesh.cell_volumes[c], psi * mesh.cell_volumes[c])
        } else if let Some(table) = table {
            table.integrate(mesh, c, exact_kernels)
        } else if let Some(this_build) = this_build {
            this_build.integrate(mesh, c, exact_kernels)
        } else {
            cell_quadrature::integrate(mesh, c, sigma, geo.empty_normal.as_ref(), exact_kernels)
        };
        if phi == 0.0 && psi == 0.0 {
            continue;
        }
        push_cell(out, (want_phi, want_psi), c, (phi, psi), &mut sums);
    }
    normalise_or_host(out, (want_phi, want_psi), sums.0, sums.1, host);
}

#[cfg(test)]
mod tests {
    use super::*;
    use spillage_model::coupling::cell_search::CellSearch;
    use spillage_model::coupling::kernel::{stencil, wall_faces};
    use spillage_model::coupling::mapping::SPHERE_WIDTH_FACTOR;
    use spillage_model::mesh::cartesian::BoxSpec;
    use spillage_model::mesh::Mesh;

    fn particle(x: Vec3, diameter: f64) -> Particle {
        Particle {
            id: 0,
            material: 0,
            diameter,
            density: 2650.0,
            position: x,
            velocity: Vec3::zeros(),
            spin: Vec3::zeros(),
            contact_force: Vec3::zeros(),
            contact_torque: Vec3::zeros(),
            contacts: 0,
        }
    }

    /// φ in lanes, on every SIMD path this CPU has, equals the model's scalar φ bit for bit:
    /// at the centre, inside, at and beyond the support, far out (underflow to 0), over runs of
    /// lengths that leave partial vectors.
    #[test]
    fn phi_in_lanes_has_the_scalar_bits_on_every_path() {
        let shapes = KernelShapes::new(0.01);
        let support2 = shapes.support2;
        let mut r2: Vec<f64> = vec![0.0, 1e-300, support2, support2 * (1.0 + f64::EPSILON), 1e3 * support2, 1e6];
        r2.extend((0..200).map(|k| support2 * (k as f64 / 150.0).powi(2)));
        type Path = fn(KernelShapes, &[f64], &mut [f64]);
        let mut paths: Vec<(&str, Path)> = vec![("portable", phi_each), ("chosen", phi_in_lanes)];
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: only called on a CPU with AVX2 (checked just above)
                paths.push(("avx2", |s, r, o| unsafe { phi_avx2(s, r, o) }));
            }
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY: only called on a CPU with AVX-512 F (checked just above)
                paths.push(("avx512", |s, r, o| unsafe { phi_avx512(s, r, o) }));
            }
        }
        for (name, path) in paths {
            for len in [1, 3, 7, 8, 9, 17, r2.len()] {
                let mut out = vec![f64::NAN; len];
                path(shapes, &r2[..len], &mut out);
                for (k, (&f, &r)) in out.iter().zip(&r2).enumerate() {
                    assert_eq!(f.to_bits(), shapes.phi(r).to_bits(), "{name}, {len} values, entry {k} (r² = {r:e})");
                }
            }
        }
        assert_eq!(shapes.phi(0.0), 1.0);
    }

    /// Against the reference's stencil, particle by particle: the same cells and, for each
    /// weight asked for, the same bits; the other weight left empty. Kernels wider than the
    /// cells (one point per cell), narrower (the cell quadrature: made once per build in the
    /// first two builds, as on a moving mesh, from the table from the third on) and mixed widths; particles in the interior, at a wall (ghost) and in a corner;
    /// a 2-D and a 3-D mesh.
    #[test]
    fn the_same_stencils_as_the_reference_for_every_weight_choice() {
        let mut flat = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(0.2, 0.3, 0.02), [20, 30, 1])).unwrap();
        for patch in ["z_min", "z_max"] {
            flat.set_patch_kind(patch, spillage_model::mesh::PatchKind::Empty).unwrap();
        }
        let cube = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(0.1, 0.1, 0.1), [10, 10, 10])).unwrap();
        // particles on the cell centres of 2 cm cells (the held suspension's lattice)
        let mut coarse = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(0.12, 0.4, 0.02), [6, 20, 1])).unwrap();
        for patch in ["z_min", "z_max"] {
            coarse.set_patch_kind(patch, spillage_model::mesh::PatchKind::Empty).unwrap();
        }
        for mesh in [&flat, &cube, &coarse] {
            let z = mesh.cell_centres[0].z;
            let positions = if std::ptr::eq(mesh, &coarse) {
                [Vec3::new(0.01, 0.01, z), Vec3::new(0.05, 0.21, z), Vec3::new(0.11, 0.39, z), Vec3::new(0.03, 0.05, z)]
            } else {
                [Vec3::new(0.05, 0.05, z), Vec3::new(0.004, 0.05, z), Vec3::new(0.003, 0.002, z), Vec3::new(0.0512, 0.0731, z)]
            };
            for diameters in [[0.01; 4], [0.01, 0.02, 0.005, 0.01]] {
                let particles: Vec<Particle> = positions.iter().zip(diameters).map(|(x, d)| particle(*x, d)).collect();
                for gamma in [1.0, 3.0, SPHERE_WIDTH_FACTOR, 0.5] {
                    let support = 3.0 * gamma * diameters.iter().fold(0.0f64, |a, &b| a.max(b));
                    let search = CellSearch::new(mesh, support);
                    let walls = wall_faces(mesh);
                    let geo = KernelGeometry {
                        mesh,
                        search: &search,
                        wall_faces: &walls,
                        truncate_at_interface: false,
                        empty_normal: cell_quadrature::empty_normal(mesh),
                    };
                    let reference: Vec<Stencil> =
                        particles.iter().map(|p| stencil(&geo, &p.position, p.diameter, gamma, mesh.locate(&p.position).unwrap(), &mut Vec::new())).collect();
                    let mut memory = None;
                    let mut fast = Vec::new();
                    for build in 0..4 {
                        for weights in [Weights::Both, Weights::Deposit, Weights::Sample] {
                            stencils_in_parallel(&geo, &particles, gamma, weights, &mut fast, &mut memory);
                            for (i, (f, r)) in fast.iter().zip(&reference).enumerate() {
                                let what = format!("particle {i}, γ = {gamma}, {weights:?}, build {build}");
                                assert_eq!(f.cells, r.cells, "{what}");
                                let same = |a: &[f64], b: &[f64]| a.len() == b.len() && a.iter().zip(b).all(|(a, b)| a.to_bits() == b.to_bits());
                                assert!(if weights == Weights::Sample { f.deposit.is_empty() } else { same(&f.deposit, &r.deposit) }, "{what}: deposit");
                                assert!(if weights == Weights::Deposit { f.sample.is_empty() } else { same(&f.sample, &r.sample) }, "{what}: sample");
                            }
                        }
                    }
                }
            }
        }
    }
}
