//! The fast DEM: the reference's soft-sphere model (Hertz–Mindlin–Tsuji contacts, triangle-mesh
//! walls, velocity-Verlet sub-steps; fluid-dem-model.md §5.7–§5.10, §7), engineered for speed
//! and held to the same bits:
//!
//! * particles as struct-of-arrays in cell order ([`arrays`]), re-sorted every outer step;
//! * a half neighbour list with a skin over a sorted cell list, contact histories beside its
//!   pairs ([`neighbour_list`]);
//! * pair forces evaluated four or eight at a time in AVX or AVX-512 lanes ([`pair_lanes`]),
//!   the list cut into one segment per thread, each pair added to its particles as it is
//!   evaluated, every particle's sum in the reference's order ([`pair_forces`]);
//! * wall contacts per particle against each wall's bounding-volume hierarchy in its body
//!   frame, the near triangles kept while the particle stays within the skin
//!   ([`wall_forces`]), evaluated by the pass that then moves the particle;
//! * the sub-step halves per particle in parallel ([`integrate`]);
//! * the parts of a sub-step run by a [`Team`] of threads kept awake for the step.
//!
//! Every sum whose order could depend on the threads is taken in a fixed order, so a run gives
//! the same bits on any number of threads.

pub mod arrays;
pub mod drag_lanes;
pub mod integrate;
pub mod neighbour_list;
pub mod pair_forces;
pub mod pair_lanes;
#[cfg(target_arch = "x86_64")]
mod pair_lanes_avx;
#[cfg(target_arch = "x86_64")]
mod pair_lanes_avx512;
pub mod segments;
#[cfg(test)]
mod substep_allocations;
pub mod wall_forces;

use spillage_model::case::Case;
use spillage_model::closure::drag::FluidAtParticle;
use spillage_model::particles::dem_setup::{DemSetup, WallMeshes};
use spillage_model::particles::guards::{EnergyBudget, Fault};
use spillage_model::particles::substeps::substeps_for;
use spillage_model::particles::{ImpactRecord, ParticleState, Partner};
use spillage_model::solver::{SolverError, StepReport};
use spillage_model::state::State;
use spillage_model::step::{ParticleLoad, ParticlePhase, StepContext};
use spillage_model::walls::state::{WallFrame, WallState};

use crate::team::{with_team, DisjointSlices, Team};
use arrays::ParticleArrays;
use integrate::{advance_particles, NothingToAdd, Pass, PassSums, StepSums, BLOCK};
use neighbour_list::{History, NeighbourList, TouchingTotals};
use pair_forces::{evaluate_and_add, first_fault, PairContext};
use wall_forces::{BlockWalls, CandidateMarks, FarFromWalls, NearTriangles, WallContext, WallFound, WallSide};

/// The neighbour-list skin as a fraction of the largest diameter: pairs closer than this gap
/// are listed, and the list lasts until a particle has moved half of it (a tenth of a diameter
/// keeps the list short in a dense bed and lasts ≈ 50 sub-steps of a 2 m/s rock at the
/// cutter head's sub-step).
const SKIN_FRACTION: f64 = 0.1;

/// Outer steps between two sorts of the particles by cell when nothing else reloads them
/// (particles that move apart in space also drift apart in memory).
const RESORT_STEPS: u64 = 20;

fn unsupported(what: impl Into<String>) -> SolverError {
    SolverError::Unsupported(what.into())
}

