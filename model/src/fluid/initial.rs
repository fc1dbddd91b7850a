//! The fluid state a run starts from when the state holds none (both solvers).

use crate::case::Case;
use crate::mesh::{Mesh, Vec3};

use super::state::FluidState;

/// The case's initial velocity in every cell (at rest without a `[fluid]` section), zero
/// pressure, α_c = 1, and on internal faces the flux of the linearly interpolated initial
/// velocity, (w u_P + (1−w) u_N)·S (made divergence-free by the first step); the old levels
/// equal the new ones. A cutter head's haul velocity is added outside the head
/// ([`crate::cutter_head::current::initial_velocity`]).
pub fn initial_fluid_state(case: &Case, mesh: &Mesh) -> FluidState {
    let n_cells = mesh.n_cells();
    let mut state = FluidState::at_rest(n_cells, mesh.n_faces(), mesh.n_internal_faces);
    if let Some(fluid) = &case.fluid {
        let rotor = case.rotor.as_ref().map(|r| (r.angular_velocity() * r.axis[2].signum(), r.origin));
        for c in 0..n_cells {
            let x = mesh.cell_centres[c];
            state.velocity[c] = fluid.initial.velocity_at([x.x, x.y, x.z], rotor);
        }
        // a cutter head's current (haul velocity) starts outside the head
        if let Some(section) = case.cutter_head.as_ref().filter(|h| h.has_current()) {
            let head = crate::cutter_head::CutterHead::new(section);
            for c in 0..n_cells {
                let x = mesh.cell_centres[c];
                state.velocity[c] = crate::cutter_head::current::initial_velocity(&head, section.haul_velocity, [x.x, x.y, x.z], state.velocity[c]);
            }
        }
    }
    state.velocity_old = state.velocity.clone();
    for face in 0..mesh.n_internal_faces {
        let (p, nb) = (mesh.face_owner[face], mesh.face_neighbour[face]);
        let w = mesh.face_weight[face];
        let u = Vec3::from(state.velocity[p]) * w + Vec3::from(state.velocity[nb]) * (1.0 - w);
        state.flux[face] = u.dot(&mesh.face_areas[face]);
    }
    state.flux_old = state.flux.clone();
    state.turbulence = initial_turbulence(case, mesh);
    state
}

/// Uniform `[turbulence] initial_k` and `initial_epsilon` for a k–ε case, `None` for a laminar one.
fn initial_turbulence(case: &Case, mesh: &Mesh) -> Option<crate::turbulence::TurbulenceState> {
    let t = &case.turbulence;
    t.is_k_epsilon().then(|| {
        crate::turbulence::TurbulenceState::uniform(mesh.n_cells(), mesh.n_faces() - mesh.n_internal_faces, t.initial_k, t.initial_epsilon, t.constants.c_mu)
    })
}

/// The fluid state of `state` ready for a run on `mesh`: the initial state when there is none,
/// the old flux filled in for checkpoints written before it was stored, and the sizes checked
/// against the mesh (a checkpoint of another mesh is refused). A k–ε case continuing a laminar
/// checkpoint starts its turbulence from the initial k and ε (spin-up laminar, then turbulent);
/// a laminar case drops the turbulence of a k–ε checkpoint.
pub fn prepare_fluid_state(state: &mut crate::state::State, case: &Case, mesh: &Mesh) -> Result<(), String> {
    let fluid = state.fluid.get_or_insert_with(|| initial_fluid_state(case, mesh));
    fluid.fill_missing_old_flux(mesh);
    if case.turbulence.is_k_epsilon() != fluid.turbulence.is_some() {
        fluid.turbulence = initial_turbulence(case, mesh);
    }
    fluid.check_matches(mesh)
}
