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

use super::Particle;
use crate::closure::solids_pressure::{solids_pressure, solids_pressure_slope_per_density, VelocityMoments};
use crate::mesh::{Mesh, Vec3};

mod settings;
#[cfg(test)]
mod tests;

pub use settings::{KtgfForce, SolidsPressureSection, Treatment};

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
    pub settings: SolidsPressureSection,
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
        Self { settings, ..Self::default() }
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
        let settings = self.settings;
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
