//! Steps 2–5 of the driver, the particles' part of a step, in the order they run: the feeds
//! place what they owe ([`bookkeeping::feed`]) and the solids pressure corrects the velocities
//! ([`SolidsPressure::correct`]); each particle samples the fluid it sees for the whole step;
//! the DEM sub-steps take particles and walls to tⁿ⁺¹ ([`ParticlePhase::advance`]); the particles
//! that left are removed and logged, and a cutter head's counts are checked to be conserved.

use super::*;

impl<F: FluidPhase, P: ParticlePhase> Coupled<F, P> {
    /// Steps 2–5 (the batches due are placed before, [`Self::place_due_batches`]). Returns the
    /// particles' load on the fluid, `None` without a particle phase or when the phase returns
    /// none (one-way coupling).
    pub(super) fn advance_particles(&mut self, ctx: &StepContext, report: &mut StepReport) -> Result<Option<ParticleLoad>, SolverError> {
        if self.particles.is_none() {
            return Ok(None);
        }
        self.feed_particles(ctx);
        self.correct_solids_pressure(ctx, report)?;
        self.sample_fluid();
        let mut load = self.run_dem(ctx, report)?;
        self.remove_exited(ctx, load.as_mut());
        self.report_particle_counts(ctx, report)?;
        Ok(load)
    }

    /// Step 2: the particles the feeds owe for this step. A head's blades turn: a new particle
    /// must be inside the contour (or it would count as spilled at once) and clear of the blades
    /// at both ends of the step.
    fn feed_particles(&mut self, ctx: &StepContext) {
        let section = self.particle_section.as_ref().expect("a particle phase has a [particles] section");
        let particles = self.state.particles.as_mut().expect("checked in new");
        let head = self.head.as_ref().map(|(h, _)| h);
        let angles = ctx.rotor.map(|r| [self.state.rotor_angle, r.angle]);
        bookkeeping::feed(section, particles, ctx.time, ctx.dt, |p, radius| match (head, angles) {
            (Some(head), Some(angles)) => {
                let r = p.x.hypot(p.y);
                head.inside_hull(r + radius, p.z) && angles.iter().all(|a| head.sphere_is_clear(r, p.y.atan2(p.x) - a, p.z, radius))
            }
            _ => true,
        });
    }

    /// Step 2, with `[particles.solids_pressure]` and a fluid: the KTGF correction of the
    /// particles' velocities.
    fn correct_solids_pressure(&mut self, ctx: &StepContext, report: &mut StepReport) -> Result<(), SolverError> {
        let (Some(solids), Some(fluid), Some(section), Some(particles)) =
            (self.solids_pressure.as_mut(), &self.fluid, &self.particle_section, self.state.particles.as_mut())
        else {
            return Ok(());
        };
        let done = solids.correct(fluid.mesh(), &mut particles.particles, section.modifier, ctx.dt).map_err(|e| diverged(ctx, e.to_string()))?;
        report.values.extend([
            ("solids_fraction_max", done.largest_fraction),
            ("solids_fraction_max_after", done.largest_fraction_after),
            ("solids_pressure_correction_max", done.largest_correction),
            ("solids_pressure_iterations", done.iterations as f64),
        ]);
        Ok(())
    }

    /// Step 3: the fluid each particle sees, held for the whole step (§5.10): through the
    /// coupling's kernel when there is one, else from the containing cell; without a fluid, the
    /// still `[particles.ambient]`.
    fn sample_fluid(&mut self) {
        let particles = self.state.particles.as_ref().expect("checked in new");
        self.samples.clear();
        match (&self.fluid, &self.state.fluid, &self.mapping) {
            (Some(fluid), Some(fluid_state), Some(map)) => {
                map.sample_with(&mut self.stencils, &fluid.sample_source(fluid_state), &particles.particles, &mut self.samples)
            }
            (Some(fluid), Some(fluid_state), None) => sample_containing_cell(&fluid.sample_source(fluid_state), &particles.particles, &mut self.samples),
            _ => self.samples.resize(particles.particles.len(), self.ambient),
        }
    }

