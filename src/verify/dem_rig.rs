//! The reference DEM on a particle-only run of the step driver, opened below the step for the
//! impact checks of [`super::dem`], which drive single DEM sub-steps and watch every one.

use anyhow::anyhow;
use spillage_model::case::Case;
use spillage_model::closure::drag::FluidAtParticle;
use spillage_model::particles::{Particle, ParticleState};
use spillage_model::solver::{Solver, SolverError, StepReport};
use spillage_model::state::State;
use spillage_model::step::{Coupled, ParticlesOnly, RotorPose};
use spillage_model::walls::state::WallState;
use spillage_reference::dem::{ContactSample, ReferenceDem};

/// The reference DEM on a particle-only run of the step driver, with access below the step:
/// the impact checks drive single sub-steps and watch every one.
pub struct DemRig {
    run: ParticlesOnly<ReferenceDem>,
    /// The rotor at angle 0 (sub-steps place the rotor walls at ω t).
    rotor: Option<RotorPose>,
}

impl DemRig {
    pub fn dem(&self) -> &ReferenceDem {
        self.run.particle_phase().expect("a particle run")
    }
    pub fn particle_state(&self) -> &ParticleState {
        self.run.state().particles.as_ref().expect("a particle run")
    }
    pub fn particles(&self) -> &[Particle] {
        &self.particle_state().particles
    }
    pub fn walls(&self) -> &WallState {
        self.run.state().walls.as_ref().expect("a particle run")
    }
    pub fn step(&mut self) -> Result<StepReport, SolverError> {
        self.run.step()
    }
    pub fn substeps_for(&self, dt: f64) -> u64 {
        self.dem().substeps_for(dt, self.particles(), self.walls())
    }
    pub fn collision_time(&self) -> f64 {
        self.dem().collision_time(self.particles(), self.walls())
    }
    pub fn contact_samples(&self) -> &[ContactSample] {
        self.dem().contact_samples()
    }
    pub fn kinetic_energy(&self) -> f64 {
        self.particles().iter().map(|p| p.kinetic_energy()).sum()
    }
    /// One DEM sub-step from `t`, the particles seeing `fluid`.
    pub fn substep(&mut self, t: f64, dt: f64, fluid: &dyn Fn(&Particle) -> Option<FluidAtParticle>) {
        let rotor_end = self.rotor.map(|r| r.advanced(t + dt));
        let (_, dem, state) = self.run.parts_mut();
        let dem = dem.expect("a particle run");
        let (particles, walls) = (state.particles.as_mut().expect("a particle run"), state.walls.as_mut().expect("a particle run"));
        dem.substep(particles, walls, dt, t + dt, rotor_end.as_ref(), &|_, p| fluid(p));
    }
}

pub fn solver(case: &Case, particles: ParticleState) -> anyhow::Result<DemRig> {
    let located = |e: SolverError| anyhow!("{}: {e}", case.path.display());
    let mut state = State { particles: Some(particles), ..Default::default() };
    let mut dem = ReferenceDem::new(case, &mut state).map_err(located)?;
    dem.load_history(state.particles.as_ref().expect("set above"));
    let run = Coupled::new(case, state, None, Some(dem)).map_err(located)?;
    Ok(DemRig { run, rotor: RotorPose::from_case(case, 0.0) })
}
