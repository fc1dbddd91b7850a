//! The realizable k–ε model of the fast fluid: the discretisation of the reference
//! (`spillage_reference::fluid::turbulence` module doc, steps 1–4; spec fluid-dem-model.md §3)
//! on the fast solver's links and boundary arrays, per-link coefficients gathered per cell in
//! ascending link order (the reference's accumulation order, independent of the thread count),
//! Jacobi-BiCGStab solves, and buffers sized once.

use spillage_model::fluid::conditions::Condition;
use spillage_model::mesh::Vec3;
use spillage_model::solver::SolverError;
use spillage_model::turbulence::realizable::{eddy_viscosity, StrainRate};
use spillage_model::turbulence::state::{EPSILON_MIN, K_MIN};
use spillage_model::turbulence::wall_function::{self, y_plus_laminar};
use spillage_model::turbulence::{TurbulenceSection, TurbulenceState};

use super::assembly::{par_for, vec_of, Out};
use super::settings::{unconverged, worst_cell};
use super::step_inputs::{Discretisation, TimeStep, VolumeFractions};
use crate::linear::bicgstab::BiCgStab;
use crate::linear::{Csr, Tolerance};

/// The k–ε model's settings and work arrays (reused every step).
pub struct FastTurbulence {
    section: TurbulenceSection,
    y_plus_lam: f64,
    /// Per condition index: the `y_plus_<patch>` diagnostic name of a wall condition.
    y_plus_names: Vec<Option<&'static str>>,
    strain: Vec<StrainRate>,
    production: Vec<f64>,
    /// ε of wall cells (NaN elsewhere).
    fixed_epsilon: Vec<f64>,
    divergence: Vec<f64>,
    /// Per link: upwind convection flux α_f(φ − φ_mesh) and diffusion coefficient.
    link_flux: Vec<f64>,
    link_diffusion: Vec<f64>,
    matrix: Csr,
    rhs: Vec<f64>,
    solution: Vec<f64>,
    /// (Σ y⁺ A, Σ A) per condition.
    patch_sums: Vec<(f64, f64)>,
    solver: BiCgStab,
    /// The diagnostics of the last step (k_max, nu_t_max, y_plus_<patch>).
    values: Vec<(&'static str, f64)>,
}

/// What the model reads of the finished outer loop.
pub struct TurbulenceInputs<'a> {
    pub disc: Discretisation<'a>,
    pub time: TimeStep,
    /// α at the new level (`current`) and the previous one (`old`).
    pub alpha: VolumeFractions<'a>,
    pub nu: f64,
    pub velocity: &'a [Vec<f64>; 3],
    pub boundary_velocity: &'a [Vec3],
    pub velocity_gradient: &'a [[Vec3; 3]],
    pub link_flux: &'a [f64],
    pub boundary_flux: &'a [f64],
    pub tolerance: Tolerance,
    pub step: u64,
    pub time_end: f64,
}

/// Which transport equation is being assembled.
#[derive(Clone, Copy)]
enum Field {
    Epsilon,
    K,
}

impl FastTurbulence {
    /// `wall_patches`: per condition index the mesh patch name of a wall condition.
    pub fn new(section: TurbulenceSection, wall_patches: Vec<Option<String>>) -> Self {
        let y_plus_lam = y_plus_laminar(&section.constants);
        let y_plus_names = wall_function::y_plus_names(wall_patches);
        Self {
            section,
            y_plus_lam,
            y_plus_names,
            strain: Vec::new(),
            production: Vec::new(),
            fixed_epsilon: Vec::new(),
            divergence: Vec::new(),
            link_flux: Vec::new(),
            link_diffusion: Vec::new(),
            matrix: Csr::default(),
            rhs: Vec::new(),
            solution: Vec::new(),
            patch_sums: Vec::new(),
            solver: BiCgStab::default(),
            values: Vec::new(),
        }
    }

