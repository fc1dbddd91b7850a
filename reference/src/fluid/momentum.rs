//! Momentum matrix of spec (T4.16) in volume-averaged form, per cell (integrated over the
//! cell, units m⁴/s² per component, coefficients m³/s):
//!
//!   [c₀ αⁿu V + c₁ αᵒuᵒ V + c₂ αᵒᵒuᵒᵒ V]/Δt + Σ_f α_f u_f (φ_f − φ_mesh,f)
//!     = Σ_f (αν)_f (∇u)_f·S_f + Σ_f (αν)_f [(∇u)_fᵀ − ⅔ tr(∇u)_f I]·S_f + g V − V ∇P,
//!
//! with ν the effective viscosity ν + ν_t of a turbulence model (spec §2.5, §3.1, T3.8–T3.9;
//! the isotropic −⅔ρk I part of the Reynolds stress is absorbed in the pressure, as OpenFOAM).
//!
//! With particles (spec §8.4, §8.5) the cell load adds +C_j/ρ to the diagonal (the implicit
//! drag −C_j u_j, sign corrected) and F_j/ρ to the source (the explicit particle force).
//!
//! In a rotating frame (`[physics.rotating_frame]`, wear-model.md §2.6 [R]) the source also gets
//! α_c(−2Ω×u* − Ω×(Ω×(x_c − x₀)))V per cell (x_c the cell centre), next to the body force: the
//! centrifugal part is a body force; the Coriolis part is explicit in the latest outer iterate
//! u*, like the convecting flux φ* and the explicit stress parts. At outer-loop convergence it
//! is then implicit at tⁿ⁺¹ (BDF2 keeps its order; an old-level −2Ω×uⁿ would be first order
//! and, alone, grow the velocity by √(1 + (2ΩΔt)²) per step); with one outer iteration u* = uⁿ.
//! As a fixed-point iteration it contracts by about 2|Ω|Δt/c₀ per outer iteration (the Coriolis
//! term against the time term of the diagonal), so it needs 2|Ω|Δt/c₀ < 1 (an estimate; the
//! verification cases run at 0.13).
//!
//! In a frozen-rotor step (the start-up of `[fluid] initial = { type = "frozen_rotor" }`,
//! spillage_model::fluid::frozen_rotor, spillage-and-flow-verification.md §4.2) the rotor
//! zone's cells also get −α_c Ω×u* V (OpenFOAM's MRF term), explicit in u* like Coriolis.
//!
//! Convection is implicit with the latest flux φ* and the scheme's face weight; the Laplacian
//! is implicit with the over-relaxed non-orthogonal split and an explicit correction; the
//! transpose and dilatation parts are explicit from the latest iterate (spec §8.2). The pressure
//! gradient is *not* part of the system: it is added to the right-hand side of the predictor
//! and left out of H (spec T4.24).

use spillage_model::closure::rotating_frame::RotatingFrame;
use spillage_model::coupling::mask::{band_weight, BandRate};
use spillage_model::coupling::CellLoad;
use spillage_model::fluid::frozen_rotor::FrozenRotor;
use spillage_model::fluid::moving_cells::particle_share_of_mesh_flux;
use spillage_model::fluid::settings::NumericsSection;
use spillage_model::mesh::Vec3;
use spillage_model::turbulence::Viscosity;
use spillage_model::wear::fluid_mesh::{deforming_alpha_rate_volume, receding_slip_velocity};

use super::boundary::{Condition, Conditions};
use super::geometry::{Geometry, RotorMotion};
use super::gradient::directional;
use super::linear::SparseMatrix;
use super::schemes::convection_weight;

