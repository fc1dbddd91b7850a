//! The rotor's torque balance (issue 16 check 3; spillage-and-flow-verification.md §2.4, the
//! Euler turbine equation Eq. 4.60–4.61, applied to the computed flow instead of to velocity
//! triangles): the axial angular momentum of the water, L = ρ Σ_c α_c ((x_c − x₀) × u_c)·â V_c,
//! changes by the torques on it and by what its boundaries carry out,
//!
//!   dL/dt = T_rotor + T_walls + T_open + T_g − Σ_b ρ α_P ((x_f − x₀) × u_b)·â (φ_b − φ_mesh,b) + R,
//!
//! each term from the discrete solution (fluid-dem-model.md §8.1–8.2, reference fluid
//! momentum.rs) and shared by both solvers:
//!
//! - **T_rotor**: the rotating walls (`rotating = true`: the head's blocked-cell faces, the
//!   shaft) on the water: pressure −ρ P_b S and the viscous face force of the momentum
//!   assembly, ρ γ [|S|/d_n (u_b − u_P) + ((∇u)_Pᵀ − ⅔ tr(∇u)_P I)·S], γ = α_P (ν + ν_t,b),
//!   its moment (x_f − x₀) × F about the rotor axis â. Shaft power is T_rotor ω.
//! - **T_walls**: the same of the walls at rest (the tank); **T_open**: the stress on the open
//!   boundaries (the floor's no-slip inflow holds the swirl back; pressure on planar and
//!   axisymmetric faces has no moment about the axis).
//! - **T_g**: the body force ρ Σ α_c V_c ((x_c − x₀) × g)·â (the tilted gravity of a ladder;
//!   P includes the hydrostatic part, so T_g balances its share of the wall pressures).
//! - the flux term: what leaves through the suction pipe or an eccentric mouth (u_P, zero-gradient)
//!   or enters through the floor (u_b ∥ â: none); walls carry nothing (φ_b = φ_mesh). The
//!   back plate around an eccentric mouth is a wall at rest on the rest of each face.
//! - **dL/dt** with the solver's time scheme, (c₀Lⁿ⁺¹ + c₁Lⁿ + c₂Lⁿ⁻¹)/Δt, each Lᵏ with the
//!   cells where they were at tᵏ (the rotor's cells turned back by ω(tⁿ⁺¹ − tᵏ)).
//! - **R**, the imbalance. Summing (x_c − x₀) × (cell momentum equation) over the cells, the
//!   internal face fluxes F_f do not cancel as they do for linear momentum: what remains is
//!   Σ_f (x_P − x_N) × F_f plus Σ_b (x_P − x_f) × F_b, zero for the pressure on orthogonal
//!   faces but not for convection, diffusion and the sliding interface's overlap links (whose
//!   cell centres lie at different θ). A collocated finite-volume scheme conserves linear
//!   momentum to solver tolerance but angular momentum only to truncation error; R measures
//!   it, and falls with the cell size: on circular Couette flow through the sliding interface
//!   |R|/T = 3.6e-3 → 1.8e-4 → 1.7e-4 (8×32, 12×48, 32×128; tests/head_torque.rs), on the
//!   shipped head 0.22 of the torque at 5 cm cells (cases/verification/cutter_head/, README).
//!
//! With a contour hull (the cells [`super::spillage::inside_cells`] calls inside) the same
//! balance is closed on the control volume of the hull: its walls (the rotor's faces that
//! bound the hull's cells), its T_g, and across its control surface (the hull faces of
//! [`HullFaces`] and the mouth) the convective flux ρ α_f ((x_f − x₀) × u_f)·â (φ_f − φ_mesh,f),
//! u_f the convection scheme's face value (limitedLinearV falls back to upwind where the swirl
//! jumps from the blades' cells to the still water outside within one cell; linear
//! interpolation there left half the head's torque unaccounted at 5 cm cells, the scheme's
//! value is what the discrete equations carry), and the viscous traction of the outside
//! water, ρ γ_f [(u_N − u_P)
//! |S|²/(d·S) + (∇u)_f·(S − |S|²/(d·S) d) + ((∇u)_fᵀ − ⅔ tr I)·S] (the assembly's face
//! terms). The hull is a surface of revolution, so pressure has no moment across it, and it
//! turns with the rotor without sweeping volume (φ_mesh = 0 on its faces). In a steady,
//! periodic state the balance is the Euler turbine equation: T_rotor,hull = what leaves the
//! hull minus what enters it, ρ Σ (r × u)·â φ.
//!
//! Not counted: the particles' load on the fluid (with particles R also holds their torque),
//! a `[physics.rotating_frame]`'s fictitious forces (cutter heads use the sliding mesh).
//! On the sliding interface the cell gradient uses the cell's own value on interface faces
//! (the solvers use the overlap links); it enters only the explicit stress of wall faces of
//! cells at the interface.

