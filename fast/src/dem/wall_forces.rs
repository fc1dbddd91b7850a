//! Particle–wall contacts of one sub-step (fluid-dem-model.md §7.4, §7.8), per particle in
//! parallel. Each particle keeps, per wall, the triangles near it in the wall's body frame
//! (from the wall's bounding-volume hierarchy: closer than its radius plus the neighbour list's
//! skin) and queries the hierarchy again only when it has moved more than the skin relative to
//! the wall; the
//! contacts among those triangles are exactly those of the whole mesh
//! ([`WallMesh::sphere_contacts_among`]).

use std::cell::RefCell;

use spillage_model::closure::contact::{hertz_mindlin_force, PairConstants};
use spillage_model::particles::first_touch::{continued_wall_contact, impact, wall_record};
use spillage_model::particles::guards::{wall_fault, Fault, MAX_OVERLAP_RATIO};
use spillage_model::particles::materials::MaterialTable;
use spillage_model::particles::state::Vec3;
use spillage_model::particles::{ContactRecord, ImpactRecord, Partner};
use spillage_model::walls::geometry::{ContactScratch, WallMesh};
use spillage_model::walls::state::{Wall, WallFrame};
use spillage_model::wear::sliding::sliding_impact;

use super::arrays::ParticleProperties;
use super::integrate::BeforeMove;

/// The triangles of one wall near one particle.
#[derive(Clone, Debug, Default)]
pub struct NearTriangles {
    /// Body-frame centre of the particle when they were found.
    centre: Vec3,
    /// World centre of the particle when they were found, and the wall's pose then
    /// ([`WallContext::poses`]): while the wall keeps that pose, a particle far from it is
    /// followed in the world frame, without moving to the body frame.
    world: Vec3,
    pose: u64,
    /// The wall mesh generation they were found in (0: never).
    generation: u64,
    /// Body-frame centre of the particle at this sub-step.
    body: Vec3,
    triangles: Vec<u32>,
}

/// Where a particle was when every wall, each unmoved since, was last looked at from there and
/// none had a triangle near it: until a wall moves or is rebuilt (`epoch`), and while the
/// particle stays within [`STILL_WALL_REACH`] of `world`, it has no wall contact, and the pass
/// over the walls reads these 32 bytes instead of its near triangles and contact side (85 % of
/// the sub-steps of the 10⁴ settling bed's particles). Not checkpointed: it changes no result.
#[derive(Clone, Copy, Debug, Default)]
pub struct FarFromWalls {
    world: Vec3,
    /// [`WallContext::epoch`] when it was found; 0: not far (the epoch is at least 1).
    epoch: u64,
}

impl FarFromWalls {
    /// Whether the particle, found far from every wall in the walls' `epoch`, stays so (its
    /// [`evaluate_walls`] returns false) for as long as the neighbour list built at `built_at`
    /// lasts and no wall moves: the list lasts while no particle moves more than half the
    /// `skin` from where it was built, so a particle within 0.49 skin of where it was found far
    /// ([`within_listed_reach`]) stays within 0.99 skin of there ([`STILL_WALL_REACH`]; the 0.01
    /// skin between the two is far above the round-off of the lengths).
    pub fn stays_far_while_listed(&self, built_at: &Vec3, epoch: u64, skin: f64) -> bool {
        self.epoch == epoch && within_listed_reach(built_at, &self.world, skin)
    }
}

/// Whether `a` lies within 0.49 `skin` of `b`: how far from where its neighbour list was built
/// a particle's far mark may lie and still last the list's life
/// ([`FarFromWalls::stays_far_while_listed`]).
fn within_listed_reach(a: &Vec3, b: &Vec3, skin: f64) -> bool {
    (a - b).norm_squared() <= (0.49 * skin) * (0.49 * skin)
}

/// The squared fraction of the skin a particle far from a wall that keeps its pose may move
/// before its near triangles are looked for again: (0.99)², a margin far above the round-off
/// between world and body lengths.
const STILL_WALL_REACH: f64 = 0.99 * 0.99;

