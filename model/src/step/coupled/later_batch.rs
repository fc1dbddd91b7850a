//! The head batches placed once the water has turned ([`crate::particles::batch`]): step 2 of
//! the driver places those due and counts them at the fluid's earlier time levels.

use super::*;

impl<F: FluidPhase, P: ParticlePhase> Coupled<F, P> {
    /// Places the head batches due in the step of `ctx` ([`batch`]), with the blades where they
    /// stand at its start, and counts them as present at the fluid's earlier time levels.
    pub(super) fn place_due_batches(&mut self, ctx: &StepContext) -> Result<(), SolverError> {
        let (Some((head, _)), Some(rotor), Some(section), Some(particles)) = (&self.head, &self.rotor, &self.particle_section, self.state.particles.as_mut())
        else {
            return Ok(());
        };
        let first = particles.particles.len();
        for b in self.later_batches.iter().filter(|b| b.is_due(ctx.time, ctx.time_end())) {
            let at = format!("placing the batch at t = {:e} s: ", ctx.time);
            batch::place(section, rotor.omega, head, b, self.state.rotor_angle, particles).map_err(|e| field_error(&at, e))?;
        }
        if particles.particles.len() > first {
            self.count_batch_as_present(first, ctx)?;
        }
        Ok(())
    }

    /// Counts the batch just placed (the state's particles from `first` on) as present at the
    /// fluid's earlier time levels too, as a batch placed at the start is
    /// ([`Self::map_initial_fraction`]). Otherwise ∂α_c/∂t (fluid-dem-model.md T3.92) would read
    /// the rock's whole volume as appearing within one step, and the pressure equation would
    /// drive that volume of water out of the batch's cells as a burst (measured on the coarse
    /// test head: 10 Q_m out of the mouth in that step): the rock is placed, it does not
    /// displace the water within a step [R]. The batch is mapped with the mesh where it stood at
    /// the step's start, as the earlier levels were, then the mesh is turned to the step's end.
    fn count_batch_as_present(&mut self, first: usize, ctx: &StepContext) -> Result<(), SolverError> {
        let (Some(map), Some(f), Some(fluid), Some(p)) = (&self.mapping, self.fluid.as_mut(), self.state.fluid.as_mut(), &self.state.particles) else {
            return Ok(());
        };
        let batch = &p.particles[first..];
        let volumes = ParticleLoad { volume: batch.iter().map(|p| p.volume()).collect(), ..ParticleLoad::zeros(batch.len()) };
        let mut cells = CellLoad::default();
        f.place_rotor(ctx.rotor_start.as_ref())?;
        map.deposit(f.mesh(), batch, &volumes, &mut cells);
        f.place_rotor(ctx.rotor.as_ref())?;
        for level in [&mut fluid.alpha, &mut fluid.alpha_old, &mut fluid.alpha_old_old] {
            for (a, added) in level.iter_mut().zip(&cells.particle_fraction) {
                *a = (*a - added).max(map.min_fluid_fraction);
            }
        }
        Ok(())
    }
}
