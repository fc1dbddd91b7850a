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
//! quadratures), which the builder keys on what it depends on itself, and the binning of the
//! cell centres the stencils were found with ([`KeptSearch`]), keyed on its radius and the
//! mesh's points and cell centres: on a mesh that stands still it is binned once per run
//! instead of once per mapping (P3 fine: about 1 ms of every step, on one thread).

use super::cell_search::CellSearch;
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
    /// The cell search of the last build.
    search: Option<KeptSearch>,
}

/// A cell search and what it was binned from: the radius and the bits of the mesh's points and
/// cell centres (its buckets, reaches and spans are functions of these and of the mesh's
/// topology, which a run does not change).
pub(super) struct KeptSearch {
    radius: u64,
    points: Vec<Vec3>,
    centres: Vec<Vec3>,
    pub(super) search: CellSearch,
}

impl Clone for StencilCache {
    /// The stencils and their keys; not the builder's memory (rebuilt on demand).
    fn clone(&self) -> Self {
        Self {
            stencils: self.stencils.clone(),
            memory: None,
            keys: self.keys.clone(),
            gamma: self.gamma,
            weights: self.weights,
            centres: self.centres.clone(),
            search: None,
        }
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

    /// The cell search of radius `radius` on `mesh` as it stands: the kept one if it was binned
    /// from the same radius, points and cell centres (bit for bit), else a new one; to be given
    /// back with [`Self::keep_search`].
    pub(super) fn take_search(&mut self, mesh: &Mesh, radius: f64) -> KeptSearch {
        match self.search.take() {
            Some(kept) if kept.radius == radius.to_bits() && same_bits(&kept.points, &mesh.points) && same_bits(&kept.centres, &mesh.cell_centres) => kept,
            _ => {
                KeptSearch { radius: radius.to_bits(), points: mesh.points.clone(), centres: mesh.cell_centres.clone(), search: CellSearch::new(mesh, radius) }
            }
        }
    }

    /// Keeps a search from [`Self::take_search`] for the next mapping.
    pub(super) fn keep_search(&mut self, kept: KeptSearch) {
        self.search = Some(kept);
    }

    /// Forgets the stencils (keeps their storage): the next mapping builds them again.
    pub fn forget(&mut self) {
        self.weights = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coupling::{CellLoad, CouplingSection, Feedback, MappingMethod, MappingSolvers, ParticleMeshMap};
    use crate::mesh::cartesian::BoxSpec;
    use crate::step::ParticleLoad;

    fn particle(x: Vec3) -> Particle {
        Particle {
            id: 0,
            material: 0,
            diameter: 0.01,
            density: 2650.0,
            position: x,
            velocity: Vec3::zeros(),
            spin: Vec3::zeros(),
            contact_force: Vec3::zeros(),
            contact_torque: Vec3::zeros(),
            contacts: 0,
        }
    }

    /// A solver that reuses stencils bins the cell centres once while the mesh stands still
    /// (the kept search's storage is the same from mapping to mapping) and again when it moves;
    /// its deposits have the bits of deposits that bin afresh every time.
    #[test]
    fn the_cell_search_is_kept_while_the_mesh_stands_still_and_changes_no_bit() {
        let section = CouplingSection {
            method: MappingMethod::Kernel,
            distance_factor: 1.0,
            feedback: Feedback::default(),
            interface_mask: false,
            drag: Default::default(),
            min_fluid_fraction: 0.05,
        };
        let fresh = ParticleMeshMap::new(&section);
        let mut keeping = fresh.clone();
        keeping.solvers = MappingSolvers { reuse_stencils: true, ..MappingSolvers::IN_ORDER };
        let mut mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(0.2, 0.3, 0.02), [20, 30, 1])).unwrap();
        let mut cache = StencilCache::default();
        let mut kept_storage = None;
        for step in 0..4 {
            if step == 3 {
                // the mesh moves: a new search, binned from the new points
                for p in mesh.points.iter_mut() {
                    p.x += 0.0013;
                }
                mesh.update_all_geometry();
            }
            let particles: Vec<Particle> =
                (0..3).map(|i| particle(Vec3::new(0.05 + 0.04 * i as f64 + 0.003 * step as f64, 0.1 + 0.01 * step as f64, 0.01))).collect();
            let mut load = ParticleLoad::zeros(particles.len());
            for (i, p) in particles.iter().enumerate() {
                load.volume[i] = p.volume();
                load.implicit_drag[i] = 0.01 * (i + 1) as f64;
                load.explicit_force[i] = [0.3, -((i + 1) as f64), 0.2];
            }
            let (mut kept, mut afresh) = (CellLoad::default(), CellLoad::default());
            keeping.deposit_with(&mut cache, &mesh, &particles, &load, &mut kept);
            fresh.deposit(&mesh, &particles, &load, &mut afresh);
            let bits = |c: &CellLoad| {
                let mut b: Vec<u64> = c.particle_fraction.iter().chain(&c.implicit_drag).map(|v| v.to_bits()).collect();
                b.extend(c.explicit_force.iter().flat_map(|f| f.iter().map(|v| v.to_bits()).collect::<Vec<_>>()));
                b
            };
            assert_eq!(bits(&kept), bits(&afresh), "step {step}: the bits of a fresh binning");
            let search = cache.search.as_ref().expect("a kept search");
            assert!(same_bits(&search.points, &mesh.points), "step {step}: binned from the mesh as it stands");
            let storage = search.points.as_ptr();
            match step {
                0 => kept_storage = Some(storage),
                1 | 2 => assert_eq!(Some(storage), kept_storage, "step {step}: the same search, not binned again"),
                _ => assert_ne!(Some(storage), kept_storage, "the mesh moved: binned again"),
            }
        }
    }
}
