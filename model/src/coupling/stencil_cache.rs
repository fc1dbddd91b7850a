//! The kernel stencils of the last mapping, kept for the next one: a coupled step deposits at
//! the particles' positions at tⁿ⁺¹ and the next step samples at the same positions, so with
//! the kernel method (the same σ = γ d both ways) the sample can take the deposit's stencils.
//!
//! A stencil is a function of its particle's position and diameter, σ and the mesh alone
//! ([`super::kernel::stencil`]), so the cache is keyed on exactly those: the bits of every
//! particle's position and diameter, of γ, and of the mesh's cell centres (a rotor zone moves
//! between the deposit and the next sample). A reused stencil is therefore the one a rebuild
//! would give, bit for bit; a changed key rebuilds all of them.
//!
//! It also keeps the builder's own memory ([`BuilderMemory`]: the fast builder's table of cell
//! quadratures), which the builder keys on what it depends on itself.

use super::kernel::Stencil;
use crate::mesh::{Mesh, Vec3};
use crate::particles::Particle;

/// Which of a stencil's weights a builder must compute: a builder may leave the other one
/// empty (the fast solver's does; the reference's always computes both).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Weights {
    /// φ̂ only (particle → mesh).
    Deposit,
    /// ψ̂ only (mesh → particle).
    Sample,
    Both,
}

impl Weights {
    /// Whether stencils with these weights serve a use that needs `need`.
    pub fn covers(self, need: Weights) -> bool {
        self == Weights::Both || self == need
    }
}

/// What a [`super::StencilBuilder`] keeps between builds, its own type inside (none for the
/// reference's). It must give the same stencils as a build without it.
pub type BuilderMemory = Option<Box<dyn std::any::Any + Send + Sync>>;

/// The stencils of the last build and what they were built from.
#[derive(Default)]
pub struct StencilCache {
    pub(super) stencils: Vec<Stencil>,
    pub(super) memory: BuilderMemory,
    /// Per particle: the bits of its position and diameter.
    keys: Vec<[u64; 4]>,
    gamma: u64,
    weights: Option<Weights>,
    /// The mesh's cell centres at the build.
    centres: Vec<Vec3>,
}

impl Clone for StencilCache {
    /// The stencils and their keys; not the builder's memory (rebuilt on demand).
    fn clone(&self) -> Self {
        Self { stencils: self.stencils.clone(), memory: None, keys: self.keys.clone(), gamma: self.gamma, weights: self.weights, centres: self.centres.clone() }
    }
}

impl std::fmt::Debug for StencilCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StencilCache")
            .field("stencils", &self.stencils.len())
            .field("gamma", &f64::from_bits(self.gamma))
            .field("weights", &self.weights)
            .finish()
    }
}

fn key(p: &Particle) -> [u64; 4] {
    [p.position.x.to_bits(), p.position.y.to_bits(), p.position.z.to_bits(), p.diameter.to_bits()]
}

fn same_bits(a: &[Vec3], b: &[Vec3]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(a, b)| a.iter().zip(b.iter()).all(|(x, y)| x.to_bits() == y.to_bits()))
}

impl StencilCache {
    /// Whether the cached stencils are those of `particles` on `mesh` with `gamma`, and carry
    /// the weights `need`.
    pub(super) fn holds(&self, mesh: &Mesh, particles: &[Particle], gamma: f64, need: Weights) -> bool {
        self.weights.is_some_and(|w| w.covers(need))
            && self.gamma == gamma.to_bits()
            && self.keys.len() == particles.len()
            && self.keys.iter().zip(particles).all(|(k, p)| *k == key(p))
            && same_bits(&self.centres, &mesh.cell_centres)
    }

    /// Records that `stencils` now hold the stencils of `particles` on `mesh` with `gamma` and
    /// `weights`.
    pub(super) fn record(&mut self, mesh: &Mesh, particles: &[Particle], gamma: f64, weights: Weights) {
        self.keys.clear();
        self.keys.extend(particles.iter().map(key));
        self.gamma = gamma.to_bits();
        self.weights = Some(weights);
        self.centres.clone_from(&mesh.cell_centres);
    }

    /// Forgets the stencils (keeps their storage): the next mapping builds them again.
    pub fn forget(&mut self) {
        self.weights = None;
    }
}
