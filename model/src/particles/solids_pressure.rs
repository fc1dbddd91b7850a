//! `[particles.solids_pressure]`: the thesis' four-way coupling of representative particles
//! through the KTGF solids pressure (spec wear-model.md §2.3–§2.5, §4), applied once per step
//! as a change of the particle velocities, before the DEM moves them.
//!
//! Per cell of the fluid mesh, from the particles whose centre it holds (each counting
//! `[particles] modifier` real ones, as the wear model's control volumes count them): α_p and
//! the granular temperature Θ of their velocities (Eq. 2.19). The acceleration on a particle
//! is −∇p_p/(α_p ρ_p) (§4.4, sign and 1/α_p corrected, §13 row 11), with p_p of Eq. 2.25; over
//! the step Δt it changes the velocity by Δu = −Δt ∇(p_p/ρ_p)/α_p. On the faces:
//!
//! - `treatment = "explicit"` (the thesis): Δu_f·S_f = −Δt g_f (q_N − q_P)/α_p,f with q = p_p/ρ_p
//!   of each cell and g_f = |S_f|²/(S_f·d_f). It diverges as soon as cells pack: near α_max g₀
//!   makes p_p so steep that one step's Δu carries grains through each other (measured on the
//!   fine-sand Coriolis arm, `cases/wear/coriolis_fine_sand.toml`).
//! - `treatment = "implicit"` (the default) [R]: the gradient is taken of the α_p* the step's
//!   own correction leads to, with p_p linearised at the step's start,
//!   Δu_f·S_f = −Δt (∂q/∂α_p)_f g_f (α*_N − α*_P)/α*_f, and α_p* from the particle phase's
//!   continuity over the step, α_p* − α_p = ∇·(Δt² ∂q/∂α_p ∇α_p*): OpenFOAM's implicit MPPIC
//!   packing model (`PackingModels/Implicit`, with its `applyLimiting`, below). Unconditionally
//!   stable: a packed cell's excess spreads over its neighbours within the step, however steep
//!   g₀ is, and Σ α_p V is kept to round-off. It drops the part of ∇p_p that comes from Θ
//!   varying between cells, as OpenFOAM's does. Its limit: past α_max the slope is held at
//!   ~10¹³ Θ (closure::solids_pressure), so an over-packed cell is emptied to its neighbours'
//!   level within the one step, at a velocity ~ Δx/Δt that does not shrink with Δt (up to 40
//!   m/s in the fine sand's feed, 1 mm cells and 25 µs steps).
//!
//! `force = "thesis_literal"` drops the 1/α_p (module [`KtgfForce`]).
//!
//! Both then limit each face's correction as OpenFOAM's `applyLimiting` does: where the
//! particles' mean velocity already crosses the face the way the correction points, only what
//! they lack is added, so that a correction is a velocity the particles should have rather
//! than a kick repeated every step. [R] A correction of exactly zero stays zero (OpenFOAM's
//! branches would set it to minus the particles' own flux, stopping them). The correction flows only through the mesh's internal
//! faces: walls, open boundaries and a sliding interface carry none. A particle takes its
//! cell's velocity reconstructed from the face fluxes (OpenFOAM's `fvc::reconstruct`) plus its
//! Gauss gradient times the particle's offset from the cell centre, so that the particles of a
//! packed cell are spread apart, not moved as a block.
//!
//! The ψ kernel of `[coupling]` is not used: α_p here is the wear model's per-control-volume
//! count (§4.1), and the correction is independent of whether the run is one- or two-way
//! coupled.

use serde::Deserialize;

use super::Particle;
use crate::case::error::{in_range, FieldError};
use crate::closure::solids_pressure::{solids_pressure, solids_pressure_slope_per_density, VelocityMoments, PACKING_LIMIT, RESTITUTION};
use crate::mesh::{Mesh, Vec3};

/// `[particles.solids_pressure]`
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SolidsPressureSection {
    /// α_max of Eq. 2.26 (default 0.6).
    #[serde(default = "default_packing_limit")]
    pub packing_limit: f64,
    /// Particle–particle restitution e of Eq. 2.25 (default 0.99).
    #[serde(default = "default_restitution")]
    pub restitution: f64,
    /// `"implicit"` (the default) or `"explicit"` (the thesis' form, module doc).
    #[serde(default)]
    pub treatment: Treatment,
    /// `"per_particle_volume"` (the default) or `"thesis_literal"` ([`KtgfForce`]).
    #[serde(default)]
    pub force: KtgfForce,
}