/// One particle's side of its wall contacts: what persists (the contact history) and what the
/// last evaluation found.
#[derive(Clone, Debug, Default)]
pub struct WallSide {
    /// The contact history with every wall, in the reference's order (wall, then contact).
    pub history: Vec<ContactRecord>,
    /// Impacts of contacts that began at the last evaluation (and sliding wear's equivalent
    /// impacts), logged into its block's list ([`BlockWalls::impacts`]).
    pub impacts: u32,
    pub power: f64,
    pub elastic: f64,
    pub placed: f64,
    pub contacts: u32,
    pub max_overlap_ratio: f64,
    pub fault: Option<Fault>,
    /// The contact constants of the particle against the wall material of its last wall
    /// contact (a particle's size and mass stay while it is loaded; reloading makes new sides).
    constants: Option<(usize, PairConstants)>,
}

/// What the wall evaluation reads besides the particles.
pub struct WallContext<'a> {
    pub materials: &'a MaterialTable,
    pub wet_fluid: Option<(f64, f64)>,
    /// Per wall: whether its contacts book sliding wear (`spillage_model::wear::sliding`).
    pub sliding_walls: &'a [bool],
    pub walls: &'a [Wall],
    pub meshes: &'a [WallMesh],
    /// Each wall's frame at the end of the sub-step.
    pub frames: &'a [WallFrame],
    /// Each mesh's generation (bumped when a worn wall's mesh is rebuilt).
    pub generations: &'a [u64],
    /// Each wall's pose count (bumped when its frame changes; a static wall keeps its count).
    pub poses: &'a [u64],
    /// Σ poses + Σ generations: changes whenever any wall moves or is rebuilt (both only grow).
    pub epoch: u64,
    pub skin: f64,
    pub time: f64,
    pub dt: f64,
    pub fed_from: u64,
}

/// The wall pass over one block of the particles ([`super::integrate::BLOCK`]), run particle
/// by particle by the pass that then moves them: each particle's state here is the block's
/// slice of the bed's.
pub struct BlockWalls<'a> {
    pub context: &'a WallContext<'a>,
    pub candidates: CandidateMarks<'a>,
    pub far: &'a mut [FarFromWalls],
    pub sides: &'a mut [WallSide],
    /// Whether the particle's last evaluation found a wall contact, an impact or a fault.
    pub at_wall: &'a mut [bool],
    /// Whether the particle may touch a wall while the marks hold.
    pub may_touch: &'a mut [bool],
    /// The particles' near triangles, [`WallContext::meshes`] per particle.
    pub near: &'a mut [NearTriangles],
    /// The block's first particle (internal index).
    pub start: usize,
    /// What the block's particles at a wall found, in internal order, for the step's totals
    /// (written at the end of the block's pass).
    pub found: &'a mut Vec<WallFound>,
    /// The impacts of the block's particles in this pass, in internal order (empty at the
    /// block's start; one list per block, kept from pass to pass, instead of one per particle,
    /// whose first impact would allocate in a sub-step).
    pub impacts: &'a mut Vec<ImpactRecord>,
}

/// What one particle at a wall (`at_wall`) found in a sub-step, copied from its [`WallSide`]
/// by the pass while that is still in the cache: the serial totals after the pass read these,
/// a block's in a row, instead of chasing each particle's side through memory (at 10⁵
/// spheres those cold reads made a serial stretch of every sub-step).
#[derive(Clone, Copy, Debug)]
pub struct WallFound {
    /// The particle (internal index).
    pub k: u32,
    pub contacts: u32,
    pub max_overlap_ratio: f64,
    pub elastic: f64,
    pub placed: f64,
    pub power: f64,
    /// It has a fault: the totals read its side for it.
    pub eventful: bool,
}

/// How the pass uses and makes the marks of the particles that may touch a wall (the
/// driver's `WallCandidates`).
#[derive(Clone, Copy)]
pub struct CandidateMarks<'a> {
    /// Skip the particles not marked.
    pub pick: bool,
    /// Mark the particles (the walls kept their poses for a sub-step).
    pub mark: bool,
    /// The neighbour list's build positions (internal order).
    pub built_at: &'a [Vec3],
}