/// The fast DEM: a particle phase of the step driver ([`spillage_model::step::Coupled`]).
pub struct FastDem {
    setup: DemSetup,
    wall_meshes: WallMeshes,
    arrays: ParticleArrays,
    list: NeighbourList,
    /// Each particle's wall contacts, in internal order.
    wall_sides: Vec<WallSide>,
    /// Each particle's near triangles of each wall (particle-major, in internal order).
    near: Vec<NearTriangles>,
    /// Whether each particle is known to be far from every wall (internal order).
    far: Vec<FarFromWalls>,
    /// Whether the last evaluation gave each particle a wall contact, impact or fault: each
    /// block of the pass lists its own into `wall_found`, and the serial totals read only those
    /// (a dense bed has a few particles at its walls; a pass over all would bound the scaling
    /// with threads).
    at_wall: Vec<bool>,
    /// Per block of the pass ([`BLOCK`]): what its particles at a wall found in the last
    /// sub-step, in internal order (after a pair fault, which returns before the pass, still
    /// the sub-step before's, and not read).
    wall_found: Vec<Vec<WallFound>>,
    /// Per block of the pass: the impacts its particles logged in the last sub-step, in
    /// internal order (moved onto the step's log, the buffers kept).
    wall_impacts: Vec<Vec<ImpactRecord>>,
    /// Which particles the wall pass looks at while the neighbour list and every wall's pose
    /// stay as they were when it was marked ([`WallCandidates`]).
    candidates: WallCandidates,
    /// The pieces' sums of [`NeighbourList::touching_totals`] (kept: no sub-step allocates).
    touching_totals: Vec<TouchingTotals>,
    frames: Vec<WallFrame>,
    /// Each wall's pose count: bumped whenever its frame changes (from 1, so a particle's
    /// never-filled near triangles, at 0, never match).
    poses: Vec<u64>,
    sums: StepSums,
    budget: EnergyBudget,
    /// Outer steps since the particles were last loaded (and sorted), and the contact records
    /// the last step stored (both tell whether the state still holds what the arrays hold).
    steps_since_load: u64,
    stored_records: usize,
    /// The first id of the particles fed in the current step.
    fed_from: u64,
}

/// The particles that may touch a wall before the neighbour list is built again, while no
/// wall moves: the others stay far from every wall ([`FarFromWalls::stays_far_while_listed`]),
/// and the wall pass skips them without reading their memory (85 % of the 10⁴ settling bed:
/// half a megabyte less per sub-step). With walls that move at every sub-step (a turning head)
/// no marks are made and every particle is looked at, as before.
#[derive(Default)]
struct WallCandidates {
    /// Per particle (internal order): it may touch a wall.
    may_touch: Vec<bool>,
    /// The walls' epoch the marks hold for; None: not marked for the current list.
    epoch: Option<u64>,
    /// The epoch of the last wall pass (marks are made once the walls kept their poses for a
    /// sub-step).
    last_epoch: Option<u64>,
}

/// A sub-step's fault: the sub-step (from 0), its end time and what happened.
struct SubstepFault {
    substep: u64,
    time: f64,
    fault: Fault,
}

/// What the contacts of one sub-step add up to.
#[derive(Default)]
struct ContactTotals {
    contacts: usize,
    max_overlap_ratio: f64,
    elastic: f64,
    placed: f64,
    wall_power: f64,
}

impl FastDem {
    /// Sets up the DEM for `case`; missing particle or wall states in `state` are built from the
    /// case (as [`DemSetup::new`] does for both particle phases).
    pub fn new(case: &Case, state: &mut State) -> Result<Self, SolverError> {
        let setup = DemSetup::new(case, state).map_err(unsupported)?;
        let walls = state.walls.as_ref().expect("the setup builds the walls");
        Ok(Self {
            wall_meshes: WallMeshes::new(walls).map_err(unsupported)?,
            arrays: ParticleArrays::default(),
            list: NeighbourList::default(),
            wall_sides: Vec::new(),
            near: Vec::new(),
            far: Vec::new(),
            at_wall: Vec::new(),
            wall_found: Vec::new(),
            wall_impacts: Vec::new(),
            candidates: WallCandidates::default(),
            touching_totals: Vec::new(),
            frames: Vec::new(),
            poses: Vec::new(),
            sums: StepSums::default(),
            budget: EnergyBudget::default(),
            steps_since_load: 0,
            stored_records: usize::MAX,
            fed_from: state.particles.as_ref().map_or(0, |p| p.next_id),
            setup,
        })
    }

