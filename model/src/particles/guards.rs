//! What stops a DEM step whose contacts or energy mean nothing (issue 14 item 4), shared by both
//! particle phases so they stop on the same faults with the same words: overlaps beyond
//! [`MAX_OVERLAP_RATIO`], contacts without a direction, and steps that create energy
//! ([`EnergyBudget`]).

use super::state::{Particle, Partner, Vec3};
use crate::solver::SolverError;
use crate::step::StepContext;
use crate::walls::state::Wall;

/// Largest overlap of a contact as a fraction of the particle's radius (of the smaller one for
/// a pair). Hertz's law assumes overlaps far below the radius (≲ 1 %); the softened rock of the
/// thesis' cutter runs (E = 10 MPa) reaches ≈ 30 % in a 5 m/s impact (measured: 9 % at the
/// end of steps of the fed cutter head). At half the radius the contact circle is 70 % of the
/// sphere's and the model means nothing: a particle started inside a wall or tunnelling
/// through another, which a run must not finish as `completed` (issue 14 item 4). Particles
/// fed in the step are exempt for that step: a feed outside a cutter head does not avoid the
/// walls, and places a particle up to its radius into a turning blade (one_way_rotor.toml puts
/// one 60 % in at step 17); its push out is the feed's doing.
pub const MAX_OVERLAP_RATIO: f64 = 0.5;

/// Energy a step may create beyond what gravity, the fluid and the moving walls supplied, as a
/// fraction of the step's energy scale (kinetic and elastic energy at its ends, the work
/// supplied, and every particle at the case's collision speed). Measured over the shipped DEM,
/// coupled and wear cases: at most 1.3e-5 (a disc dragging a sphere), 3.6e-4 in 150 steps of
/// the cutter head fed with rock (cutter_head_feed.toml); the elastic energy
/// estimated through the damped force errs by at most its damping part. A blow-up multiplies
/// the energy many times over (6.6e-4 J → 2 111 J).
pub const ENERGY_GAIN_MAX: f64 = 0.1;

/// What makes a sub-step's contacts meaningless: the first one found stops the run (pairs in
/// ascending ids first, then walls by particle id and wall index).
#[derive(Clone, Debug, PartialEq)]
pub enum Fault {
    /// Two particle centres at one point: no contact normal exists.
    Coincident { particle: u64, other: u64, position: Vec3 },
    /// A particle's centre on a wall's surface: no contact normal exists.
    CentreOnWall { particle: u64, wall: u32, position: Vec3 },
    /// An overlap beyond [`MAX_OVERLAP_RATIO`] of the radius.
    Overlap { particle: u64, partner: Partner, ratio: f64, position: Vec3 },
}

impl Fault {
    /// In words, the walls by their names.
    pub fn describe(&self, walls: &[Wall]) -> String {
        let at = |p: &Vec3| format!("[{:e}, {:e}, {:e}] m", p.x, p.y, p.z);
        let wall = |w: &u32| walls.get(*w as usize).map_or(format!("wall {w}"), |x| format!("wall `{}`", x.name));
        match self {
            Fault::Coincident { particle, other, position } => {
                format!("particles {particle} and {other} have their centres at the same point {} (no contact direction)", at(position))
            }
            Fault::CentreOnWall { particle, wall: w, position } => format!("particle {particle} at {} has its centre on {} (no contact direction)", at(position), wall(w)),
            Fault::Overlap { particle, partner, ratio, position } => format!(
                "particle {particle} at {} overlaps {} by {ratio:.3} of its radius (at most {MAX_OVERLAP_RATIO}: started inside it, or a step too long for the collision)",
                at(position),
                match partner {
                    Partner::Particle(id) => format!("particle {id}"),
                    Partner::Wall(w) => wall(w),
                }
            ),
        }
    }
}

/// The fault of a pair contact, if any (`a` the particle with the smaller id; `fed`: either was
/// fed in this step, exempt from the overlap limit). `distance` is |x_b − x_a|.
pub fn pair_fault(a: &Particle, b: &Particle, distance: f64, overlap: f64, fed: bool) -> Option<Fault> {
    if distance == 0.0 {
        return Some(Fault::Coincident { particle: a.id, other: b.id, position: a.position });
    }
    if overlap > MAX_OVERLAP_RATIO * a.radius().min(b.radius()) && !fed {
        let (small, other) = if a.radius() <= b.radius() { (a, b) } else { (b, a) };
        return Some(Fault::Overlap { particle: small.id, partner: Partner::Particle(other.id), ratio: overlap / small.radius(), position: small.position });
    }
    None
}

