//! The fluid seen by a particle, as the one-way coupling samples it from the stored fluid state
//! (spec fluid-dem-model.md §5.7: u_c|p and Du_c/Dt|p at the particle).
//!
//! [R, our construction; the seam of issue 12] The particle sees the cell that contains its
//! centre: the cell velocity uⁿ and the material acceleration
//! Du/Dt ≈ (uⁿ − uⁿ⁻¹)/Δtⁿ + (1/V) Σ_f (φ_f − φ_mesh,f)(u_f − u_P), the convective part in the
//! conservative-minus-continuity form ∇·(uu) − u∇·u with linear face values (boundary and
//! sliding-interface faces contribute nothing: u_f = u_P there). A cell of the rotor zone moves
//! with the mesh, so its (uⁿ − uⁿ⁻¹)/Δt already follows the mesh (∂u/∂t + u_mesh·∇u): its
//! convective part takes the flux relative to the mesh, φ − φ_mesh, with
//! φ_mesh,f = (ω × (x_f − x₀))·S_f (spec §4.1), or the mesh motion would count twice.
//! The volume-averaged coupling replaces this by the kernel sampling that matches its mapping.

use crate::closure::drag::FluidAtParticle;
use crate::fluid::state::FluidState;
use crate::mesh::{Mesh, Vec3};
use crate::particles::Particle;
use crate::step::RotorZone;

/// The fluid seen by particles: its properties, the fluid state and the mesh it lives on.
pub struct FluidSample<'a> {
    pub mesh: &'a Mesh,
    /// The mesh's rotor zone at its current pose, if any.
    pub rotor: Option<&'a RotorZone>,
    pub fluid: &'a FluidState,
    pub density: f64,
    pub kinematic_viscosity: f64,
    /// The last fluid step (0 before the first: no local acceleration).
    pub dt_old: f64,
    /// Per face, the mesh flux of a mesh that follows a receding wall over the last step (the
    /// motion that brought it to tⁿ), empty on a mesh that does not deform.
    pub deforming_flux: &'a [f64],
}

/// Per particle (in order), the fluid of the cell containing its centre, `None` outside the mesh.
pub fn sample_containing_cell(source: &FluidSample, particles: &[Particle], out: &mut Vec<Option<FluidAtParticle>>) {
    for p in particles {
        out.push(source.mesh.locate(&p.position).map(|cell| FluidAtParticle {
            density: source.density,
            kinematic_viscosity: source.kinematic_viscosity,
            velocity: Vec3::from(source.fluid.velocity[cell]),
            material_acceleration: material_acceleration(source, cell),
            fluid_fraction: source.fluid.alpha[cell],
        }));
    }
}

/// Du/Dt in `cell` (module doc).
pub fn material_acceleration(source: &FluidSample, cell: usize) -> Vec3 {
    let FluidSample { mesh, fluid, dt_old, .. } = *source;
    let moving = source.rotor.filter(|r| mesh.cell_zone[cell] == r.zone);
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
        let mesh_flux = moving.map_or(0.0, |r| r.velocity_at(&mesh.face_centres[face]).dot(&mesh.face_areas[face]));
        let mesh_flux = if source.deforming_flux.is_empty() { mesh_flux } else { mesh_flux + source.deforming_flux[face] };
        // flux relative to the mesh, out of `cell`
        let relative = fluid.flux[face] - mesh_flux;
        let out_flux = if owner == cell { relative } else { -relative };
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
            let source = FluidSample { mesh: &mesh, rotor: None, fluid: &fluid, density: 1000.0, kinematic_viscosity: 1e-6, dt_old: 0.05, deforming_flux: &[] };
            let a = material_acceleration(&source, c);
            // (0.1, 0, 0)/0.05 = (2, 0, 0); the convective part is round-off of O(|u|)
            assert!((a - Vec3::new(2.0, 0.0, 0.0)).norm() < 1e-12, "cell {c}: {a}");
        }
    }

    /// Fluid in solid-body rotation with the rotor (ω = 1 rad/s, rotor_stator case, mesh turned
    /// on by ωΔt since the last step) has Du/Dt = −ω² r in every cell, static or turning with
    /// the rotor: the turning cells' local term already carries the mesh motion, so counting it
    /// again in the convective term would give −2ω² r there (100 % off). The static cells are
    /// exact to round-off (the velocity is linear in x, so linear face values are exact:
    /// measured 2.3e-15); the turning cells carry the backward difference of the local term
    /// along the cell path, a relative error ωΔt/2 = 2.5 % (measured 2.500e-2), bounded here by
    /// 0.6 ωΔt.
    #[test]
    fn solid_body_rotation_has_centripetal_acceleration_in_rotor_and_stator() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/rotor_stator.toml");
        let case = crate::case::Case::load(&path).unwrap();
        let mut mesh = crate::mesh::build(case.mesh.as_ref().unwrap()).unwrap();
        let mut rotor = RotorZone::from_case(&case, &mesh).unwrap().unwrap();
        let (omega, dt, angle) = (rotor.pose.omega, 0.05, 0.3);
        let pose = crate::step::RotorPose { angle, ..rotor.pose };
        rotor.place(&mut mesh, &pose).unwrap();
        let spin = |x: &Vec3| Vec3::new(-omega * x.y, omega * x.x, 0.0);
        let turn_back = nalgebra::Rotation3::from_axis_angle(&Vec3::z_axis(), -omega * dt);
        let mut fluid = FluidState::at_rest(mesh.n_cells(), mesh.n_faces(), mesh.n_internal_faces);
        for c in 0..mesh.n_cells() {
            let x = mesh.cell_centres[c];
            fluid.velocity[c] = spin(&x).into();
            let x_old = if mesh.cell_zone[c] == rotor.zone { turn_back * x } else { x };
            fluid.velocity_old[c] = spin(&x_old).into();
        }
        for f in 0..mesh.n_faces() {
            fluid.flux[f] = spin(&mesh.face_centres[f]).dot(&mesh.face_areas[f]);
        }
        let source =
            FluidSample { mesh: &mesh, rotor: Some(&rotor), fluid: &fluid, density: 1000.0, kinematic_viscosity: 1e-6, dt_old: dt, deforming_flux: &[] };
        let mut squared = [0.0f64; 2];
        let mut count = [0usize; 2];
        for c in 0..mesh.n_cells() {
            let x = mesh.cell_centres[c];
            let exact = -omega * omega * Vec3::new(x.x, x.y, 0.0);
            let a = material_acceleration(&source, c);
            let k = usize::from(mesh.cell_zone[c] == rotor.zone);
            squared[k] += (a - exact).norm_squared() / exact.norm_squared();
            count[k] += 1;
        }
        let rms = [(squared[0] / count[0] as f64).sqrt(), (squared[1] / count[1] as f64).sqrt()];
        eprintln!("Du/Dt relative rms error: stator {:.3e}, rotor {:.3e}", rms[0], rms[1]);
        assert!(rms[0] < 1e-12, "static cells: relative rms error {}", rms[0]);
        assert!(rms[1] < 0.6 * omega * dt, "turning cells: relative rms error {}", rms[1]);
    }
}
