//! DEM checks with walls and many particles (issue #5): moving walls, a tessellated plane, a pile.

use super::*;

/// Check 5: moving walls. `kind = "resting"`: a sphere resting on a rotating disc ends up with
/// its contact point moving with the disc surface (the sticking limit); `kind = "impact"`: a
/// sphere at rest hit by a rotating blade leaves at (1 + e) times the blade's surface speed at
/// the contact point (rigid, infinitely massive wall).
pub(super) fn moving_wall(case: &Case) -> anyhow::Result<Vec<CheckRow>> {
    let name = &case.case.name;
    let kind = params(case)
        .get("kind")
        .and_then(|v| v.as_str())
        .ok_or_else(|| anyhow!("{}: verify.params.kind must be \"resting\" or \"impact\"", case.path.display()))?;
    let (omega, axis, origin) = match case.walls.first().map(|w| &w.motion) {
        Some(spillage_model::walls::settings::MotionSection::Rotate { omega, axis, origin }) => (*omega, Vec3::from(*axis).normalize(), Vec3::from(*origin)),
        _ => bail!("{}: this check needs a rotating first wall", case.path.display()),
    };
    let state = particles(case)?;
    let p0 = state.particles[0].clone();
    let mut dem = solver(case, state)?;
    let mut rows = Vec::new();
    match kind {
        "resting" => {
            let steps = case.time.steps.ok_or_else(|| anyhow!("{}: needs time.steps", case.path.display()))?;
            for _ in 0..steps {
                dem.step().map_err(|e| anyhow!("{e}"))?;
            }
            let p = &dem.particles()[0];
            let normal = -axis; // the sphere rests on the disc, whose axis points up
            let contact = p.position + p.radius() * normal;
            let contact_velocity = p.velocity + p.spin.cross(&(p.radius() * normal));
            let r = contact - origin;
            let surface = (omega * axis).cross(&(r - axis * r.dot(&axis)));
            let slip = (contact_velocity - surface).norm() / surface.norm();
            // Sticking limit: the residual is the decaying elastic oscillation of the tangential
            // spring; 1e-3 of the surface speed.
            rows.push(CheckRow::at_most(name, "contact-point slip / disc surface speed", SOLVER, slip, 1e-3));
            rows.push(CheckRow::absolute(name, "contacts with the disc", SOLVER, p.contacts as f64, 1.0, 0.0));
        }
        "impact" => {
            let e = materials(case)?[p0.material].restitution;
            let rel = p0.position - origin;
            let rho = (rel - axis * rel.dot(&axis)).norm();
            let surface_speed = omega.abs() * (rho * rho - p0.radius() * p0.radius()).sqrt();
            let outer = case.time.dt.ok_or_else(|| anyhow!("needs time.dt"))?;
            let dt = outer / dem.substeps_for(outer) as f64;
            let (mut t, mut touched) = (0.0, false);
            for _ in 0..10_000_000u64 {
                dem.substep(t, dt, &no_fluid);
                t += dt;
                let contacts = dem.contact_samples().len();
                if contacts > 0 {
                    touched = true;
                } else if touched {
                    break;
                }
            }
            if !touched {
                bail!("{}: the blade never hit the sphere", case.path.display());
            }
            let speed = dem.particles()[0].velocity.norm();
            // 1 %: the blade turns by ω t_col during the contact.
            rows.push(CheckRow::relative(name, "rebound speed / blade surface speed", SOLVER, speed / surface_speed, 1.0 + e, 0.01));
            let impact = dem.particle_state().impacts.first().ok_or_else(|| anyhow!("no impact logged"))?;
            rows.push(CheckRow::relative(name, "logged impact normal speed / blade surface speed", SOLVER, impact.normal_speed / surface_speed, 1.0, 0.01));
            rows.push(CheckRow::absolute(name, "logged impact angle [°]", SOLVER, impact.angle.to_degrees(), 90.0, 1.0));
        }
        other => bail!("{}: verify.params.kind = {other:?}; expected \"resting\" or \"impact\"", case.path.display()),
    }
    Ok(rows)
}

