//! The pairs that may touch: a half neighbour list with a skin, found over a sorted cell
//! list, with each pair's contact history kept in its slot (a flat table, no map lookups in
//! the sub-steps).
//!
//! A pair is listed when its gap is below the skin at the build; it is rebuilt once some
//! particle has moved more than half the skin, so no pair can come into contact unlisted.
//! Cells are as wide as the largest diameter plus the skin, so listed pairs lie in the same or
//! an adjacent cell whatever the size distribution.

use rayon::prelude::*;

use spillage_model::closure::contact::PairConstants;
use spillage_model::particles::materials::MaterialTable;
use spillage_model::particles::state::Vec3;
use spillage_model::particles::{ContactRecord, Partner};

use super::arrays::{Grid, ParticleArrays};

/// One listed pair and what its last evaluation found besides the forces. `a` has the smaller
/// id (the side the history is kept on, as in the reference).
#[derive(Clone, Debug)]
pub struct PairSlot {
    pub a: u32,
    pub b: u32,
    pub constants: PairConstants,
    /// The contact's history; `Some` while the pair touches.
    pub record: Option<ContactRecord>,
    pub overlap: f64,
    /// Stored elastic energy, and the part of a first touch of a fed particle [J].
    pub elastic: f64,
    pub placed: f64,
    /// The evaluation found a fault ([`spillage_model::particles::guards::pair_fault`]).
    pub fault: bool,
}

/// The forces of a slot's last evaluation, apart from the rest so the per-particle sums read
/// little memory: force on a (b's is `−force`), torques on a and b.
#[derive(Clone, Copy, Debug, Default)]
pub struct PairForce {
    pub touching: bool,
    pub force: Vec3,
    pub torque_a: Vec3,
    pub torque_b: Vec3,
}

/// Where a new list takes the histories of its pairs from.
#[derive(Clone, Copy)]
pub enum History<'a> {
    /// The state's records (sorted by particle id, then partner).
    Records(&'a [ContactRecord]),
    /// The previous list (same internal particle order).
    Previous,
}

#[derive(Default)]
pub struct NeighbourList {
    /// Gap below which a pair is listed [m].
    pub skin: f64,
    pub slots: Vec<PairSlot>,
    /// The forces of each slot (same index).
    pub forces: Vec<PairForce>,
    /// Slots of the pairs whose lower internal index is k: `first[k]..first[k + 1]`.
    first: Vec<usize>,
    /// Each particle's slots in ascending partner id (the reference's order of summation):
    /// `(slot, particle is the pair's a)`.
    pub adjacency: Vec<(u32, bool)>,
    pub adjacency_start: Vec<usize>,
    /// Positions at the last build.
    built_at: Vec<Vec3>,
    previous_slots: Vec<PairSlot>,
    previous_first: Vec<usize>,
    /// (cell key, internal index), sorted.
    sorted_cells: Vec<(u64, u32)>,
}

impl NeighbourList {
    /// Positions at the last build (the drift measures the displacement since).
    pub fn built_at(&self) -> &[Vec3] {
        &self.built_at
    }

    /// True when a particle moved more than half the skin since the last build
    /// (`max_displacement_sq`: the largest squared displacement, NaN if unknown) or the list
    /// was never built for these particles.
    pub fn is_stale(&self, arrays: &ParticleArrays, max_displacement_sq: f64) -> bool {
        let half = 0.5 * self.skin;
        self.built_at.len() != arrays.len() || !(max_displacement_sq <= half * half)
    }

