//! Step 3 of the algorithm (module doc of `spillage_reference::fluid`): the starting values of
//! the outer loop. u* = uᵒ and P* = Pᵒ from the state; φ* = φᵒ on internal faces that did not
//! move, the interpolated velocity's flux on faces of the moving zone and on overlap links
//! (their geometry changed); the time-derivative flux correction; and the boundary data of the
//! conditions: boundary pressures from the state, fixed velocities, prescribed fluxes.

use spillage_model::cutter_head::mouth::balancing_speed;
use spillage_model::fluid::conditions::{fluid_volume_rate, Conditions};
use spillage_model::fluid::moving_cells::particle_share_of_mesh_flux;
use spillage_model::fluid::state::FluidState;
use spillage_model::mesh::Vec3;
use spillage_model::solver::SolverError;

use super::assembly::{par_for, vec_of, Out};
use super::layout::{rotor_velocity, Boundary, Links, Rotor};
use super::step_inputs::TimeStep;

/// Which cells moved since the stored fluxes were computed.
#[derive(Clone, Copy)]
pub struct MovedCells<'a> {
    /// Whether the rotor zone turned this step.
    pub rotor_turns: bool,
    /// Whether the whole mesh deformed this step (a mesh that follows a receding wall).
    pub mesh_deforms: bool,
    /// Per cell: whether it belongs to the rotor zone.
    pub in_rotor: &'a [bool],
}

impl MovedCells<'_> {
    /// True for an internal face whose owner did not move: its stored fluxes belong to its
    /// current geometry. Faces of the moving zone or of a deforming mesh, and overlap links
    /// (rebuilt every step) have no such flux.
    #[inline]
    pub fn keeps_stored_flux(&self, links: &Links, l: usize) -> bool {
        l < links.n_internal && !self.mesh_deforms && !(self.rotor_turns && self.in_rotor[links.owner[l] as usize])
    }
}

/// Cell velocity and pressure at the start of the step: u* = uᵒ = uⁿ of the state, uᵒᵒ, P* = Pⁿ.
pub fn time_levels_from_state(
    fluid: &FluidState,
    velocity: &mut [Vec<f64>; 3],
    velocity_old: &mut [Vec<f64>; 3],
    velocity_old_old: &mut [Vec<f64>; 3],
    pressure: &mut [f64],
) {
    for c in 0..fluid.velocity.len() {
        for j in 0..3 {
            velocity[j][c] = fluid.velocity[c][j];
            velocity_old[j][c] = fluid.velocity[c][j];
            velocity_old_old[j][c] = fluid.velocity_old[c][j];
        }
    }
    pressure.copy_from_slice(&fluid.pressure);
}

/// Starting flux φ* per link: the stored flux `stored_flux` (per mesh face) where the link kept
/// its geometry, else the flux (w u_P + (1−w) u_N)·S of the interpolated `velocity`.
pub fn starting_link_fluxes(links: &Links, moved: MovedCells, stored_flux: &[f64], velocity: &[Vec<f64>; 3], link_flux: &mut [f64]) {
    let out = Out::of(link_flux);
    par_for(links.len(), |l| {
        let (p, q) = (links.owner[l] as usize, links.neighbour[l] as usize);
        let flux = if moved.keeps_stored_flux(links, l) {
            stored_flux[l]
        } else {
            let w = links.weight[l];
            (vec_of(velocity, p) * w + vec_of(velocity, q) * (1.0 - w)).dot(&links.area[l])
        };
        unsafe { out.set(l, flux) };
    });
}

/// The old time levels the time-derivative flux correction compares: velocities, fractions and
/// face fluxes (per mesh face) one and two steps back.
#[derive(Clone, Copy)]
pub struct OldLevels<'a> {
    pub velocity_old: &'a [Vec<f64>; 3],
    pub velocity_old_old: &'a [Vec<f64>; 3],
    pub alpha_old: &'a [f64],
    pub alpha_old_old: &'a [f64],
    pub flux_old: &'a [f64],
    pub flux_old_old: &'a [f64],
}

/// α_f φ − (αu)_f·S on link `l`: how far a stored flux is from the flux of the interpolated
/// velocity of its time level.
#[inline]
fn flux_mismatch(links: &Links, l: usize, alpha: &[f64], velocity: &[Vec<f64>; 3], flux: f64) -> f64 {
    let (p, q) = (links.owner[l] as usize, links.neighbour[l] as usize);
    let w = links.weight[l];
    links.interpolate(l, alpha[p], alpha[q]) * flux - (vec_of(velocity, p) * alpha[p] * w + vec_of(velocity, q) * alpha[q] * (1.0 - w)).dot(&links.area[l])
}

