//! [`ParticleMeshMap`]: the selected mapping between particles and cells, both ways (spec
//! fluid-dem-model.md §6.8):
//!
//! | method    | particle → mesh (α_p, C_implicit, F_explicit)      | mesh → particle (u, α_c, Du/Dt)           |
//! |-----------|-----------------------------------------------------|-------------------------------------------|
//! | centroid  | host cell (T3.69)                                   | host cell                                 |
//! | kernel    | φ̂, ghosts, one side of the interface (T3.75, T3.93) | ψ̂, the same cells (T3.85, T3.86)          |
//! | diffusion | own-width φ̂, then smoothed (T3.78–T3.81)           | u and Du/Dt smoothed (T3.87), then ψ̂      |
//!
//! Every method conserves: Σ_j α_p,j V_j = Σ_n V_p,n, Σ_j C_j = Σ_n K_n and Σ_j F_j = Σ_n F_n to
//! round-off (§12 U-19, U-24). The fluid fraction a particle sees for its hindered drag is the
//! ψ̂ average for the kernel and diffusion methods, also next to a sliding interface, and the
//! host cell's value for the centroid method.
//!
//! [R, deviation from §6.7 / Table 4.2] The thesis takes α_c|p next to the interface from the
//! cell field at the particle centre ("not by ψ"), because its ψ would reach across the
//! interface; ours stops at the interface and is renormalised on the particle's side, so it can
//! be used there too. The centre value counts the particle's own volume: at γ = 1, d_p/Δx = 1
//! the host cell's α_p is 0.037, α_c^{1−β} adds 10 % drag, and the P2 particle settled 4 % slow
//! for as long as it was within 3σ of the interface (measured 2.9e-2 m/s below the run without
//! an interface; with ψ̂: 1.6e-3 m/s; cases/coupling/interface_crossing.toml, oblique crossing).
//!
//! [R] The diffusion method samples its smoothed fields with the kernel's ψ̂ rather than at the
//! particle centre: the thesis does not say how the smoothed field is sampled (§6.5), and the
//! centre value holds the particle's own disturbance — its own volume (α_c|p 3–4 % low at γ = 1,
//! so α_c^{1−β} adds ~10 % drag) and the fluid it drags along — which is what ψ (zero at the
//! centre) exists to leave out. Measured on P1 (d_p/Δx = 1, γ = 1): the centre value settled
//! 7.6 % slow.

use super::accumulate::{accumulate_in_order, Accumulator, CellSums};
use super::cell_search::CellSearch;
use super::diffusion::Diffusion;
use super::kernel::{self, KernelGeometry, Stencil};
use super::settings::{CouplingSection, InterfaceTreatment, MappingMethod};
use super::stencil_cache::{BuilderMemory, StencilCache, Weights};
use crate::closure::drag::FluidAtParticle;
use crate::fluid::sampling::{material_acceleration, FluidSample};
use crate::mesh::{Mesh, PatchKind, Vec3};
use crate::particles::Particle;
use crate::step::ParticleLoad;

/// The width of the diffusion method's initial deposit, as a fraction of d_p: the Gaussian with
/// a sphere's own second moment (a²/5 per axis, a = d_p/2, so σ₀ = d_p/(2√5)), integrated over
/// the cells like the kernel's φ [R, deviation from T3.78].
///
/// The thesis starts the diffusion from the host cell (the centroid method) and smooths that.
/// On cells wider than the kernel the smoothing hardly moves it, so the particle's volume still
/// jumps from cell to cell: at P1's d_p/Δx = 0.1 (diffusion γ = 3, D Δt/Δx² = 0.045) the
/// settling velocity dipped by 5.3 % of u_t at each crossing. Starting from the particle's own
/// small Gaussian carries its position inside the cell; the smoothing then adds the rest of the
/// variance, so the total stays (γ d_p)² (T4.46).
pub const SPHERE_WIDTH_FACTOR: f64 = 0.223_606_797_749_979;