impl BeforeMove for BlockWalls<'_> {
    /// Returns at once for a particle not marked as a candidate (most of a bed's), without the
    /// cost of a call; the others are looked at out of line.
    #[inline(always)]
    fn before_move(
        &mut self,
        j: usize,
        k: usize,
        properties: &ParticleProperties,
        position: &Vec3,
        velocity: &Vec3,
        spin: &Vec3,
        force: &mut Vec3,
        torque: &mut Vec3,
        count: &mut u32,
    ) {
        self.prefetch_ahead(j);
        if self.candidates.pick && !self.may_touch[j] {
            return;
        }
        self.look_at_walls(j, k, properties, position, velocity, spin, force, torque, count);
    }

    /// The block's particles at a wall, in order, into `found`.
    fn after_block(&mut self) {
        self.found.clear();
        for (j, _) in self.at_wall.iter().enumerate().filter(|(_, at)| **at) {
            let side = &self.sides[j];
            self.found.push(WallFound {
                k: (self.start + j) as u32,
                contacts: side.contacts,
                max_overlap_ratio: side.max_overlap_ratio,
                elastic: side.elastic,
                placed: side.placed,
                power: side.power,
                eventful: side.fault.is_some(),
            });
        }
    }
}

/// How many particles ahead of the one it moves the pass asks for the wall state of the next
/// ones it will look at ([`BlockWalls::prefetch_ahead`]): their far marks, sides and near
/// triangles at twice this distance, the buffers these point to (contact histories, triangle
/// lists) at this distance, by when the first have arrived. A candidate's few hundred bytes of
/// wall state lie scattered beyond the caches after a sub-step's pairs; waiting on them took
/// most of the wall pass's time (prefetched, a 10⁴ bed's one-thread run took 7 % less, median
/// of 16 interleaved pairs). A prefetch changes no value.
const PREFETCH_DISTANCE: usize = 4;

/// Asks the processor to bring the cache line at `p` near: a hint, which never faults and
/// changes nothing the program sees.
#[inline(always)]
fn prefetch<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch reads nothing the program sees and never faults, whatever the address
    unsafe {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        _mm_prefetch::<_MM_HINT_T0>(p.cast::<i8>());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

impl BlockWalls<'_> {
    /// Prefetches the wall state of the particles [`PREFETCH_DISTANCE`] and twice that ahead of
    /// particle `j` that the pass will look at.
    #[inline(always)]
    fn prefetch_ahead(&self, j: usize) {
        let n_walls = self.context.meshes.len();
        let looked_at = |i: usize| i < self.far.len() && (!self.candidates.pick || self.may_touch[i]);
        let two_ahead = j + 2 * PREFETCH_DISTANCE;
        if looked_at(two_ahead) {
            prefetch(&self.far[two_ahead]);
            let side: *const WallSide = &self.sides[two_ahead];
            prefetch(side);
            prefetch(side.cast::<u8>().wrapping_add(64));
            for near in &self.near[two_ahead * n_walls..(two_ahead + 1) * n_walls] {
                prefetch(near);
            }
        }
        let one_ahead = j + PREFETCH_DISTANCE;
        if looked_at(one_ahead) {
            // an empty buffer's pointer is a placeholder: nothing to bring
            let history = &self.sides[one_ahead].history;
            if !history.is_empty() {
                prefetch(history.as_ptr());
            }
            for near in &self.near[one_ahead * n_walls..(one_ahead + 1) * n_walls] {
                if !near.triangles.is_empty() {
                    prefetch(near.triangles.as_ptr());
                }
            }
        }
    }

    /// [`BeforeMove::before_move`] for a particle that may touch a wall.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn look_at_walls(
        &mut self,
        j: usize,
        k: usize,
        properties: &ParticleProperties,
        position: &Vec3,
        velocity: &Vec3,
        spin: &Vec3,
        force: &mut Vec3,
        torque: &mut Vec3,
        count: &mut u32,
    ) {
        let CandidateMarks { mark, built_at, .. } = self.candidates;
        let n_walls = self.context.meshes.len();
        let near = &mut self.near[j * n_walls..(j + 1) * n_walls];
        let (far, side) = (&mut self.far[j], &mut self.sides[j]);
        let particle = WallParticle { k, position: *position, velocity: *velocity, spin: *spin, properties: *properties };
        let skin = self.context.skin;
        if mark
            && within_listed_reach(position, &built_at[k], skin)
            && far.epoch == self.context.epoch
            && !far.stays_far_while_listed(&built_at[k], self.context.epoch, skin)
        {
            // found far from every wall before the list was built, and too far from where the
            // list was built for the mark to last the list's life, while the particle itself is
            // near there: looked at afresh from here (every wall queried again), it is marked
            // far from here and skipped until the next list, instead of being looked at in
            // every sub-step (in the 10⁴ bed 5.0e6 looks in 1000 sub-steps became 1.6e6, the
            // same bits). A fresh look finds what the old mark vouched for: no triangle within
            // the radius.
            far.epoch = 0;
            for near in near.iter_mut() {
                near.generation = 0;
            }
        }
        // a particle far from every wall keeps its empty side and `at_wall` false
        if evaluate_walls(&particle, self.context, far, near, side, self.impacts, force, torque) {
            *count += side.contacts;
            self.at_wall[j] = side.contacts > 0 || side.fault.is_some() || side.impacts > 0;
        }
        if mark {
            self.may_touch[j] = !far.stays_far_while_listed(&built_at[k], self.context.epoch, skin);
        }
    }
}

