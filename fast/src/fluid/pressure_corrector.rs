//! Step 4d of the algorithm (module doc of `spillage_reference::fluid`, reference
//! `pressure::correct`): one PISO corrector. HbyA and rAU from the latest velocity; the
//! pressure equation (per-link coefficients gathered per cell) with its non-orthogonal
//! correctors, solved by AMG-preconditioned CG; conservative fluxes from the solved pressure;
//! the relaxed pressure, its boundary values (the fixed-flux wall condition) and the corrected
//! velocity u = HbyA − rAU ∇P.

use rayon::prelude::*;
use spillage_model::coupling::mask::{band_weight, BandRate};
use spillage_model::fluid::conditions::Condition;
use spillage_model::fluid::moving_cells::particle_share_of_mesh_flux;
use spillage_model::fluid::settings::PressureWallCondition;
use spillage_model::mesh::Vec3;
use spillage_model::solver::SolverError;

use super::assembly::{directional, interpolate_tensor, par_for, Out};
use super::buffers::{CorrectorBuffers, MomentumSystem};
use super::layout::NO_CELL;
use super::settings::{unconverged, worst_cell, SolveCounts};
use super::step_inputs::{Discretisation, StepConstants};
use crate::linear::amg::Amg;
use crate::linear::pcg::Pcg;
use crate::linear::{par_update, Csr, SolveStats, Tolerance};

/// The pressure solver: flexible CG preconditioned with an aggregation AMG set up once per time
/// step, from the step's first pressure matrix (its values; the aggregation too where a rotor
/// turns, made once per run on the geometric matrix on a fixed mesh,
/// [`PressureSolver::on_a_fixed_mesh`]). The later outer iterations change the matrix's
/// values through rAU (the momentum diagonal), not its pattern; the step's hierarchy stays as
/// good a preconditioner for them (P3 fine and the default head took the same CG iterations, outer
/// iteration by outer iteration, as with a hierarchy set up anew for every momentum assembly),
/// and CG converges to the tolerance whatever the preconditioner. Setting the values up again at
/// every assembly took 0.6 ms a step on P3 fine and 3 ms on the head, one thread. A solve that
/// fails with the step's hierarchy (a step going wrong: the matrix then moves far from the first
/// outer iteration's) is set up for its own matrix and solved again, so a step fails where it
/// failed with a hierarchy for every assembly (`tests/time_stepping.rs` names the stage).
#[derive(Default)]
pub struct PressureSolver {
    pcg: Pcg,
    amg: Amg,
    /// The mesh does not move: the hierarchy is aggregated once, on the geometric pressure
    /// matrix ([`PressureSolver::on_a_fixed_mesh`]).
    fixed_mesh: bool,
    /// Whether the hierarchy was set up in this step.
    hierarchy_current: bool,
    /// The start of a solve with the step's hierarchy, kept to solve again with a fresh one.
    start: Vec<f64>,
}

impl PressureSolver {
    /// A new time step begins: its first solve aggregates afresh from that step's matrix. The
    /// aggregation depends on the matrix values, so keeping one from an earlier step would make
    /// the preconditioner — and the solution, to the solver tolerance — depend on where the run
    /// started: a run restarted from a checkpoint must aggregate exactly as the uninterrupted
    /// run did. (Found by the two-way coupled restart test, where α_c changes the pressure
    /// matrix every step; with a turning rotor the pattern changes every step anyway.)
    pub fn new_step(&mut self) {
        if !self.fixed_mesh {
            self.amg.forget_aggregation();
        }
        self.hierarchy_current = false;
    }

    /// A solver for a mesh that does not move: the hierarchy is aggregated on the geometric
    /// pressure matrix (|S|²/(d·S) per link, the fixed-pressure faces' |S|/d_n), once for the
    /// run, and each step sets up only the values of its own matrix on it. The aggregation
    /// depends on the mesh alone, so a restarted run aggregates as the uninterrupted one did;
    /// on P3 fine the fresh aggregation had been a third of a millisecond a step on one thread,
    /// while the other waited. (A turning rotor moves the interface's links every step, and its
    /// hierarchy is aggregated afresh from each step's first matrix.)
    pub fn on_a_fixed_mesh() -> Self {
        PressureSolver { fixed_mesh: true, ..Default::default() }
    }