/// A step's energy balance (issue 14 item 4: a sphere started on a wall went from 6.6e-4 J to
/// 2 111 J and the run ended `completed`). Contacts only store and return energy (Hertz springs)
/// or dissipate it (damping, friction); everything else that changes the kinetic energy is
/// measured where it acts: gravity, the fluid and the rotating frame in the fluid-force update,
/// the moving walls as Σ F·v_wall dt. So kinetic plus stored elastic energy may grow by at
/// most what those supplied.
#[derive(Clone, Debug, Default)]
pub struct EnergyBudget {
    /// Work of the non-contact forces in this step [J] (kinetic-energy change of their updates).
    pub external: f64,
    /// Work of the moving walls in this step [J].
    pub walls: f64,
    /// Elastic energy of the first touches of particles fed in this step: where the feed put
    /// them, not what a contact made [J].
    pub placed: f64,
    /// Elastic energy stored at the end of the last step [J]; `None` before the first step of
    /// this phase (a restart's contacts are unknown until their first evaluation).
    pub elastic_end: Option<f64>,
    /// Kinetic energy of each particle at the start of the step (reused).
    pub start: Vec<f64>,
}

impl EnergyBudget {
    /// Starts a step: the particles' kinetic energies now, nothing supplied yet.
    pub fn start_step(&mut self, particles: &[Particle]) {
        self.start.clear();
        self.start.extend(particles.iter().map(|p| p.kinetic_energy()));
        (self.external, self.walls, self.placed) = (0.0, 0.0, 0.0);
    }

    /// Ends a step: an error naming the particle whose kinetic energy grew most when the step
    /// created energy. `elastic_end`: the energy stored in the contacts of the last sub-step;
    /// `elastic_start`: the stored energy at the step's start when known without the last step
    /// (0 when no contact is in the history).
    pub fn check(
        &mut self,
        ctx: &StepContext,
        particles: &[Particle],
        elastic_end: f64,
        elastic_start: Option<f64>,
        collision_speed: f64,
    ) -> Result<(), SolverError> {
        let (kinetic_start, kinetic_end): (f64, f64) = (self.start.iter().sum(), particles.iter().map(|p| p.kinetic_energy()).sum());
        let Some(elastic_start) = self.elastic_end.replace(elastic_end).or(elastic_start) else { return Ok(()) };
        let supplied = self.external + self.walls + self.placed;
        let gain = (kinetic_end + elastic_end) - (kinetic_start + elastic_start) - supplied;
        let at_collision_speed: f64 = particles.iter().map(|p| 0.5 * p.mass() * collision_speed.powi(2)).sum();
        let scale = kinetic_start + kinetic_end + elastic_start + elastic_end + self.external.abs() + self.walls.abs() + self.placed + at_collision_speed;
        if gain <= ENERGY_GAIN_MAX * scale {
            return Ok(());
        }
        let worst = particles.iter().zip(&self.start).max_by(|a, b| (a.0.kinetic_energy() - a.1).total_cmp(&(b.0.kinetic_energy() - b.1)));
        let culprit = worst.map_or(String::new(), |(p, start)| {
            format!(
                "; particle {} at [{:e}, {:e}, {:e}] m went from {start:.3e} J to {:.3e} J",
                p.id,
                p.position.x,
                p.position.y,
                p.position.z,
                p.kinetic_energy()
            )
        });
        Err(SolverError::Diverged {
            step: ctx.step,
            time: ctx.time_end(),
            what: format!(
                "the particles' kinetic energy grew from {kinetic_start:.3e} J to {kinetic_end:.3e} J, {gain:.3e} J more than gravity, the fluid, the moving walls and new contacts supplied ({supplied:.3e} J) and the contacts had stored ({elastic_start:.3e} J){culprit}"
            ),
        })
    }
}

/// The fault of a wall contact, if any: `distance` from the particle's centre to the wall's
/// closest point, `overlap` = r − distance (`fed`: fed in this step, exempt from the overlap
/// limit).
pub fn wall_fault(p: &Particle, wall: u32, distance: f64, overlap: f64, fed: bool) -> Option<Fault> {
    if distance <= 1e-12 * p.radius() {
        return Some(Fault::CentreOnWall { particle: p.id, wall, position: p.position });
    }
    if overlap > MAX_OVERLAP_RATIO * p.radius() && !fed {
        return Some(Fault::Overlap { particle: p.id, partner: Partner::Wall(wall), ratio: overlap / p.radius(), position: p.position });
    }
    None
}
