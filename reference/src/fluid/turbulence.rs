//! The turbulence model of the reference fluid (spec fluid-dem-model.md §3): a
//! [`TurbulenceModel`] selected by `[turbulence] model`, giving the momentum equation its
//! effective viscosity and solving its own transport equations once per time step, after the
//! outer loop (Algorithm 1 line 25, spec §8.7).
//!
//! # Realizable k–ε, discretised (the fast solver reproduces this step by step)
//! Volume-averaged (T3.14, T3.15 corrected), per cell of volume V, with the fluxes φ and the
//! velocity u of the finished outer loop, k*, ε*, ν_t* of the previous step:
//! 1. ∇u (Gauss, as the momentum equation), the strain invariants and C₁ per cell
//!    ([`spillage_model::turbulence::realizable`]); production G = ν_t* ∇u : dev(2 sym ∇u).
//! 2. Wall cells (cells with a face on a `wall` patch): ε and G from the standard wall
//!    functions with k* ([`spillage_model::turbulence::wall_function`]), averaged over the cell's
//!    wall faces; ε of a wall cell is then fixed (its row eliminated, as OpenFOAM's
//!    `epsilonWallFunction`).
//! 3. ε equation: α V (ε − ε*ᵒ)/Δt + Σ_f α_f(φ − φ_mesh) ε_f − Σ_f α_f(ν + ν_t,f*/σ_ε)
//!    |S|²/(d·S)(ε_N − ε_P) = C₁ α |S| ε* V − C₂ α ε*/(k* + √(ν ε*)) ε V.
//!    k equation, with the new ε: the same operators with σ_k, source α G V,
//!    −⅔ α (∇·φ) k V (implicit where it removes k, explicit where it adds, OpenFOAM `SuSp`)
//!    and the sink −α (ε/k*) k V.
//! 4. Both bounded below (`K_MIN`, `EPSILON_MIN`); a failed or non-finite solve is an error
//!    naming the field, step and time. Then ν_t = C_μ k²/ε with the realizable C_μ of the new
//!    k, ε, and on wall faces ν_t,w and y⁺ from the new k.
//!
//! Choices, with their reasons:
//! * Implicit Euler in time for k and ε whatever `[numerics] time_scheme` says: with upwind
//!   convection and the implicit sinks the matrices are M-matrices and the right-hand sides
//!   non-negative, so k, ε stay positive (BDF2 is not positivity-preserving); the thesis'
//!   cutter runs use Euler throughout (spec §8.10).
//! * Upwind convection for k and ε (the thesis' particles-in-cutter case, §8.10) for the same
//!   boundedness; the momentum equation keeps its own scheme.
//! * Orthogonal diffusion only (no explicit non-orthogonal correction): a boundedness choice
//!   again; the meshes are orthogonal apart from the sliding-interface overlaps.
//! * Velocity inlets: Dirichlet k, ε from `[turbulence] inlet_intensity` and
//!   `inlet_length_scale`; walls, symmetry and pressure boundaries: zero gradient, and fluid
//!   entering through a pressure boundary brings the cell's previous value (explicit, bounded).
//! * ν_t on boundary faces that are not walls is the cell's ν_t (zero gradient).

use spillage_model::fluid::conditions::Condition;
use spillage_model::fluid::state::FluidState;
use spillage_model::mesh::Vec3;
use spillage_model::solver::SolverError;
use spillage_model::turbulence::realizable::{eddy_viscosity, StrainRate};
use spillage_model::turbulence::state::{EPSILON_MIN, K_MIN};
use spillage_model::turbulence::wall_function::{self, y_plus_laminar};
use spillage_model::turbulence::{TurbulenceSection, TurbulenceState, Viscosity};

use super::boundary::Conditions;
use super::geometry::Geometry;
use super::gradient::vector_gradient;
use super::linear::SparseMatrix;

/// What the turbulence model sees of the finished outer loop.
pub struct TurbulenceInputs<'a> {
    pub geo: &'a Geometry,
    pub conditions: &'a Conditions,
    pub volumes: &'a [f64],
    pub cell_centres: &'a [Vec3],
    pub nu: f64,
    pub dt: f64,
    pub alpha: &'a [f64],
    pub alpha_old: &'a [f64],
    /// Cell velocity and boundary-face velocities (per `geo.boundary` entry).
    pub u: &'a [Vec3],
    pub boundary_u: &'a [Vec3],
    /// Absolute fluxes per link and per `geo.boundary` entry.
    pub link_flux: &'a [f64],
    pub boundary_flux: &'a [f64],
    pub step: u64,
    pub time: f64,
}

