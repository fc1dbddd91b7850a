//! The pairs that may touch: a half neighbour list with a skin, found over a sorted cell
//! list, with each pair's contact history kept beside it (flat tables, no map lookups in the
//! sub-steps).
//!
//! A pair is listed when its gap is below the skin at the build; it is rebuilt once some
//! particle has moved more than half the skin, so no pair can come into contact unlisted.
//! Cells are as wide as the largest diameter plus the skin, so listed pairs lie in the same or
//! an adjacent cell whatever the size distribution.

use std::collections::HashMap;

use rayon::prelude::*;

use spillage_model::closure::contact::PairConstants;
use spillage_model::particles::materials::MaterialTable;
use spillage_model::particles::state::Vec3;
use spillage_model::particles::{ContactRecord, Partner};

use super::arrays::{Grid, ParticleArrays};
pub use super::segments::Segments;

/// One listed pair: `a` has the smaller id (the side the history is kept on, as in the
/// reference); `constants` indexes [`NeighbourList::constants`].
#[derive(Clone, Copy, Debug)]
pub struct Pair {
    pub a: u32,
    pub b: u32,
    pub constants: u32,
}

/// The part of a pair's contact history every sub-step reads and updates, kept apart from the
/// rest of its [`ContactRecord`] so the sub-steps stream 32 bytes per pair, not the record's
/// hundred: the pair loop is bound by memory traffic (with a flag of its own for "touching"
/// the entry took 40 bytes, a fifth more of a stream that, with the particles' arrays,
/// overflows a core's 4 MB cache in the 10⁴ bed: docs/performance.md). Laid out
/// as four f64 (`repr(C)`), which the AVX and AVX-512 kernels load at once.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub struct Touch {
    pub tangential_overlap: Vec3,
    /// α_η of the contact; NaN while the pair does not touch (has no contact record), which
    /// [`damping_ratio`](spillage_model::closure::contact::damping_ratio) never returns.
    damping_ratio: f64,
}

impl Default for Touch {
    /// Apart.
    fn default() -> Self {
        Self { tangential_overlap: Vec3::zeros(), damping_ratio: f64::NAN }
    }
}

impl Touch {
    /// A contact with this history.
    pub fn touching(tangential_overlap: Vec3, damping_ratio: f64) -> Self {
        debug_assert!(!damping_ratio.is_nan(), "a contact's damping ratio is never NaN");
        Self { tangential_overlap, damping_ratio }
    }

    /// Whether the pair touches (has a contact record).
    #[inline]
    pub fn active(&self) -> bool {
        !self.damping_ratio.is_nan()
    }

    /// α_η of a touching pair (NaN for a pair apart).
    #[inline]
    pub fn damping_ratio(&self) -> f64 {
        self.damping_ratio
    }
}

/// What the energy guard reads of a touching pair's last evaluation, measured only when asked
/// for: overlap [m], stored elastic energy, and the part of a fed particle's first touch [J].
#[derive(Clone, Copy, Debug, Default)]
pub struct PairEnergy {
    pub overlap: f64,
    pub elastic: f64,
    pub placed: f64,
}

/// The forces of a pair's last evaluation, apart from the rest so the per-particle sums read
/// little memory: force on a (b's is `−force`), torques on a and b. Laid out as nine f64, then
/// the flag (`repr(C)`), which the AVX and AVX-512 kernels store as three rows: force and torque on a four
/// doubles at a time (each over the next one's first), the torque on b three.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C)]
pub struct PairForce {
    pub force: Vec3,
    pub torque_a: Vec3,
    pub torque_b: Vec3,
    pub touching: bool,
}

const _: () = assert!(
    std::mem::offset_of!(PairForce, torque_a) == 24 && std::mem::offset_of!(PairForce, torque_b) == 48 && std::mem::offset_of!(PairForce, touching) == 72
);
const _: () = assert!(std::mem::size_of::<Touch>() == 32 && std::mem::offset_of!(Touch, damping_ratio) == 24);
// the AVX kernel reads and writes a Vec3 as three packed f64
const _: () = assert!(std::mem::size_of::<Vec3>() == 24 && std::mem::align_of::<Vec3>() == 8);