use super::spillage::HullFaces;
use crate::case::Case;
use crate::fluid::conditions::{Condition, Conditions};
use crate::fluid::settings::ConvectionScheme;
use crate::fluid::state::FluidState;
use crate::fluid::velocity_gradient::{boundary_velocities, explicit_stress, gauss_velocity_gradient};
use crate::mesh::{Mesh, PatchKind, Vec3};
use crate::step::{RotorPose, StepContext};

/// The control volume of a contour hull: its cells and its control surface.
#[derive(Clone, Debug)]
pub struct ControlVolume {
    /// Per cell: inside the hull.
    pub inside: Vec<bool>,
    /// (face, +1 when its area vector points out of the hull) of the hull faces.
    pub hull: Vec<(usize, f64)>,
    /// The same for the mouth faces (into the suction pipe).
    pub mouth: Vec<(usize, f64)>,
}

impl ControlVolume {
    pub fn new(inside: Vec<bool>, faces: &HullFaces) -> ControlVolume {
        ControlVolume { inside, hull: faces.hull.iter().map(|&(f, s, _)| (f, s)).collect(), mouth: faces.mouth.clone() }
    }
}

/// What a boundary patch is in the balance.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Role {
    /// Empty or sliding interface: no boundary of the water.
    None,
    RotorWall,
    StaticWall,
    Open,
}

/// The angular-momentum budget of a fluid mesh with a rotor (module doc).
#[derive(Clone, Debug)]
pub struct TorqueBudget {
    conditions: Conditions,
    role: Vec<Role>,
    rotor_cells: Vec<bool>,
    density: f64,
    nu: f64,
    body_force: Vec3,
    /// The momentum equation's convection scheme (the face value the hull's flux carries).
    convection: ConvectionScheme,
    linear_fraction: f64,
    control: Option<ControlVolume>,
}

/// L at one time level [kg m²/s]: the whole water and the hull's control volume (0 without).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Momenta {
    pub whole: f64,
    pub control: f64,
}

/// Lⁿ and Lⁿ⁻¹ of a step, taken before the fluid advances ([`TorqueBudget::before`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Before {
    pub now: Momenta,
    pub old: Momenta,
}

/// The terms of one step (module doc), axial components about the rotor axis [N m].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TorqueTerms {
    /// T_rotor: the rotating walls on the water.
    pub rotor: f64,
    /// T_walls: walls at rest.
    pub static_walls: f64,
    /// T_open: stress on the open boundaries.
    pub open: f64,
    /// T_g.
    pub gravity: f64,
    /// Angular momentum carried out through the boundaries per second.
    pub outflow: f64,
    /// dL/dt.
    pub rate: f64,
    /// R = dL/dt − (T_rotor + T_walls + T_open + T_g − outflow).
    pub imbalance: f64,
    pub control: Option<ControlTerms>,
}

/// The hull's control volume [N m].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ControlTerms {
    /// The walls bounding the hull's cells (the rotor's faces inside the hull; with an eccentric
    /// mouth also the back plate at rest around it) on its water.
    pub walls: f64,
    pub gravity: f64,
    /// Convective angular-momentum flux out through the hull faces.
    pub hull_flux: f64,
    /// The same out through the mouth (into the pipe, or through an eccentric mouth's plate faces).
    pub mouth_flux: f64,
    /// Torque of the outside water's viscous traction across hull and mouth.
    pub surface_stress: f64,
    /// Carried out through the other boundary faces of the hull's cells (walls at rest or turning
    /// with the mesh: none).
    pub boundary_outflow: f64,
    pub rate: f64,
    /// rate − (walls + gravity + surface_stress − hull_flux − mouth_flux − boundary_outflow).
    pub imbalance: f64,
}