/// `ktgf_force` of wear-model.md §4.4: how the solids-pressure gradient becomes a particle's
/// acceleration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum KtgfForce {
    /// −∇p_p/(α_p ρ_p): Eq. 2.11 is written per unit particle volume, ∇p_p per unit mixture
    /// volume (§4.4, §13 row 11).
    #[default]
    PerParticleVolume,
    /// −∇p_p/ρ_p: the thesis' printed F_KTGF without the 1/α_p (Eq. 2.12, §2.5), α_p times
    /// weaker. The printed sign (+∇p_p) is not offered: it drives grains up the pressure, into
    /// the packing.
    ThesisLiteral,
}

fn default_packing_limit() -> f64 {
    PACKING_LIMIT
}

fn default_restitution() -> f64 {
    RESTITUTION
}

/// How α_p enters the step's solids-pressure gradient (module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Treatment {
    /// α_p* from the diffusion solve (backward Euler in α_p).
    #[default]
    Implicit,
    /// α_p at the step's start (the thesis).
    Explicit,
}

impl Default for SolidsPressureSection {
    fn default() -> Self {
        Self { packing_limit: PACKING_LIMIT, restitution: RESTITUTION, treatment: Treatment::Implicit, force: KtgfForce::PerParticleVolume }
    }
}

impl SolidsPressureSection {
    pub fn validate(&self) -> Result<(), FieldError> {
        if !(self.packing_limit > 0.0 && self.packing_limit < 1.0) {
            return Err(FieldError::new("particles.solids_pressure.packing_limit", self.packing_limit, "a volume fraction in (0, 1) (the thesis: 0.6)"));
        }
        in_range("particles.solids_pressure.restitution", self.restitution, 0.0, 1.0, "(the thesis: 0.99)")
    }
}

/// What one step's correction did (the run's series and log).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolidsPressureReport {
    /// Largest α_p of a cell before the correction.
    pub largest_fraction: f64,
    /// Largest α_p* of a cell after it (implicit; the explicit form repeats α_p).
    pub largest_fraction_after: f64,
    /// Largest |Δu| given to a particle [m/s].
    pub largest_correction: f64,
    /// Iterations of the α_p* solve.
    pub iterations: usize,
}

/// Why a step's solids pressure could not be applied.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SolidsPressureError {
    #[error("the solids pressure's α_p* solve did not converge in {iterations} iterations (residual {residual:e} of the cells' particle volume ‖V α_p‖)")]
    NotConverged { iterations: usize, residual: f64 },
    #[error("the solids pressure of cell {cell} is not finite (α_p {fraction}, Θ {temperature} m²/s²)")]
    NotFinite { cell: usize, fraction: f64, temperature: f64 },
    #[error("the solids pressure needs a step > 0, got {0} s")]
    BadStep(f64),
}

/// Residual, relative to the cells' particle volume ‖V α_p‖, to which α_p* is solved: the
/// correction's velocity is a difference of α_p* between neighbours, so the solve must be far
/// below the smallest α_p difference that matters. In a packed cluster, where c_f ≫ 10⁴ V, the
/// true residual cannot reach it (its round-off is ~10⁻¹⁶ c_f); the conjugate gradients' own
/// recurrence then decides, and `conserve_change` keeps the volume exact.
const TOLERANCE: f64 = 1e-12;

/// At most this many conjugate-gradient iterations (or 10 per cell on small meshes): a packed
/// cluster is local, and a solve that needs more has met a system it cannot handle.
const MAX_ITERATIONS: usize = 5000;

/// The per-cell fields and solver memory, reused from step to step.
#[derive(Clone, Debug, Default)]
pub struct SolidsPressure {
    pub settings: Option<SolidsPressureSection>,
    /// α_p per cell (the step's start).
    pub fraction: Vec<f64>,
    /// Θ per cell [m²/s²].
    pub temperature: Vec<f64>,
    /// α_p* per cell.
    pub fraction_after: Vec<f64>,
    /// Reconstructed velocity correction per cell [m/s].
    pub correction: Vec<Vec3>,
    /// Its gradient per cell, (∇u)_ab = ∂u_b/∂x_a [1/s].
    pub correction_gradient: Vec<nalgebra::Matrix3<f64>>,
    moments: Vec<VelocityMoments>,
    host: Vec<Option<usize>>,
    /// δ = α_p* − α_p per cell.
    change: Vec<f64>,
    kinematic_pressure: Vec<f64>,
    slope: Vec<f64>,
    geometric: Vec<f64>,
    face_coefficient: Vec<f64>,
    /// Per internal face, the particle volume the implicit correction passes owner → neighbour.
    transfer: Vec<f64>,
    face_flux: Vec<f64>,
    diagonal: Vec<f64>,
    residual: Vec<f64>,
    direction: Vec<f64>,
    product: Vec<f64>,
    preconditioned: Vec<f64>,
}

