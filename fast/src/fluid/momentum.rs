//! Steps 4a–4c of the algorithm (module doc of `spillage_reference::fluid`, reference
//! `momentum`): boundary velocities, the momentum matrix assembled as per-link coefficients
//! gathered per cell in ascending link order, and the predictor solve M u = b − V∇P* for every
//! solved component (Jacobi-BiCGStab).

use spillage_model::closure::rotating_frame::RotatingFrame;
use spillage_model::fluid::conditions::Condition;
use spillage_model::fluid::frozen_rotor::FrozenRotor;
use spillage_model::mesh::Vec3;
use spillage_model::solver::SolverError;
use spillage_model::turbulence::Viscosity;
use spillage_model::wear::fluid_mesh::receding_slip_velocity;

use super::assembly::{convection_weight, directional, explicit_stress, interpolate_tensor, par_for, vec_of, Out};
use super::buffers::{MomentumLinkCoefficients, MomentumSystem};
use super::settings::{unconverged, worst_cell, SolveCounts};
use super::step_inputs::{Discretisation, StepConstants};
use crate::linear::bicgstab::BiCgStab;
use crate::linear::{par_update, Tolerance};

/// Velocity of every boundary face from the latest cell `velocity`: the fixed velocity where the
/// condition fixes one, the tangential part of the cell velocity on symmetry faces, the cell
/// velocity elsewhere (zero gradient); a receding symmetry face's normal speed on a deforming mesh.
pub fn boundary_velocities(disc: &Discretisation, fixed_velocity: &[Vec3], velocity: &[Vec<f64>; 3], boundary_velocity: &mut [Vec3]) {
    let bnd = disc.boundary;
    for b in 0..bnd.len() {
        let cell_velocity = vec_of(velocity, bnd.cell[b] as usize);
        boundary_velocity[b] = if !fixed_velocity[b].x.is_nan() {
            fixed_velocity[b]
        } else if let Condition::Symmetry = disc.condition(b) {
            if disc.deforming {
                receding_slip_velocity(cell_velocity, bnd.area[b], bnd.mesh_flux[b])
            } else {
                let normal = bnd.area[b].normalize();
                cell_velocity - normal * cell_velocity.dot(&normal)
            }
        } else {
            cell_velocity
        };
    }
}

/// What the momentum matrix is assembled from.
pub struct MomentumInputs<'a> {
    pub step: StepConstants<'a>,
    /// ν, or ν + ν_t of the turbulence model (as the reference's `StepInputs::viscosity`).
    pub viscosity: Viscosity<'a>,
    /// Kinematic body force (gravity + `[numerics] body_force`) [m/s²].
    pub body_force: Vec3,
    /// The case's rotating frame, if any, and the cell centres it is evaluated at: the source
    /// gets α_c(−2Ω×u* − Ω×(Ω×(x_c − x₀)))V, Coriolis in the latest outer iterate u*, as in the
    /// reference (`spillage_reference::fluid::momentum` doc, wear-model.md §2.6 [R]).
    pub rotating_frame: Option<&'a RotatingFrame>,
    pub cell_centres: &'a [Vec3],
    /// The frame term of a frozen-rotor step, −α_c Ω×u* V in the rotor zone's cells
    /// (`in_rotor`), as in the reference (spillage_model::fluid::frozen_rotor).
    pub frozen_rotor: Option<FrozenRotor>,
    pub in_rotor: &'a [bool],
    /// Latest velocity u*, and uᵒ, uᵒᵒ (old levels in the source), by component.
    pub velocity: &'a [Vec<f64>; 3],
    pub velocity_old: &'a [Vec<f64>; 3],
    pub velocity_old_old: &'a [Vec<f64>; 3],
    /// ∇u* per cell, g[i][j] = ∂u_j/∂x_i.
    pub velocity_gradient: &'a [[Vec3; 3]],
    /// What the `limited_linear` limiter reads: the two above, or the step's first iterate's
    /// ([`spillage_model::fluid::settings::LimiterUpdate`]).
    pub limiter_velocity: &'a [Vec<f64>; 3],
    pub limiter_gradient: &'a [[Vec3; 3]],
    pub boundary_velocity: &'a [Vec3],
    /// Latest fluxes φ* per link and per boundary face.
    pub link_flux: &'a [f64],
    pub boundary_flux: &'a [f64],
}