/// Where a new list takes the histories of its pairs from.
#[derive(Clone, Copy)]
pub enum History<'a> {
    /// The state's records (sorted by particle id, then partner).
    Records(&'a [ContactRecord]),
    /// The previous list (same internal particle order).
    Previous,
}

/// The listed pairs, one entry per pair in each of the parallel arrays `pairs`, `touch`,
/// `records`, `energy` and `forces`, in ascending (id of a, id of b).
#[derive(Default)]
pub struct NeighbourList {
    /// Gap below which a pair is listed [m].
    pub skin: f64,
    pub pairs: Vec<Pair>,
    /// The distinct material constants of the listed pairs (one entry for a monodisperse bed).
    pub constants: Vec<PairConstants>,
    pub touch: Vec<Touch>,
    /// Each touching pair's contact record; its tangential overlap and normal are brought up to
    /// date from `touch` and the positions by [`NeighbourList::sync_records`].
    pub records: Vec<Option<ContactRecord>>,
    pub energy: Vec<PairEnergy>,
    pub forces: Vec<PairForce>,
    /// How the pairs are split among the threads ([`Segments`]).
    pub segments: Segments,
    /// Lists built so far.
    pub builds: u64,
    /// Each segment's contributions set aside (buffers reused from sub-step to sub-step).
    pub set_aside: Vec<Vec<super::pair_forces::SetAside>>,
    /// Positions at the last build.
    built_at: Vec<Vec3>,
    previous_pairs: Vec<Pair>,
    previous_touch: Vec<Touch>,
    previous_records: Vec<Option<ContactRecord>>,
    /// (cell key, internal index), sorted.
    sorted_cells: Vec<(u64, u32)>,
    /// Where each cell key's entries begin in `sorted_cells` (and one past the last key), when
    /// the grid has few enough cells for a table; empty otherwise (binary search instead).
    key_start: Vec<u32>,
    /// Found pairs (id of a, id of b, a, b) of the last build.
    found: Vec<(u64, u64, u32, u32)>,
}