/// A turbulence model of the reference fluid.
pub trait TurbulenceModel: Send {
    fn name(&self) -> &'static str;
    /// The momentum equation's viscosity for the state `fluid`.
    fn viscosity<'s>(&self, fluid: &'s FluidState, nu: f64) -> Viscosity<'s>;
    /// Solves the model's transport equations of this step into `fluid` and appends its
    /// diagnostics to `values`.
    fn correct(&self, inputs: &TurbulenceInputs, fluid: &mut FluidState, values: &mut Vec<(&'static str, f64)>) -> Result<(), SolverError>;
}

/// The model `[turbulence] model` selects. `wall_patches` names the wall patches (mesh patch
/// name per condition index, `None` for other conditions) for the per-patch y⁺ diagnostics.
pub fn from_case(section: &TurbulenceSection, wall_patches: Vec<Option<String>>) -> Box<dyn TurbulenceModel> {
    if section.is_k_epsilon() {
        Box::new(RealizableKEpsilon::new(section.clone(), wall_patches))
    } else {
        Box::new(Laminar)
    }
}

/// No model: ν_eff = ν.
pub struct Laminar;

impl TurbulenceModel for Laminar {
    fn name(&self) -> &'static str {
        "laminar"
    }
    fn viscosity<'s>(&self, _: &'s FluidState, nu: f64) -> Viscosity<'s> {
        Viscosity::Uniform(nu)
    }
    fn correct(&self, _: &TurbulenceInputs, _: &mut FluidState, _: &mut Vec<(&'static str, f64)>) -> Result<(), SolverError> {
        Ok(())
    }
}

/// Realizable k–ε with standard wall functions (module doc).
pub struct RealizableKEpsilon {
    section: TurbulenceSection,
    y_plus_lam: f64,
    /// Per condition index: the `y_plus_<patch>` diagnostic name of a wall condition.
    y_plus_names: Vec<Option<&'static str>>,
}

impl RealizableKEpsilon {
    pub fn new(section: TurbulenceSection, wall_patches: Vec<Option<String>>) -> Self {
        let y_plus_lam = y_plus_laminar(&section.constants);
        let y_plus_names = wall_function::y_plus_names(wall_patches);
        Self { section, y_plus_lam, y_plus_names }
    }
}

/// A transport equation's matrix with some cells fixed (their rows eliminated).
struct Transport {
    matrix: SparseMatrix,
    source: Vec<f64>,
}