    /// (rows, off-diagonal entries, colours) of the multigrid levels.
    pub fn level_sizes(&self) -> Vec<(usize, usize, usize)> {
        self.amg.level_sizes()
    }

    /// Solves `matrix` x = `rhs` from the given x, counting iterations and time in `counts`.
    fn solve(&mut self, disc: &Discretisation, matrix: &Csr, rhs: &[f64], x: &mut [f64], tolerance: Tolerance, counts: &mut SolveCounts) -> SolveStats {
        // the hierarchy is set up at the first solve of a step (the overlap links have moved by
        // then), and again should the matrix change its size within a step (none does: the
        // check keeps a hierarchy from being applied to a matrix it does not fit)
        let kept = self.hierarchy_current && self.amg.fits(matrix);
        if !kept {
            self.set_up(disc, matrix, counts);
        } else {
            self.start.clear();
            self.start.extend_from_slice(x);
        }
        let stats = self.solve_counted(matrix, rhs, x, tolerance, counts);
        let failed = !stats.final_residual.is_finite() || unconverged(&stats, tolerance).is_some();
        if !(kept && failed) {
            return stats;
        }
        // the step's hierarchy no longer preconditions this matrix (a step going wrong changes
        // the matrix far from its first outer iteration's): set up for it and solve again from
        // the same start, as a hierarchy set up for every momentum assembly would have
        x.copy_from_slice(&self.start);
        self.set_up(disc, matrix, counts);
        self.solve_counted(matrix, rhs, x, tolerance, counts)
    }

    fn set_up(&mut self, disc: &Discretisation, matrix: &Csr, counts: &mut SolveCounts) {
        let clock = std::time::Instant::now();
        if self.fixed_mesh && !self.amg.has_pattern_of(matrix) {
            // the run's first solve: aggregated on the geometry, which every later setup keeps
            // (the same pattern), setting up only its own matrix's values
            self.amg.setup(&geometric_pressure_matrix(disc, matrix));
        }
        self.amg.setup(matrix);
        self.hierarchy_current = true;
        counts.amg_setup_seconds += clock.elapsed().as_secs_f64();
    }

    fn solve_counted(&mut self, matrix: &Csr, rhs: &[f64], x: &mut [f64], tolerance: Tolerance, counts: &mut SolveCounts) -> SolveStats {
        let clock = std::time::Instant::now();
        let stats = self.pcg.solve(matrix, rhs, x, &mut self.amg, tolerance);
        counts.pressure_seconds += clock.elapsed().as_secs_f64();
        if let Some(slot) = counts.pressure_per_solve.get_mut(counts.pressure_solves) {
            *slot = stats.iterations.min(u16::MAX as usize) as u16;
        }
        counts.pressure_solves += 1;
        counts.pressure_iterations += stats.iterations;
        stats
    }
}

/// HbyA = (b − Σ_N a_N u_N)/a_P (zero in unsolved components) and rAU = V/a_P from `velocity`.
fn h_by_a_and_r_au(disc: &Discretisation, momentum: &MomentumSystem, velocity: &[Vec<f64>; 3], work: &mut CorrectorBuffers) {
    let n = disc.n_cells();
    let matrix = &momentum.matrix;
    for j in 0..3 {
        if !disc.solved[j] {
            continue;
        }
        matrix.multiply_off_diagonal(&velocity[j], &mut work.neighbour_sum);
        let (source, neighbour_sum, diagonal) = (&momentum.source, &work.neighbour_sum, &matrix.diag);
        let out = Out::of(&mut work.h_by_a);
        par_for(n, |c| unsafe { (&mut *out.ptr(c))[j] = (source[c][j] - neighbour_sum[c]) / diagonal[c] });
    }
    for j in 0..3 {
        if !disc.solved[j] {
            work.h_by_a.par_iter_mut().for_each(|h| h[j] = 0.0);
        }
    }
    let (vol, diagonal) = (disc.cell_volumes, &matrix.diag);
    par_update(&mut work.r_au[..], |c, r| *r = vol[c] / diagonal[c]);
}