/// The key the constants of a pair depend on ([`MaterialTable::constants`]): both materials,
/// radii and masses, exactly.
type ConstantsKey = (usize, usize, u64, u64, u64, u64);

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

    /// The unit normal from a to b at the current positions, as the pair evaluation computes it.
    #[inline]
    pub fn normal(arrays: &ParticleArrays, pair: &Pair) -> Vec3 {
        let offset = arrays.position[pair.b as usize] - arrays.position[pair.a as usize];
        offset / offset.norm()
    }

    /// Brings each touching pair's record up to date: its tangential overlap from `touch`, its
    /// normal from the positions of the last evaluation (call after a sub-step's second half,
    /// which moves no particle).
    pub fn sync_records(&mut self, arrays: &ParticleArrays) {
        for ((record, touch), pair) in self.records.iter_mut().zip(&self.touch).zip(&self.pairs) {
            if let Some(record) = record {
                record.tangential_overlap = touch.tangential_overlap;
                record.normal = Self::normal(arrays, pair);
            }
        }
    }

    /// Lists every pair with a gap below the skin at the current positions.
    pub fn build(&mut self, arrays: &ParticleArrays, materials: &MaterialTable, history: History) {
        self.builds += 1;
        let n = arrays.len();
        let d_max = arrays.diameter.iter().copied().fold(0.0, f64::max);
        let grid = Grid::spanning(arrays.position.iter().copied(), d_max + self.skin);
        self.sorted_cells.clear();
        self.sorted_cells.extend(arrays.position.iter().enumerate().map(|(k, p)| (grid.key(grid.cell_of(*p)), k as u32)));
        self.sorted_cells.sort_unstable();
        // a table of where each key begins spares 9 binary searches per particle; a cloud
        // spread thin over a large box keeps the searches instead of a huge table
        self.key_start.clear();
        let keys = grid.dims.iter().product::<u64>();
        if keys <= 8 * n as u64 + 4096 {
            self.key_start.resize(keys as usize + 1, 0);
            for &(key, _) in &self.sorted_cells {
                self.key_start[key as usize + 1] += 1;
            }
            for k in 0..keys as usize {
                self.key_start[k + 1] += self.key_start[k];
            }
        }

        std::mem::swap(&mut self.pairs, &mut self.previous_pairs);
        std::mem::swap(&mut self.touch, &mut self.previous_touch);
        std::mem::swap(&mut self.records, &mut self.previous_records);
        let (cells, skin) = (CellIndex { sorted: &self.sorted_cells, key_start: &self.key_start }, self.skin);
        self.found.clear();
        // each pair as (id of a, id of b, a, b): a has the smaller id
        let pair = |k: usize, j: usize| {
            let (a, b) = if arrays.id[k] < arrays.id[j] { (k, j) } else { (j, k) };
            (arrays.id[a], arrays.id[b], a as u32, b as u32)
        };
        // one buffer per job, not per particle (the order is the sort's below)
        let per_job = (0..n).into_par_iter().with_min_len(256).fold(Vec::new, |mut found, k| {
            for_each_partner(&grid, &cells, arrays, skin, k, |j| found.push(pair(k, j)));
            found
        });
        self.found.par_extend(per_job.flatten_iter());

        // pairs in ascending (id of a, id of b): each particle meets its pairs in ascending
        // partner id, the reference's order of summation, so each pair's force can be added to
        // its particles as it is evaluated, segment by segment ([`Segments`])
        self.found.par_sort_unstable();

        // the histories are in the same order (the state's records by particle, then partner;
        // the previous list, built for these particles, by ids), so each pair's is found by
        // walking that list once beside the found pairs, not by a search per pair
        let previous_valid = self.built_at.len() == n;
        let mut sources = HistorySources { history, previous_pairs: &self.previous_pairs, previous_valid, next: 0 };
        // each pair's history, and its constants interned (a bed of one size has one entry)
        self.pairs.clear();
        self.touch.clear();
        self.records.clear();
        self.constants.clear();
        let mut interned: HashMap<ConstantsKey, u32> = HashMap::new();
        let mut last: Option<(ConstantsKey, u32)> = None;
        for &(id_a, id_b, a, b) in &self.found {
            let source = sources.find(arrays, id_a, id_b);
            let (i, j) = (a as usize, b as usize);
            let key = (
                arrays.material[i],
                arrays.material[j],
                arrays.radius[i].to_bits(),
                arrays.radius[j].to_bits(),
                arrays.mass[i].to_bits(),
                arrays.mass[j].to_bits(),
            );
            let constants = match last {
                Some((k, c)) if k == key => c,
                _ => {
                    let c = *interned.entry(key).or_insert_with(|| {
                        self.constants.push(materials.constants(
                            arrays.material[i],
                            arrays.material[j],
                            arrays.radius[i],
                            arrays.radius[j],
                            arrays.mass[i],
                            arrays.mass[j],
                        ));
                        (self.constants.len() - 1) as u32
                    });
                    last = Some((key, c));
                    c
                }
            };
            self.pairs.push(Pair { a, b, constants });
            let (record, touch) = match (history, source) {
                (History::Records(records), Some(r)) => {
                    let r = &records[r];
                    (Some(r.clone()), Touch::touching(r.tangential_overlap, r.damping_ratio))
                }
                (History::Previous, Some(p)) => (self.previous_records[p].clone(), self.previous_touch[p]),
                _ => (None, Touch::default()),
            };
            self.records.push(record);
            self.touch.push(touch);
        }
        self.forces.clear();
        self.forces.resize(self.pairs.len(), PairForce::default());
        self.energy.clear();
        self.energy.resize(self.pairs.len(), PairEnergy::default());
        self.segments.plan(&self.pairs, &self.touch, n, rayon::current_num_threads());
        self.built_at.clear();
        self.built_at.extend_from_slice(&arrays.position);
    }
}

/// Where a new list's pairs find their histories, visited in ascending (id of a, id of b).
struct HistorySources<'a> {
    history: History<'a>,
    previous_pairs: &'a [Pair],
    /// The previous list was built for these particles.
    previous_valid: bool,
    /// The first entry not yet passed.
    next: usize,
}