/// Per-thread work buffers (reused across sub-steps: nothing is allocated once they grew).
struct Scratch {
    contacts: ContactScratch,
    old_history: Vec<ContactRecord>,
    /// Whether each old record has been continued at this sub-step.
    continued: Vec<bool>,
}

/// Room the per-thread buffers start with: candidate triangles and wall contacts of one
/// particle. A particle in a box's corner has three contacts among some twenty triangles; with
/// this room a thread that steals a block of particles busier than any it met before (which
/// depends on timing) still allocates nothing.
const SCRATCH_ROOM: usize = 64;

impl Scratch {
    fn new() -> Self {
        Self {
            contacts: ContactScratch::with_capacity(SCRATCH_ROOM),
            old_history: Vec::with_capacity(SCRATCH_ROOM),
            continued: Vec::with_capacity(SCRATCH_ROOM),
        }
    }
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::new());
}

/// A particle whose wall contacts are evaluated: its internal index, where it is and how it
/// moves at the sub-step's end (read from its block before the pass moves it on), and what it is.
pub struct WallParticle<'a> {
    pub k: usize,
    pub position: Vec3,
    pub velocity: Vec3,
    pub spin: Vec3,
    pub properties: ParticleProperties<'a>,
}

impl WallParticle<'_> {
    /// As the shared model functions take it (first touches, faults).
    fn particle(&self) -> spillage_model::particles::Particle {
        self.properties.particle(self.k, self.position, self.velocity, self.spin)
    }
}