    /// Takes the particles of the state for this step: when they are the ones the last step
    /// left (no feed, exit or restart since), the arrays, the neighbour list and the near
    /// triangles carry on; otherwise, or every [`RESORT_STEPS`] steps so neighbours stay close
    /// in memory, they are loaded in cell order again.
    fn take(&mut self, particles: &ParticleState, team: &Team) {
        let a = &self.arrays;
        let unchanged = self.steps_since_load < RESORT_STEPS
            && a.len() == particles.particles.len()
            && self.stored_records == particles.contacts.len()
            && a.state_index.iter().enumerate().all(|(k, &i)| {
                let p = &particles.particles[i];
                p.id == a.id[k]
                    && p.position == a.position[k]
                    && p.velocity == a.velocity[k]
                    && p.spin == a.spin[k]
                    && p.contact_force == a.force[k]
                    && p.contact_torque == a.torque[k]
            });
        if unchanged {
            self.steps_since_load += 1;
            self.sums.reset(a.len());
        } else {
            self.steps_since_load = 0;
            self.load(particles, team);
        }
    }

    /// Loads the particles and their contact histories from the state (cell order).
    fn load(&mut self, particles: &ParticleState, team: &Team) {
        let d_max = particles.particles.iter().map(|p| p.diameter).fold(0.0, f64::max);
        self.list.skin = SKIN_FRACTION * d_max;
        self.arrays.load(&particles.particles, d_max + self.list.skin);
        self.list.build(&self.arrays, &self.setup.materials, History::Records(&particles.contacts), team);
        // the particles are in a new order: every one is a candidate until marked again
        self.candidates.may_touch.clear();
        self.candidates.may_touch.resize(self.arrays.len(), true);
        (self.candidates.epoch, self.candidates.last_epoch) = (None, None);
        let n = self.arrays.len();
        self.wall_sides.clear();
        self.wall_sides.resize_with(n, WallSide::default);
        // the particles are in a new order: their near triangles are found again
        self.near.clear();
        self.near.resize(n * self.wall_meshes.meshes.len(), NearTriangles::default());
        self.far.clear();
        self.far.resize(n, FarFromWalls::default());
        self.at_wall.clear();
        self.at_wall.resize(n, false);
        let records = &particles.contacts;
        for (k, side) in self.wall_sides.iter_mut().enumerate() {
            let id = self.arrays.id[k];
            let start = records.partition_point(|r| (r.particle, r.partner) < (id, Partner::Wall(0)));
            side.history.extend(records[start..].iter().take_while(|r| r.particle == id).cloned());
        }
        self.sums.reset(n);
    }

    /// The contact history in the state's form: sorted by (particle, partner), a wall's
    /// records in the order they were found. The list's pair records are in that order already
    /// (ascending ids of a, then b) and each side's wall records follow its pairs (walls sort
    /// after particles), so the sides are ordered by id and merged in, not the whole history
    /// sorted again.
    fn store_history(&mut self, particles: &mut ParticleState, team: &Team) {
        self.list.sync_records(&self.arrays, team);
        let mut sides: Vec<(u64, usize)> =
            self.wall_sides.iter().enumerate().filter(|(_, s)| !s.history.is_empty()).map(|(k, _)| (self.arrays.id[k], k)).collect();
        sides.sort_unstable();
        let mut records = std::mem::take(&mut particles.contacts);
        records.clear();
        let mut pairs = self.list.records.iter().flatten().peekable();
        for (id, k) in sides {
            while let Some(pair) = pairs.next_if(|r| r.particle <= id) {
                records.push(pair.clone());
            }
            records.extend(self.wall_sides[k].history.iter().cloned());
        }
        records.extend(pairs.cloned());
        debug_assert!(records.is_sorted_by(|x, y| (x.particle, x.partner) <= (y.particle, y.partner)));
        self.stored_records = records.len();
        particles.contacts = records;
    }

