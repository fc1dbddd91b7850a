//! A rock at rest next to turning cells (spillage_model::fluid::moving_cells): the rotor's cells
//! slide under the footprint of a rock held still in still water, so their α_c, which follows
//! them, changes while nothing moves. The water must stay at rest: the continuity takes the
//! rate at the cell's place, the particles' share of the mesh fluxes taken off. What is left
//! comes from the edge of the kernel's truncated footprint, which steps across the cells; the
//! check asks that the rock sees little of it on this mesh and on one twice as fine.

use super::*;
use spillage_model::mesh::Vec3;

/// The largest water speed the rock sees over the run (u_c|p, sampled through its kernel), over
/// α_p,max ω r_p: the speed a rock sweeping past the cells at their own speed would displace the
/// water with.
fn spurious_speed(case: &Case, solver: FluidSolver) -> Result<f64> {
    let trace = run(case, solver)?;
    let fluid = trace.state.fluid.as_ref().ok_or_else(|| anyhow!("no fluid state"))?;
    let speed = trace.seen_speed.iter().copied().fold(0.0, f64::max);
    let alpha_p = fluid.alpha.iter().map(|a| 1.0 - a).fold(0.0, f64::max);
    let particles = trace.state.particles.as_ref().ok_or_else(|| anyhow!("no particles"))?;
    let rock = particles.particles.first().ok_or_else(|| anyhow!("the case needs one held particle"))?;
    let rotor = case.rotor.as_ref().ok_or_else(|| anyhow!("{}: the check needs a turning [rotor]", case.path.display()))?;
    let axis = Vec3::from(rotor.axis).normalize();
    let from_origin = rock.position - Vec3::from(rotor.origin);
    let mesh_speed = rotor.angular_velocity().abs() * (from_origin - axis * from_origin.dot(&axis)).norm();
    if !(alpha_p > 0.0 && mesh_speed > 0.0) {
        bail!("{}: the rock must lie in turning cells (α_p,max {alpha_p}, cell speed at the rock {mesh_speed} m/s)", case.path.display());
    }
    Ok(speed / (alpha_p * mesh_speed))
}

pub(super) fn rock_at_rest(base: &Case, solver: FluidSolver) -> Result<Vec<CheckRow>> {
    let name = base.case.name.as_str();
    let tolerance = number(base, "tolerance")?;
    Ok(vec![
        CheckRow::at_most(name, "largest water speed at the rock / (α_p,max ω r_p)", solver.label(), spurious_speed(base, solver)?, tolerance),
        CheckRow::at_most(name, "the same on a mesh twice as fine", solver.label(), spurious_speed(&interface::refined(base, 2)?, solver)?, tolerance),
    ])
}