/// Boundary pressures for cell pressure `pressure` (reference `pressure::boundary_pressures`):
/// the fixed value on pressure boundaries; on prescribed-flux boundaries
/// P_b = P_P + d_n ∂P/∂n with ∂P/∂n = (HbyA·S − φ_b)/(rAU|S|) from the cell
/// (`fixed_flux_extrapolated`), extrapolated linearly from the cell and the one across it
/// (`fixed_flux_linear`), or 0 (`zero_gradient`); the cell value elsewhere.
pub fn boundary_pressures(
    disc: &Discretisation,
    pressure_wall: PressureWallCondition,
    h_by_a: &[Vec3],
    r_au: &[f64],
    prescribed_flux: &[f64],
    pressure: &[f64],
    boundary_pressure: &mut [f64],
) {
    let bnd = disc.boundary;
    for b in 0..bnd.len() {
        let c = bnd.cell[b] as usize;
        boundary_pressure[b] = match disc.condition(b) {
            Condition::FixedPressure { pressure } => *pressure,
            _ if !prescribed_flux[b].is_nan() => {
                let from_cell = |c: usize| (h_by_a[c].dot(&bnd.area[b]) - prescribed_flux[b]) / (r_au[c] * bnd.area[b].norm());
                let normal_gradient = match pressure_wall {
                    PressureWallCondition::ZeroGradient => 0.0,
                    PressureWallCondition::FixedFluxLinear if bnd.across[b] != NO_CELL => {
                        let (at_cell, at_across) = (from_cell(c), from_cell(bnd.across[b] as usize));
                        at_cell + bnd.across_ratio[b] * (at_cell - at_across)
                    }
                    PressureWallCondition::FixedFluxExtrapolated | PressureWallCondition::FixedFluxLinear => from_cell(c),
                };
                pressure[c] + bnd.normal_distance[b] * normal_gradient
            }
            _ => pressure[c],
        };
    }
}

/// What a corrector reads.
pub struct CorrectorInputs<'a> {
    pub step: StepConstants<'a>,
    /// Whether every link's non-orthogonal part is negligible (`Links::all_orthogonal`): the
    /// explicit non-orthogonal flux is then dropped and no extra correctors run.
    pub orthogonal: bool,
    pub momentum: &'a MomentumSystem,
    /// Time-derivative flux correction per link divided by rAU_f.
    pub ddt_flux_correction: &'a [f64],
    /// Prescribed flux per boundary face (NaN where the pressure is fixed).
    pub prescribed_boundary_flux: &'a [f64],
    /// ∇u of this outer iteration (the skewness correction of overlap links).
    pub velocity_gradient: &'a [[Vec3; 3]],
    pub tolerance: Tolerance,
}

/// The fields a corrector updates.
pub struct CorrectorFields<'a> {
    pub velocity: &'a mut [Vec<f64>; 3],
    pub pressure: &'a mut [f64],
    pub boundary_pressure: &'a mut [f64],
    pub pressure_gradient: &'a mut [Vec3],
    pub link_flux: &'a mut [f64],
    pub boundary_flux: &'a mut [f64],
}

