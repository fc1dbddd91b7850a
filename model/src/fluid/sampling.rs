//! The fluid seen by a particle, as the one-way coupling samples it from the stored fluid state
//! (spec fluid-dem-model.md §5.7: u_c|p and Du_c/Dt|p at the particle).
//!
//! [R, our construction; the seam of issue 12] The particle sees the cell that contains its
//! centre: the cell velocity uⁿ and the material acceleration
//! Du/Dt ≈ (uⁿ − uⁿ⁻¹)/Δtⁿ + (1/V) Σ_f φ_f (u_f − u_P), the convective part in the
//! conservative-minus-continuity form ∇·(uu) − u∇·u with the stored absolute face fluxes and
//! linear face values (boundary and sliding-interface faces contribute nothing: u_f = u_P there).
//! The volume-averaged coupling replaces this by the kernel sampling that matches its mapping.

use crate::closure::drag::FluidAtParticle;
use crate::fluid::state::FluidState;
use crate::mesh::{Mesh, Vec3};
use crate::particles::Particle;

/// Per particle (in order), the fluid of the cell containing its centre, `None` outside the mesh.
/// `dt_old` is the last fluid step (0 before the first: no local acceleration).
pub fn sample_containing_cell(
    mesh: &Mesh,
    fluid: &FluidState,
    density: f64,
    kinematic_viscosity: f64,
    dt_old: f64,
    particles: &[Particle],
    out: &mut Vec<Option<FluidAtParticle>>,
) {
    for p in particles {
        out.push(mesh.locate(&p.position).map(|cell| FluidAtParticle {
            density,
            kinematic_viscosity,
            velocity: Vec3::from(fluid.velocity[cell]),
            material_acceleration: material_acceleration(mesh, fluid, dt_old, cell),
            hindrance: 1.0,
        }));
    }
}

/// Du/Dt in `cell` (module doc).
pub fn material_acceleration(mesh: &Mesh, fluid: &FluidState, dt_old: f64, cell: usize) -> Vec3 {
    let u = |c: usize| Vec3::from(fluid.velocity[c]);
    let local = if dt_old > 0.0 { (u(cell) - Vec3::from(fluid.velocity_old[cell])) / dt_old } else { Vec3::zeros() };
    let mut convective = Vec3::zeros();
    for &face in &mesh.cell_faces[mesh.cell_face_offsets[cell]..mesh.cell_face_offsets[cell + 1]] {
        if face >= mesh.n_internal_faces {
            continue;
        }
        let (owner, neighbour) = (mesh.face_owner[face], mesh.face_neighbour[face]);
        let w = mesh.face_weight[face];
        let u_face = u(owner) * w + u(neighbour) * (1.0 - w);
        // flux out of `cell`
        let out_flux = if owner == cell { fluid.flux[face] } else { -fluid.flux[face] };
        convective += out_flux * (u_face - u(cell));
    }
    local + convective / mesh.cell_volumes[cell]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::cartesian::BoxSpec;

    /// A uniform flow has no material acceleration; a uniformly accelerating one has exactly
    /// its ∂u/∂t.
    #[test]
    fn uniform_flow_has_only_its_local_acceleration() {
        let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::repeat(1.0), [4, 4, 4])).unwrap();
        let mut fluid = FluidState::at_rest(mesh.n_cells(), mesh.n_faces(), mesh.n_internal_faces);
        let u = Vec3::new(1.0, 2.0, 0.5);
        for c in 0..mesh.n_cells() {
            fluid.velocity[c] = u.into();
            fluid.velocity_old[c] = (u - Vec3::new(0.1, 0.0, 0.0)).into();
        }
        for f in 0..mesh.n_faces() {
            fluid.flux[f] = u.dot(&mesh.face_areas[f]);
        }
        for c in [0, 21, 63] {
            let a = material_acceleration(&mesh, &fluid, 0.05, c);
            // (0.1, 0, 0)/0.05 = (2, 0, 0); the convective part is round-off of O(|u|)
            assert!((a - Vec3::new(2.0, 0.0, 0.0)).norm() < 1e-12, "cell {c}: {a}");
        }
    }
}