/// The particle load spread over the cells.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CellLoad {
    /// α_p per cell (as mapped: may exceed 1 with the centroid method, §6.1).
    pub particle_fraction: Vec<f64>,
    /// C_j = Σ_n w_j,n K_n [kg/s], ≥ 0: the fluid in cell j receives −C_j u_j, implicit in u
    /// (spec §8.4, with its sign corrected: +C_j/ρ on the momentum diagonal).
    pub implicit_drag: Vec<f64>,
    /// F_j = Σ_n w_j,n F_n [N]: the explicit part of the particles' force on the fluid of cell j
    /// (spec §8.4, F_explicit).
    pub explicit_force: Vec<Vec3>,
    /// Cells whose ∂α_c/∂t the pressure equation replaces by their share of the band's net rate
    /// (T4.54 and [`super::mask`]: the redistribution inside the band is left out): within the kernel
    /// support 3γ d_max of a sliding interface, when `[coupling] interface_mask` is on.
    pub masked: Vec<bool>,
}

impl CellLoad {
    /// An empty load on `n` cells.
    pub fn zeros(n: usize) -> Self {
        Self { particle_fraction: vec![0.0; n], implicit_drag: vec![0.0; n], explicit_force: vec![Vec3::zeros(); n], masked: vec![false; n] }
    }

    /// Force density on the fluid f_j = (F_j − C_j u_j)/V_j [N/m³] for the cell velocities `u`.
    pub fn force_density(&self, mesh: &Mesh, u: &[[f64; 3]]) -> Vec<[f64; 3]> {
        (0..mesh.n_cells()).map(|c| ((self.explicit_force[c] - Vec3::from(u[c]) * self.implicit_drag[c]) / mesh.cell_volumes[c]).into()).collect()
    }
}

/// The mapping of a case (`[coupling]`).
#[derive(Clone, Debug)]
pub struct ParticleMeshMap {
    pub method: MappingMethod,
    pub distance_factor: f64,
    /// Where a kernel may reach at a sliding interface.
    pub interface: InterfaceTreatment,
    pub interface_mask: bool,
    pub min_fluid_fraction: f64,
    /// Real particles each simulated one stands for (`[particles] modifier`): the deposited
    /// volume, drag coefficient and force count this many times (wear-model.md §2.4 [R]).
    pub modifier: f64,
    /// How the stencils are built and the diffusion fields smoothed ([`MappingSolvers::IN_ORDER`]
    /// unless a solver sets its own).
    pub solvers: MappingSolvers,
}

/// The interchangeable pieces of work inside the mapping: building the kernel stencils,
/// smoothing the diffusion method's fields and reading the fluid through the stencils. The
/// reference does them one after the other ([`MappingSolvers::IN_ORDER`]); the fast solver
/// brings parallel ones with the same stencils and samples and a smoothing within round-off,
/// and reuses a deposit's stencils for the next sample.
#[derive(Clone, Copy, Debug)]
pub struct MappingSolvers {
    pub stencils: StencilBuilder,
    pub smoother: Smoother,
    pub sampler: Sampler,
    /// How the deposit weights sum the particles' loads into the cells.
    pub accumulator: Accumulator,
    /// Whether a sample may take the stencils of the deposit before it when they are the same
    /// ([`StencilCache`]: same particles, σ and mesh, so the same bits). The reference builds
    /// every stencil it uses.
    pub reuse_stencils: bool,
}

impl MappingSolvers {
    /// One particle, one field after the other.
    pub const IN_ORDER: MappingSolvers = MappingSolvers {
        stencils: stencils_in_order,
        smoother: smooth_in_order,
        sampler: sample_in_order,
        accumulator: accumulate_in_order,
        reuse_stencils: false,
    };
}

/// Smooths each of `fields` with one diffusion operator (one backward-Euler step,
/// [`Diffusion::smooth`]), in place. The fields are independent: a solver may smooth them in
/// any order or at once, and with its own linear solver, as long as it converges as tightly
/// and folds its residual back (Σ V q kept to round-off).
pub type Smoother = fn(diffusion: &Diffusion, fields: &mut [Vec<f64>]);