impl TurbulenceModel for RealizableKEpsilon {
    fn name(&self) -> &'static str {
        "realizable-k-epsilon"
    }

    fn viscosity<'s>(&self, fluid: &'s FluidState, nu: f64) -> Viscosity<'s> {
        match &fluid.turbulence {
            Some(t) => t.viscosity(nu),
            None => Viscosity::Uniform(nu),
        }
    }

    fn correct(&self, inputs: &TurbulenceInputs, fluid: &mut FluidState, values: &mut Vec<(&'static str, f64)>) -> Result<(), SolverError> {
        let Some(old) = fluid.turbulence.as_ref() else {
            return Err(SolverError::Unsupported("the k–ε model has no turbulence state (k, ε) to start from".into()));
        };
        let c = &self.section.constants;
        let geo = inputs.geo;
        let n = geo.n_cells();
        let nu = inputs.nu;
        let grad_u = vector_gradient(geo, inputs.volumes, inputs.u, inputs.boundary_u);
        let strain: Vec<StrainRate> = grad_u.iter().map(StrainRate::of_gradient).collect();

        // 2. wall functions with the previous k
        let mut wall_faces = vec![0usize; n];
        let mut wall_epsilon = vec![0.0; n];
        let mut wall_production = vec![0.0; n];
        for (b, face) in geo.boundary.iter().enumerate() {
            if !inputs.conditions.wall[face.patch] {
                continue;
            }
            let p = face.cell;
            let y = face.normal_distance;
            let k = old.k[p];
            let y_plus = wall_function::y_plus(k, y, nu, c);
            let nu_t_wall = wall_function::wall_eddy_viscosity(y_plus, nu, self.y_plus_lam, c);
            let slip = (inputs.u[p] - inputs.boundary_u[b]).norm();
            wall_faces[p] += 1;
            wall_epsilon[p] += wall_function::wall_cell_dissipation(k, y, c);
            wall_production[p] += wall_function::wall_cell_production(nu, nu_t_wall, slip, k, y, c);
        }
        let production: Vec<f64> = (0..n)
            .map(|cell| match wall_faces[cell] {
                0 => old.nu_t[cell] * strain[cell].production_per_nu_t,
                count => wall_production[cell] / count as f64,
            })
            .collect();
        let fixed_epsilon: Vec<Option<f64>> = (0..n).map(|cell| (wall_faces[cell] > 0).then(|| wall_epsilon[cell] / wall_faces[cell] as f64)).collect();

        // 3a. ε
        let inlet = |b: usize| self.inlet_values(inputs, b);
        let mut eq = self.transport(inputs, &old.nu_t, c.sigma_epsilon, &old.epsilon, |b| inlet(b).map(|(_, e)| e));
        for cell in 0..n {
            let (k, eps) = (old.k[cell], old.epsilon[cell]);
            let a_v = inputs.alpha[cell] * inputs.volumes[cell];
            eq.source[cell] += strain[cell].c1(k, eps) * a_v * strain[cell].magnitude * eps;
            eq.matrix.add_diagonal(cell, c.c2 * a_v * eps / (k + (nu * eps).sqrt()));
        }
        let epsilon = self.solve(eq, &fixed_epsilon, "epsilon", EPSILON_MIN, inputs)?;

        // 3b. k, with the new ε
        let mut eq = self.transport(inputs, &old.nu_t, c.sigma_k, &old.k, |b| inlet(b).map(|(k, _)| k));
        let divergence = flux_divergence(inputs);
        for cell in 0..n {
            let a_v = inputs.alpha[cell] * inputs.volumes[cell];
            eq.source[cell] += a_v * production[cell];
            let dilatation = 2.0 / 3.0 * inputs.alpha[cell] * divergence[cell];
            if dilatation > 0.0 {
                eq.matrix.add_diagonal(cell, dilatation * inputs.volumes[cell]);
            } else {
                eq.source[cell] -= dilatation * inputs.volumes[cell] * old.k[cell];
            }
            eq.matrix.add_diagonal(cell, a_v * epsilon[cell] / old.k[cell]);
        }
        let k = self.solve(eq, &vec![None; n], "k", K_MIN, inputs)?;

        // 4. eddy viscosity, wall-function viscosity and y⁺ with the new k, ε
        let nu_t: Vec<f64> = (0..n).map(|cell| eddy_viscosity(&strain[cell], k[cell], epsilon[cell], c)).collect();
        let mut new = TurbulenceState { k, epsilon, nu_t, nu_t_boundary: vec![0.0; old.nu_t_boundary.len()], y_plus: vec![0.0; old.y_plus.len()] };
        let mut patch_sums = vec![(0.0, 0.0); inputs.conditions.conditions.len()];
        for face in &geo.boundary {
            let p = face.cell;
            if inputs.conditions.wall[face.patch] {
                let y_plus = wall_function::y_plus(new.k[p], face.normal_distance, nu, c);
                new.y_plus[face.index] = y_plus;
                new.nu_t_boundary[face.index] = wall_function::wall_eddy_viscosity(y_plus, nu, self.y_plus_lam, c);
                let area = face.area.norm();
                patch_sums[face.patch].0 += y_plus * area;
                patch_sums[face.patch].1 += area;
            } else {
                new.nu_t_boundary[face.index] = new.nu_t[p];
            }
        }
        values.push(("k_max", new.k.iter().fold(0.0f64, |m, v| m.max(*v))));
        values.push(("nu_t_max", new.nu_t.iter().fold(0.0f64, |m, v| m.max(*v))));
        for (condition, name) in self.y_plus_names.iter().enumerate() {
            if let Some(name) = name {
                let (sum, area) = patch_sums[condition];
                values.push((name, if area > 0.0 { sum / area } else { 0.0 }));
            }
        }
        fluid.turbulence = Some(new);
        Ok(())
    }
}

impl RealizableKEpsilon {
    /// (k, ε) entering through boundary entry `b` if it is a velocity inlet (not a wall).
    fn inlet_values(&self, inputs: &TurbulenceInputs, b: usize) -> Option<(f64, f64)> {
        let face = &inputs.geo.boundary[b];
        match inputs.conditions.conditions[face.patch] {
            Condition::FixedVelocity { .. } if !inputs.conditions.wall[face.patch] => Some(self.section.inlet_values(inputs.boundary_u[b].norm())),
            _ => None,
        }
    }