/// One PISO corrector; returns the initial residual of its first pressure solve (the outer
/// loop's convergence measure).
pub fn correct(
    inputs: &CorrectorInputs,
    fields: CorrectorFields,
    work: &mut CorrectorBuffers,
    solver: &mut PressureSolver,
    counts: &mut SolveCounts,
) -> Result<f64, SolverError> {
    let disc = &inputs.step.disc;
    let numerics = inputs.step.numerics;
    let prescribed = inputs.prescribed_boundary_flux;
    h_by_a_and_r_au(disc, inputs.momentum, fields.velocity, work);
    for (flux, &prescribed) in fields.boundary_flux.iter_mut().zip(prescribed) {
        if !prescribed.is_nan() {
            *flux = prescribed;
        }
    }
    work.pressure_start.copy_from_slice(fields.pressure);
    work.pressure_solution.copy_from_slice(fields.pressure);
    let mut initial_residual = 0.0;
    let non_orthogonal_correctors = if inputs.orthogonal { 0 } else { numerics.non_orthogonal_correctors };
    for corrector in 0..=non_orthogonal_correctors {
        // the pressure gradient enters only the explicit non-orthogonal flux term, below 1e-12
        // of the gradient flux on orthogonal links: there it is dropped instead of computed
        // (one gradient per corrector less)
        if !inputs.orthogonal {
            boundary_pressures(disc, numerics.pressure_wall, &work.h_by_a, &work.r_au, prescribed, &work.pressure_solution, fields.boundary_pressure);
            disc.scalar_gradient(&work.pressure_solution, fields.boundary_pressure, fields.pressure_gradient);
        }
        predicted_link_fluxes(inputs, fields.pressure_gradient, work);
        assemble_pressure_equation(inputs, work);
        let stats = solver.solve(disc, &work.pressure_matrix, &work.pressure_rhs, &mut work.pressure_solution, inputs.tolerance, counts);
        if corrector == 0 {
            // CG starts from pressure_solution = pressure_start, so its initial residual is this
            // corrector's
            initial_residual = stats.initial_residual;
        }
        let failure = if !stats.final_residual.is_finite() { Some("residual not finite".to_string()) } else { unconverged(&stats, inputs.tolerance) };
        if let Some(message) = failure {
            let place = worst_cell(&work.pressure_matrix, &work.pressure_rhs, &work.pressure_solution, inputs.step.disc.cell_centres);
            return Err(SolverError::LinearSolve(format!("pressure equation: {message}; {place}")));
        }
    }
    conservative_fluxes(disc, work, fields.link_flux, fields.boundary_flux);
    let relax = numerics.relax_pressure;
    let (start, solution) = (&work.pressure_start, &work.pressure_solution);
    par_update(&mut fields.pressure[..], |c, p| *p = start[c] + relax * (solution[c] - start[c]));
    boundary_pressures(disc, numerics.pressure_wall, &work.h_by_a, &work.r_au, prescribed, fields.pressure, fields.boundary_pressure);
    disc.scalar_gradient(fields.pressure, fields.boundary_pressure, fields.pressure_gradient);
    for j in 0..3 {
        let (h_by_a, r_au, gradient) = (&work.h_by_a, &work.r_au, &*fields.pressure_gradient);
        let solved = disc.solved[j];
        par_update(&mut fields.velocity[j][..], |c, u| *u = if solved { h_by_a[c][j] - r_au[c] * gradient[c][j] } else { 0.0 });
    }
    Ok(initial_residual)
}

/// Per link: the predicted flux HbyA_f·S − rAU_f (∇P)_f·T + rAU_f·(ddt correction), α_f times
/// it, and the Laplacian coefficient α_f rAU_f |S|²/(d·S).
fn predicted_link_fluxes(inputs: &CorrectorInputs, pressure_gradient: &[Vec3], work: &mut CorrectorBuffers) {
    let links = inputs.step.disc.links;
    let alpha = inputs.step.alpha.current;
    let orthogonal = inputs.orthogonal;
    let (r_au, h_by_a, ddt_flux_correction, velocity_gradient) = (&work.r_au, &work.h_by_a, inputs.ddt_flux_correction, inputs.velocity_gradient);
    let (out_predicted, out_coefficient, out_alpha_predicted) =
        (Out::of(&mut work.predicted_link_flux), Out::of(&mut work.pressure_laplacian_coefficient), Out::of(&mut work.alpha_predicted_link_flux));
    par_for(links.len(), |l| {
        let (p, q) = (links.owner[l] as usize, links.neighbour[l] as usize);
        let w = links.weight[l];
        let alpha_f = w * alpha[p] + (1.0 - w) * alpha[q];
        let r_au_f = w * r_au[p] + (1.0 - w) * r_au[q];
        let mut h_by_a_f = h_by_a[p] * w + h_by_a[q] * (1.0 - w);
        if l >= links.n_internal {
            // overlap link: skewness correction (k·∇u)_f, as the reference's `pressure` (issue 12)
            h_by_a_f += directional(&interpolate_tensor(w, &velocity_gradient[p], &velocity_gradient[q]), &links.skew[l - links.n_internal]);
        }
        let non_orthogonal_flux = if orthogonal {
            0.0
        } else {
            let gradient_f = pressure_gradient[p] * w + pressure_gradient[q] * (1.0 - w);
            r_au_f * gradient_f.dot(&links.non_orthogonal[l])
        };
        let predicted = h_by_a_f.dot(&links.area[l]) - non_orthogonal_flux + r_au_f * ddt_flux_correction[l];
        unsafe {
            out_predicted.set(l, predicted);
            out_coefficient.set(l, alpha_f * r_au_f * links.laplacian[l]);
            out_alpha_predicted.set(l, alpha_f * predicted);
        }
    });
}