/// The fields one after the other, each by [`Diffusion::smooth`].
pub fn smooth_in_order(diffusion: &Diffusion, fields: &mut [Vec<f64>]) {
    for field in fields {
        diffusion.smooth(field);
    }
}

/// Builds the kernel stencil of every particle (σ = γ d, in particle order) into `out` (one per
/// particle), with at least the weights `weights`. Each stencil is a function of its own
/// particle and the mesh alone, so any builder gives the same stencils: the reference builds
/// them one after the other ([`stencils_in_order`]), the fast solver in parallel, reusing the
/// storage in `out` and computing only the weights asked for.
/// `memory` is the builder's own, kept between builds ([`BuilderMemory`]).
pub type StencilBuilder = fn(geo: &KernelGeometry, particles: &[Particle], gamma: f64, weights: Weights, out: &mut Vec<Stencil>, memory: &mut BuilderMemory);

/// The stencils one particle after the other, both weights of each.
pub fn stencils_in_order(geo: &KernelGeometry, particles: &[Particle], gamma: f64, _weights: Weights, out: &mut Vec<Stencil>, _memory: &mut BuilderMemory) {
    let mut scratch = Vec::new();
    out.clear();
    out.extend(particles.iter().map(|p| kernel::stencil(geo, &p.position, p.diameter, gamma, host_cell(geo.mesh, &p.position), &mut scratch)));
}

/// Reads `fields` (u_x, u_y, u_z, Du/Dt x, y, z, α_c per cell) through each stencil's sample
/// weights into `out` (one row per stencil, in order; [`sample_one`] each). The rows are
/// independent: a solver may take them in any order or at once.
pub type Sampler = fn(stencils: &[Stencil], fields: &[&[f64]; 7], out: &mut Vec<[f64; 7]>);

/// The rows one stencil after the other.
pub fn sample_in_order(stencils: &[Stencil], fields: &[&[f64]; 7], out: &mut Vec<[f64; 7]>) {
    out.clear();
    out.extend(stencils.iter().map(|s| sample_one(s, fields)));
}

/// Σ_j s_j q_j of each field over one stencil, in its cell order.
#[inline]
pub fn sample_one(s: &Stencil, fields: &[&[f64]; 7]) -> [f64; 7] {
    let mut sum = [0.0; 7];
    for (&c, &w) in s.cells.iter().zip(&s.sample) {
        for (total, field) in sum.iter_mut().zip(fields) {
            *total += field[c] * w;
        }
    }
    sum
}

/// The host cell of a particle: the cell holding its centre, or, in the sliver between a
/// sliding interface's polygonal rings where no cell holds it, the cell with the nearest centre.
pub fn host_cell(mesh: &Mesh, x: &Vec3) -> usize {
    mesh.locate(x).unwrap_or_else(|| {
        (0..mesh.n_cells()).min_by(|&a, &b| (mesh.cell_centres[a] - x).norm_squared().total_cmp(&(mesh.cell_centres[b] - x).norm_squared())).unwrap_or(0)
    })
}

impl ParticleMeshMap {
    pub fn new(section: &CouplingSection) -> Self {
        Self {
            method: section.method,
            distance_factor: section.distance_factor,
            interface: section.interface,
            interface_mask: section.masks_interface(),
            min_fluid_fraction: section.min_fluid_fraction,
            modifier: 1.0,
            solvers: MappingSolvers::IN_ORDER,
        }
    }

    /// The mapping of a case: its `[coupling]` with its particles' `modifier`.
    pub fn of_case(section: &CouplingSection, case: &crate::case::Case) -> Self {
        Self { modifier: case.particle_modifier(), ..Self::new(section) }
    }

    /// α_c = max(1 − α_p, α_c,min) per cell into `alpha` (T3.90); returns the number of cells
    /// held at the bound.
    pub fn fluid_fraction(&self, load: &CellLoad, alpha: &mut [f64]) -> usize {
        let mut clamped = 0;
        for (a, p) in alpha.iter_mut().zip(&load.particle_fraction) {
            *a = 1.0 - p;
            if *a < self.min_fluid_fraction {
                *a = self.min_fluid_fraction;
                clamped += 1;
            }
        }
        clamped
    }