    /// The walls' frames at this sub-step, counting the poses of the walls that moved.
    fn place_frames(&mut self, walls: &WallState) {
        if self.frames.len() != walls.walls.len() {
            self.frames.clear();
            self.poses.resize(walls.walls.len(), 0);
        }
        for (w, wall) in walls.walls.iter().enumerate() {
            let frame = wall.frame();
            match self.frames.get_mut(w) {
                Some(same) if *same == frame => continue,
                Some(moved) => *moved = frame,
                None => self.frames.push(frame),
            }
            self.poses[w] += 1;
        }
    }

    /// The step's `n` sub-steps of equal length, as the reference takes them
    /// (`ReferenceDem::advance`), their impacts logged into `impacts`; the last sub-step's
    /// contact totals, or the first fault and where it happened.
    #[allow(clippy::too_many_arguments)]
    fn substeps(
        &mut self,
        ctx: &StepContext,
        walls: &mut WallState,
        fluid: &[Option<FluidAtParticle>],
        n: u64,
        feeding: bool,
        impacts: &mut Vec<ImpactRecord>,
        team: &Team,
    ) -> Result<ContactTotals, SubstepFault> {
        let dt_s = ctx.dt / n as f64;
        let mut pass =
            advance_particles(Pass::First, &mut self.arrays, &mut self.sums, &self.setup.forces, fluid, dt_s, self.list.built_at(), team, |_| NothingToAdd);
        self.budget.external += pass.work_first;
        let mut totals = ContactTotals::default();
        for k in 0..n {
            let elapsed = (k + 1) as f64 * dt_s;
            // the last sub-step ends exactly where the step does (tⁿ⁺¹, the step's rotor pose)
            let (end_time, rotor_end) = if k + 1 == n { (ctx.time_end(), ctx.rotor) } else { (ctx.time + elapsed, ctx.rotor_after(elapsed)) };
            let max_displacement_sq = pass.max_displacement_sq;
            walls.place(end_time, rotor_end.as_ref());
            // this sub-step's second half, with the next one's first half when there is one
            let next = if k + 1 == n { Pass::Second } else { Pass::Between };
            let (sub, fault, sums) = self.substep(next, walls, fluid, end_time, dt_s, max_displacement_sq, feeding || k + 1 == n, impacts, team);
            self.budget.walls += dt_s * sub.wall_power;
            self.budget.placed += sub.placed;
            if let Some(fault) = fault {
                return Err(SubstepFault { substep: k, time: end_time, fault });
            }
            pass = sums;
            self.budget.external += pass.work_second;
            if next == Pass::Between {
                self.budget.external += pass.work_first;
            }
            totals = sub;
        }
        Ok(totals)
    }