impl TorqueBudget {
    /// The budget of `case` on `mesh` (its rotor zone from `[rotor] zone`), with the hull's
    /// control volume if given. `None` without a fluid or a rotor.
    pub fn new(case: &Case, mesh: &Mesh, control: Option<ControlVolume>) -> Result<Option<TorqueBudget>, String> {
        let (Some(fluid), Some(_)) = (&case.fluid, &case.rotor) else { return Ok(None) };
        let conditions = Conditions::from_case(case, mesh, fluid.density).map_err(|e| e.to_string())?;
        let zone = crate::step::RotorZone::from_case(case, mesh)?.map(|z| z.zone);
        let mut rotor_cells = vec![false; mesh.n_cells()];
        if let Some(z) = zone {
            for &c in &mesh.zones[z].cells {
                rotor_cells[c] = true;
            }
        }
        let role = mesh
            .patches
            .iter()
            .zip(&conditions.patch_condition)
            .map(|(patch, condition)| match (&patch.kind, condition) {
                (PatchKind::Empty | PatchKind::Interface { .. }, _) | (_, None) => Role::None,
                (_, Some(c)) => match &conditions.conditions[*c] {
                    Condition::FixedVelocity { rotating: true, .. } if conditions.wall[*c] => Role::RotorWall,
                    Condition::FixedVelocity { .. } if conditions.wall[*c] => Role::StaticWall,
                    _ => Role::Open,
                },
            })
            .collect();
        Ok(Some(TorqueBudget {
            conditions,
            role,
            rotor_cells,
            density: fluid.density,
            nu: fluid.kinematic_viscosity,
            body_force: case.numerics.kinematic_body_force(case.physics.gravity),
            convection: case.numerics.convection,
            linear_fraction: case.numerics.linear_fraction,
            control,
        }))
    }

    /// ρ Σ α ((x − x₀) × u)·â V of `velocity`, the rotor's cells turned by `turn` from where
    /// the mesh holds them now (a rotation about â leaves the axial moment of x × u unchanged
    /// when both turn, so turning u back by −`turn` is the same).
    pub fn angular_momentum(&self, mesh: &Mesh, pose: &RotorPose, velocity: &[[f64; 3]], alpha: &[f64], turn: f64) -> Momenta {
        let (sin, cos) = turn.sin_cos();
        let a = pose.axis;
        let mut m = Momenta::default();
        for c in 0..velocity.len() {
            let mut u = Vec3::from(velocity[c]);
            if self.rotor_cells[c] && turn != 0.0 {
                // Rodrigues, by −turn: (R(θ)x) × u · â = x × (R(−θ)u) · â
                u = u * cos - a.cross(&u) * sin + a * (a.dot(&u) * (1.0 - cos));
            }
            let l = (mesh.cell_centres[c] - pose.origin).cross(&u).dot(&a) * alpha[c] * mesh.cell_volumes[c] * self.density;
            m.whole += l;
            if self.control.as_ref().is_some_and(|cv| cv.inside[c]) {
                m.control += l;
            }
        }
        m
    }

    /// Lⁿ and Lⁿ⁻¹ from the fluid state before the step's fluid phase (velocity uⁿ, old
    /// velocity uⁿ⁻¹; α_old and α_old_old their fractions), the mesh already at tⁿ⁺¹.
    pub fn before(&self, mesh: &Mesh, fluid: &FluidState, ctx: &StepContext) -> Before {
        let Some(pose) = ctx.rotor else { return Before::default() };
        Before {
            now: self.angular_momentum(mesh, &pose, &fluid.velocity, &fluid.alpha_old, -pose.omega * ctx.dt),
            old: self.angular_momentum(mesh, &pose, &fluid.velocity_old, &fluid.alpha_old_old, -pose.omega * (ctx.dt + ctx.dt_old)),
        }
    }