    /// Kernel support radius 3γd of a particle of diameter `d`.
    pub fn support(&self, diameter: f64) -> f64 {
        3.0 * self.distance_factor * diameter
    }

    /// The diffusion method's smoothing of a field that is already spread to the width
    /// `initial_factor` d̄: T·D = ((γ d̄)² − (initial_factor d̄)²)/2, so the result has the
    /// variance (γ d̄)² of T4.46 (T = Δt) — variances of successive spreads add. d̄ is the mean
    /// diameter: the thesis' diffusion is monodisperse (§6.6), one D for all particles.
    fn diffusion(&self, mesh: &Mesh, particles: &[Particle], initial_factor: f64) -> Diffusion {
        let mean = particles.iter().map(|p| p.diameter).sum::<f64>() / particles.len().max(1) as f64;
        let variance = (self.distance_factor * mean).powi(2) - (initial_factor * mean).powi(2);
        Diffusion::new(mesh, 0.5 * variance.max(0.0))
    }

    /// The largest kernel support 3γ d_max among `particles`.
    fn largest_support(&self, particles: &[Particle]) -> f64 {
        self.support(particles.iter().map(|p| p.diameter).fold(0.0, f64::max))
    }

    /// The cell search of `mesh` at its current position, binned at the largest support.
    fn cell_search(&self, mesh: &Mesh, particles: &[Particle]) -> CellSearch {
        CellSearch::new(mesh, self.largest_support(particles))
    }

    /// The cell search for kernels of width σ = `gamma` d, binned at their largest support
    /// 3γ d_max (the diffusion's deposit kernel is 13 times narrower than its support
    /// 3γ d_max: binned at that, a query would test ~40 times the cells it finds).
    fn kernel_search(&self, mesh: &Mesh, particles: &[Particle], gamma: f64) -> CellSearch {
        CellSearch::new(mesh, self.kernel_radius(particles, gamma))
    }

    /// The binning radius of [`Self::kernel_search`].
    fn kernel_radius(&self, particles: &[Particle], gamma: f64) -> f64 {
        3.0 * gamma * particles.iter().map(|p| p.diameter).fold(0.0, f64::max)
    }

    /// Whether the ∂α/∂t mask applies (an interface, particles and `interface_mask` on).
    fn masking(&self, mesh: &Mesh, particles: &[Particle]) -> bool {
        self.interface_mask && !mesh.interfaces.is_empty() && !particles.is_empty()
    }

