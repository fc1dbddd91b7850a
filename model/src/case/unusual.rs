//! Values a case may hold but rarely means: `spillage check` warns about them (issue 14 item 6).
//! The limits beyond which a value is refused are [`super::limits`].

use super::Case;
use crate::fluid::settings::BoundaryCondition;

/// Speed above which a dredger's flow is unusual [m/s]: cutter tips move at 2–5 m/s, suction
/// pipes carry 3–8 m/s.
const FAST: f64 = 50.0;
/// Sub-steps per collision outside this range resolve a collision poorly or waste sub-steps
/// (the verification cases resolve theirs with 400).
const STEPS_PER_COLLISION: (f64, f64) = (5.0, 500.0);
/// Particle diameters outside this range [m] are not rock, gravel or sand.
const DIAMETER: (f64, f64) = (1e-5, 1.0);
/// Particle densities outside this range [kg/m³] are neither rock nor any mineral.
const DENSITY: (f64, f64) = (500.0, 25_000.0);
/// Steps above which a run takes days.
const MANY_STEPS: f64 = 1e7;
/// Haul velocity above which a swing is unusual [m/s]: prototypes swing at 0.1–0.2 m/s, the
/// 1:4 model at 0.05–0.1 m/s (spillage-and-flow-verification.md §1.4, Tab. 2.1).
const FAST_HAUL: f64 = 0.5;

/// Warnings about allowed but unusual values, each naming the key, the value and why.
pub fn warnings(case: &Case) -> Vec<String> {
    let mut out = Vec::new();
    let norm = |v: &[f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    for (name, bc) in &case.boundary {
        let v = match bc {
            BoundaryCondition::Wall { velocity, .. } | BoundaryCondition::VelocityInlet { velocity, .. } => norm(velocity),
            _ => 0.0,
        };
        if v > FAST {
            out.push(format!("boundary.{name}.velocity: {v:e} m/s is fast for a dredger (above {FAST} m/s)"));
        }
    }
    if let Some(head) = &case.cutter_head {
        let v = norm(&head.haul_velocity);
        if v > FAST_HAUL {
            out.push(format!(
                "cutter_head.haul_velocity: {v} m/s is a fast swing (above {FAST_HAUL} m/s; prototypes 0.1–0.2, the 1:4 model 0.05–0.1 m/s): a larger tank.radius keeps the far field away from the head"
            ));
        }
    }
    let steps = match (case.time.dt, case.time.end_time, case.time.steps) {
        (_, _, Some(n)) => n as f64,
        (Some(dt), Some(end), None) => end / dt,
        _ => 0.0,
    };
    if steps > MANY_STEPS {
        out.push(format!("time: {steps:e} steps (above {MANY_STEPS:e}): a run of days; a larger time.dt?"));
    }
    if let Some(p) = &case.particles {
        let (lo, hi) = STEPS_PER_COLLISION;
        if p.substep.is_none() && !(lo..=hi).contains(&p.steps_per_collision) {
            out.push(format!("particles.steps_per_collision = {}: usually {lo} to {hi}", p.steps_per_collision));
        }
        for (i, m) in p.materials.iter().enumerate() {
            if !(DENSITY.0..=DENSITY.1).contains(&m.density) {
                out.push(format!("particles.materials.{i}.density = {} kg/m³: usually {} to {}", m.density, DENSITY.0, DENSITY.1));
            }
        }
        let diameters = p.feed.iter().enumerate().map(|(i, f)| (format!("particles.feed.{i}.diameter"), &f.diameter));
        let groups = p.groups.iter().enumerate().map(|(i, g)| {
            use crate::particles::settings::GroupSection::*;
            let d = match g {
                List { diameter, .. } | Lattice { diameter, .. } | HeadLattice { diameter, .. } | Random { diameter, .. } => diameter,
            };
            (format!("particles.groups.{i}.diameter"), d)
        });
        for (key, d) in diameters.chain(groups) {
            if d.smallest() < DIAMETER.0 || d.largest() > DIAMETER.1 {
                out.push(format!("{key}: {}…{} m is outside the usual {}…{} m", d.smallest(), d.largest(), DIAMETER.0, DIAMETER.1));
            }
        }
        for (i, f) in p.feed.iter().enumerate() {
            if norm(&f.velocity) > FAST {
                out.push(format!("particles.feed.{i}.velocity: {:e} m/s is fast for a dredger (above {FAST} m/s)", norm(&f.velocity)));
            }
        }
    }
    out
}
