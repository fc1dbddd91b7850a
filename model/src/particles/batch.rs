//! A head's batch placed after the water has turned: `[[particles.groups]]` with
//! `placement = "head_lattice"` and `after_revolutions` > 0. The thesis did not insert its rock
//! into still water: it solved the frozen-rotor flow, turned the head one rotation with water
//! alone, and only then inserted the particles (spillage-and-flow-verification.md §5.4,
//! initialisation, steps 1–3). Steps 2–3 are this; the frozen-rotor start-up of step 1 is for
//! fluid-only cases ([`crate::fluid::frozen_rotor`]), so a case with particles starts its water
//! from `[fluid] initial` (the shipped head: turning with the head inside it).
//!
//! The batch's time is t_b = after_revolutions · 2π/|ω|. It is placed at the start of the step
//! whose interval [tⁿ, tⁿ⁺¹) holds t_b, on the lattice sites of its sector (lab frame) that are
//! clear of the head's solids with the blades where they stand at tⁿ and clear of the particles
//! already there. Every sequence of steps has exactly one such step, so the batch needs no state
//! of its own: a step retried with a smaller Δt starts again from the restored state, and a
//! restarted run takes the same steps.

use super::initial::{add_head_lattice, HeadPose};
use super::settings::{GroupSection, ParticlesSection};
use super::state::ParticleState;
use crate::case::{Case, FieldError};
use crate::cutter_head::CutterHead;

/// A `head_lattice` group placed during the run.
#[derive(Clone, Debug, PartialEq)]
pub struct LaterBatch {
    /// Its index in `[[particles.groups]]`.
    pub group: usize,
    /// `after_revolutions`, and t_b [s].
    pub revolutions: f64,
    pub time: f64,
}

impl LaterBatch {
    /// Whether the step over [time, time_end) places it.
    pub fn is_due(&self, time: f64, time_end: f64) -> bool {
        time <= self.time && self.time < time_end
    }
}

/// The case's batches placed during the run, in group order. They need a turning rotor to count
/// revolutions, and a `[cutter_head]` to be placed in.
pub fn later_batches(case: &Case) -> Result<Vec<LaterBatch>, FieldError> {
    let Some(section) = &case.particles else { return Ok(Vec::new()) };
    let mut batches = Vec::new();
    for (g, group) in section.groups.iter().enumerate() {
        let GroupSection::HeadLattice { after_revolutions, .. } = group else { continue };
        if *after_revolutions == 0.0 {
            continue;
        }
        let key = format!("particles.groups.{g}.after_revolutions");
        let omega = case.rotor.as_ref().map_or(0.0, |r| r.angular_velocity()).abs();
        if case.cutter_head.is_none() || omega == 0.0 {
            return Err(FieldError::new(key, after_revolutions, "0 unless the case has a [cutter_head] and a turning [rotor] to count revolutions"));
        }
        batches.push(LaterBatch { group: g, revolutions: *after_revolutions, time: after_revolutions * std::f64::consts::TAU / omega });
    }
    Ok(batches)
}

/// Places each of the case's later `batches` ([`later_batches`]) alone where the blades will
/// stand at its time (for a constant ω), so a batch with no room is the case's error before the
/// run, not one revolution into it.
pub fn check_later_batches(case: &Case, batches: &[LaterBatch]) -> Result<(), FieldError> {
    let (Some(section), Some(head), Some(rotor)) = (&case.particles, &case.cutter_head, &case.rotor) else { return Ok(()) };
    let head = CutterHead::new(head);
    let omega = rotor.angular_velocity();
    for batch in batches {
        place(section, omega, &head, batch, omega * batch.time, &mut ParticleState::default())?;
    }
    Ok(())
}

/// Places `batch` of `section` into `state` with the blades at rotor `angle` [rad] (a rotor of
/// angular velocity `omega`, which co-rotating particles take); returns how many particles it
/// placed (ids from `state.next_id`, counted as created).
pub fn place(
    section: &ParticlesSection,
    omega: f64,
    head: &CutterHead,
    batch: &LaterBatch,
    angle: f64,
    state: &mut ParticleState,
) -> Result<usize, FieldError> {
    let key = format!("particles.groups.{}", batch.group);
    let pose = HeadPose { angle, skip_occupied: true };
    let placed = add_head_lattice(section, &section.groups[batch.group], &key, head, omega, pose, state)?;
    state.counts.created += placed as u64;
    Ok(placed)
}