impl SolidsPressure {
    pub fn new(settings: SolidsPressureSection) -> Self {
        Self { settings: Some(settings), ..Self::default() }
    }

    /// Bins `particles` into their cells (α_p with `modifier` real particles per simulated
    /// one, Θ by Eq. 2.19) and changes each velocity by its cell's correction over `dt`.
    /// Particles outside the mesh are left alone.
    pub fn correct(&mut self, mesh: &Mesh, particles: &mut [Particle], modifier: f64, dt: f64) -> Result<SolidsPressureReport, SolidsPressureError> {
        let n = mesh.n_cells();
        self.fraction.clear();
        self.fraction.resize(n, 0.0);
        self.moments.clear();
        self.moments.resize(n, VelocityMoments::default());
        self.host.clear();
        for p in particles.iter() {
            let cell = mesh.locate(&p.position);
            if let Some(c) = cell {
                self.fraction[c] += modifier * p.volume();
                self.moments[c].add([p.velocity.x, p.velocity.y, p.velocity.z], modifier);
            }
            self.host.push(cell);
        }
        for (a, v) in self.fraction.iter_mut().zip(&mesh.cell_volumes) {
            *a /= v;
        }
        self.temperature.clear();
        self.temperature.extend(self.moments.iter().map(VelocityMoments::granular_temperature));
        let mut report = self.correction_field(mesh, dt)?;
        for (p, cell) in particles.iter_mut().zip(&self.host) {
            if let Some(c) = *cell {
                let du = self.correction_at(mesh, c, &p.position);
                p.velocity += du;
                report.largest_correction = report.largest_correction.max(du.norm());
            }
        }
        Ok(report)
    }