/// Everything fixed during one time step.
pub struct StepInputs<'a> {
    pub geo: &'a Geometry,
    pub conditions: &'a Conditions,
    pub rotor: Option<&'a RotorMotion>,
    pub numerics: &'a NumericsSection,
    pub volumes: &'a [f64],
    /// Cell volumes at tⁿ (equal to `volumes` unless the mesh deforms).
    pub volumes_old: &'a [f64],
    /// Whether the mesh deforms this step (`[wear.fluid_mesh]`; implicit Euler only).
    pub deforming: bool,
    /// ν, or ν + ν_t of the turbulence model (faces: ν_t linearly interpolated; boundary
    /// faces: the wall-function ν_t,w on walls).
    pub viscosity: Viscosity<'a>,
    pub dt: f64,
    /// BDF coefficients (c₀, c₁, c₂) of d/dt ≈ (c₀ qⁿ + c₁ qᵒ + c₂ qᵒᵒ)/Δt.
    pub time_coefficients: [f64; 3],
    pub alpha: &'a [f64],
    pub alpha_old: &'a [f64],
    pub alpha_old_old: &'a [f64],
    pub u_old: &'a [Vec3],
    pub u_old_old: &'a [Vec3],
    /// Kinematic body force (gravity + `numerics.body_force`) [m/s²].
    pub body_force: Vec3,
    /// The case's rotating frame (module doc), if any, and the cell centres it is evaluated at.
    pub rotating_frame: Option<RotatingFrame>,
    pub cell_centres: &'a [Vec3],
    /// The frame term of a frozen-rotor step (module doc), if this is one, and which cells
    /// are the rotor zone's.
    pub frozen_rotor: Option<FrozenRotor>,
    pub in_rotor: &'a [bool],
    /// Fixed boundary velocity of each boundary face (`None` for pressure/symmetry faces).
    pub boundary_velocity: &'a [Option<Vec3>],
    /// Per link: the time-derivative flux correction divided by rAU_f (module doc step 4d),
    /// −(1/Δt)[c₁(α_fᵒ φᵒ − (αᵒuᵒ)_f·S) + c₂(α_fᵒᵒ φᵒᵒ − (αᵒᵒuᵒᵒ)_f·S)]; zero on moved and
    /// overlap links and with `ddt_flux_correction = false`.
    pub ddt_flux_correction: &'a [f64],
    /// The particle load mapped to the cells (two-way coupling) and the fluid density that
    /// turns it kinematic.
    pub load: Option<&'a CellLoad>,
    pub density: f64,
}

impl StepInputs<'_> {
    /// ∂α/∂t · V per cell (zero without particles); on a deforming mesh d(αV)/dt less the mesh's
    /// own dV/dt ([`deforming_alpha_rate_volume`]).
    pub fn alpha_rate_volume(&self, cell: usize) -> f64 {
        let [c0, c1, c2] = self.time_coefficients;
        if self.deforming {
            return deforming_alpha_rate_volume(
                self.time_coefficients,
                self.dt,
                self.alpha[cell],
                self.alpha_old[cell],
                self.volumes[cell],
                self.volumes_old[cell],
            );
        }
        (c0 * self.alpha[cell] + c1 * self.alpha_old[cell] + c2 * self.alpha_old_old[cell]) * self.volumes[cell] / self.dt
    }

    /// Σ_f (α_f − 1) φ_mesh,f per cell, the faces oriented out of it: the particles' share of
    /// the mesh fluxes that a turning cell's ∂α/∂t V, which follows the cell, owes its
    /// continuity (spillage_model::fluid::moving_cells). Zero on a mesh that stands still or
    /// without a particle load (α_c ≡ 1).
    pub fn mesh_flux_shares_per_cell(&self) -> Vec<f64> {
        let mut share = vec![0.0; self.volumes.len()];
        if (self.rotor.is_none() && !self.deforming) || self.load.is_none() {
            return share;
        }
        for link in &self.geo.links {
            let s = particle_share_of_mesh_flux(link.interpolate(self.alpha[link.owner], self.alpha[link.neighbour]), link.mesh_flux);
            share[link.owner] += s;
            share[link.neighbour] -= s;
        }
        for face in &self.geo.boundary {
            share[face.cell] += particle_share_of_mesh_flux(self.alpha[face.cell], face.mesh_flux);
        }
        share
    }

    /// The rate the pressure equation takes per cell: ∂α/∂t · V following the cell less the
    /// particles' share of its mesh fluxes ([`Self::mesh_flux_shares_per_cell`]), which is the
    /// rate at the cell's place; in the cells the interface mask covers, their share of the
    /// band's net rate (T4.54, §6.7; spillage_model::coupling::mask: the redistribution inside
    /// the band is left out, the volume entering or leaving it is not).
    pub fn alpha_rates_volume_in_pressure(&self) -> Vec<f64> {
        let n = self.volumes.len();
        let shares = self.mesh_flux_shares_per_cell();
        let rate = |c: usize| self.alpha_rate_volume(c) - shares[c];
        let Some(load) = self.load.filter(|l| l.masked.iter().any(|m| *m)) else {
            return (0..n).map(rate).collect();
        };
        let weight = |c: usize| band_weight(self.alpha[c], self.alpha_old[c], self.alpha_old_old[c], self.volumes[c]);
        let band = BandRate::of(&load.masked, rate, weight);
        (0..n).map(|c| if load.masked[c] { band.share(weight(c), rate(c)) } else { rate(c) }).collect()
    }
}