/// Check 6: a sphere sliding and rolling across a finely tessellated plane (edges and vertices)
/// feels the same force as on the same plane made of one quad whose diagonal it never crosses.
pub(super) fn tessellated_plane(case: &Case) -> anyhow::Result<Vec<CheckRow>> {
    let name = &case.case.name;
    let mut flat = case.clone();
    match flat.walls.first_mut().map(|w| &mut w.shape) {
        Some(ShapeSection::Plane { divisions, .. }) => *divisions = [1, 1],
        _ => bail!("{}: this check needs a plane as its first wall", case.path.display()),
    }
    let steps = case.time.steps.ok_or_else(|| anyhow!("{}: needs time.steps", case.path.display()))?;
    let trace = |case: &Case| -> anyhow::Result<(Vec<Vec3>, usize, Vec<Particle>)> {
        let mut dem = solver(case, particles(case)?)?;
        let outer = case.time.dt.ok_or_else(|| anyhow!("needs time.dt"))?;
        let mut forces = Vec::new();
        let mut max_contacts = 0;
        for _ in 0..steps {
            let n = dem.substeps_for(outer);
            let dt = outer / n as f64;
            for k in 0..n {
                dem.substep(k as f64 * dt, dt, &no_fluid);
                forces.push(dem.particles()[0].contact_force);
                max_contacts = max_contacts.max(dem.contact_samples().len());
            }
        }
        Ok((forces, max_contacts, dem.particles().to_vec()))
    };
    let (tess, tess_contacts, tess_end) = trace(case)?;
    let (exact, exact_contacts, exact_end) = trace(&flat)?;
    if tess.len() != exact.len() {
        bail!("different sub-step counts");
    }
    let scale = exact.iter().map(|f| f.norm()).fold(0.0, f64::max);
    let worst = tess.iter().zip(&exact).map(|(a, b)| (a - b).norm()).fold(0.0, f64::max) / scale;
    // 1e-9 (issue #5): the same contact on any triangle, up to round-off of the projection.
    let mut rows = vec![CheckRow::at_most(name, "max |F_tessellated − F_plane| / max |F_plane|", SOLVER, worst, 1e-9)];
    rows.push(CheckRow::absolute(name, "most contacts at once (tessellated)", SOLVER, tess_contacts as f64, 1.0, 0.0));
    rows.push(CheckRow::absolute(name, "most contacts at once (one quad)", SOLVER, exact_contacts as f64, 1.0, 0.0));
    let travelled = (exact_end[0].position - particles(case)?.particles[0].position).norm();
    rows.push(CheckRow::at_most(
        name,
        "end position difference / distance travelled",
        SOLVER,
        (tess_end[0].position - exact_end[0].position).norm() / travelled,
        1e-9,
    ));
    Ok(rows)
}

/// Check 7: spheres poured into a box come to rest inside it, and none is lost. The coarse
/// level keeps the first `coarse_count` spheres.
pub(super) fn pile(case: &Case, full: bool) -> anyhow::Result<Vec<CheckRow>> {
    let name = &case.case.name;
    let (min, max) = match case.walls.first().map(|w| &w.shape) {
        Some(ShapeSection::Box { min, max, .. }) => (Vec3::from(*min), Vec3::from(*max)),
        _ => bail!("{}: this check needs a box as its first wall", case.path.display()),
    };
    let mut state = particles(case)?;
    if !full {
        let keep = number(case, "coarse_count")? as usize;
        state.particles.truncate(keep);
        state.counts.created = state.particles.len() as u64;
    }
    let count = state.particles.len();
    let mut dem = solver(case, state)?;
    let steps = case.time.steps.ok_or_else(|| anyhow!("{}: needs time.steps", case.path.display()))?;
    // The full pile is deeper and takes longer to settle.
    let steps = if full { params(case).get("full_steps").and_then(|v| v.as_integer()).map(|n| n as u64).unwrap_or(steps) } else { steps };
    let mut peak: f64 = 0.0;
    for _ in 0..steps {
        dem.step().map_err(|e| anyhow!("{}: {e}", case.path.display())).context("pile run")?;
        peak = peak.max(dem.kinetic_energy());
    }
    let ps = dem.particle_state();
    let inside = ps.particles.iter().filter(|p| (0..3).all(|k| p.position[k] > min[k] && p.position[k] < max[k])).count();
    let g = Vec3::from(case.physics.gravity).norm();
    let scale: f64 = ps.particles.iter().map(|p| p.mass() * g * p.diameter).sum();
    let max_overlap = dem.contact_samples().iter().map(|s| s.overlap / s.radius).fold(0.0, f64::max);
    let rest = number(case, "rest_kinetic_energy")?;
    Ok(vec![
        // At rest: kinetic energy against the energy of lifting every sphere by one diameter.
        CheckRow::at_most(name, "final kinetic energy / Σ m g d", SOLVER, dem.kinetic_energy() / scale, rest),
        CheckRow::absolute(name, "spheres inside the box", SOLVER, inside as f64, count as f64, 0.0),
        CheckRow::absolute(name, "created − present − escaped", SOLVER, ps.counts.created as f64 - ps.particles.len() as f64 - ps.escaped() as f64, 0.0, 0.0),
        CheckRow::absolute(name, "escaped", SOLVER, ps.escaped() as f64, 0.0, 0.0),
        // Softened contacts must still stay small against the radius (§7.6).
        CheckRow::at_most(name, "largest overlap / radius at rest", SOLVER, max_overlap, 0.05),
        CheckRow::at_least(name, "peak kinetic energy / Σ m g d (the pour happened)", SOLVER, peak / scale, 0.1),
    ])
}