/// The pressure equation, gathered per cell: Σ α_f rAU_f |S|²/(d·S)(P_N − P_P) equals the
/// divergence of α_f φ_pred plus the boundary terms and ∂α/∂t V at the cell's place (the rate
/// following the cell less its particles' share of the mesh fluxes). Without a fixed-pressure
/// boundary, cell 0 is pinned (diagonal doubled).
fn assemble_pressure_equation(inputs: &CorrectorInputs, work: &mut CorrectorBuffers) {
    let StepConstants { disc, time, alpha, particles, .. } = inputs.step;
    let (adj, bnd, vol) = (disc.adjacency, disc.boundary, disc.cell_volumes);
    let prescribed = inputs.prescribed_boundary_flux;
    let (coefficient, alpha_predicted, r_au, h_by_a) = (&work.pressure_laplacian_coefficient, &work.alpha_predicted_link_flux, &work.r_au, &work.h_by_a);
    let (out_diagonal, out_values, out_rhs) =
        (Out::of(&mut work.pressure_matrix.diag), Out::of(&mut work.pressure_matrix.val), Out::of(&mut work.pressure_rhs));
    // the interface mask's band: its net ∂α/∂t V and the weight it is spread by (serial, in
    // cell order, as the reference: the same bits on any thread count)
    let weight = |c: usize| band_weight(alpha.current[c], alpha.old[c], alpha.old_old[c], vol[c]);
    // ∂α/∂t V at the cell's place: following the cell, less the particles' share of its mesh
    // fluxes (spillage_model::fluid::moving_cells)
    let rate = |c: usize| disc.alpha_rate_volume(alpha, time, c) - cell_mesh_flux_share(&disc, alpha.current, c);
    let band = particles.map_or_else(BandRate::default, |p| BandRate::of(&p.masked, rate, weight));
    par_for(disc.n_cells(), |c| {
        let a = alpha.current;
        let mut diag = 0.0;
        let mut rhs = 0.0;
        for k in adj.row_start[c] as usize..adj.row_start[c + 1] as usize {
            let e = adj.entry[k] as usize;
            let l = e >> 1;
            diag += coefficient[l];
            unsafe { out_values.set(k, -coefficient[l]) };
            if e & 1 == 1 {
                rhs -= alpha_predicted[l];
            } else {
                rhs += alpha_predicted[l];
            }
        }
        for &b in disc.boundary_faces_of(c) {
            let b = b as usize;
            match disc.condition(b) {
                Condition::FixedPressure { pressure } => {
                    let k = a[c] * r_au[c] * bnd.area[b].norm() / bnd.normal_distance[b];
                    diag += k;
                    rhs += k * pressure - a[c] * h_by_a[c].dot(&bnd.area[b]);
                }
                _ if !prescribed[b].is_nan() => rhs -= a[c] * prescribed[b],
                _ => {}
            }
        }
        // ∂α/∂t V at the cell's place; where the interface mask covers the cell, its share of
        // the band's net rate (T4.54; spillage_model::coupling::mask)
        if particles.is_some_and(|p| p.masked[c]) {
            rhs -= band.share(weight(c), rate(c));
        } else {
            rhs -= rate(c);
        }
        unsafe {
            out_diagonal.set(c, diag);
            out_rhs.set(c, rhs);
        }
    });
    if !disc.conditions.has_fixed_pressure {
        work.pressure_matrix.diag[0] *= 2.0;
    }
}