    /// The terms of the step just solved (`fluid` at tⁿ⁺¹, the mesh at tⁿ⁺¹) given its
    /// [`Before`].
    pub fn after(&self, mesh: &Mesh, fluid: &FluidState, ctx: &StepContext, before: &Before) -> TorqueTerms {
        let Some(pose) = ctx.rotor else { return TorqueTerms::default() };
        let rho = self.density;
        let (a, x0) = (pose.axis, pose.origin);
        let moment = |x: &Vec3, f: &Vec3| (x - x0).cross(f).dot(&a);
        let u = |c: usize| Vec3::from(fluid.velocity[c]);
        let nu_t = fluid.turbulence.as_ref();
        let n_internal = mesh.n_internal_faces;
        let mesh_flux = |f: usize| if self.rotor_cells[mesh.face_owner[f]] { pose.velocity_at(&mesh.face_centres[f]).dot(&mesh.face_areas[f]) } else { 0.0 };
        // boundary values as the assembly takes them; interface faces take the cell's own value
        // (module doc), which `boundary_velocities` gives patches without a condition
        let conditions = self.conditions.with_solved_suction(mesh, &fluid.flux);
        let boundary_u = boundary_velocities(mesh, &conditions, &fluid.velocity, Some(&pose));
        let grad = gauss_velocity_gradient(mesh, &fluid.velocity, |f, _| Some(boundary_u[f - n_internal]));

        let mut t = TorqueTerms::default();
        let mut cv = self.control.as_ref().map(|_| ControlTerms::default());
        for (k, patch) in mesh.patches.iter().enumerate() {
            let role = self.role[k];
            if role == Role::None {
                continue;
            }
            let condition = self.conditions.patch_condition[k].map(|i| &self.conditions.conditions[i]);
            for f in patch.faces() {
                let b = f - n_internal;
                let c = mesh.face_owner[f];
                let s = mesh.face_areas[f];
                let alpha = fluid.alpha[c];
                let gamma = alpha * (self.nu + nu_t.map_or(0.0, |t| t.nu_t_boundary[b]));
                let normal_distance = (mesh.face_centres[f] - mesh.cell_centres[c]).dot(&s.normalize());
                let implicit = match condition {
                    Some(Condition::FixedPressure { .. }) => Vec3::zeros(),
                    // a suction mouth's share of the face passes the water, the rest is the plate at rest
                    Some(Condition::FixedVelocity { suction: Some(window), .. }) => {
                        -u(c) * ((1.0 - window.share(&mesh.face_centres[f])) * gamma * s.norm() / normal_distance)
                    }
                    _ => (boundary_u[b] - u(c)) * (gamma * s.norm() / normal_distance),
                };
                // what the water carries out: the cell's velocity through a suction mouth
                let carried_velocity = match condition {
                    Some(Condition::FixedVelocity { suction: Some(_), .. }) => u(c),
                    _ => boundary_u[b],
                };
                let force = (implicit + explicit_stress(&grad[c], &s) * gamma) * rho - s * (rho * fluid.boundary_pressure[b]);
                let torque = moment(&mesh.face_centres[f], &force);
                let relative = match condition {
                    Some(Condition::Symmetry) => 0.0,
                    _ => fluid.flux[f] - mesh_flux(f),
                };
                let carried = rho * alpha * moment(&mesh.face_centres[f], &carried_velocity) * relative;
                match role {
                    Role::RotorWall => t.rotor += torque,
                    Role::StaticWall => t.static_walls += torque,
                    _ => t.open += torque,
                }
                t.outflow += carried;
                if let (Some(cv), Some(control)) = (cv.as_mut(), &self.control) {
                    if control.inside[c] {
                        cv.walls += torque;
                        // an eccentric mouth's plate faces are the hull's mouth
                        if matches!(condition, Some(Condition::FixedVelocity { suction: Some(_), .. })) {
                            cv.mouth_flux += carried;
                        } else {
                            cv.boundary_outflow += carried;
                        }
                    }
                }
            }
        }
        let g = self.body_force;
        for c in 0..mesh.n_cells() {
            let tg = rho * fluid.alpha[c] * mesh.cell_volumes[c] * moment(&mesh.cell_centres[c], &g);
            t.gravity += tg;
            if let (Some(cv), Some(control)) = (cv.as_mut(), &self.control) {
                if control.inside[c] {
                    cv.gravity += tg;
                }
            }
        }
        let [c0, c1, c2] = ctx.time_coefficients;
        let now = self.angular_momentum(mesh, &pose, &fluid.velocity, &fluid.alpha, 0.0);
        t.rate = (c0 * now.whole + c1 * before.now.whole + c2 * before.old.whole) / ctx.dt;
        t.imbalance = t.rate - (t.rotor + t.static_walls + t.open + t.gravity - t.outflow);
        if let (Some(mut cv), Some(control)) = (cv, &self.control) {
            for (faces, mouth) in [(&control.hull, false), (&control.mouth, true)] {
                for &(f, sign) in faces {
                    let (p, n) = (mesh.face_owner[f], mesh.face_neighbour[f]);
                    let w = mesh.face_weight[f];
                    let s = mesh.face_areas[f];
                    let alpha_f = w * fluid.alpha[p] + (1.0 - w) * fluid.alpha[n];
                    let relative = fluid.flux[f] - mesh_flux(f);
                    let lambda = self.convection_weight(w, relative, u(p), u(n), &grad[p], &grad[n], &mesh.face_delta[f]);
                    let u_f = u(p) * lambda + u(n) * (1.0 - lambda);
                    let carried = sign * rho * alpha_f * moment(&mesh.face_centres[f], &u_f) * relative;
                    if mouth {
                        cv.mouth_flux += carried;
                    } else {
                        cv.hull_flux += carried;
                    }
                    // viscous force on the owner's water from the neighbour's (the assembly's face terms)
                    let nu_f = self.nu + nu_t.map_or(0.0, |t| w * t.nu_t[p] + (1.0 - w) * t.nu_t[n]);
                    let d = mesh.face_delta[f];
                    let coefficient = s.norm_squared() / d.dot(&s);
                    let grad_f = [grad[p][0] * w + grad[n][0] * (1.0 - w), grad[p][1] * w + grad[n][1] * (1.0 - w), grad[p][2] * w + grad[n][2] * (1.0 - w)];
                    let tangential = s - d * coefficient;
                    let on_owner = ((u(n) - u(p)) * coefficient
                        + grad_f[0] * tangential[0]
                        + grad_f[1] * tangential[1]
                        + grad_f[2] * tangential[2]
                        + explicit_stress(&grad_f, &s))
                        * (rho * alpha_f * nu_f);
                    cv.surface_stress += sign * moment(&mesh.face_centres[f], &on_owner);
                }
            }
            cv.rate = (c0 * now.control + c1 * before.now.control + c2 * before.old.control) / ctx.dt;
            cv.imbalance = cv.rate - (cv.walls + cv.gravity + cv.surface_stress - cv.hull_flux - cv.mouth_flux - cv.boundary_outflow);
            t.control = Some(cv);
        }
        t
    }
}