    /// The kernel stencils (σ = `gamma` d) of `particles` on `mesh` at its current position
    /// with the weights `need`, in `cache`: taken from it if it holds them and the solvers reuse
    /// stencils, else built with the weights `build` (which cover `need`; the cell search is
    /// binned if `search` has none yet).
    #[allow(clippy::too_many_arguments)]
    fn stencils<'c>(
        &self,
        mesh: &Mesh,
        particles: &[Particle],
        search: &mut Option<CellSearch>,
        gamma: f64,
        (need, build): (Weights, Weights),
        cache: &'c mut StencilCache,
    ) -> &'c [Stencil] {
        let reuse = self.solvers.reuse_stencils;
        if !(reuse && cache.holds(mesh, particles, gamma, need)) {
            // a solver that reuses stencils also keeps the cell search while the mesh stands still
            let mut kept = (reuse && search.is_none()).then(|| cache.take_search(mesh, self.kernel_radius(particles, gamma)));
            let search = match &mut kept {
                Some(kept) => &kept.search,
                None => search.get_or_insert_with(|| self.kernel_search(mesh, particles, gamma)),
            };
            let walls = kernel::wall_faces(mesh);
            let geo = KernelGeometry {
                mesh,
                search,
                wall_faces: &walls,
                truncate_at_interface: !mesh.interfaces.is_empty() && self.interface == InterfaceTreatment::Truncate,
                empty_normal: super::cell_quadrature::empty_normal(mesh),
            };
            (self.solvers.stencils)(&geo, particles, gamma, build, &mut cache.stencils, &mut cache.memory);
            if let Some(kept) = kept {
                cache.keep_search(kept);
            }
            if reuse {
                cache.record(mesh, particles, gamma, build);
            } else {
                cache.forget();
            }
        }
        &cache.stencils
    }

    /// Cells within 3γ d_max of a sliding-interface face (call only when [`Self::masking`]).
    fn mask(&self, mesh: &Mesh, particles: &[Particle], search: &CellSearch, masked: &mut [bool]) {
        let radius = self.largest_support(particles);
        let mut near = Vec::new();
        for patch in mesh.patches.iter().filter(|p| matches!(p.kind, PatchKind::Interface { .. })) {
            for f in patch.faces() {
                near.clear();
                search.within(mesh, &mesh.face_centres[f], radius, &mut near);
                for &c in &near {
                    masked[c] = true;
                }
            }
        }
    }

    /// Particle → mesh: spreads each particle's volume, implicit drag coefficient and explicit
    /// force (`load`, in the order of `particles`) over the cells of `mesh` into `out`.
    pub fn deposit(&self, mesh: &Mesh, particles: &[Particle], load: &ParticleLoad, out: &mut CellLoad) {
        self.deposit_with(&mut StencilCache::default(), mesh, particles, load, out);
    }

    /// [`Self::deposit`], keeping its stencils in `cache` for the next sample (a coupled run's).
    pub fn deposit_with(&self, cache: &mut StencilCache, mesh: &Mesh, particles: &[Particle], load: &ParticleLoad, out: &mut CellLoad) {
        let n = mesh.n_cells();
        *out = CellLoad::zeros(n);
        // one binning of the cell centres serves the mask and the kernels of the same support
        let mut search = None;
        if self.masking(mesh, particles) {
            let search = search.insert(self.cell_search(mesh, particles));
            self.mask(mesh, particles, search, &mut out.masked);
        }
        if self.method != MappingMethod::Kernel {
            search = None;
        }
        let mut sums = CellSums::zeros(n);
        match self.method {
            MappingMethod::Kernel | MappingMethod::Diffusion => {
                let kernel = self.method == MappingMethod::Kernel;
                let gamma = if kernel { self.distance_factor } else { SPHERE_WIDTH_FACTOR };
                // the kernel's next sample is at these positions with this σ: its weights too
                let build = if kernel && self.solvers.reuse_stencils { Weights::Both } else { Weights::Deposit };
                let stencils = self.stencils(mesh, particles, &mut search, gamma, (Weights::Deposit, build), cache);
                (self.solvers.accumulator)(stencils, load, &mut sums);
            }
            MappingMethod::Centroid => {
                let CellSums { volume, drag, force: [fx, fy, fz] } = &mut sums;
                for (i, p) in particles.iter().enumerate() {
                    let c = host_cell(mesh, &p.position);
                    CellSums::add(&mut volume[c], &mut drag[c], [&mut fx[c], &mut fy[c], &mut fz[c]], 1.0, load, i);
                }
            }
        }
        let CellSums { mut volume, mut drag, mut force } = sums;
        if self.modifier != 1.0 {
            // each simulated particle stands for `modifier` real ones (a linear scaling, so it
            // may come before the diffusion's smoothing)
            for field in [&mut volume, &mut drag].into_iter().chain(force.iter_mut()) {
                field.iter_mut().for_each(|q| *q *= self.modifier);
            }
        }
        // per-volume fields for α_p and the diffusion; C and F stay totals per cell
        volume.iter_mut().zip(&mesh.cell_volumes).for_each(|(q, v)| *q /= v);
        if self.method == MappingMethod::Diffusion && !particles.is_empty() {
            let diffusion = self.diffusion(mesh, particles, SPHERE_WIDTH_FACTOR);
            // α_p as it is; C and F are diffused as densities (per volume) and integrated back
            let mut fields = vec![std::mem::take(&mut volume), std::mem::take(&mut drag)];
            fields.extend(force.iter_mut().map(std::mem::take));
            for field in fields[1..].iter_mut() {
                field.iter_mut().zip(&mesh.cell_volumes).for_each(|(q, v)| *q /= v);
            }
            (self.solvers.smoother)(&diffusion, &mut fields);
            for field in fields[1..].iter_mut() {
                field.iter_mut().zip(&mesh.cell_volumes).for_each(|(q, v)| *q *= v);
            }
            let mut fields = fields.into_iter();
            volume = fields.next().expect("five fields");
            drag = fields.next().expect("five fields");
            for (k, f) in fields.enumerate() {
                force[k] = f;
            }
        }
        out.particle_fraction = volume;
        out.implicit_drag = drag;
        out.explicit_force = (0..n).map(|c| Vec3::new(force[0][c], force[1][c], force[2][c])).collect();
    }

    /// Mesh → particle: the fluid each particle sees (velocity, fluid fraction, material
    /// acceleration), appended to `out` in particle order.
    pub fn sample(&self, source: &FluidSample, particles: &[Particle], out: &mut Vec<Option<FluidAtParticle>>) {
        self.sample_with(&mut StencilCache::default(), source, particles, out);
    }

    /// [`Self::sample`], taking the stencils of the last deposit from `cache` when they apply.
    pub fn sample_with(&self, cache: &mut StencilCache, source: &FluidSample, particles: &[Particle], out: &mut Vec<Option<FluidAtParticle>>) {
        let mesh = source.mesh;
        let fluid = source.fluid;
        let n = mesh.n_cells();
        let mut velocity: [Vec<f64>; 3] = std::array::from_fn(|k| fluid.velocity.iter().map(|u| u[k]).collect());
        let acceleration: Vec<Vec3> = (0..n).map(|c| material_acceleration(source, c)).collect();
        let mut acceleration: [Vec<f64>; 3] = std::array::from_fn(|k| acceleration.iter().map(|a| a[k]).collect());
        let at = |fields: &[Vec<f64>; 3], c: usize| Vec3::new(fields[0][c], fields[1][c], fields[2][c]);
        let seen = |velocity: Vec3, acceleration: Vec3, fluid_fraction: f64| FluidAtParticle {
            density: source.density,
            kinematic_viscosity: source.kinematic_viscosity,
            velocity,
            material_acceleration: acceleration,
            fluid_fraction,
        };
        if self.method == MappingMethod::Diffusion && !particles.is_empty() {
            let diffusion = self.diffusion(mesh, particles, 0.0);
            let mut fields: Vec<Vec<f64>> = velocity.iter_mut().chain(acceleration.iter_mut()).map(std::mem::take).collect();
            (self.solvers.smoother)(&diffusion, &mut fields);
            for (field, smoothed) in velocity.iter_mut().chain(acceleration.iter_mut()).zip(fields) {
                *field = smoothed;
            }
        }
        match self.method {
            MappingMethod::Kernel | MappingMethod::Diffusion => {
                let weights = (Weights::Sample, Weights::Sample);
                let stencils = self.stencils(mesh, particles, &mut None, self.distance_factor, weights, cache);
                let fields = [&velocity[0][..], &velocity[1], &velocity[2], &acceleration[0], &acceleration[1], &acceleration[2], &fluid.alpha];
                let mut sums = Vec::new();
                (self.solvers.sampler)(stencils, &fields, &mut sums);
                out.extend(sums.iter().map(|s| Some(seen(Vec3::new(s[0], s[1], s[2]), Vec3::new(s[3], s[4], s[5]), s[6]))));
            }
            MappingMethod::Centroid => {
                for p in particles {
                    let host = host_cell(mesh, &p.position);
                    out.push(Some(seen(at(&velocity, host), at(&acceleration, host), fluid.alpha[host])));
                }
            }
        }
    }
}

#[cfg(test)]
pub(super) mod tests;