/// Time-derivative flux correction per link divided by rAU_f (reference
/// `solver::ddt_flux_correction`), −(1/Δt)[c₁(α_fᵒ φᵒ − (αᵒuᵒ)_f·S) + c₂(α_fᵒᵒ φᵒᵒ − (αᵒᵒuᵒᵒ)_f·S)];
/// zero when not `enabled` and on moved faces and overlap links, whose geometry changed since
/// φᵒ was stored.
pub fn ddt_flux_corrections(links: &Links, moved: MovedCells, enabled: bool, time: TimeStep, old: OldLevels, correction: &mut [f64]) {
    let [_, c1, c2] = time.coefficients;
    let out = Out::of(correction);
    par_for(links.len(), |l| {
        let value = if enabled && moved.keeps_stored_flux(links, l) {
            let mismatch_old = flux_mismatch(links, l, old.alpha_old, old.velocity_old, old.flux_old[l]);
            let mismatch_old_old = flux_mismatch(links, l, old.alpha_old_old, old.velocity_old_old, old.flux_old_old[l]);
            -(c1 * mismatch_old + c2 * mismatch_old_old) / time.dt
        } else {
            0.0
        };
        unsafe { out.set(l, value) };
    });
}

/// The boundary data of the step, per boundary face.
pub struct BoundaryStart<'a> {
    /// Kinematic pressure from the state.
    pub boundary_pressure: &'a mut [f64],
    /// Fixed velocity of the condition (NaN where none).
    pub fixed_velocity: &'a mut [Vec3],
    /// Prescribed flux of the condition (NaN where the pressure is fixed).
    pub prescribed_flux: &'a mut [f64],
    /// The prescribed flux, or the state's flux where the pressure is fixed.
    pub boundary_flux: &'a mut [f64],
}

/// Boundary pressures, fixed velocities and fluxes at the start of the step from the conditions
/// (rotating walls with the rotor's velocity) and the state.
pub fn boundary_starting_values(
    boundary: &Boundary,
    conditions: &Conditions,
    rotor: Option<&Rotor>,
    fluid: &FluidState,
    n_internal_faces: usize,
    out: BoundaryStart,
) {
    for b in 0..boundary.len() {
        let condition = boundary.condition[b] as usize;
        let face = boundary.face[b] as usize;
        out.boundary_pressure[b] = fluid.boundary_pressure[face - n_internal_faces];
        out.fixed_velocity[b] = conditions.fixed_velocity(condition, &boundary.centre[b], rotor_velocity(rotor)).unwrap_or(Vec3::repeat(f64::NAN));
        let prescribed = conditions.prescribed_flux(condition, &boundary.centre[b], &boundary.area[b], boundary.mesh_flux[b], rotor_velocity(rotor));
        out.prescribed_flux[b] = prescribed.unwrap_or(f64::NAN);
        out.boundary_flux[b] = prescribed.unwrap_or(fluid.flux[face]);
    }
}

/// Sets the suction mouth's speed of the step (`condition` carries it): the speed at which the
/// water leaves through it what continuity leaves for it (spillage_model::cutter_head::mouth::
/// balancing_speed), from the prescribed fluxes at unit speed, each weighted by α of its cell,
/// less every boundary face's particle share of its mesh flux (spillage_model::fluid::moving_cells).
pub fn balance_suction(
    boundary: &Boundary,
    conditions: &mut Conditions,
    condition: usize,
    rotor: Option<&Rotor>,
    fluid: &FluidState,
    volumes: &[f64],
    time: TimeStep,
) -> Result<(), SolverError> {
    conditions.set_suction_speed(1.0);
    let (mut unit, mut other) = (0.0, 0.0);
    for b in 0..boundary.len() {
        let c = boundary.condition[b] as usize;
        if let Some(flux) = conditions.prescribed_flux(c, &boundary.centre[b], &boundary.area[b], boundary.mesh_flux[b], rotor_velocity(rotor)) {
            let weighted = fluid.alpha[boundary.cell[b] as usize] * flux;
            if c == condition {
                unit += weighted;
            } else {
                other += weighted;
            }
        }
        other -= particle_share_of_mesh_flux(fluid.alpha[boundary.cell[b] as usize], boundary.mesh_flux[b]);
    }
    let rate = fluid_volume_rate([&fluid.alpha, &fluid.alpha_old, &fluid.alpha_old_old], volumes, time.coefficients, time.dt);
    let speed = balancing_speed(unit, other, rate).map_err(SolverError::Unsupported)?;
    conditions.set_suction_speed(speed);
    Ok(())
}