    /// Lists every pair with a gap below the skin at the current positions.
    pub fn build(&mut self, arrays: &ParticleArrays, materials: &MaterialTable, history: History) {
        let n = arrays.len();
        let d_max = arrays.diameter.iter().copied().fold(0.0, f64::max);
        let grid = Grid::spanning(arrays.position.iter().copied(), d_max + self.skin);
        self.sorted_cells.clear();
        self.sorted_cells.extend(arrays.position.iter().enumerate().map(|(k, p)| (grid.key(grid.cell_of(*p)), k as u32)));
        self.sorted_cells.sort_unstable();

        std::mem::swap(&mut self.slots, &mut self.previous_slots);
        std::mem::swap(&mut self.first, &mut self.previous_first);
        let (cells, skin) = (&self.sorted_cells, self.skin);
        let (previous_slots, previous_first) = (&self.previous_slots, &self.previous_first);
        self.slots.clear();
        self.slots.par_extend((0..n).into_par_iter().with_min_len(256).flat_map_iter(|k| {
            let mut found = Vec::new();
            for_each_partner(&grid, cells, arrays, skin, k, |j| found.push(j));
            found.into_iter().map(move |j| {
                let (a, b) = if arrays.id[k] < arrays.id[j] { (k, j) } else { (j, k) };
                let record = match history {
                    History::Records(records) => {
                        let key = (arrays.id[a], Partner::Particle(arrays.id[b]));
                        records.binary_search_by(|r| (r.particle, r.partner).cmp(&key)).ok().map(|i| records[i].clone())
                    }
                    History::Previous if previous_first.len() == n + 1 => previous_slots[previous_first[k]..previous_first[k + 1]]
                        .iter()
                        .find(|s| s.a as usize == a && s.b as usize == b)
                        .and_then(|s| s.record.clone()),
                    History::Previous => None,
                };
                PairSlot {
                    a: a as u32,
                    b: b as u32,
                    constants: materials.constants(arrays.material[a], arrays.material[b], arrays.radius[a], arrays.radius[b], arrays.mass[a], arrays.mass[b]),
                    record,
                    overlap: 0.0,
                    elastic: 0.0,
                    placed: 0.0,
                    fault: false,
                }
            })
        }));
        // the slots come grouped by their lower internal index k (the search's order)
        self.first.clear();
        self.first.resize(n + 1, 0);
        for slot in &self.slots {
            self.first[slot.a.min(slot.b) as usize + 1] += 1;
        }
        for k in 0..n {
            self.first[k + 1] += self.first[k];
        }
        self.forces.clear();
        self.forces.resize(self.slots.len(), PairForce::default());
        self.build_adjacency(arrays);
        self.built_at.clear();
        self.built_at.extend_from_slice(&arrays.position);
    }

    fn build_adjacency(&mut self, arrays: &ParticleArrays) {
        let n = arrays.len();
        self.adjacency_start.clear();
        self.adjacency_start.resize(n + 1, 0);
        for s in &self.slots {
            self.adjacency_start[s.a as usize + 1] += 1;
            self.adjacency_start[s.b as usize + 1] += 1;
        }
        for k in 0..n {
            self.adjacency_start[k + 1] += self.adjacency_start[k];
        }
        self.adjacency.clear();
        self.adjacency.resize(self.adjacency_start[n], (0, false));
        let mut next = self.adjacency_start.clone();
        for (i, s) in self.slots.iter().enumerate() {
            for (k, is_a) in [(s.a as usize, true), (s.b as usize, false)] {
                self.adjacency[next[k]] = (i as u32, is_a);
                next[k] += 1;
            }
        }
        let slots = &self.slots;
        let partner = |&(slot, is_a): &(u32, bool)| {
            let s = &slots[slot as usize];
            arrays.id[if is_a { s.b } else { s.a } as usize]
        };
        for k in 0..n {
            self.adjacency[self.adjacency_start[k]..self.adjacency_start[k + 1]].sort_unstable_by_key(partner);
        }
    }
}

