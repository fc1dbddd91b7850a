//! The pairs that may touch: a half neighbour list with a skin, found over a sorted cell
//! list, with each pair's contact history kept beside it (flat tables, no map lookups in the
//! sub-steps).
//!
//! A pair is listed when its gap is below the skin at the build; it is rebuilt once some
//! particle has moved more than half the skin, so no pair can come into contact unlisted.
//! Cells are as wide as the largest diameter plus the skin, so listed pairs lie in the same or
//! an adjacent cell whatever the size distribution.

use std::collections::HashMap;

use spillage_model::closure::contact::PairConstants;
use spillage_model::particles::state::Vec3;
use spillage_model::particles::ContactRecord;

use super::arrays::ParticleArrays;
pub use super::segments::Segments;
use crate::team::{DisjointSlices, Team};
use build::{BuildPiece, ConstantsKey};

mod build;

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
    /// The particles' internal indices in ascending id.
    by_id: Vec<u32>,
    /// The last build's pieces (buffers kept from build to build).
    pieces: Vec<BuildPiece>,
    /// Where each piece's pairs begin in the list (and the list's end).
    offsets: Vec<usize>,
    /// The list's constants by key (a buffer kept from build to build).
    interned: HashMap<ConstantsKey, u32>,
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

    /// The unit normal from a to b at the current positions, as the pair evaluation computes it.
    #[inline]
    pub fn normal(arrays: &ParticleArrays, pair: &Pair) -> Vec3 {
        let offset = arrays.position[pair.b as usize] - arrays.position[pair.a as usize];
        offset / offset.norm()
    }

    /// Brings each touching pair's record up to date: its tangential overlap from `touch`, its
    /// normal from the positions of the last evaluation (call after a sub-step's second half,
    /// which moves no particle). In pieces of [`PAIR_PIECE`] pairs on `team`.
    pub fn sync_records(&mut self, arrays: &ParticleArrays, team: &Team) {
        let (pairs, touch, len) = (&self.pairs, &self.touch, self.records.len());
        let records = DisjointSlices::new(&mut self.records);
        team.run(len.div_ceil(PAIR_PIECE), &|p| {
            let range = p * PAIR_PIECE..len.min((p + 1) * PAIR_PIECE);
            // SAFETY: piece p's own range of the records
            let records = unsafe { records.range(range.clone()) };
            for ((record, touch), pair) in records.iter_mut().zip(&touch[range.clone()]).zip(&pairs[range]) {
                if let Some(record) = record {
                    record.tangential_overlap = touch.tangential_overlap;
                    record.normal = Self::normal(arrays, pair);
                }
            }
        });
    }

    /// What the touching pairs of the last evaluation add up to (measured when it was asked
    /// for their energies), for the energy guard: summed in pieces of [`PAIR_PIECE`] pairs on
    /// `team` and the pieces' sums added in piece order, the same bits on any number of
    /// threads (a sum over the whole list in one loop differs in its last bits: only the
    /// guard's margin reads them). `pieces` is a buffer kept between calls (no sub-step
    /// allocates).
    pub fn touching_totals(&self, radius: &[f64], pieces: &mut Vec<TouchingTotals>, team: &Team) -> TouchingTotals {
        let len = self.pairs.len();
        let n_pieces = len.div_ceil(PAIR_PIECE);
        pieces.clear();
        pieces.resize(n_pieces, TouchingTotals::default());
        let sums = DisjointSlices::new(pieces);
        team.run(n_pieces, &|p| {
            let range = p * PAIR_PIECE..len.min((p + 1) * PAIR_PIECE);
            // SAFETY: piece p's own entry
            let sum = &mut unsafe { sums.range(p..p + 1) }[0];
            for ((pair, e), _) in self.pairs[range.clone()].iter().zip(&self.energy[range.clone()]).zip(&self.forces[range]).filter(|(_, f)| f.touching) {
                sum.contacts += 1;
                sum.max_overlap_ratio = sum.max_overlap_ratio.max(e.overlap / radius[pair.a as usize]);
                sum.elastic += e.elastic;
                sum.placed += e.placed;
            }
        });
        pieces.iter().fold(TouchingTotals::default(), |total, piece| TouchingTotals {
            contacts: total.contacts + piece.contacts,
            max_overlap_ratio: total.max_overlap_ratio.max(piece.max_overlap_ratio),
            elastic: total.elastic + piece.elastic,
            placed: total.placed + piece.placed,
        })
    }
}

/// Pairs per piece of the passes over the list's pairs run on a team (a build's pieces are
/// particles, [`build`]).
const PAIR_PIECE: usize = 4096;

/// The touching pairs' totals ([`NeighbourList::touching_totals`]): how many, the largest
/// overlap over the radius of side a, the stored elastic energy and the part of fed
/// particles' first touches [J].
#[derive(Clone, Copy, Debug, Default)]
pub struct TouchingTotals {
    pub contacts: usize,
    pub max_overlap_ratio: f64,
    pub elastic: f64,
    pub placed: f64,
}