/// Σ_f (α_f − 1) φ_mesh,f of cell `c`, the faces oriented out of it: the particles' share of
/// the mesh fluxes that its ∂α/∂t V, which follows the turning cell, owes the continuity
/// (spillage_model::fluid::moving_cells; the reference's `mesh_flux_shares_per_cell`). Zero,
/// and not summed, unless particles meet turning cells.
pub(super) fn cell_mesh_flux_share(disc: &Discretisation, alpha: &[f64], c: usize) -> f64 {
    if !disc.particles_in_turning_cells {
        return 0.0;
    }
    let (links, adj, bnd) = (disc.links, disc.adjacency, disc.boundary);
    let mut share = 0.0;
    for k in adj.row_start[c] as usize..adj.row_start[c + 1] as usize {
        let e = adj.entry[k] as usize;
        let l = e >> 1;
        let s = particle_share_of_mesh_flux(links.interpolate(l, alpha[links.owner[l] as usize], alpha[links.neighbour[l] as usize]), links.mesh_flux[l]);
        if e & 1 == 1 {
            share += s;
        } else {
            share -= s;
        }
    }
    for &b in disc.boundary_faces_of(c) {
        share += particle_share_of_mesh_flux(alpha[c], bnd.mesh_flux[b as usize]);
    }
    share
}

/// The pressure matrix of `matrix`'s pattern with the geometric coefficients alone: −|S|²/(d·S)
/// per link, the diagonal their sum plus |S|/d_n per fixed-pressure face, cell 0 pinned as in
/// [`assemble_pressure_equation`].
fn geometric_pressure_matrix(disc: &Discretisation, matrix: &Csr) -> Csr {
    let (adj, bnd, laplacian) = (disc.adjacency, disc.boundary, &disc.links.laplacian);
    let mut out =
        Csr { n: matrix.n, row_start: matrix.row_start.clone(), col: matrix.col.clone(), val: vec![0.0; matrix.val.len()], diag: vec![0.0; matrix.n] };
    for c in 0..matrix.n {
        let mut diag = 0.0;
        for k in adj.row_start[c] as usize..adj.row_start[c + 1] as usize {
            let l = adj.entry[k] as usize >> 1;
            diag += laplacian[l];
            out.val[k] = -laplacian[l];
        }
        for &b in disc.boundary_faces_of(c) {
            if let Condition::FixedPressure { .. } = disc.condition(b as usize) {
                diag += bnd.area[b as usize].norm() / bnd.normal_distance[b as usize];
            }
        }
        out.diag[c] = diag;
    }
    if !disc.conditions.has_fixed_pressure {
        out.diag[0] *= 2.0;
    }
    out
}

/// Conservative fluxes from the solved pressure (T4.28): φ = φ_pred − rAU_f |S|²/(d·S)(P_N − P_P)
/// per link, and HbyA·S − rAU|S|/d_n (P_b − P_P) on fixed-pressure boundaries.
fn conservative_fluxes(disc: &Discretisation, work: &CorrectorBuffers, link_flux: &mut [f64], boundary_flux: &mut [f64]) {
    let links = disc.links;
    let (r_au, solution, predicted) = (&work.r_au, &work.pressure_solution, &work.predicted_link_flux);
    par_update(link_flux, |l, f| {
        let (p, q) = (links.owner[l] as usize, links.neighbour[l] as usize);
        let r_au_f = links.interpolate(l, r_au[p], r_au[q]);
        *f = predicted[l] - r_au_f * links.laplacian[l] * (solution[q] - solution[p]);
    });
    let bnd = disc.boundary;
    for (b, flux) in boundary_flux.iter_mut().enumerate() {
        if let Condition::FixedPressure { pressure } = disc.condition(b) {
            let c = bnd.cell[b] as usize;
            *flux = work.h_by_a[c].dot(&bnd.area[b]) - work.r_au[c] * bnd.area[b].norm() / bnd.normal_distance[b] * (pressure - solution[c]);
        }
    }
}