/// Calls `found(j)` for every particle j > k (internal order) whose gap to k is below `skin`.
fn for_each_partner(grid: &Grid, cells: &[(u64, u32)], arrays: &ParticleArrays, skin: f64, k: usize, mut found: impl FnMut(usize)) {
    let (x, r) = (arrays.position[k], arrays.radius[k]);
    let [cx, cy, cz] = grid.cell_of(x);
    for z in cz - 1..=cz + 1 {
        for y in cy - 1..=cy + 1 {
            // the three cells x − 1 … x + 1 of this row are one range of keys
            let (lo, hi) = (grid.key([cx - 1, y, z]), grid.key([cx + 1, y, z]));
            let start = cells.partition_point(|c| c.0 < lo);
            for &(key, j) in &cells[start..] {
                if key > hi {
                    break;
                }
                let j = j as usize;
                if j > k && (arrays.position[j] - x).norm() < r + arrays.radius[j] + skin {
                    found(j);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use spillage_model::closure::contact::SlipTest;
    use spillage_model::particles::random::SplitMix64;
    use spillage_model::particles::settings::MaterialSection;
    use spillage_model::particles::Particle;

    fn rock() -> MaterialTable {
        let m =
            MaterialSection { name: "rock".into(), density: 2650.0, youngs_modulus: 1e7, poisson_ratio: 0.3, softening: 1.0, restitution: 0.5, friction: 0.3 };
        MaterialTable::new(&[m], SlipTest::Thesis)
    }

    fn cloud(n: usize, seed: u64, spread: f64) -> Vec<Particle> {
        let mut random = SplitMix64::new(seed);
        (0..n as u64)
            .map(|id| Particle {
                id,
                material: 0,
                diameter: random.uniform(0.01, 0.1),
                density: 2650.0,
                position: Vec3::new(random.uniform(-spread, spread), random.uniform(-spread, spread), random.uniform(-spread, spread)),
                velocity: Vec3::zeros(),
                spin: Vec3::zeros(),
                contact_force: Vec3::zeros(),
                contact_torque: Vec3::zeros(),
                contacts: 0,
            })
            .collect()
    }

    /// The list holds exactly the pairs whose gap is below the skin (all-pairs search), each
    /// once, with the smaller id as `a`, for a tenfold size range; and each particle's
    /// adjacency is in ascending partner id.
    #[test]
    fn the_list_holds_exactly_the_pairs_within_the_skin() {
        let particles = cloud(400, 11, 0.3);
        let mut arrays = ParticleArrays::default();
        let skin = 0.01;
        arrays.load(&particles, 0.1 + skin);
        let mut list = NeighbourList { skin, ..Default::default() };
        list.build(&arrays, &rock(), History::Records(&[]));
        let mut listed: Vec<(u64, u64)> = list.slots.iter().map(|s| (arrays.id[s.a as usize], arrays.id[s.b as usize])).collect();
        assert!(listed.iter().all(|(a, b)| a < b));
        listed.sort_unstable();
        let mut brute = Vec::new();
        for (i, p) in particles.iter().enumerate() {
            for q in &particles[i + 1..] {
                if (q.position - p.position).norm() < p.radius() + q.radius() + skin {
                    brute.push((p.id, q.id));
                }
            }
        }
        assert!(brute.len() > 100, "{} pairs: the test needs a dense cloud", brute.len());
        assert_eq!(listed, brute);
        for k in 0..arrays.len() {
            let row = &list.adjacency[list.adjacency_start[k]..list.adjacency_start[k + 1]];
            let partners: Vec<u64> =
                row.iter().map(|&(s, is_a)| arrays.id[if is_a { list.slots[s as usize].b } else { list.slots[s as usize].a } as usize]).collect();
            assert!(partners.windows(2).all(|w| w[0] < w[1]), "particle {}: partners {partners:?}", arrays.id[k]);
        }
    }

    /// A particle flung kilometres away or to a non-finite position neither panics the cell
    /// grid nor hides the pairs of the others.
    #[test]
    fn far_and_non_finite_particles_do_not_break_the_grid() {
        let mut particles = cloud(200, 3, 0.2);
        particles[0].position = Vec3::new(5e3, -2e3, 1e4);
        particles[1].position = Vec3::new(f64::NAN, 0.0, 0.0);
        particles[2].position = Vec3::new(f64::INFINITY, 0.0, 0.0);
        let mut arrays = ParticleArrays::default();
        arrays.load(&particles, 0.11);
        let mut list = NeighbourList { skin: 0.01, ..Default::default() };
        list.build(&arrays, &rock(), History::Records(&[]));
        let finite = &particles[3..];
        let mut brute = 0;
        for (i, p) in finite.iter().enumerate() {
            brute += finite[i + 1..].iter().filter(|q| (q.position - p.position).norm() < p.radius() + q.radius() + 0.01).count();
        }
        let listed = list.slots.iter().filter(|s| arrays.id[s.a as usize] >= 3 && arrays.id[s.b as usize] >= 3).count();
        assert!(brute > 20);
        assert_eq!(listed, brute);
    }
}