/// The relaxed momentum matrix (same for all components) and its source without −V∇P.
pub struct MomentumSystem {
    pub matrix: SparseMatrix,
    pub source: Vec<Vec3>,
    /// The velocity gradient the system was assembled with (the pressure corrector's skewness
    /// correction of (A⁻¹H)_f on overlap links uses it).
    pub grad_u: Vec<[Vec3; 3]>,
}

/// Boundary velocity of every boundary face given the latest cell velocity.
pub fn boundary_velocities(inputs: &StepInputs, u: &[Vec3]) -> Vec<Vec3> {
    inputs
        .geo
        .boundary
        .iter()
        .enumerate()
        .map(|(b, face)| match (&inputs.boundary_velocity[b], &inputs.conditions.conditions[face.patch]) {
            (Some(ub), _) => *ub,
            (None, Condition::Symmetry) if inputs.deforming => receding_slip_velocity(u[face.cell], face.area, face.mesh_flux),
            (None, Condition::Symmetry) => {
                let n = face.area.normalize();
                u[face.cell] - n * u[face.cell].dot(&n)
            }
            (None, _) => u[face.cell],
        })
        .collect()
}

/// Assembles the momentum system with the latest fluxes (`link_flux`, `boundary_flux`,
/// absolute), velocity `u` and its gradient `grad_u`, then applies implicit under-relaxation
/// a_P ← a_P/α_u, b ← b + (1 − α_u)/α_u · a_P u*. `limiter` is the velocity and gradient the
/// `limited_linear` limiter is evaluated from: (u, ∇u) itself, or the step's first iterate's
/// ([`spillage_model::fluid::settings::LimiterUpdate`]).
pub fn assemble(
    inputs: &StepInputs,
    link_flux: &[f64],
    boundary_flux: &[f64],
    (u, grad_u): (&[Vec3], &[[Vec3; 3]]),
    limiter: (&[Vec3], &[[Vec3; 3]]),
) -> MomentumSystem {
    let geo = inputs.geo;
    let n = geo.n_cells();
    let numerics = inputs.numerics;
    let mut m = SparseMatrix::new(n);
    let mut source = vec![Vec3::zeros(); n];
    let [c0, c1, c2] = inputs.time_coefficients;

    // time derivative (BDF2 / Euler; a deforming mesh steps Euler, c₂ = 0, with Vⁿ on the old
    // level) and body force
    for c in 0..n {
        let v = inputs.volumes[c];
        m.add_diagonal(c, c0 * inputs.alpha[c] * v / inputs.dt);
        source[c] -=
            (inputs.u_old[c] * (c1 * inputs.alpha_old[c]) + inputs.u_old_old[c] * (c2 * inputs.alpha_old_old[c])) * (inputs.volumes_old[c] / inputs.dt);
        source[c] += inputs.body_force * v;
        if let Some(frame) = &inputs.rotating_frame {
            source[c] += frame.fictitious_acceleration(u[c], inputs.cell_centres[c]) * (inputs.alpha[c] * v);
        }
        if let Some(frozen) = inputs.frozen_rotor.filter(|_| inputs.in_rotor[c]) {
            source[c] += frozen.acceleration(u[c]) * (inputs.alpha[c] * v);
        }
        if let Some(load) = inputs.load {
            m.add_diagonal(c, load.implicit_drag[c] / inputs.density);
            source[c] += load.explicit_force[c] / inputs.density;
        }
    }

    for (l, link) in geo.links.iter().enumerate() {
        let (p, nb) = (link.owner, link.neighbour);
        let alpha_f = link.interpolate(inputs.alpha[p], inputs.alpha[nb]);
        // convection with the flux relative to the moving mesh (spec §4.1)
        let f = link_flux[l] - link.mesh_flux;
        let lambda = convection_weight(numerics.convection, numerics.linear_fraction, link, f, limiter.0, limiter.1);
        m.add_diagonal(p, alpha_f * f * lambda);
        m.add_off_diagonal(p, nb, alpha_f * f * (1.0 - lambda));
        m.add_diagonal(nb, -alpha_f * f * (1.0 - lambda));
        m.add_off_diagonal(nb, p, -alpha_f * f * lambda);

        // diffusion: implicit orthogonal part + explicit non-orthogonal correction
        let gamma = inputs.viscosity.face(link.weight, p, nb) * alpha_f;
        let d = gamma * link.laplacian_coefficient();
        m.add_diagonal(p, d);
        m.add_diagonal(nb, d);
        m.add_off_diagonal(p, nb, -d);
        m.add_off_diagonal(nb, p, -d);
        let grad_f = interpolate_tensor(link.weight, &grad_u[p], &grad_u[nb]);
        let t = link.non_orthogonal_part();
        let correction = directional(&grad_f, &t) * gamma;
        // explicit transpose-gradient and dilatation parts (spec T4.16)
        let explicit = explicit_stress(&grad_f, &link.area) * gamma;
        source[p] += correction + explicit;
        source[nb] -= correction + explicit;
    }

    let boundary_u = boundary_velocities(inputs, u);
    for (b, face) in geo.boundary.iter().enumerate() {
        let p = face.cell;
        let alpha_p = inputs.alpha[p];
        let f = boundary_flux[b] - face.mesh_flux;
        let gamma = inputs.viscosity.boundary(face.index) * alpha_p;
        let d = gamma * face.area.norm() / face.normal_distance;
        match &inputs.conditions.conditions[face.patch] {
            Condition::FixedVelocity { suction: Some(window), .. } => {
                // the share s of the face over a suction mouth lets the water out with the
                // cell's velocity (zero gradient: its swirl leaves with it, the way the water
                // enters the pipe); the rest is the back plate, a wall at rest
                m.add_diagonal(p, alpha_p * f + (1.0 - window.share(&face.centre)) * d);
            }
            Condition::FixedVelocity { .. } => {
                source[p] -= boundary_u[b] * (alpha_p * f);
                m.add_diagonal(p, d);
                source[p] += boundary_u[b] * d;
            }
            Condition::FixedPressure { .. } => {
                // zero-gradient velocity: u_f = u_P, no viscous flux
                m.add_diagonal(p, alpha_p * f);
            }
            Condition::Symmetry => {
                // tangential slip: viscous flux towards the face value of the latest iterate
                m.add_diagonal(p, d);
                source[p] += boundary_u[b] * d;
            }
        }
        source[p] += explicit_stress(&grad_u[p], &face.area) * gamma;
    }

    // implicit under-relaxation (Patankar); exact at convergence (u = u*)
    let relax = numerics.relax_velocity;
    for c in 0..n {
        let a = m.diagonal[c];
        let relaxed = a / relax;
        source[c] += u[c] * (relaxed - a);
        m.diagonal[c] = relaxed;
    }
    MomentumSystem { matrix: m, source, grad_u: grad_u.to_vec() }
}

pub fn interpolate_tensor(w: f64, a: &[Vec3; 3], b: &[Vec3; 3]) -> [Vec3; 3] {
    [a[0] * w + b[0] * (1.0 - w), a[1] * w + b[1] * (1.0 - w), a[2] * w + b[2] * (1.0 - w)]
}

/// [(∇u)ᵀ − ⅔ tr(∇u) I]·S for g[i][j] = ∂u_j/∂x_i: component j is Σ_i S_i ∂u_i/∂x_j − ⅔ (∇·u) S_j.
fn explicit_stress(g: &[Vec3; 3], s: &Vec3) -> Vec3 {
    let trace = g[0][0] + g[1][1] + g[2][2];
    Vec3::new(g[0].dot(s), g[1].dot(s), g[2].dot(s)) - s * (2.0 / 3.0 * trace)
}