    /// One sub-step after its first half: the contact forces and torques at the current
    /// positions (§7.8), then one pass over the particles (`next`: [`Pass::Between`] or
    /// [`Pass::Second`]) that adds each particle's wall contacts just before it moves it.
    /// Returns the contacts' totals (the pairs' only when `totals_needed`, the walls' always),
    /// the first fault, if any, and the pass's sums; a pair fault returns before the pass.
    #[allow(clippy::too_many_arguments)]
    fn substep(
        &mut self,
        next: Pass,
        walls: &WallState,
        fluid: &[Option<FluidAtParticle>],
        time: f64,
        dt: f64,
        max_displacement_sq: f64,
        totals_needed: bool,
        impacts: &mut Vec<ImpactRecord>,
        team: &Team,
    ) -> (ContactTotals, Option<Fault>, PassSums) {
        if self.list.is_stale(&self.arrays, max_displacement_sq) {
            self.list.build(&self.arrays, &self.setup.materials, History::Previous, team);
            self.candidates.epoch = None;
        }
        let pair_context =
            PairContext { materials: &self.setup.materials, wet_fluid: self.setup.wet_fluid, time, dt, fed_from: self.fed_from, energy: totals_needed };
        let (list, arrays) = (&mut self.list, &mut self.arrays);
        // the last pass left the sums at zero
        let mut forces = std::mem::take(&mut arrays.force);
        let mut torques = std::mem::take(&mut arrays.torque);
        let mut counts = std::mem::take(&mut arrays.contacts);
        let pair_fault = evaluate_and_add(list, arrays, &pair_context, &mut forces, &mut torques, &mut counts, team);
        (arrays.force, arrays.torque, arrays.contacts) = (forces, torques, counts);
        // found at the positions the pairs were evaluated at, before a pass moves them
        if let Some(fault) = pair_fault.then(|| first_fault(&self.list, &self.arrays, self.fed_from)).flatten() {
            let unmoved = PassSums { work_second: 0.0, work_first: 0.0, max_displacement_sq: f64::NAN };
            return (ContactTotals::default(), Some(fault), unmoved);
        }
        self.place_frames(walls);
        let wall_context = WallContext {
            materials: &self.setup.materials,
            wet_fluid: self.setup.wet_fluid,
            sliding_walls: &self.setup.sliding_walls,
            walls: &walls.walls,
            meshes: &self.wall_meshes.meshes,
            frames: &self.frames,
            generations: &self.wall_meshes.generations,
            poses: &self.poses,
            epoch: self.poses.iter().chain(&self.wall_meshes.generations).sum(),
            skin: self.list.skin,
            time,
            dt,
            fed_from: self.fed_from,
        };
        // the walls' meshes, as the pass indexes each particle's near triangles
        let n_walls = wall_context.meshes.len();
        let pass = if n_walls > 0 {
            let epoch = wall_context.epoch;
            let candidates = &mut self.candidates;
            // only the marked particles can touch a wall; once the walls kept their poses for a
            // sub-step, the particles are marked for the rest of the list's life
            let pick = candidates.epoch == Some(epoch);
            let mark = !pick && candidates.last_epoch == Some(epoch);
            candidates.last_epoch = Some(epoch);
            let marks = CandidateMarks { pick, mark, built_at: self.list.built_at() };
            let context = &wall_context;
            let n = self.arrays.len();
            let far = DisjointSlices::new(&mut self.far);
            let sides = DisjointSlices::new(&mut self.wall_sides);
            let at_wall = DisjointSlices::new(&mut self.at_wall);
            let may_touch = DisjointSlices::new(&mut candidates.may_touch);
            let near = DisjointSlices::new(&mut self.near);
            self.wall_found.resize_with(n.div_ceil(BLOCK), Vec::new);
            self.wall_impacts.resize_with(n.div_ceil(BLOCK), Vec::new);
            let found = DisjointSlices::new(&mut self.wall_found);
            let block_impacts = DisjointSlices::new(&mut self.wall_impacts);
            // block b's share of the particles' wall state (the pass makes each block's once)
            let before = |b: usize| {
                let range = b * BLOCK..n.min((b + 1) * BLOCK);
                // SAFETY: block b's own range of each array
                unsafe {
                    BlockWalls {
                        context,
                        candidates: marks,
                        far: far.range(range.clone()),
                        sides: sides.range(range.clone()),
                        at_wall: at_wall.range(range.clone()),
                        may_touch: may_touch.range(range.clone()),
                        near: near.range(range.start * n_walls..range.end * n_walls),
                        start: range.start,
                        found: &mut found.range(b..b + 1)[0],
                        impacts: {
                            let impacts = &mut block_impacts.range(b..b + 1)[0];
                            impacts.clear();
                            impacts
                        },
                    }
                }
            };
            let pass = advance_particles(next, &mut self.arrays, &mut self.sums, &self.setup.forces, fluid, dt, self.list.built_at(), team, before);
            if mark {
                candidates.epoch = Some(epoch);
            }
            pass
        } else {
            self.wall_found.clear();
            self.wall_impacts.iter_mut().for_each(Vec::clear);
            advance_particles(next, &mut self.arrays, &mut self.sums, &self.setup.forces, fluid, dt, self.list.built_at(), team, |_| NothingToAdd)
        };

        // the pair totals feed the energy guard at the step's end and, while fed particles
        // make their first contacts, at every sub-step
        let mut totals = ContactTotals::default();
        if totals_needed {
            let pairs = self.list.touching_totals(&self.arrays.radius, &mut self.touching_totals, team);
            (totals.contacts, totals.max_overlap_ratio, totals.elastic, totals.placed) = (pairs.contacts, pairs.max_overlap_ratio, pairs.elastic, pairs.placed);
        }
        let mut wall_fault: Option<(u64, Fault)> = None;
        let first_impact = impacts.len();
        // a side without contact, impact or fault adds zeros (exactly: the sums keep their bits);
        // the blocks' particles at a wall in block order are the particles at a wall in order
        debug_assert!(self.wall_found.iter().flatten().map(|f| f.k as usize).eq(self.at_wall.iter().enumerate().filter(|(_, at)| **at).map(|(k, _)| k)));
        for found in self.wall_found.iter().flatten() {
            totals.contacts += found.contacts as usize;
            totals.max_overlap_ratio = totals.max_overlap_ratio.max(found.max_overlap_ratio);
            totals.elastic += found.elastic;
            totals.placed += found.placed;
            totals.wall_power += found.power;
            if !found.eventful {
                continue;
            }
            let (k, side) = (found.k as usize, &self.wall_sides[found.k as usize]);
            if let Some(f) = &side.fault {
                let id = self.arrays.id[k];
                if wall_fault.as_ref().is_none_or(|(first, _)| id < *first) {
                    wall_fault = Some((id, f.clone()));
                }
            }
        }
        // the blocks' impacts in block order are the particles' in internal order
        for block in &mut self.wall_impacts {
            impacts.append(block);
        }
        let fault = wall_fault.map(|(_, f)| f);
        // the reference logs a sub-step's impacts particle by particle in id order
        impacts[first_impact..].sort_by_key(|i| i.particle);
        (totals, fault, pass)
    }
}