    /// The diagnostics of the last step, in the reference's order.
    pub fn values(&self) -> &[(&'static str, f64)] {
        &self.values
    }

    fn resize(&mut self, disc: &Discretisation) {
        let n = disc.n_cells();
        let zero = StrainRate::of_gradient(&[Vec3::zeros(); 3]);
        self.strain.resize(n, zero);
        for v in [&mut self.production, &mut self.fixed_epsilon, &mut self.divergence, &mut self.rhs, &mut self.solution] {
            v.resize(n, 0.0);
        }
        let n_links = disc.links.len();
        self.link_flux.resize(n_links, 0.0);
        self.link_diffusion.resize(n_links, 0.0);
        let adjacency = disc.adjacency;
        self.matrix.n = n;
        self.matrix.row_start.clone_from(&adjacency.row_start);
        self.matrix.col.clone_from(&adjacency.col);
        self.matrix.val.resize(adjacency.col.len(), 0.0);
        self.matrix.diag.resize(n, 0.0);
        self.patch_sums.resize(disc.conditions.conditions.len(), (0.0, 0.0));
    }

    /// Solves ε then k of this step into `state` and updates ν_t, ν_t,w and y⁺
    /// (reference steps 1–4), keeping the diagnostics for [`FastTurbulence::values`].
    pub fn correct(&mut self, inputs: &TurbulenceInputs, state: Option<&mut TurbulenceState>) -> Result<(), SolverError> {
        let disc = inputs.disc;
        self.resize(&disc);
        let Some(state) = state else {
            return Err(SolverError::Unsupported("the k–ε model has no turbulence state (k, ε) to start from".into()));
        };
        let c = self.section.constants;
        let (nu, bnd, vol) = (inputs.nu, disc.boundary, disc.cell_volumes);
        let n_internal = disc.links.n_internal;

        // 1. per cell: strain invariants, ∇·φ (links in ascending order, then the cell's
        //    boundary faces, as the reference sums), and the wall functions with the previous k
        //    (production and the fixed ε of wall cells) or G = ν_t* ∇u : dev(2 sym ∇u)
        {
            let (strain, div) = (Out::of(&mut self.strain), Out::of(&mut self.divergence));
            let (production, fixed_epsilon) = (Out::of(&mut self.production), Out::of(&mut self.fixed_epsilon));
            let adj = disc.adjacency;
            let (k_old, nu_t_old) = (&state.k, &state.nu_t);
            let (y_plus_lam, wall) = (self.y_plus_lam, &disc.conditions.wall);
            par_for(disc.n_cells(), |cell| {
                let mut d = 0.0;
                for e_index in adj.row_start[cell] as usize..adj.row_start[cell + 1] as usize {
                    let e = adj.entry[e_index] as usize;
                    let l = e >> 1;
                    // e & 1 == 1: the cell is the link's owner (as the gradient kernels read it)
                    d += if e & 1 == 1 { inputs.link_flux[l] } else { -inputs.link_flux[l] };
                }
                let (mut count, mut eps, mut prod) = (0usize, 0.0, 0.0);
                for &b in disc.boundary_faces_of(cell) {
                    let b = b as usize;
                    d += inputs.boundary_flux[b];
                    if wall[bnd.condition[b] as usize] {
                        let (y, k) = (bnd.normal_distance[b], k_old[cell]);
                        let y_plus = wall_function::y_plus(k, y, nu, &c);
                        let nu_t_wall = wall_function::wall_eddy_viscosity(y_plus, nu, y_plus_lam, &c);
                        let slip = (vec_of(inputs.velocity, cell) - inputs.boundary_velocity[b]).norm();
                        count += 1;
                        eps += wall_function::wall_cell_dissipation(k, y, &c);
                        prod += wall_function::wall_cell_production(nu, nu_t_wall, slip, k, y, &c);
                    }
                }
                let rate = StrainRate::of_gradient(&inputs.velocity_gradient[cell]);
                let (g, fixed) = if count == 0 { (nu_t_old[cell] * rate.production_per_nu_t, f64::NAN) } else { (prod / count as f64, eps / count as f64) };
                unsafe {
                    strain.set(cell, rate);
                    div.set(cell, d / vol[cell]);
                    production.set(cell, g);
                    fixed_epsilon.set(cell, fixed);
                }
            });
        }

        // 2. ε, then k with the new ε
        self.assemble(inputs, &state.nu_t, c.sigma_epsilon, &state.epsilon, Field::Epsilon, &state.k, &state.epsilon);
        self.solve(inputs, &mut state.epsilon, "epsilon", EPSILON_MIN, true)?;
        self.assemble(inputs, &state.nu_t, c.sigma_k, &state.k, Field::K, &state.k, &state.epsilon);
        self.solve(inputs, &mut state.k, "k", K_MIN, false)?;

        // 3. ν_t, ν_t,w and y⁺ from the new k, ε
        for cell in 0..disc.n_cells() {
            state.nu_t[cell] = eddy_viscosity(&self.strain[cell], state.k[cell], state.epsilon[cell], &c);
        }
        self.patch_sums.fill((0.0, 0.0));
        // faces without a condition (empty patches) are not in `bnd`: zero, as the reference
        state.nu_t_boundary.fill(0.0);
        state.y_plus.fill(0.0);
        for b in 0..bnd.len() {
            let cell = bnd.cell[b] as usize;
            let index = bnd.face[b] as usize - n_internal;
            if self.is_wall(&disc, b) {
                let y_plus = wall_function::y_plus(state.k[cell], bnd.normal_distance[b], nu, &c);
                state.y_plus[index] = y_plus;
                state.nu_t_boundary[index] = wall_function::wall_eddy_viscosity(y_plus, nu, self.y_plus_lam, &c);
                let area = bnd.area[b].norm();
                let sums = &mut self.patch_sums[bnd.condition[b] as usize];
                sums.0 += y_plus * area;
                sums.1 += area;
            } else {
                state.nu_t_boundary[index] = state.nu_t[cell];
            }
        }
        self.values.clear();
        self.values.push(("k_max", state.k.iter().fold(0.0f64, |m, v| m.max(*v))));
        self.values.push(("nu_t_max", state.nu_t.iter().fold(0.0f64, |m, v| m.max(*v))));
        for (condition, name) in self.y_plus_names.iter().enumerate() {
            if let Some(name) = name {
                let (sum, area) = self.patch_sums[condition];
                self.values.push((name, if area > 0.0 { sum / area } else { 0.0 }));
            }
        }
        Ok(())
    }

    fn is_wall(&self, disc: &Discretisation, b: usize) -> bool {
        disc.conditions.wall[disc.boundary.condition[b] as usize]
    }

    /// The transport matrix of `field` (reference `transport` plus the field's sources) into
    /// `self.matrix`, `self.rhs`; `k`, `epsilon` are the latest values the sources read.
    #[allow(clippy::too_many_arguments)]
    fn assemble(&mut self, inputs: &TurbulenceInputs, nu_t: &[f64], sigma: f64, q_old: &[f64], field: Field, k: &[f64], epsilon: &[f64]) {
        let disc = inputs.disc;
        let (links, adj, bnd, vol) = (disc.links, disc.adjacency, disc.boundary, disc.cell_volumes);
        let alpha = inputs.alpha;
        let nu = inputs.nu;
        {
            let (flux, diffusion) = (Out::of(&mut self.link_flux), Out::of(&mut self.link_diffusion));
            par_for(links.len(), |l| {
                let (p, q) = (links.owner[l] as usize, links.neighbour[l] as usize);
                let alpha_f = links.interpolate(l, alpha.current[p], alpha.current[q]);
                unsafe {
                    flux.set(l, alpha_f * (inputs.link_flux[l] - links.mesh_flux[l]));
                    diffusion.set(l, alpha_f * (nu + links.interpolate(l, nu_t[p], nu_t[q]) / sigma) * links.laplacian[l]);
                }
            });
        }
        let c = self.section.constants;
        let (link_flux, link_diffusion) = (&self.link_flux, &self.link_diffusion);
        let (strain, production, divergence) = (&self.strain, &self.production, &self.divergence);
        let section = &self.section;
        let (diag, values, rhs) = (Out::of(&mut self.matrix.diag), Out::of(&mut self.matrix.val), Out::of(&mut self.rhs));
        par_for(disc.n_cells(), |cell| {
            let v = vol[cell];
            let mut a = alpha.current[cell] * v / inputs.time.dt;
            let mut b = alpha.old[cell] * v / inputs.time.dt * q_old[cell];
            for e_index in adj.row_start[cell] as usize..adj.row_start[cell + 1] as usize {
                let e = adj.entry[e_index] as usize;
                let l = e >> 1;
                let (f, g) = (link_flux[l], link_diffusion[l]);
                // e & 1 == 1: this cell owns link l
                let (diagonal, off) = if e & 1 == 1 { (f.max(0.0) + g, f.min(0.0) - g) } else { (-f.min(0.0) + g, -f.max(0.0) - g) };
                a += diagonal;
                unsafe { values.set(e_index, off) };
            }
            for &bf in disc.boundary_faces_of(cell) {
                let bf = bf as usize;
                let f = alpha.current[cell] * (inputs.boundary_flux[bf] - bnd.mesh_flux[bf]);
                let inlet = match disc.condition(bf) {
                    Condition::FixedVelocity { .. } if !disc.conditions.wall[bnd.condition[bf] as usize] => {
                        let (k_in, eps_in) = section.inlet_values(inputs.boundary_velocity[bf].norm());
                        Some(match field {
                            Field::K => k_in,
                            Field::Epsilon => eps_in,
                        })
                    }
                    _ => None,
                };
                match inlet {
                    Some(value) => {
                        let g = alpha.current[cell] * (nu + nu_t[cell] / sigma) * bnd.area[bf].norm() / bnd.normal_distance[bf];
                        a += f.max(0.0) + g;
                        b += (-f.min(0.0) + g) * value;
                    }
                    None => {
                        a += f.max(0.0);
                        b -= f.min(0.0) * q_old[cell];
                    }
                }
            }
            let a_v = alpha.current[cell] * v;
            match field {
                Field::Epsilon => {
                    let (kc, ec) = (k[cell], epsilon[cell]);
                    b += strain[cell].c1(kc, ec) * a_v * strain[cell].magnitude * ec;
                    a += c.c2 * a_v * ec / (kc + (nu * ec).sqrt());
                }
                Field::K => {
                    b += a_v * production[cell];
                    let dilatation = 2.0 / 3.0 * alpha.current[cell] * divergence[cell];
                    if dilatation > 0.0 {
                        a += dilatation * v;
                    } else {
                        b -= dilatation * v * q_old[cell];
                    }
                    a += a_v * epsilon[cell] / q_old[cell];
                }
            }
            unsafe {
                diag.set(cell, a);
                rhs.set(cell, b);
            }
        });
    }

    /// Eliminates the fixed cells (ε of wall cells) as the reference does, solves into `q` and
    /// bounds the result below by `minimum`.
    fn solve(&mut self, inputs: &TurbulenceInputs, q: &mut [f64], field: &str, minimum: f64, fix_wall_cells: bool) -> Result<(), SolverError> {
        if fix_wall_cells {
            let m = &mut self.matrix;
            for cell in 0..m.n {
                if !self.fixed_epsilon[cell].is_nan() {
                    m.diag[cell] = 1.0;
                    self.rhs[cell] = self.fixed_epsilon[cell];
                    for e in m.row_start[cell] as usize..m.row_start[cell + 1] as usize {
                        m.val[e] = 0.0;
                    }
                } else {
                    for e in m.row_start[cell] as usize..m.row_start[cell + 1] as usize {
                        let col = m.col[e] as usize;
                        if !self.fixed_epsilon[col].is_nan() {
                            self.rhs[cell] -= m.val[e] * self.fixed_epsilon[col];
                            m.val[e] = 0.0;
                        }
                    }
                }
            }
        }
        // from zero: OpenFOAM's normalisation Σ|Ax − Ax̄| + Σ|b − Ax̄| (x̄ the mean of the guess)
        // is then Σ|b|, a true relative residual. From the previous k it is dominated by the
        // sink ε/k of cells with small k and stopped solves at a true residual of 5e-7 (measured).
        self.solution.fill(0.0);
        let stats = self.solver.solve(&self.matrix, &self.rhs, &mut self.solution, inputs.tolerance);
        let failure = if !stats.final_residual.is_finite() { Some("residual not finite".to_string()) } else { unconverged(&stats, inputs.tolerance) };
        if let Some(message) = failure {
            let place = worst_cell(&self.matrix, &self.rhs, &self.solution, inputs.disc.cell_centres);
            return Err(SolverError::Diverged {
                step: inputs.step,
                time: inputs.time_end,
                what: format!("the {field} equation of the turbulence model: {message}; {place}"),
            });
        }
        for (out, value) in q.iter_mut().zip(&self.solution) {
            *out = value.max(minimum);
        }
        Ok(())
    }
}