impl HistorySources<'_> {
    /// The index of the pair (id_a, id_b)'s history in the state's records or the previous
    /// list, if it has one; the pairs are asked for in ascending ids.
    fn find(&mut self, arrays: &ParticleArrays, id_a: u64, id_b: u64) -> Option<usize> {
        match self.history {
            History::Records(records) => {
                let key = (id_a, Partner::Particle(id_b));
                while self.next < records.len() && (records[self.next].particle, records[self.next].partner) < key {
                    self.next += 1;
                }
                records.get(self.next).filter(|r| (r.particle, r.partner) == key).map(|_| self.next)
            }
            History::Previous if self.previous_valid => {
                let ids = |p: &Pair| (arrays.id[p.a as usize], arrays.id[p.b as usize]);
                let pairs = self.previous_pairs;
                while self.next < pairs.len() && ids(&pairs[self.next]) < (id_a, id_b) {
                    self.next += 1;
                }
                pairs.get(self.next).filter(|p| ids(p) == (id_a, id_b)).map(|_| self.next)
            }
            History::Previous => None,
        }
    }
}

/// The particles by cell: (key, internal index) sorted, and where each key begins when there is
/// a table.
struct CellIndex<'a> {
    sorted: &'a [(u64, u32)],
    key_start: &'a [u32],
}

impl CellIndex<'_> {
    /// The entries with keys `lo..=hi`.
    fn range(&self, lo: u64, hi: u64) -> &[(u64, u32)] {
        if self.key_start.is_empty() {
            let start = self.sorted.partition_point(|c| c.0 < lo);
            let end = start + self.sorted[start..].partition_point(|c| c.0 <= hi);
            &self.sorted[start..end]
        } else {
            &self.sorted[self.key_start[lo as usize] as usize..self.key_start[hi as usize + 1] as usize]
        }
    }
}

/// Calls `found(j)` for every particle j > k (internal order) whose gap to k is below `skin`.
fn for_each_partner(grid: &Grid, cells: &CellIndex, arrays: &ParticleArrays, skin: f64, k: usize, mut found: impl FnMut(usize)) {
    let (x, r) = (arrays.position[k], arrays.radius[k]);
    let [cx, cy, cz] = grid.cell_of(x);
    for z in cz - 1..=cz + 1 {
        for y in cy - 1..=cy + 1 {
            // the three cells x − 1 … x + 1 of this row are one range of keys
            for &(_, j) in cells.range(grid.key([cx - 1, y, z]), grid.key([cx + 1, y, z])) {
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
    use crate::dem::pair_lanes::WIDEST_GROUP;
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
    /// once, with the smaller id as `a`, in ascending ids, for a tenfold size range; and each
    /// particle's first segment is the first that holds one of its pairs.
    #[test]
    fn the_list_holds_exactly_the_pairs_within_the_skin() {
        let particles = cloud(400, 11, 0.3);
        let mut arrays = ParticleArrays::default();
        let skin = 0.01;
        arrays.load(&particles, 0.1 + skin);
        let mut list = NeighbourList { skin, ..Default::default() };
        list.build(&arrays, &rock(), History::Records(&[]));
        let mut listed: Vec<(u64, u64)> = list.pairs.iter().map(|s| (arrays.id[s.a as usize], arrays.id[s.b as usize])).collect();
        assert!(listed.iter().all(|(a, b)| a < b));
        // in ascending (id of a, id of b): the one-thread evaluation adds the pairs in this order
        assert!(listed.windows(2).all(|w| w[0] < w[1]), "pairs out of id order");
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
        // each particle's first segment is the first that holds one of its pairs
        list.segments.plan_with(&list.pairs, arrays.len(), 3, 4, |_| 1.0);
        let bounds = &list.segments.bounds;
        assert!(
            bounds.len() == 4 && bounds[1..3].iter().all(|b| b % WIDEST_GROUP == 0) && bounds.windows(2).all(|w| w[0] < w[1]),
            "three segments of whole groups: {bounds:?}"
        );
        for k in 0..arrays.len() {
            let first = bounds.windows(2).position(|w| list.pairs[w[0]..w[1]].iter().any(|s| s.a as usize == k || s.b as usize == k));
            assert_eq!(list.segments.first[k], first.map_or(u32::MAX, |s| s as u32), "particle {k}");
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
        let listed = list.pairs.iter().filter(|s| arrays.id[s.a as usize] >= 3 && arrays.id[s.b as usize] >= 3).count();
        assert!(brute > 20);
        assert_eq!(listed, brute);
    }
}
