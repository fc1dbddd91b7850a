//! A neighbour list's build: the pairs within the skin found over a sorted cell list, in
//! pieces of particles taken in id order, so each piece's pairs are the list's next ones, with
//! their histories and constants (the pieces run on the step's team).

use std::collections::HashMap;
use std::mem::MaybeUninit;

use spillage_model::particles::materials::MaterialTable;
use spillage_model::particles::Partner;

use super::{History, NeighbourList, Pair, PairEnergy, PairForce, Touch};
use crate::dem::arrays::{Grid, ParticleArrays};
use crate::team::{DisjointSlices, Team};

/// Particles per piece of a build (in id order).
const BUILD_PIECE: usize = 256;

/// A piece of a build: its pairs (a, b) in ascending (id of a, id of b), and the distinct
/// constants its pairs meet, in the order it first meets them.
#[derive(Default)]
pub(super) struct BuildPiece {
    found: Vec<(u32, u32)>,
    keys: Vec<ConstantsKey>,
    local: HashMap<ConstantsKey, u32>,
    /// Each of `keys`' index in the list's constants.
    global: Vec<u32>,
}

/// The key the constants of a pair depend on ([`MaterialTable::constants`]): both materials,
/// radii and masses, exactly.
pub(super) type ConstantsKey = (usize, usize, u64, u64, u64, u64);