impl ParticlePhase for FastDem {
    fn name(&self) -> &'static str {
        "fast"
    }

    /// The next step loads the particles and their histories from the restored state (the
    /// arrays hold the rejected step's).
    fn rewind(&mut self, particles: &ParticleState) {
        self.fed_from = particles.next_id;
        self.steps_since_load = RESORT_STEPS;
    }

    /// One outer step in DEM sub-steps of equal length, as the reference takes it
    /// (`ReferenceDem::advance`): the same sub-step count, the same guards and report.
    fn advance(
        &mut self,
        ctx: &StepContext,
        particles: &mut ParticleState,
        walls: &mut WallState,
        fluid: &[Option<FluidAtParticle>],
        report: &mut StepReport,
    ) -> Result<Option<ParticleLoad>, SolverError> {
        // a receding wall's mesh is rebuilt; its generation makes the near triangles stale
        self.wall_meshes.refresh(walls).map_err(unsupported)?;
        let elastic_start = particles.contacts.is_empty().then_some(0.0);
        let n = substeps_for(&self.setup.section, &self.setup.materials, ctx.dt, &particles.particles, walls);
        if fluid.len() != particles.particles.len() {
            return Err(unsupported(format!("the fluid was sampled for {} particles, but there are {}", fluid.len(), particles.particles.len())));
        }
        self.budget.start_step(&particles.particles);
        // without any fluid sample (a DEM-only run) the sub-steps need not look each one up
        let fluid = if fluid.iter().all(Option::is_none) { &[] } else { fluid };
        let mut impacts = std::mem::take(&mut particles.impacts);
        let logged_before = impacts.len();
        // the step's parallel parts (a new list's build, the sub-steps', the records brought up
        // to date) run on a team kept awake for the whole step
        let totals = with_team(|team| {
            self.take(particles, team);
            let feeding = self.arrays.id.iter().any(|&id| id >= self.fed_from);
            let totals = match self.substeps(ctx, walls, fluid, n, feeding, &mut impacts, team) {
                Ok(totals) => totals,
                Err(SubstepFault { substep, time, fault }) => {
                    // a pair fault leaves the particles where its sub-step evaluated the
                    // contacts; a wall fault, found by the pass that moves them, where that pass
                    // left them
                    self.arrays.store(&mut particles.particles);
                    particles.impacts = std::mem::take(&mut impacts);
                    let what = format!("{} (DEM sub-step {} of {n})", fault.describe(&walls.walls), substep + 1);
                    return Err(SolverError::Diverged { step: ctx.step, time, what });
                }
            };
            self.arrays.store(&mut particles.particles);
            particles.counts.impacts += impacts[logged_before..].iter().filter(|i| !i.sliding).count() as u64;
            particles.impacts = std::mem::take(&mut impacts);
            self.budget.check(ctx, &particles.particles, totals.elastic, elastic_start, self.setup.section.collision_speed)?;
            self.fed_from = particles.next_id;
            self.store_history(particles, team);
            Ok(totals)
        })?;
        report.values.extend([
            ("substeps", n as f64),
            ("contacts", totals.contacts as f64),
            ("particle_kinetic_energy", particles.particles.iter().map(|p| p.kinetic_energy()).sum()),
            ("max_overlap_ratio", totals.max_overlap_ratio),
        ]);
        if self.setup.forces.feedback.is_none() {
            return Ok(None);
        }
        let mut load = ParticleLoad::zeros(particles.particles.len());
        for (k, share) in self.sums.load.iter().enumerate() {
            let i = self.arrays.state_index[k];
            load.implicit_drag[i] = share.implicit_drag;
            load.explicit_force[i] = share.explicit_force.into();
            load.drag[i] = share.drag.into();
            load.slip_reynolds[i] = share.slip_reynolds;
        }
        load.time_average(&particles.particles, ctx.dt);
        Ok(Some(load))
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use spillage_model::case::Case;
    use spillage_model::solver::Solver;
    use spillage_model::state::State;
    use spillage_model::step::Coupled;
    use spillage_model::walls::settings::ShapeSection;

    use super::FastDem;

    /// Once the candidates of a list are marked, the particles of a settling bed far from its
    /// box's faces are not looked at. A candidate is one some wall's triangle came within its
    /// radius plus a skin of, queried from at most a skin from where it was at the marking, and
    /// it has moved less than a skin since: every candidate lies within its radius plus three
    /// skins of a face. The bound sits in the lattice's gap: the sites touching a face are a
    /// radius from it, the next ones 10.8 mm (r + 5.8 skins). Marks kept from an earlier list
    /// used to leave 7 140 of the 10⁴ bed's particles candidates after 8 steps, 1 444 of them
    /// touching a face.
    #[test]
    fn far_particles_are_not_wall_candidates() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/bench/settle_box_10k.toml");
        let case = Case::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let Some(ShapeSection::Box { min, max, .. }) = case.walls.first().map(|w| &w.shape) else {
            panic!("the settling bed's wall is a box");
        };
        let mut state = State::default();
        let dem = FastDem::new(&case, &mut state).expect("fast DEM");
        let mut run = Coupled::particles_only(&case, state, dem).expect("run");
        for _ in 0..8 {
            run.step().expect("step");
        }
        let dem = run.particle_phase().expect("particles");
        assert!(dem.candidates.epoch.is_some(), "the candidates are marked");
        let arrays = &dem.arrays;
        let gap_to_a_face = |k: usize| (0..3).map(|a| (arrays.position[k][a] - min[a]).min(max[a] - arrays.position[k][a])).fold(f64::INFINITY, f64::min);
        let candidates: Vec<usize> = (0..arrays.len()).filter(|&k| dem.candidates.may_touch[k]).collect();
        let beyond: Vec<usize> = candidates.iter().copied().filter(|&k| gap_to_a_face(k) >= arrays.radius[k] + 3.0 * dem.list.skin).collect();
        assert!(beyond.is_empty(), "{} of {} candidates lie beyond r + 3 skins of every face", beyond.len(), candidates.len());
        // every particle touching a face is a candidate
        let touching: Vec<usize> = (0..arrays.len()).filter(|&k| gap_to_a_face(k) < arrays.radius[k]).collect();
        assert!(
            !touching.is_empty() && touching.iter().all(|&k| dem.candidates.may_touch[k]),
            "{} candidates, {} particles touching a face",
            candidates.len(),
            touching.len()
        );
    }
}