    /// Time, upwind convection and orthogonal diffusion with diffusivity α(ν + ν_t/σ) (module
    /// doc step 3); `dirichlet(b)` is the value on boundary entry `b` if it fixes one.
    fn transport(&self, inputs: &TurbulenceInputs, nu_t: &[f64], sigma: f64, q_old: &[f64], dirichlet: impl Fn(usize) -> Option<f64>) -> Transport {
        let geo = inputs.geo;
        let n = geo.n_cells();
        let mut matrix = SparseMatrix::new(n);
        let mut source = vec![0.0; n];
        for cell in 0..n {
            let v = inputs.volumes[cell] / inputs.dt;
            matrix.add_diagonal(cell, inputs.alpha[cell] * v);
            source[cell] += inputs.alpha_old[cell] * v * q_old[cell];
        }
        for (l, link) in geo.links.iter().enumerate() {
            let (p, nb) = (link.owner, link.neighbour);
            let alpha_f = link.interpolate(inputs.alpha[p], inputs.alpha[nb]);
            let f = alpha_f * (inputs.link_flux[l] - link.mesh_flux);
            let gamma = alpha_f * (inputs.nu + link.interpolate(nu_t[p], nu_t[nb]) / sigma) * link.laplacian_coefficient();
            matrix.add_diagonal(p, f.max(0.0) + gamma);
            matrix.add_off_diagonal(p, nb, f.min(0.0) - gamma);
            matrix.add_diagonal(nb, -f.min(0.0) + gamma);
            matrix.add_off_diagonal(nb, p, -f.max(0.0) - gamma);
        }
        for (b, face) in geo.boundary.iter().enumerate() {
            let p = face.cell;
            let f = inputs.alpha[p] * (inputs.boundary_flux[b] - face.mesh_flux);
            match dirichlet(b) {
                Some(value) => {
                    let gamma = inputs.alpha[p] * (inputs.nu + nu_t[p] / sigma) * face.area.norm() / face.normal_distance;
                    matrix.add_diagonal(p, f.max(0.0) + gamma);
                    source[p] += (-f.min(0.0) + gamma) * value;
                }
                None => {
                    matrix.add_diagonal(p, f.max(0.0));
                    source[p] -= f.min(0.0) * q_old[p];
                }
            }
        }
        Transport { matrix, source }
    }

    /// Solves with the `fixed` cells eliminated (row = identity, their values moved to the
    /// other rows' sources) and bounds the result below by `minimum`; a singular or non-finite
    /// solve is a divergence naming the field, step and time.
    fn solve(&self, eq: Transport, fixed: &[Option<f64>], field: &str, minimum: f64, inputs: &TurbulenceInputs) -> Result<Vec<f64>, SolverError> {
        let Transport { matrix, mut source } = eq;
        let n = matrix.n;
        let mut reduced = SparseMatrix::new(n);
        for cell in 0..n {
            match fixed[cell] {
                Some(value) => {
                    reduced.add_diagonal(cell, 1.0);
                    source[cell] = value;
                }
                None => reduced.add_diagonal(cell, matrix.diagonal[cell]),
            }
        }
        for e in &matrix.entries {
            match (fixed[e.row], fixed[e.col]) {
                (Some(_), _) => {}
                (None, Some(value)) => source[e.row] -= e.val * value,
                (None, None) => reduced.add_off_diagonal(e.row, e.col, e.val),
            }
        }
        let mut solution = reduced
            .solve_on_cells(&[source], &format!("turbulence ({field})"), inputs.cell_centres)
            .map_err(|e| SolverError::Diverged { step: inputs.step, time: inputs.time, what: format!("the {field} equation of the turbulence model: {e}") })?
            .remove(0);
        for value in solution.iter_mut() {
            *value = value.max(minimum);
        }
        Ok(solution)
    }
}

/// ∇·φ per cell from the absolute fluxes [1/s] (OpenFOAM `fvc::div(absolute(phi))`).
fn flux_divergence(inputs: &TurbulenceInputs) -> Vec<f64> {
    let geo = inputs.geo;
    let mut div = vec![0.0; geo.n_cells()];
    for (l, link) in geo.links.iter().enumerate() {
        div[link.owner] += inputs.link_flux[l];
        div[link.neighbour] -= inputs.link_flux[l];
    }
    for (b, face) in geo.boundary.iter().enumerate() {
        div[face.cell] += inputs.boundary_flux[b];
    }
    for (d, v) in div.iter_mut().zip(inputs.volumes) {
        *d /= v;
    }
    div
}
