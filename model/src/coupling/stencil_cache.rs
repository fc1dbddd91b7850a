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
    /// The cell searches of the last builds, one per radius (at most [`KEPT_SEARCHES`]: the
    /// diffusion method's deposit and sample bin at two).
    searches: Vec<KeptSearch>,
}

/// How many cell searches of different radii a cache keeps.
const KEPT_SEARCHES: usize = 2;

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
            searches: Vec::new(),
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

    /// The cell search of radius `radius` on `mesh` as it stands: a kept one if it was binned
    /// from the same radius, points and cell centres (bit for bit), else a new one; to be given
    /// back with [`Self::keep_search`].
    pub(super) fn take_search(&mut self, mesh: &Mesh, radius: f64) -> KeptSearch {
        let fits = |k: &KeptSearch| k.radius == radius.to_bits() && same_bits(&k.points, &mesh.points) && same_bits(&k.centres, &mesh.cell_centres);
        match self.searches.iter().position(fits) {
            Some(i) => self.searches.remove(i),
            None => {
                KeptSearch { radius: radius.to_bits(), points: mesh.points.clone(), centres: mesh.cell_centres.clone(), search: CellSearch::new(mesh, radius) }
            }
        }
    }

    /// Keeps a search from [`Self::take_search`] for the next mappings, in place of the one kept
    /// longest when there are [`KEPT_SEARCHES`] already.
    pub(super) fn keep_search(&mut self, kept: KeptSearch) {
        if self.searches.len() == KEPT_SEARCHES {
            self.searches.remove(0);
        }
        self.searches.push(kept);
    }

    /// Forgets the stencils (keeps their storage): the next mapping builds them again.
    pub fn forget(&mut self) {
        self.weights = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coupling::mapping::tests::{load, map, particle};
    use crate::coupling::{CellLoad, MappingMethod, MappingSolvers};
    use crate::mesh::cartesian::BoxSpec;

    /// A solver that reuses stencils bins the cell centres once while the mesh stands still
    /// (the kept search's storage is the same from mapping to mapping) and again when it moves;
    /// its deposits have the bits of deposits that bin afresh every time.
    #[test]
    fn the_cell_search_is_kept_while_the_mesh_stands_still_and_changes_no_bit() {
        let fresh = map(MappingMethod::Kernel, false);
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
                (0..3).map(|i| particle(Vec3::new(0.05 + 0.04 * i as f64 + 0.003 * step as f64, 0.1 + 0.01 * step as f64, 0.01), 0.01)).collect();
            let load = load(&particles);
            let (mut kept, mut afresh) = (CellLoad::default(), CellLoad::default());
            keeping.deposit_with(&mut cache, &mesh, &particles, &load, &mut kept);
            fresh.deposit(&mesh, &particles, &load, &mut afresh);
            let bits = |c: &CellLoad| {
                let mut b: Vec<u64> = c.particle_fraction.iter().chain(&c.implicit_drag).map(|v| v.to_bits()).collect();
                b.extend(c.explicit_force.iter().flat_map(|f| f.iter().map(|v| v.to_bits()).collect::<Vec<_>>()));
                b
            };
            assert_eq!(bits(&kept), bits(&afresh), "step {step}: the bits of a fresh binning");
            let search = cache.searches.last().expect("a kept search");
            assert!(same_bits(&search.points, &mesh.points), "step {step}: binned from the mesh as it stands");
            let storage = search.points.as_ptr();
            match step {
                0 => kept_storage = Some(storage),
                1 | 2 => assert_eq!(Some(storage), kept_storage, "step {step}: the same search, not binned again"),
                _ => assert_ne!(Some(storage), kept_storage, "the mesh moved: binned again"),
            }
        }
    }

    /// Searches of two radii (the diffusion method's deposit and sample) are both kept; a third
    /// radius replaces the one kept longest.
    #[test]
    fn two_radii_are_kept_side_by_side() {
        let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(0.2, 0.3, 0.02), [20, 30, 1])).unwrap();
        let mut cache = StencilCache::default();
        let storage = |cache: &mut StencilCache, radius: f64| {
            let kept = cache.take_search(&mesh, radius);
            let at = kept.points.as_ptr();
            cache.keep_search(kept);
            at
        };
        let (narrow, wide) = (storage(&mut cache, 0.007), storage(&mut cache, 0.09));
        assert_eq!(storage(&mut cache, 0.007), narrow);
        assert_eq!(storage(&mut cache, 0.09), wide);
        storage(&mut cache, 0.03);
        assert_eq!(storage(&mut cache, 0.09), wide, "kept: used last but one");
        let radii: Vec<f64> = cache.searches.iter().map(|k| f64::from_bits(k.radius)).collect();
        assert_eq!(radii, [0.03, 0.09], "the narrow one replaced by the third radius");
    }
}