impl NeighbourList {
    /// Lists every pair with a gap below the skin at the current positions, the pairs found,
    /// their histories taken and their arrays filled by `team`, piece by piece of
    /// [`BUILD_PIECE`] particles in id order: each piece's pairs are the list's next ones, so
    /// the list and its bits are the same on any number of threads.
    pub fn build(&mut self, arrays: &ParticleArrays, materials: &MaterialTable, history: History, team: &Team) {
        self.builds += 1;
        let n = arrays.len();
        // until the build ends the list is stale (a build cut short leaves no list that looks
        // whole)
        let previous_valid = self.built_at.len() == n;
        self.built_at.clear();
        if let History::Records(records) = history {
            debug_assert!(records.is_sorted_by_key(|r| (r.particle, r.partner)), "the state's contact history is sorted (checkpoint validation)");
        }
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
        // the particles in ascending id (kept while the particles keep their order)
        let ids = &arrays.id;
        if !(self.by_id.len() == n && self.by_id.windows(2).all(|w| ids[w[0] as usize] < ids[w[1] as usize])) {
            self.by_id.clear();
            self.by_id.extend(0..n as u32);
            self.by_id.sort_unstable_by_key(|&k| ids[k as usize]);
        }

        std::mem::swap(&mut self.pairs, &mut self.previous_pairs);
        std::mem::swap(&mut self.touch, &mut self.previous_touch);
        std::mem::swap(&mut self.records, &mut self.previous_records);
        let (cells, skin) = (CellIndex { sorted: &self.sorted_cells, key_start: &self.key_start }, self.skin);
        let n_pieces = n.div_ceil(BUILD_PIECE);
        self.pieces.resize_with(n_pieces.max(self.pieces.len()), BuildPiece::default);
        // each piece's pairs in ascending (id of a, id of b): each particle meets its pairs in
        // ascending partner id, the reference's order of summation, so each pair's force can
        // be added to its particles as it is evaluated, segment by segment ([`Segments`])
        let by_id = &self.by_id;
        let pieces = DisjointSlices::new(&mut self.pieces[..n_pieces]);
        team.run(n_pieces, &|p| {
            // SAFETY: piece p's own entry
            let found = &mut unsafe { pieces.range(p..p + 1) }[0].found;
            found.clear();
            for &a in &by_id[p * BUILD_PIECE..n.min((p + 1) * BUILD_PIECE)] {
                let first = found.len();
                for_each_partner(&grid, &cells, arrays, skin, a as usize, |b| found.push((a, b as u32)));
                found[first..].sort_unstable_by_key(|&(_, b)| ids[b as usize]);
            }
        });
        self.offsets.clear();
        self.offsets.push(0);
        for piece in &self.pieces[..n_pieces] {
            self.offsets.push(self.offsets.last().copied().unwrap_or(0) + piece.found.len());
        }
        let total = self.offsets[n_pieces];

        // the histories are in the same order (the state's records by particle, then partner;
        // the previous list, built for these particles, by ids), so each piece finds its pairs'
        // by walking that list beside its pairs from where its first pair's would be, not by a
        // search per pair; and each piece interns the constants its pairs meet
        let (previous_pairs, previous_touch, previous_records) = (&self.previous_pairs, &self.previous_touch, &self.previous_records);
        let (offsets, pieces) = (&self.offsets, DisjointSlices::new(&mut self.pieces[..n_pieces]));
        // the pieces write every entry of the list's arrays into their emptied room (filled
        // first, the records alone took a tenth of a build on one thread)
        let (pairs, touches, records) = (room(&mut self.pairs, total), room(&mut self.touch, total), room(&mut self.records, total));
        let (forces, energy) = (room(&mut self.forces, total), room(&mut self.energy, total));
        team.run(n_pieces, &|p| {
            let range = offsets[p]..offsets[p + 1];
            // SAFETY: piece p's own entry and its own range of the list's arrays
            let (piece, pairs, touches, records, forces, energy) = unsafe {
                (
                    &mut pieces.range(p..p + 1)[0],
                    pairs.range(range.clone()),
                    touches.range(range.clone()),
                    records.range(range.clone()),
                    forces.range(range.clone()),
                    energy.range(range),
                )
            };
            let BuildPiece { found, keys, local, .. } = piece;
            keys.clear();
            local.clear();
            let mut sources = HistorySources { history, previous_pairs, previous_valid, next: 0 };
            if let Some(&(a, b)) = found.first() {
                sources.start_at(arrays, ids[a as usize], ids[b as usize]);
            }
            let mut last: Option<(ConstantsKey, u32)> = None;
            for (i, &(a, b)) in found.iter().enumerate() {
                let source = sources.find(arrays, ids[a as usize], ids[b as usize]);
                let (i_a, i_b) = (a as usize, b as usize);
                let key = (
                    arrays.material[i_a],
                    arrays.material[i_b],
                    arrays.radius[i_a].to_bits(),
                    arrays.radius[i_b].to_bits(),
                    arrays.mass[i_a].to_bits(),
                    arrays.mass[i_b].to_bits(),
                );
                let constants = match last {
                    Some((k, c)) if k == key => c,
                    _ => {
                        let c = *local.entry(key).or_insert_with(|| {
                            keys.push(key);
                            (keys.len() - 1) as u32
                        });
                        last = Some((key, c));
                        c
                    }
                };
                pairs[i].write(Pair { a, b, constants });
                let (record, touch) = match (history, source) {
                    (History::Records(state_records), Some(r)) => {
                        let r = &state_records[r];
                        (Some(r.clone()), Touch::touching(r.tangential_overlap, r.damping_ratio))
                    }
                    (History::Previous, Some(s)) => (previous_records[s].clone(), previous_touch[s]),
                    _ => (None, Touch::default()),
                };
                records[i].write(record);
                touches[i].write(touch);
                forces[i].write(PairForce::default());
                energy[i].write(PairEnergy::default());
            }
        });
        // SAFETY: the pieces wrote every entry below `total` (their ranges tile it), and a
        // piece's panic returned before this through `team.run`
        unsafe {
            self.pairs.set_len(total);
            self.touch.set_len(total);
            self.records.set_len(total);
            self.forces.set_len(total);
            self.energy.set_len(total);
        }

        // the pieces' constants in the list's, in the order the list first meets them (a bed
        // of one size has one entry)
        self.constants.clear();
        self.interned.clear();
        let mut renumbered = false;
        for piece in &mut self.pieces[..n_pieces] {
            piece.global.clear();
            for &key in &piece.keys {
                let (material_a, material_b, radius_a, radius_b, mass_a, mass_b) = key;
                let global = *self.interned.entry(key).or_insert_with(|| {
                    let [radius_a, radius_b, mass_a, mass_b] = [radius_a, radius_b, mass_a, mass_b].map(f64::from_bits);
                    self.constants.push(materials.constants(material_a, material_b, radius_a, radius_b, mass_a, mass_b));
                    (self.constants.len() - 1) as u32
                });
                renumbered |= global as usize != piece.global.len();
                piece.global.push(global);
            }
        }
        if renumbered {
            let (offsets, pieces, pairs) = (&self.offsets, &self.pieces, DisjointSlices::new(&mut self.pairs));
            team.run(n_pieces, &|p| {
                // SAFETY: piece p's own range of the pairs
                for pair in unsafe { pairs.range(offsets[p]..offsets[p + 1]) } {
                    pair.constants = pieces[p].global[pair.constants as usize];
                }
            });
        }
        self.segments.plan(&self.pairs, &self.touch, n, rayon::current_num_threads());
        self.built_at.extend_from_slice(&arrays.position);
    }
}

/// `entries` emptied, with room for `total` entries to be written in place.
fn room<T>(entries: &mut Vec<T>, total: usize) -> DisjointSlices<'_, MaybeUninit<T>> {
    entries.clear();
    entries.reserve(total);
    DisjointSlices::new(&mut entries.spare_capacity_mut()[..total])
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
    /// Skips the entries before pair (id_a, id_b)'s: a piece's walk starts where its first
    /// pair's history would be (the walk from the first entry would find the same).
    fn start_at(&mut self, arrays: &ParticleArrays, id_a: u64, id_b: u64) {
        self.next = match self.history {
            History::Records(records) => records.partition_point(|r| (r.particle, r.partner) < (id_a, Partner::Particle(id_b))),
            History::Previous if self.previous_valid => {
                self.previous_pairs.partition_point(|p| (arrays.id[p.a as usize], arrays.id[p.b as usize]) < (id_a, id_b))
            }
            History::Previous => 0,
        };
    }

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