    /// From `fraction` and `temperature` (one value per cell): α_p* and the cells' velocity
    /// corrections over `dt` (module doc). The limiting reads the particles' mean velocities
    /// binned by the last [`SolidsPressure::correct`] (none if it has not run, or after
    /// `moments` is cleared).
    pub fn correction_field(&mut self, mesh: &Mesh, dt: f64) -> Result<SolidsPressureReport, SolidsPressureError> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(SolidsPressureError::BadStep(dt));
        }
        let settings = self.settings.clone().unwrap_or_default();
        let (e, limit) = (settings.restitution, settings.packing_limit);
        let n = mesh.n_cells();
        let n_faces = mesh.n_internal_faces;
        // per cell p_p/ρ_p and its slope in α_p (ρ_p cancels from the particle's acceleration)
        self.kinematic_pressure.clear();
        self.kinematic_pressure.extend(self.fraction.iter().zip(&self.temperature).map(|(&a, &theta)| solids_pressure(a, 1.0, theta, e, limit)));
        self.slope.clear();
        self.slope.extend(self.fraction.iter().zip(&self.temperature).map(|(&a, &theta)| solids_pressure_slope_per_density(a, theta, e, limit)));
        // per face: g_f = |S|²/(S·d), the orthogonal part of the face gradient (0 on a face
        // whose cells' centres do not lie across it: no gradient is taken there); the slope
        // interpolated like OpenFOAM's fvc::interpolate(Δt τ'/ρ); c_f = Δt² slope_f g_f, times
        // the face's α_p for the thesis' literal force (Δu without the 1/α_p)
        self.geometric.clear();
        self.face_coefficient.clear();
        for f in 0..n_faces {
            let (o, nb, w) = (mesh.face_owner[f], mesh.face_neighbour[f], mesh.face_weight[f]);
            let s = mesh.face_areas[f];
            let along = s.dot(&mesh.face_delta[f]);
            let g = if along > 0.0 && along.is_finite() { s.norm_squared() / along } else { 0.0 };
            self.geometric.push(g);
            let literal = match settings.force {
                KtgfForce::PerParticleVolume => 1.0,
                KtgfForce::ThesisLiteral => w * self.fraction[o] + (1.0 - w) * self.fraction[nb],
            };
            self.face_coefficient.push(dt * dt * (w * self.slope[o] + (1.0 - w) * self.slope[nb]) * g * literal);
        }
        if let Some(j) = (0..n).find(|&j| !(self.kinematic_pressure[j].is_finite() && self.slope[j].is_finite() && self.fraction[j].is_finite())) {
            return Err(SolidsPressureError::NotFinite { cell: j, fraction: self.fraction[j], temperature: self.temperature[j] });
        }
        let mut report = SolidsPressureReport { largest_fraction: self.fraction.iter().cloned().fold(0.0, f64::max), ..Default::default() };
        self.change.clear();
        self.change.resize(n, 0.0);
        if settings.treatment == Treatment::Implicit {
            report.iterations = self.solve_change(mesh)?;
            self.conserve_change(mesh);
        }
        self.fraction_after.clear();
        self.fraction_after.extend(self.fraction.iter().zip(&self.change).map(|(a, d)| a + d));
        report.largest_fraction_after = self.fraction_after.iter().cloned().fold(0.0, f64::max);
        // the correction's volumetric face fluxes, Δu_f·S_f = −Δt ∇(p_p/ρ_p)·S_f / α_f:
        // implicit, −c_f (α*_N − α*_P)/(Δt α*_f); explicit, −Δt g_f (q_N − q_P)/α_f with
        // q = p_p/ρ_p of each cell (Eq. 2.25, its own α_p and Θ)
        self.face_flux.clear();
        for f in 0..n_faces {
            let (o, nb, w) = (mesh.face_owner[f], mesh.face_neighbour[f], mesh.face_weight[f]);
            let alpha_face = w * self.fraction_after[o] + (1.0 - w) * self.fraction_after[nb];
            let correction = match (settings.treatment, settings.force) {
                (Treatment::Implicit, _) if alpha_face > 0.0 => self.transfer[f] / (dt * alpha_face),
                (Treatment::Explicit, KtgfForce::PerParticleVolume) if alpha_face > 0.0 => {
                    -dt * self.geometric[f] * (self.kinematic_pressure[nb] - self.kinematic_pressure[o]) / alpha_face
                }
                (Treatment::Explicit, KtgfForce::ThesisLiteral) => -dt * self.geometric[f] * (self.kinematic_pressure[nb] - self.kinematic_pressure[o]),
                _ => 0.0,
            };
            // OpenFOAM's applyLimiting: where the particles already cross the face the way the
            // correction points, it adds only what they lack (the correction is a velocity the
            // particles should have, not a kick on top of every step's)
            let mean = |c: usize| self.moments.get(c).map_or(Vec3::zeros(), |m| Vec3::from(m.mean()));
            let current = (w * mean(o) + (1.0 - w) * mean(nb)).dot(&mesh.face_areas[f]);
            let limited = if current * correction <= 0.0 {
                correction
            } else if correction > 0.0 {
                (correction - current).max(0.0)
            } else {
                (correction - current).min(0.0)
            };
            self.face_flux.push(limited);
        }
        self.reconstruct(mesh, n);
        Ok(report)
    }

    /// The change δ = α_p* − α_p that the step's own correction makes: the particle phase's
    /// continuity V_j δ_j = −Δt Σ_f α*_f Δu_f·S_f with the implicit flux above,
    /// (V_j + Σ_f c_f) δ_j − Σ_f c_f δ_nb = Σ_f c_f (α_nb − α_j),
    /// solved by conjugate gradients with the diagonal as preconditioner (symmetric positive
    /// definite: V_j > 0, c_f ≥ 0).
    fn solve_change(&mut self, mesh: &Mesh) -> Result<usize, SolidsPressureError> {
        let n = mesh.n_cells();
        self.diagonal.clear();
        self.diagonal.extend_from_slice(&mesh.cell_volumes);
        self.residual.clear();
        self.residual.resize(n, 0.0);
        for f in 0..mesh.n_internal_faces {
            let (o, nb) = (mesh.face_owner[f], mesh.face_neighbour[f]);
            self.diagonal[o] += self.face_coefficient[f];
            self.diagonal[nb] += self.face_coefficient[f];
            let push = self.face_coefficient[f] * (self.fraction[nb] - self.fraction[o]);
            self.residual[o] += push;
            self.residual[nb] -= push;
        }
        // δ = 0 to start, so r = b; the scale is the cells' particle volume
        let scale = mesh.cell_volumes.iter().zip(&self.fraction).map(|(v, a)| (v * a).powi(2)).sum::<f64>().sqrt();
        if scale == 0.0 {
            return Ok(0);
        }
        self.preconditioned.clear();
        self.preconditioned.extend(self.residual.iter().zip(&self.diagonal).map(|(r, d)| r / d));
        self.direction.clear();
        self.direction.extend_from_slice(&self.preconditioned);
        let mut rz: f64 = self.residual.iter().zip(&self.preconditioned).map(|(r, z)| r * z).sum();
        let max_iterations = (10 * n + 100).min(MAX_ITERATIONS);
        for iteration in 0..max_iterations {
            let norm_r = self.residual.iter().map(|r| r * r).sum::<f64>().sqrt();
            if norm_r <= TOLERANCE * scale {
                return Ok(iteration);
            }
            self.multiply(mesh);
            let pap: f64 = self.direction.iter().zip(&self.product).map(|(p, q)| p * q).sum();
            let step = rz / pap;
            for j in 0..n {
                self.change[j] += step * self.direction[j];
                self.residual[j] -= step * self.product[j];
                self.preconditioned[j] = self.residual[j] / self.diagonal[j];
            }
            let rz_next: f64 = self.residual.iter().zip(&self.preconditioned).map(|(r, z)| r * z).sum();
            let beta = rz_next / rz;
            rz = rz_next;
            for j in 0..n {
                self.direction[j] = self.preconditioned[j] + beta * self.direction[j];
            }
        }
        let residual = self.residual.iter().map(|r| r * r).sum::<f64>().sqrt() / scale;
        Err(SolidsPressureError::NotConverged { iterations: max_iterations, residual })
    }

    /// The volume each face passes over the step, Δt α*_f Δu_f·S_f = −c_f (α*_N − α*_P), from
    /// the solved α*; then δ_j = −Σ_f (outward transfer)/V_j, so that Σ_j V_j δ_j = 0 to
    /// round-off whatever the solve left. In a packed cluster c_f reaches 10⁹ V: the solve's
    /// round-off, ~10⁻¹⁶ c_f, is 10⁻⁷ of a cell's α_p, while the differences α*_N − α*_P that
    /// carry the transfer are solved to 10⁻¹⁶.
    fn conserve_change(&mut self, mesh: &Mesh) {
        self.transfer.clear();
        self.product.clear();
        self.product.resize(mesh.n_cells(), 0.0);
        for f in 0..mesh.n_internal_faces {
            let (o, nb) = (mesh.face_owner[f], mesh.face_neighbour[f]);
            let transfer = -self.face_coefficient[f] * (self.change[nb] - self.change[o] + self.fraction[nb] - self.fraction[o]);
            self.transfer.push(transfer);
            self.product[o] -= transfer;
            self.product[nb] += transfer;
        }
        for (j, d) in self.change.iter_mut().enumerate() {
            *d = self.product[j] / mesh.cell_volumes[j];
        }
    }

    /// product = A · direction.
    fn multiply(&mut self, mesh: &Mesh) {
        let x = &self.direction;
        self.product.clear();
        self.product.extend(x.iter().zip(&self.diagonal).map(|(x, d)| d * x));
        for f in 0..mesh.n_internal_faces {
            let (o, nb) = (mesh.face_owner[f], mesh.face_neighbour[f]);
            self.product[o] -= self.face_coefficient[f] * x[nb];
            self.product[nb] -= self.face_coefficient[f] * x[o];
        }
    }

    /// u_j = [Σ_f S_f S_fᵀ/|S_f|]⁻¹ Σ_f S_f φ_f/|S_f| over all faces of cell j, boundary faces
    /// with φ = 0 (OpenFOAM's fvc::reconstruct); then its Gauss gradient from face values whose
    /// normal part is the face's own flux φ_f/|S_f| and whose tangential part is interpolated
    /// (zero-gradient at boundary faces), so the velocity inside the cell spreads or gathers
    /// the particles as the face fluxes say: its divergence is the cell's net outflow Σ φ_f/V.
    fn reconstruct(&mut self, mesh: &Mesh, n: usize) {
        self.correction.clear();
        self.correction.resize(n, Vec3::zeros());
        for j in 0..n {
            let mut tensor = nalgebra::Matrix3::<f64>::zeros();
            let mut sum = Vec3::zeros();
            for &f in mesh.faces_of_cell(j) {
                let s = mesh.face_areas[f];
                let area = s.norm();
                if area == 0.0 {
                    continue;
                }
                tensor += s * s.transpose() / area;
                if f < mesh.n_internal_faces {
                    // the flux is owner → neighbour; both see the same S_f and φ_f
                    sum += s * self.face_flux[f] / area;
                }
            }
            self.correction[j] = tensor.try_inverse().map_or(Vec3::zeros(), |inverse| inverse * sum);
        }
        self.correction_gradient.clear();
        self.correction_gradient.resize(n, nalgebra::Matrix3::zeros());
        for f in 0..mesh.n_faces() {
            let s = mesh.face_areas[f];
            let area_squared = s.norm_squared();
            if area_squared == 0.0 {
                continue;
            }
            let o = mesh.face_owner[f];
            let (tangential, flux) = if f < mesh.n_internal_faces {
                let (nb, w) = (mesh.face_neighbour[f], mesh.face_weight[f]);
                (w * self.correction[o] + (1.0 - w) * self.correction[nb], self.face_flux[f])
            } else {
                (self.correction[o], 0.0)
            };
            // the face value: its tangential part, and the flux's normal part
            let value = tangential - s * (s.dot(&tangential) / area_squared) + s * (flux / area_squared);
            let contribution = s * value.transpose();
            self.correction_gradient[o] += contribution;
            if f < mesh.n_internal_faces {
                self.correction_gradient[mesh.face_neighbour[f]] -= contribution;
            }
        }
        for (g, v) in self.correction_gradient.iter_mut().zip(&mesh.cell_volumes) {
            *g /= *v;
        }
    }

    /// The correction at `position` inside `cell`: u_j + (x − x_j)·∇u_j.
    pub fn correction_at(&self, mesh: &Mesh, cell: usize, position: &Vec3) -> Vec3 {
        self.correction[cell] + self.correction_gradient[cell].transpose() * (position - mesh.cell_centres[cell])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::closure::solids_pressure::{solids_pressure_slope_per_density, VelocityMoments};
    use crate::mesh::BoxSpec;

    /// N cells along a periodic x of length 1 (one cell across y and z, whose walls carry no
    /// correction).
    fn periodic_row(n: usize) -> Mesh {
        let h = 1.0 / n as f64;
        Mesh::cartesian_box(&BoxSpec { periodic: [true, false, false], ..BoxSpec::uniform(Vec3::zeros(), Vec3::new(1.0, h, h), [n, 1, 1]) }).unwrap()
    }

    fn stage(treatment: Treatment) -> SolidsPressure {
        SolidsPressure::new(SolidsPressureSection { treatment, ..SolidsPressureSection::default() })
    }

    /// α_p = 0.3 + 0.1 sin 2πx at the cell centres, Θ uniform.
    fn wave(mesh: &Mesh, theta: f64, treatment: Treatment, dt: f64) -> SolidsPressure {
        let mut s = stage(treatment);
        s.fraction = mesh.cell_centres.iter().map(|c| 0.3 + 0.1 * (2.0 * std::f64::consts::PI * c.x).sin()).collect();
        s.temperature = vec![theta; mesh.n_cells()];
        s.correction_field(mesh, dt).unwrap();
        s
    }

    /// −(1/α_p) ∂(p_p/ρ_p)/∂x of the wave at x: the acceleration of §4.4 in closed form.
    fn wave_acceleration(x: f64, theta: f64) -> f64 {
        let k = 2.0 * std::f64::consts::PI;
        let alpha = 0.3 + 0.1 * (k * x).sin();
        -solids_pressure_slope_per_density(alpha, theta, RESTITUTION, PACKING_LIMIT) * 0.1 * k * (k * x).cos() / alpha
    }

    #[test]
    fn explicit_acceleration_converges_at_second_order_to_the_closed_form() {
        let theta = 2.0;
        let dt = 1e-6;
        let errors: Vec<f64> = [16, 32, 64]
            .iter()
            .map(|&n| {
                let mesh = periodic_row(n);
                let s = wave(&mesh, theta, Treatment::Explicit, dt);
                (0..n).map(|j| (s.correction[j].x / dt - wave_acceleration(mesh.cell_centres[j].x, theta)).abs()).fold(0.0, f64::max)
            })
            .collect();
        // central differences of p_p and the average of two face velocities: order 2 (1.8
        // leaves room for the nonlinearity of g₀ on the coarsest mesh)
        for w in errors.windows(2) {
            let order = (w[0] / w[1]).log2();
            assert!(order > 1.8, "errors {errors:?}: order {order}");
        }
        assert!(errors[2] < 1e-2 * wave_acceleration(0.0, theta).abs(), "errors {errors:?}");
    }

    #[test]
    fn implicit_correction_tends_to_the_explicit_one_at_second_order_in_the_step() {
        // α_p* differs from α_p by the step's own displacement, Δt² a: the implicit velocity
        // change over Δt, divided by Δt, moves by O(Δt²) as Δt shrinks (successive differences
        // fall 4×; 3.5 allows for the next term)
        let mesh = periodic_row(64);
        let theta = 10.0;
        let per_step = |dt: f64| -> Vec<f64> { wave(&mesh, theta, Treatment::Implicit, dt).correction.iter().map(|u| u.x / dt).collect() };
        let results: Vec<Vec<f64>> = [4e-4, 2e-4, 1e-4].iter().map(|&dt| per_step(dt)).collect();
        let difference = |a: &Vec<f64>, b: &Vec<f64>| a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
        let (d1, d2) = (difference(&results[0], &results[1]), difference(&results[1], &results[2]));
        assert!(d1 / d2 > 3.5 && d1 / d2 < 4.5, "successive differences {d1:e}, {d2:e}");
        // and the largest step still moves the acceleration by a visible amount (the test
        // would pass trivially if the solve did nothing)
        assert!(d1 > 1e-3 * results[0].iter().fold(0.0_f64, |a, v| a.max(v.abs())), "d1 {d1:e}");
        // its limit is the acceleration of §4.4: at the smallest step within the explicit
        // form's spatial error at 64 cells (1e-2 of the largest, as in the explicit test)
        let scale = wave_acceleration(0.0, theta).abs();
        let worst = (0..64).map(|j| (results[2][j] - wave_acceleration(mesh.cell_centres[j].x, theta)).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-2 * scale, "implicit at Δt 1e-4 against the closed form: {worst:e} of {scale:e}");
    }

    #[test]
    fn an_over_packed_cell_unpacks_in_one_implicit_step_and_keeps_the_particle_volume() {
        let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(5e-3, 5e-3, 5e-3), [5, 5, 5])).unwrap();
        let centre = mesh.locate(&Vec3::new(2.5e-3, 2.5e-3, 2.5e-3)).unwrap();
        for treatment in [Treatment::Implicit, Treatment::Explicit] {
            let mut s = stage(treatment);
            s.fraction = vec![0.1; mesh.n_cells()];
            s.fraction[centre] = 2.0;
            s.temperature = vec![1.0; mesh.n_cells()];
            let report = s.correction_field(&mesh, 2.5e-5).unwrap();
            assert_eq!(report.largest_fraction, 2.0);
            if treatment == Treatment::Implicit {
                let before: f64 = s.fraction.iter().zip(&mesh.cell_volumes).map(|(a, v)| a * v).sum();
                let after: f64 = s.fraction_after.iter().zip(&mesh.cell_volumes).map(|(a, v)| a * v).sum();
                // the solve's transfers cancel face by face: round-off of 125 terms
                assert!((after - before).abs() <= 1e-14 * before, "Σ α V {before:e} → {after:e}");
            }
            // the packed cell's particles are spread outward: a positive divergence there
            let nb = centre + 1;
            assert!(
                s.correction_gradient[centre].trace() > 0.0,
                "{treatment:?}: trace {:e}, α* {} {} flux {:?} δ {} {}",
                s.correction_gradient[centre].trace(),
                s.fraction_after[centre],
                s.fraction_after[nb],
                mesh.faces_of_cell(centre).iter().filter(|&&f| f < mesh.n_internal_faces).map(|&f| s.face_flux[f]).collect::<Vec<_>>(),
                s.change[centre],
                s.change[nb]
            );
            if treatment == Treatment::Implicit {
                assert!(report.largest_fraction_after < PACKING_LIMIT, "{report:?}");
                assert!(report.iterations > 0);
            } else {
                assert_eq!(report.largest_fraction_after, 2.0);
            }
        }
    }

    #[test]
    fn particles_are_binned_with_their_modifier_and_take_their_cells_correction() {
        let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(3e-3, 1e-3, 1e-3), [3, 1, 1])).unwrap();
        let particle = |id: u64, x: f64, u: f64| Particle {
            id,
            material: 0,
            diameter: 1e-4,
            density: 2500.0,
            position: Vec3::new(x, 5e-4, 5e-4),
            velocity: Vec3::new(u, 0.0, 0.0),
            spin: Vec3::zeros(),
            contact_force: Vec3::zeros(),
            contact_torque: Vec3::zeros(),
            contacts: 0,
        };
        // A34 in the first cell (±1 m/s: Θ = 1/3), one particle in the second, none in the third
        let mut particles = vec![particle(0, 4e-4, 1.0), particle(1, 6e-4, -1.0), particle(2, 1.5e-3, 0.0), particle(3, 9.0, 0.0)];
        let before = particles.clone();
        let mut s = stage(Treatment::Implicit);
        let modifier = 100.0;
        s.correct(&mesh, &mut particles, modifier, 1e-5).unwrap();
        assert!((s.temperature[0] - 1.0 / 3.0).abs() <= 1e-14);
        assert_eq!(s.temperature[1], 0.0);
        let binned: f64 = s.fraction.iter().zip(&mesh.cell_volumes).map(|(a, v)| a * v).sum();
        let real = modifier * 3.0 * before[0].volume();
        assert!((binned - real).abs() <= 1e-15 * real, "{binned:e} vs {real:e}");
        for (p, q) in particles.iter().zip(&before).take(3) {
            let cell = mesh.locate(&q.position).unwrap();
            let expected = s.correction_at(&mesh, cell, &q.position);
            // (u + Δu) − u: round-off of u
            assert!((p.velocity - q.velocity - expected).norm() <= 1e-15 * q.velocity.norm().max(1.0), "{:?} vs {expected:?}", p.velocity - q.velocity);
        }
        // the first cell pushes its particles toward the emptier second cell
        assert!(s.correction[0].x > 0.0);
        // outside the mesh: untouched
        assert_eq!(particles[3].velocity, before[3].velocity);
    }

    #[test]
    fn particles_already_moving_apart_get_only_what_they_lack() {
        // the packed-cell set-up of a 3-cell row, its particles' mean velocities given: moving
        // outward faster than the correction, they get none on those faces; at rest, all of it
        let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(3e-3, 1e-3, 1e-3), [3, 1, 1])).unwrap();
        let run = |outward: f64| {
            let mut s = stage(Treatment::Implicit);
            s.fraction = vec![0.1, 1.0, 0.1];
            s.temperature = vec![1.0; 3];
            s.moments = [-outward, 0.0, outward]
                .iter()
                .map(|&u| {
                    let mut m = VelocityMoments::default();
                    m.add([u, 0.0, 0.0], 1.0);
                    m
                })
                .collect();
            s.correction_field(&mesh, 2.5e-5).unwrap();
            s.face_flux.clone()
        };
        let at_rest = run(0.0);
        assert!(at_rest[0] < 0.0 && at_rest[1] > 0.0, "{at_rest:?}");
        // face velocity of the mean motion: ±u/2 (the middle cell is at rest), times the area
        let area = 1e-6;
        let fast = 4.0 * at_rest[1].abs() / area;
        assert_eq!(run(fast), vec![0.0, 0.0]);
        let slow = 0.5 * at_rest[1].abs() / area;
        let partly = run(slow);
        for (p, r) in partly.iter().zip(&at_rest) {
            assert!((p - (r - r.signum() * 0.5 * slow * area)).abs() <= 1e-12 * r.abs(), "{partly:?} against {at_rest:?}");
        }
    }

    #[test]
    fn the_thesis_literal_force_lacks_the_fraction() {
        // explicit: face by face the per-particle-volume correction times α_p,f (exactly, up to
        // the one division); implicit: a weaker correction of the same sign on the wave
        let mesh = periodic_row(32);
        let dt = 1e-5;
        let field = |treatment, force| {
            let mut s = SolidsPressure::new(SolidsPressureSection { treatment, force, ..SolidsPressureSection::default() });
            s.fraction = mesh.cell_centres.iter().map(|c| 0.3 + 0.1 * (2.0 * std::f64::consts::PI * c.x).sin()).collect();
            s.temperature = vec![2.0; mesh.n_cells()];
            s.correction_field(&mesh, dt).unwrap();
            s
        };
        let volume = field(Treatment::Explicit, KtgfForce::PerParticleVolume);
        let literal = field(Treatment::Explicit, KtgfForce::ThesisLiteral);
        for f in 0..mesh.n_internal_faces {
            let (o, nb, w) = (mesh.face_owner[f], mesh.face_neighbour[f], mesh.face_weight[f]);
            let alpha = w * volume.fraction[o] + (1.0 - w) * volume.fraction[nb];
            assert!((literal.face_flux[f] - alpha * volume.face_flux[f]).abs() <= 1e-15 * literal.face_flux[f].abs().max(1e-300), "face {f}");
        }
        let volume = field(Treatment::Implicit, KtgfForce::PerParticleVolume);
        let literal = field(Treatment::Implicit, KtgfForce::ThesisLiteral);
        for (l, v) in literal.correction.iter().zip(&volume.correction) {
            assert!(l.x * v.x >= 0.0 && l.x.abs() < 0.45 * v.x.abs().max(1e-300) + 1e-300, "{l:?} vs {v:?}");
        }
    }

    #[test]
    fn bad_settings_name_their_key() {
        let bad = SolidsPressureSection { packing_limit: 1.2, ..SolidsPressureSection::default() };
        assert_eq!(bad.validate().unwrap_err().key, "particles.solids_pressure.packing_limit");
        let bad = SolidsPressureSection { restitution: -0.1, ..SolidsPressureSection::default() };
        assert_eq!(bad.validate().unwrap_err().key, "particles.solids_pressure.restitution");
        assert_eq!(stage(Treatment::Implicit).correction_field(&periodic_row(4), 0.0).unwrap_err(), SolidsPressureError::BadStep(0.0));
    }
}