/// Assembles the relaxed momentum matrix and its source (reference `momentum::assemble`): per
/// link the convection and diffusion coefficients and the explicit viscous flux, then per cell
/// the time term, the gathered link terms, the boundary terms and the implicit under-relaxation.
pub fn assemble(inputs: &MomentumInputs, links_out: &mut MomentumLinkCoefficients, system: &mut MomentumSystem) {
    let StepConstants { disc, time, alpha, numerics, particles } = inputs.step;
    let (viscosity, body_force) = (inputs.viscosity, inputs.body_force);
    let n_internal_faces = disc.links.n_internal;
    let (rotating_frame, cell_centres) = (inputs.rotating_frame, inputs.cell_centres);
    let (frozen_rotor, in_rotor) = (inputs.frozen_rotor, inputs.in_rotor);
    let links = disc.links;
    let (velocity, gradient) = (inputs.velocity, inputs.velocity_gradient);
    {
        let link_flux = inputs.link_flux;
        let (owner_row, neighbour_row, viscous) =
            (Out::of(&mut links_out.owner_row), Out::of(&mut links_out.neighbour_row), Out::of(&mut links_out.explicit_viscous_flux));
        par_for(links.len(), |l| {
            let (p, q) = (links.owner[l] as usize, links.neighbour[l] as usize);
            let alpha_f = links.interpolate(l, alpha.current[p], alpha.current[q]);
            let relative_flux = link_flux[l] - links.mesh_flux[l];
            let owner_weight = convection_weight(
                numerics.convection,
                numerics.linear_fraction,
                links.weight[l],
                &links.delta[l],
                relative_flux,
                vec_of(inputs.limiter_velocity, p),
                vec_of(inputs.limiter_velocity, q),
                |owner_upwind| inputs.limiter_gradient[if owner_upwind { p } else { q }],
            );
            let diffusivity = viscosity.face(links.weight[l], p, q) * alpha_f;
            let diffusion = diffusivity * links.laplacian[l];
            let gradient_f = interpolate_tensor(links.weight[l], &gradient[p], &gradient[q]);
            let explicit = directional(&gradient_f, &links.non_orthogonal[l]) * diffusivity + explicit_stress(&gradient_f, &links.area[l]) * diffusivity;
            unsafe {
                owner_row.set(l, alpha_f * relative_flux * (1.0 - owner_weight) - diffusion);
                neighbour_row.set(l, -alpha_f * relative_flux * owner_weight - diffusion);
                viscous.set(l, explicit);
            }
        });
    }
    let [c0, c1, c2] = time.coefficients;
    let dt = time.dt;
    let (vol, adj, bnd) = (disc.cell_volumes, disc.adjacency, disc.boundary);
    let relax = numerics.relax_velocity;
    let (owner_row, neighbour_row, viscous) = (&links_out.owner_row, &links_out.neighbour_row, &links_out.explicit_viscous_flux);
    let (velocity_old, velocity_old_old) = (inputs.velocity_old, inputs.velocity_old_old);
    let (boundary_flux, boundary_velocity) = (inputs.boundary_flux, inputs.boundary_velocity);
    let (out_diagonal, out_source, out_values) = (Out::of(&mut system.matrix.diag), Out::of(&mut system.source), Out::of(&mut system.matrix.val));
    par_for(disc.n_cells(), |c| {
        let v = vol[c];
        let mut diag = c0 * alpha.current[c] * v / dt;
        // (a deforming mesh steps Euler, c₂ = 0, with Vⁿ on the old level)
        let mut source =
            -(vec_of(velocity_old, c) * (c1 * alpha.old[c]) + vec_of(velocity_old_old, c) * (c2 * alpha.old_old[c])) * (disc.cell_volumes_old[c] / dt);
        source += body_force * v;
        if let Some(frame) = rotating_frame {
            source += frame.fictitious_acceleration(vec_of(velocity, c), cell_centres[c]) * (alpha.current[c] * v);
        }
        if let Some(frozen) = frozen_rotor.filter(|_| in_rotor[c]) {
            source += frozen.acceleration(vec_of(velocity, c)) * (alpha.current[c] * v);
        }
        if let Some(particles) = particles {
            diag += particles.implicit_drag[c];
            source += particles.explicit_force[c];
        }
        for k in adj.row_start[c] as usize..adj.row_start[c + 1] as usize {
            let e = adj.entry[k] as usize;
            let l = e >> 1;
            if e & 1 == 1 {
                diag -= neighbour_row[l];
                source += viscous[l];
                unsafe { out_values.set(k, owner_row[l]) };
            } else {
                diag -= owner_row[l];
                source -= viscous[l];
                unsafe { out_values.set(k, neighbour_row[l]) };
            }
        }
        for &b in disc.boundary_faces_of(c) {
            let b = b as usize;
            let alpha_p = alpha.current[c];
            let relative_flux = boundary_flux[b] - bnd.mesh_flux[b];
            let diffusivity = viscosity.boundary(bnd.face[b] as usize - n_internal_faces) * alpha_p;
            let diffusion = diffusivity * bnd.area[b].norm() / bnd.normal_distance[b];
            match disc.condition(b) {
                // the mouth's share lets the water out at the cell's velocity, the rest is the
                // plate at rest (reference fluid momentum.rs)
                Condition::FixedVelocity { suction: Some(window), .. } => diag += alpha_p * relative_flux + (1.0 - window.share(&bnd.centre[b])) * diffusion,
                Condition::FixedVelocity { .. } => {
                    source -= boundary_velocity[b] * (alpha_p * relative_flux);
                    diag += diffusion;
                    source += boundary_velocity[b] * diffusion;
                }
                Condition::FixedPressure { .. } => diag += alpha_p * relative_flux,
                Condition::Symmetry => {
                    diag += diffusion;
                    source += boundary_velocity[b] * diffusion;
                }
            }
            source += explicit_stress(&gradient[c], &bnd.area[b]) * diffusivity;
        }
        let relaxed = diag / relax;
        source += vec_of(velocity, c) * (relaxed - diag);
        unsafe {
            out_diagonal.set(c, relaxed);
            out_source.set(c, source);
        }
    });
}