impl TorqueBudget {
    /// Owner weight λ of the convected face value u_f = λ u_P + (1 − λ) u_N, the reference
    /// fluid's schemes.rs (spec §8.10) with the limiter of `limitedLinearV 1` from the step's
    /// final velocity and gradient (the solver's from its last outer iterate: equal at
    /// outer-loop convergence; with `[numerics] limiter_update = "time_step"` the solver's is the
    /// step's first iterate's, and the budget differs from it by the limiter's change over one
    /// step).
    #[allow(clippy::too_many_arguments)]
    fn convection_weight(&self, weight: f64, flux: f64, u_p: Vec3, u_n: Vec3, grad_p: &[Vec3; 3], grad_n: &[Vec3; 3], delta: &Vec3) -> f64 {
        let upwind = if flux >= 0.0 { 1.0 } else { 0.0 };
        match self.convection {
            ConvectionScheme::Linear => weight,
            ConvectionScheme::Upwind => upwind,
            ConvectionScheme::Blended => self.linear_fraction * weight + (1.0 - self.linear_fraction) * upwind,
            ConvectionScheme::LimitedLinear => {
                let g = if flux >= 0.0 { grad_p } else { grad_n };
                let limiter = crate::fluid::limiter::limited_linear_v(&u_p, &u_n, &(g[0] * delta[0] + g[1] * delta[1] + g[2] * delta[2]));
                limiter * weight + (1.0 - limiter) * upwind
            }
        }
    }
}

impl TorqueTerms {
    /// The terms into the step report (`series.csv`) [N m; shaft power T_rotor ω in W].
    pub fn report(&self, omega: f64, report: &mut crate::solver::StepReport) {
        report.values.extend([
            ("head_torque", self.rotor),
            ("shaft_power", self.rotor * omega),
            ("static_wall_torque", self.static_walls),
            ("open_boundary_torque", self.open),
            ("gravity_torque", self.gravity),
            ("boundary_angular_momentum_outflow", self.outflow),
            ("angular_momentum_rate", self.rate),
            ("torque_imbalance", self.imbalance),
        ]);
        if let Some(cv) = &self.control {
            report.values.extend([
                ("hull_wall_torque", cv.walls),
                ("hull_gravity_torque", cv.gravity),
                ("hull_angular_momentum_flux", cv.hull_flux),
                ("mouth_angular_momentum_flux", cv.mouth_flux),
                ("hull_stress_torque", cv.surface_stress),
                ("hull_angular_momentum_rate", cv.rate),
                ("hull_torque_imbalance", cv.imbalance),
            ]);
        }
    }
}