    /// Step 4: the DEM sub-steps. The load must come back one entry per particle, and no
    /// particle may come back non-finite.
    fn run_dem(&mut self, ctx: &StepContext, report: &mut StepReport) -> Result<Option<ParticleLoad>, SolverError> {
        let phase = self.particles.as_mut().expect("checked by the caller");
        let particles = self.state.particles.as_mut().expect("checked in new");
        let walls = self.state.walls.as_mut().expect("checked in new");
        let load = phase.advance(ctx, particles, walls, &self.samples, report)?;
        if let Some(l) = &load {
            if [l.volume.len(), l.implicit_drag.len(), l.explicit_force.len()].iter().any(|&n| n != particles.particles.len()) {
                return Err(unsupported(format!(
                    "the particle phase returned a load for {} particles, but there are {}",
                    l.volume.len(),
                    particles.particles.len()
                )));
            }
        }
        if let Some(p) = particles.particles.iter().find(|p| !(p.position.iter().chain(p.velocity.iter()).chain(p.spin.iter()).all(|v| v.is_finite()))) {
            return Err(diverged(
                ctx,
                format!(
                    "particle {} has a non-finite value: position {:?} m, velocity {:?} m/s, spin {:?} rad/s",
                    p.id,
                    p.position.as_slice(),
                    p.velocity.as_slice(),
                    p.spin.as_slice()
                ),
            ));
        }
        Ok(load)
    }

    /// Step 5: the particles that left are removed and logged with their route, together with
    /// their entries of the load and of the samples (both stay in particle order, for output).
    fn remove_exited(&mut self, ctx: &StepContext, load: Option<&mut ParticleLoad>) {
        let section = self.particle_section.as_ref().expect("a particle phase has a [particles] section");
        let particles = self.state.particles.as_mut().expect("checked in new");
        let mesh = self.fluid.as_ref().map(|f| f.mesh());
        let closed = &self.closed_patches;
        // a receding wall's crater lies beyond the fluid mesh (which does not follow the
        // wear), as deep as the wall has receded: a particle in it has not left
        let crater = self.state.wear.as_ref().map_or(0.0, |w| w.walls.iter().flat_map(|w| &w.node_depth).fold(0.0, |a: f64, d| a.max(*d)));
        let domain = section.domain.as_ref();
        let head = self.head.as_ref().map(|(h, _)| h);
        let (mut index, mut gone) = (0, Vec::new());
        bookkeeping::remove_exited(particles, load, ctx.time_end(), |p| {
            let route = match head {
                // a head's particles leave by its rules (its solids' staircase cells are
                // no exit)
                Some(head) => exit_route(domain, None, &[], &p.position, p.diameter).or_else(|| spillage::exit_route(head, &p.position)),
                None => exit_route(domain, mesh, closed, &p.position, p.diameter + crater),
            };
            if route.is_some() {
                gone.push(index);
            }
            index += 1;
            route
        });
        if !gone.is_empty() {
            let mut i = 0;
            self.samples.retain(|_| {
                i += 1;
                gone.binary_search(&(i - 1)).is_err()
            });
        }
    }

    /// The step's particle columns of `series.csv`; a cutter head's counts must be conserved
    /// exactly (issue 16 check 4). Every step reports the same columns (the series has one
    /// header): 0 while a feed has not placed any particle yet.
    fn report_particle_counts(&self, ctx: &StepContext, report: &mut StepReport) -> Result<(), SolverError> {
        let particles = self.state.particles.as_ref().expect("checked in new");
        report.values.push(("particles", particles.particles.len() as f64));
        report.values.push(("escaped", particles.escaped() as f64));
        if self.head.is_some() {
            let counts = SpillageCounts::from_exits(&particles.exits);
            let created = particles.counts.created;
            if created != particles.particles.len() as u64 + counts.sucked + counts.spilled + counts.other {
                return Err(diverged(
                    ctx,
                    format!(
                        "particle counts not conserved: {created} created, {} inside, {} sucked, {} spilled, {} left otherwise",
                        particles.particles.len(),
                        counts.sucked,
                        counts.spilled,
                        counts.other
                    ),
                ));
            }
            let fraction = |n: u64| if created > 0 { n as f64 / created as f64 } else { 0.0 };
            report.values.extend([
                ("sucked", counts.sucked as f64),
                ("spilled", counts.spilled as f64),
                ("production", fraction(counts.sucked)),
                ("spillage", fraction(counts.spilled)),
            ]);
        }
        report.values.push(("impacts", particles.counts.impacts as f64));
        if let Some(down) = self.down {
            let settling = if particles.particles.is_empty() { 0.0 } else { median(particles.particles.iter().map(|p| p.velocity.dot(&down)).collect()) };
            report.values.push(("settling_velocity", settling));
        }
        Ok(())
    }
}