/// Calls `found(j)` for every particle j of a larger id than k's whose gap to k is below `skin`.
fn for_each_partner(grid: &Grid, cells: &CellIndex, arrays: &ParticleArrays, skin: f64, k: usize, mut found: impl FnMut(usize)) {
    let (x, r) = (arrays.position[k], arrays.radius[k]);
    let [cx, cy, cz] = grid.cell_of(x);
    for z in cz - 1..=cz + 1 {
        for y in cy - 1..=cy + 1 {
            // the three cells x − 1 … x + 1 of this row are one range of keys
            for &(_, j) in cells.range(grid.key([cx - 1, y, z]), grid.key([cx + 1, y, z])) {
                let j = j as usize;
                if arrays.id[j] > arrays.id[k] && (arrays.position[j] - x).norm() < r + arrays.radius[j] + skin {
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
    use crate::team::with_team;
    use spillage_model::closure::contact::SlipTest;
    use spillage_model::particles::random::SplitMix64;
    use spillage_model::particles::settings::MaterialSection;
    use spillage_model::particles::state::Vec3;
    use spillage_model::particles::{ContactRecord, Particle};

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
        with_team(|team| list.build(&arrays, &rock(), History::Records(&[]), team));
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

    /// A build gives the same list on one thread and on three, whichever thread runs which
    /// piece: the pairs, their constants (a cloud of many sizes, where each piece meets
    /// constants of its own and they are renumbered into the list's, in the order the list
    /// first meets them), and the histories, taken from the state's records and then, after
    /// some particles moved, from the previous list; each pair's constants and history are its
    /// own.
    #[test]
    fn a_build_is_the_same_on_any_number_of_threads() {
        let particles = cloud(1500, 5, 0.4);
        let skin = 0.01;
        // a history for every third touching pair, in the state's order
        let mut records = Vec::new();
        for (i, p) in particles.iter().enumerate() {
            for q in particles[i + 1..].iter().filter(|q| (q.position - p.position).norm() < p.radius() + q.radius()).step_by(3) {
                records.push(ContactRecord {
                    particle: p.id,
                    partner: Partner::Particle(q.id),
                    tangential_overlap: Vec3::new(1e-6 * q.id as f64, 0.0, 0.0),
                    damping_ratio: 0.1,
                    approach_speed: 0.5,
                    normal: Vec3::x(),
                    start_time: 0.0,
                    restitution: 0.5,
                    normal_impulse: 0.0,
                });
            }
        }
        records.sort_by_key(|r| (r.particle, r.partner));
        let own = |list: &NeighbourList, arrays: &ParticleArrays| {
            let mut next_new = 0;
            for (pair, record) in list.pairs.iter().zip(&list.records) {
                let (a, b) = (pair.a as usize, pair.b as usize);
                let constants = rock().constants(arrays.material[a], arrays.material[b], arrays.radius[a], arrays.radius[b], arrays.mass[a], arrays.mass[b]);
                assert_eq!(list.constants[pair.constants as usize], constants, "pair {a}-{b}'s constants");
                assert!(pair.constants <= next_new, "constants out of the order of first appearance");
                next_new += u32::from(pair.constants == next_new);
                assert!(record.as_ref().is_none_or(|r| (r.particle, r.partner) == (arrays.id[a], Partner::Particle(arrays.id[b]))));
            }
            assert_eq!(next_new as usize, list.constants.len());
            format!("{:?} {:?} {:?} {:?}", list.pairs, list.constants, list.touch, list.records)
        };
        let lists = [1, 3].map(|threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut arrays = ParticleArrays::default();
                arrays.load(&particles, 0.1 + skin);
                let mut list = NeighbourList { skin, ..Default::default() };
                with_team(|team| {
                    list.build(&arrays, &rock(), History::Records(&records), team);
                    let first = own(&list, &arrays);
                    let carried = list.records.iter().flatten().count();
                    // every seventh particle moves by half the skin: the touching pairs stay listed
                    for k in (0..arrays.len()).step_by(7) {
                        arrays.position[k].x += 0.5 * skin;
                    }
                    list.build(&arrays, &rock(), History::Previous, team);
                    assert_eq!(list.records.iter().flatten().count(), carried, "{threads} threads: the previous list's histories carried over");
                    (first, own(&list, &arrays), carried, list.constants.len())
                })
            })
        });
        let (_, _, carried, constants) = &lists[0];
        assert!(particles.len() > 5 * BUILD_PIECE && *carried == records.len() && records.len() > 100, "{carried} of {} histories", records.len());
        assert!(*constants > 1000, "{constants} constants: the cloud has many sizes");
        assert!(lists[0].0 == lists[1].0 && lists[0].1 == lists[1].1, "the lists of one and three threads differ");
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
        with_team(|team| list.build(&arrays, &rock(), History::Records(&[]), team));
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