/// Evaluates `particle`'s wall contacts into `side`, its impacts onto `impacts`, adding their
/// force and torque to `force` and `torque` (in the reference's order: wall by wall, contact by
/// contact). `near`
/// holds the particle's near triangles of each wall (kept in one flat array for all particles:
/// a pointer per particle to chase cost a third of the walls' time).
///
/// Returns false, touching neither `near` nor `side`, when `far` shows the particle far from
/// every wall: `side` then still holds the empty result of the evaluation that found it far.
#[allow(clippy::too_many_arguments)]
pub fn evaluate_walls(
    particle: &WallParticle,
    context: &WallContext,
    far: &mut FarFromWalls,
    near: &mut [NearTriangles],
    side: &mut WallSide,
    impacts: &mut Vec<ImpactRecord>,
    force: &mut Vec3,
    torque: &mut Vec3,
) -> bool {
    let reach_sq = STILL_WALL_REACH * context.skin * context.skin;
    if far.epoch == context.epoch && (particle.position - far.world).norm_squared() <= reach_sq {
        return false;
    }
    far.epoch = 0;
    side.impacts = 0;
    (side.power, side.elastic, side.placed, side.contacts, side.max_overlap_ratio, side.fault) = (0.0, 0.0, 0.0, 0, 0.0, None);
    let (k, properties) = (particle.k, &particle.properties);
    let (id, r, x) = (properties.id[k], properties.radius[k], particle.position);
    let fed = id >= context.fed_from;
    // most particles are far from every wall: find that out without touching the buffers
    let mut near_any = false;
    for (w, (near, mesh)) in near.iter_mut().zip(context.meshes).enumerate() {
        let same_pose = near.pose == context.poses[w] && near.generation == context.generations[w];
        // a rigid map keeps lengths (to round-off, which the 1 % margin covers): nothing came
        // within reach of a particle that has no near triangle and moved less than the skin
        if same_pose && near.triangles.is_empty() && (x - near.world).norm_squared() <= reach_sq {
            continue;
        }
        near.body = context.frames[w].to_body(x);
        if near.generation != context.generations[w] || !((near.body - near.centre).norm() <= context.skin) {
            mesh.triangles_within(near.body, r + context.skin, &mut near.triangles);
            (near.centre, near.generation) = (near.body, context.generations[w]);
            (near.world, near.pose) = (x, context.poses[w]);
        }
        near_any |= !near.triangles.is_empty();
    }
    if !near_any {
        side.history.clear();
        // every wall, in its present pose and mesh, was looked at from here: the per-wall test
        // above holds for each while no wall moves and the particle stays within reach of here
        let looked_from_here = near.iter().enumerate().all(|(w, n)| n.world == x && n.pose == context.poses[w] && n.generation == context.generations[w]);
        if looked_from_here {
            *far = FarFromWalls { world: x, epoch: context.epoch };
        }
        return true;
    }
    SCRATCH.with(|scratch| {
        let scratch = &mut *scratch.borrow_mut();
        // copied, not swapped: a swap would hand the buffers round the particles, and one that
        // never touched a wall (no capacity) would make the next particle's pushes allocate
        scratch.old_history.clear();
        scratch.old_history.extend_from_slice(&side.history);
        side.history.clear();
        scratch.continued.clear();
        scratch.continued.resize(scratch.old_history.len(), false);
        for (w, (wall, mesh)) in context.walls.iter().zip(context.meshes).enumerate() {
            let frame = &context.frames[w];
            let near = &near[w];
            let body = near.body;
            if near.triangles.is_empty() {
                continue;
            }
            mesh.sphere_contacts_among(&near.triangles, body, r, &mut scratch.contacts);
            for contact in &scratch.contacts.accepted {
                let point = frame.to_world(contact.point);
                let overlap = r - contact.distance;
                if contact.distance <= 1e-12 * r || (overlap > MAX_OVERLAP_RATIO * r && !fed) {
                    let fault = wall_fault(&particle.particle(), w as u32, contact.distance, overlap, fed);
                    let on_wall = matches!(fault, Some(Fault::CentreOnWall { .. }));
                    if side.fault.is_none() {
                        side.fault = fault;
                    }
                    if on_wall {
                        continue;
                    }
                }
                let normal = (point - x) / contact.distance;
                let wall_velocity = wall.surface_velocity(point);
                let v_rel = particle.velocity + particle.spin.cross(&(r * normal)) - wall_velocity;
                let (old, continued) = (&scratch.old_history, &scratch.continued);
                let previous = old.iter().enumerate().filter(|(k, h)| h.partner == Partner::Wall(w as u32) && !continued[*k]);
                let matched = continued_wall_contact(previous, &normal);
                let new_contact = matched.is_none();
                let mut record = match matched {
                    Some(m) => {
                        scratch.continued[m] = true;
                        scratch.old_history[m].clone()
                    }
                    None => {
                        let p = particle.particle();
                        impacts.push(impact(&p, w as u32, contact, body, wall_velocity, normal, context.time));
                        side.impacts += 1;
                        wall_record(context.materials, context.wet_fluid, &p, w as u32, wall.material, normal, v_rel, context.time)
                    }
                };
                let constants = match side.constants {
                    Some((material, constants)) if material == wall.material => constants,
                    _ => {
                        let constants = context.materials.constants(properties.material[k], wall.material, r, f64::INFINITY, properties.mass[k], f64::INFINITY);
                        side.constants = Some((wall.material, constants));
                        constants
                    }
                };
                let f = hertz_mindlin_force(&constants, record.damping_ratio, normal, overlap, v_rel, &mut record.tangential_overlap, context.dt);
                record.normal = normal;
                if context.sliding_walls[w] {
                    let p = particle.particle();
                    if let Some(sliding) = sliding_impact(&mut record, &p, w as u32, contact, body, wall_velocity, normal, f.normal, context.dt, context.time) {
                        impacts.push(sliding);
                        side.impacts += 1;
                    }
                }
                let elastic = 0.4 * f.normal.norm() * overlap;
                side.elastic += elastic;
                if new_contact && fed {
                    side.placed += elastic;
                }
                side.power += (f.normal + f.tangential).dot(&wall_velocity);
                *force += f.normal + f.tangential;
                *torque += (r * normal).cross(&f.tangential);
                side.contacts += 1;
                side.max_overlap_ratio = side.max_overlap_ratio.max(overlap / r);
                side.history.push(record);
            }
        }
    });
    true
}