/// The momentum solver, its controls and the step's counters.
pub struct MomentumSolve<'a> {
    pub solver: &'a mut BiCgStab,
    pub tolerance: Tolerance,
    pub counts: &'a mut SolveCounts,
}

/// Momentum predictor: solves M u = b − V∇P* for every solved component of `velocity`
/// (starting from it), with `rhs` as the right-hand side buffer.
pub fn predict(
    disc: &Discretisation,
    system: &MomentumSystem,
    pressure_gradient: &[Vec3],
    rhs: &mut [Vec<f64>; 3],
    velocity: &mut [Vec<f64>; 3],
    solve: MomentumSolve,
) -> Result<(), SolverError> {
    let vol = disc.cell_volumes;
    for j in 0..3 {
        if !disc.solved[j] {
            continue;
        }
        let source = &system.source;
        par_update(&mut rhs[j][..], |c, r| *r = source[c][j] - vol[c] * pressure_gradient[c][j]);
        let clock = std::time::Instant::now();
        let stats = solve.solver.solve(&system.matrix, &rhs[j], &mut velocity[j], solve.tolerance);
        solve.counts.momentum_seconds += clock.elapsed().as_secs_f64();
        solve.counts.momentum_iterations += stats.iterations;
        let failure = if !stats.final_residual.is_finite() { Some("residual not finite".to_string()) } else { unconverged(&stats, solve.tolerance) };
        if let Some(message) = failure {
            let place = worst_cell(&system.matrix, &rhs[j], &velocity[j], disc.cell_centres);
            return Err(SolverError::LinearSolve(format!("momentum predictor (component {j}): {message}; {place}")));
        }
    }
    Ok(())
}
