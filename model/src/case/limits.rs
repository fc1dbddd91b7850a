//! Values outside physical sense, refused with the allowed range (issue 14 item 6: an inlet at
//! 1e308 m/s gave "Reynolds inf" and then "ok", 1e10 sub-steps per collision, 1e11 m particles,
//! a mesh 1e-300 m high). The sections' own checks say "finite and positive"; these say "a value
//! this model can mean". [`super::unusual`] warns about values inside these limits that are
//! still far from a dredger's.

use super::error::FieldError;
use super::{Case, MeshSection};
use crate::fluid::settings::{BoundaryCondition, InitialVelocity};
use crate::particles::settings::{Diameter, GroupSection};
use crate::walls::settings::MotionSection;

/// Largest speed [m/s]: the fluid is incompressible, which holds below about a third of the
/// speed of sound in water (1480 m/s); a particle or wall beyond it has blown up.
pub const SPEED_MAX: f64 = 500.0;
/// Shortest and longest length of a mesh [m]: below a micrometre a cell is below any particle
/// the model sizes (and its volume below 1e-18 m³ loses digits against the others); above 10 km
/// no dredger.
pub const LENGTH: (f64, f64) = (1e-6, 1e4);
/// Farthest coordinate [m]: positions beyond it lose the micrometre to round-off (1e5 · 2⁻⁵² ≈ 2e-11).
pub const COORDINATE_MAX: f64 = 1e5;
/// Particle diameters [m]: from fine silt to boulders larger than any cutter.
pub const DIAMETER: (f64, f64) = (1e-6, 10.0);
/// Densities [kg/m³] of particles and fluids: above every element (osmium 22 590).
pub const DENSITY_MAX: f64 = 1e5;
/// Young's modulus [Pa]: diamond is 1.2e12.
pub const YOUNGS_MAX: f64 = 1e13;
/// Kinematic viscosity [m²/s]: above molten glass at working temperature.
pub const VISCOSITY_MAX: f64 = 10.0;
/// DEM sub-steps per collision: 1 resolves nothing, more than 1000 resolves nothing more
/// (OpenFOAM's default is 10, the thesis' runs 10–50).
pub const STEPS_PER_COLLISION: (f64, f64) = (1.0, 1000.0);
/// Sub-steps per step with a fixed `particles.substep`, and steps per run.
pub const STEPS_MAX: f64 = 1e9;
/// DEM sub-steps per step from the collision time: each costs a contact search over every
/// particle, so 1e7 of them are hours per step.
pub const SUBSTEPS_MAX: f64 = 1e7;
/// Particles a group or a feed may make.
pub const PARTICLES_MAX: f64 = 1e7;
/// |g| [m/s²]: a centrifuge reaches 1e4 g; nothing here does.
pub const GRAVITY_MAX: f64 = 1e4;
/// Haul velocity of a cutter head [m/s]: ten times a prototype's fastest swing (0.2 m/s,
/// spillage-and-flow-verification.md §1.4 Tab. 2.1) and about the 1:4 head's tip speed at
/// 60 rpm. Beyond it the head is towed rather than swung, and the tank wall, the current's
/// Dirichlet far field (`cutter_head::current`), would have to lie far beyond any tank the
/// mesh can afford.
pub const HAUL_MAX: f64 = 2.0;

fn norm(v: &[f64; 3]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn at_most(key: &str, value: f64, max: f64, what: &str) -> Result<(), FieldError> {
    if value.abs() <= max {
        Ok(())
    } else {
        Err(FieldError::new(key, format!("{value:e}"), format!("{what} of at most {max:e}")))
    }
}

fn speed(key: &str, v: &[f64; 3]) -> Result<(), FieldError> {
    if norm(v) <= SPEED_MAX {
        Ok(())
    } else {
        Err(FieldError::new(key, format!("{v:?}"), format!("a velocity of at most {SPEED_MAX:e} m/s (the flow is incompressible)")))
    }
}

fn between(key: &str, value: f64, (lo, hi): (f64, f64), what: &str) -> Result<(), FieldError> {
    if value >= lo && value <= hi {
        Ok(())
    } else {
        Err(FieldError::new(key, format!("{value:e}"), format!("{what} from {lo:e} to {hi:e}")))
    }
}

fn diameter(key: &str, d: &Diameter) -> Result<(), FieldError> {
    between(key, d.smallest(), DIAMETER, "a diameter in m")?;
    between(key, d.largest(), DIAMETER, "a diameter in m")
}

fn coordinates(key: &str, p: &[f64; 3]) -> Result<(), FieldError> {
    match p.iter().find(|c| c.abs() > COORDINATE_MAX) {
        Some(c) => Err(FieldError::new(key, format!("{p:?}"), format!("coordinates within ±{COORDINATE_MAX:e} m (this one has {c:e})"))),
        None => Ok(()),
    }
}

/// The first value of `case` outside physical sense (the case has passed the sections' checks).
pub fn check(case: &Case) -> Result<(), FieldError> {
    at_most("physics.gravity", norm(&case.physics.gravity), GRAVITY_MAX, "an acceleration (m/s²)")?;
    let dt = case.time.dt.or(case.time.max_dt);
    if let (Some(dt), Some(end)) = (case.time.dt, case.time.end_time) {
        at_most("time.dt", end / dt, STEPS_MAX, &format!("a step giving a number of steps to end_time = {end} s"))?;
    }
    if let Some(n) = case.time.steps {
        at_most("time.steps", n as f64, STEPS_MAX, "a number of steps")?;
    }
    if let Some(fluid) = &case.fluid {
        at_most("fluid.density", fluid.density, DENSITY_MAX, "a density (kg/m³)")?;
        at_most("fluid.kinematic_viscosity", fluid.kinematic_viscosity, VISCOSITY_MAX, "a kinematic viscosity (m²/s)")?;
        if let InitialVelocity::Uniform { velocity } = &fluid.initial {
            speed("fluid.initial.velocity", velocity)?;
        }
    }
    if let Some(head) = &case.cutter_head {
        let v = norm(&head.haul_velocity);
        if v > HAUL_MAX {
            return Err(FieldError::new(
                "cutter_head.haul_velocity",
                format!("{:?} (|U| = {v:e} m/s)", head.haul_velocity),
                format!("a current of at most {HAUL_MAX} m/s (a dredger swings at 0.1–0.2 m/s, a 1:4 model at 0.05–0.1 m/s)"),
            ));
        }
    }
    // the farthest radius a wall or the rotor turns at
    let r_max = match &case.mesh {
        Some(mesh) => mesh_lengths(mesh)?,
        None => case.cutter_head.as_ref().map_or(0.0, |h| h.contour.iter().map(|p| p[1]).fold(0.0, f64::max)),
    };
    for (name, bc) in &case.boundary {
        let key = format!("boundary.{name}");
        match bc {
            BoundaryCondition::Wall { velocity, angular_velocity, .. } => {
                speed(&format!("{key}.velocity"), velocity)?;
                at_most(&format!("{key}.angular_velocity"), angular_velocity * r_max, SPEED_MAX, "a surface speed ω·r (m/s)")?;
            }
            BoundaryCondition::VelocityInlet { velocity, .. } => speed(&format!("{key}.velocity"), velocity)?,
            BoundaryCondition::PressureOutlet { .. } | BoundaryCondition::Symmetry => {}
        }
    }
    if let Some(rotor) = &case.rotor {
        let key = if rotor.omega.is_some() { "rotor.omega" } else { "rotor.rpm" };
        at_most(key, rotor.angular_velocity() * r_max, SPEED_MAX, &format!("a rotor whose tip at r = {r_max} m moves at a speed (m/s)"))?;
    }
    if let Some(p) = &case.particles {
        between("particles.steps_per_collision", p.steps_per_collision, STEPS_PER_COLLISION, "a number of sub-steps per collision")?;
        at_most("particles.collision_speed", p.collision_speed, SPEED_MAX, "a speed (m/s)")?;
        if let (Some(sub), Some(dt)) = (p.substep, dt) {
            at_most("particles.substep", dt / sub, STEPS_MAX, &format!("a sub-step giving a number of sub-steps per step of {dt} s"))?;
        }
        if let (None, Some(dt)) = (p.substep, dt) {
            // the sub-step of the smallest, stiffest pair at the collision speed, as the DEM
            // sets it (spec §7.6; `spillage check` prints it)
            let d_min = p.feed.iter().map(|f| f.diameter.smallest()).chain(p.groups.iter().map(|g| group_diameter(g).smallest())).fold(f64::INFINITY, f64::min);
            let stiffest = p
                .materials
                .iter()
                .map(|m| (m.density, m.contact_youngs_modulus() / (2.0 * (1.0 - m.poisson_ratio * m.poisson_ratio))))
                .fold((0.0, 0.0), |a: (f64, f64), b| (a.0.max(b.0), a.1.max(b.1)));
            if d_min.is_finite() && stiffest.1 > 0.0 {
                let t_col = crate::closure::collision_time::collision_time(stiffest.0, stiffest.1, 0.25 * d_min, p.collision_speed);
                let key = if case.time.dt.is_some() { "time.dt" } else { "time.max_dt" };
                at_most(
                    key,
                    dt * p.steps_per_collision / t_col,
                    SUBSTEPS_MAX,
                    &format!("a step giving DEM sub-steps (collisions last {t_col:.3e} s) per step"),
                )?;
            }
        }
        for (i, m) in p.materials.iter().enumerate() {
            at_most(&format!("particles.materials.{i}.density"), m.density, DENSITY_MAX, "a density (kg/m³)")?;
            at_most(&format!("particles.materials.{i}.youngs_modulus"), m.youngs_modulus, YOUNGS_MAX, "a Young's modulus (Pa)")?;
        }
        if let Some(a) = &p.ambient {
            at_most("particles.ambient.density", a.density, DENSITY_MAX, "a density (kg/m³)")?;
            at_most("particles.ambient.kinematic_viscosity", a.kinematic_viscosity, VISCOSITY_MAX, "a kinematic viscosity (m²/s)")?;
        }
        for (i, g) in p.groups.iter().enumerate() {
            let key = format!("particles.groups.{i}");
            match g {
                GroupSection::List { diameter: d, positions, velocities, spins: _, .. } => {
                    diameter(&format!("{key}.diameter"), d)?;
                    at_most(&format!("{key}.positions"), positions.len() as f64, PARTICLES_MAX, "a number of particles")?;
                    for (j, x) in positions.iter().enumerate() {
                        coordinates(&format!("{key}.positions.{j}"), x)?;
                    }
                    for (j, v) in velocities.iter().enumerate() {
                        speed(&format!("{key}.velocities.{j}"), v)?;
                    }
                }
                GroupSection::Lattice { diameter: d, region, spacing, velocity, .. } => {
                    diameter(&format!("{key}.diameter"), d)?;
                    coordinates(&format!("{key}.region.min"), &region.min)?;
                    coordinates(&format!("{key}.region.max"), &region.max)?;
                    let count: f64 = (0..3).map(|k| ((region.max[k] - region.min[k]) / spacing).floor() + 1.0).product();
                    at_most(&format!("{key}.spacing"), count, PARTICLES_MAX, "a spacing giving a number of particles in the region")?;
                    speed(&format!("{key}.velocity"), velocity)?;
                }
                GroupSection::HeadLattice { diameter: d, .. } => diameter(&format!("{key}.diameter"), d)?,
                GroupSection::Random { diameter: d, region, count, velocity, .. } => {
                    diameter(&format!("{key}.diameter"), d)?;
                    coordinates(&format!("{key}.region.min"), &region.min)?;
                    coordinates(&format!("{key}.region.max"), &region.max)?;
                    at_most(&format!("{key}.count"), *count as f64, PARTICLES_MAX, "a number of particles")?;
                    speed(&format!("{key}.velocity"), velocity)?;
                }
            }
        }
        for (i, f) in p.feed.iter().enumerate() {
            let key = format!("particles.feed.{i}");
            diameter(&format!("{key}.diameter"), &f.diameter)?;
            speed(&format!("{key}.velocity"), &f.velocity)?;
            coordinates(&format!("{key}.region.min"), &f.region.min)?;
            coordinates(&format!("{key}.region.max"), &f.region.max)?;
            at_most(&format!("{key}.rate"), f.rate, PARTICLES_MAX, "a rate (particles per second)")?;
        }
    }
    for (i, w) in case.walls.iter().enumerate() {
        match &w.motion {
            MotionSection::Translate { velocity } => speed(&format!("walls.{i}.motion.velocity"), velocity)?,
            MotionSection::Rotate { omega, .. } => at_most(&format!("walls.{i}.motion.omega"), *omega, SPEED_MAX / LENGTH.0, "an angular velocity (rad/s)")?,
            MotionSection::Static | MotionSection::Rotor => {}
        }
    }
    Ok(())
}

/// Refuses a mesh of absurd size; returns its largest radius (0 for a box).
fn mesh_lengths(mesh: &MeshSection) -> Result<f64, FieldError> {
    let length = |key: &str, value: f64| between(key, value, LENGTH, "an extent (the difference to the value before it) in m");
    match mesh {
        MeshSection::Box { min, max, .. } => {
            coordinates("mesh.min", min)?;
            coordinates("mesh.max", max)?;
            for k in 0..3 {
                length("mesh.max", max[k] - min[k])?;
            }
            Ok(0.0)
        }
        MeshSection::Annulus { r_inner, r_outer, z_min, z_max, .. } => {
            length("mesh.r_inner", *r_inner)?;
            length("mesh.r_outer", r_outer - r_inner)?;
            coordinates("mesh.z_min", &[0.0, 0.0, *z_min])?;
            length("mesh.z_max", z_max - z_min)?;
            Ok(*r_outer)
        }
        MeshSection::RotorStator { r_inner, r_interface, r_outer, z_min, z_max, .. } => {
            length("mesh.r_inner", *r_inner)?;
            length("mesh.r_interface", r_interface - r_inner)?;
            length("mesh.r_outer", r_outer - r_interface)?;
            coordinates("mesh.z_min", &[0.0, 0.0, *z_min])?;
            length("mesh.z_max", z_max - z_min)?;
            Ok(*r_outer)
        }
    }
}

fn group_diameter(g: &GroupSection) -> &Diameter {
    match g {
        GroupSection::List { diameter, .. }
        | GroupSection::Lattice { diameter, .. }
        | GroupSection::HeadLattice { diameter, .. }
        | GroupSection::Random { diameter, .. } => diameter,
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use crate::case::Case;

    fn edited(file: &str, from: &str, to: &str) -> Result<Case, String> {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases").join(file);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains(from), "{file} holds {from}");
        Case::from_toml(&text.replacen(from, to, 1), Path::new(file)).map_err(|e| e.to_string())
    }

    /// Issue 14 item 6: each value `check` accepted, now refused naming the key, the value and
    /// the allowed range.
    #[test]
    fn absurd_values_are_refused_with_the_allowed_range() {
        let inlet = "verification/fluid/poiseuille_inlet_outlet.toml";
        let err = edited(inlet, "velocity = [1.0, 0.0, 0.0]", "velocity = [1e308, 0.0, 0.0]").unwrap_err();
        assert!(err.contains(":27:12: key `boundary.x_min.velocity` = [1e308, 0.0, 0.0]") && err.contains("at most 5e2"), "{err}");
        let err = edited("pour.toml", "steps_per_collision = 12", "steps_per_collision = 1e10").unwrap_err();
        assert!(err.contains("key `particles.steps_per_collision` = 1e10") && err.contains("from 1e0 to 1e3"), "{err}");
        let err = edited("pour.toml", "diameter = { min = 0.015, max = 0.02 }", "diameter = { min = 0.015, max = 1e11 }").unwrap_err();
        assert!(err.contains("key `particles.feed.0.diameter` = 1e11") && err.contains("from 1e-6 to 1e1"), "{err}");
        let err = edited("rotor_stator.toml", "z_max = 0.1", "z_max = 1e-300").unwrap_err();
        assert!(err.contains("key `mesh.z_max` = 1e-300") && err.contains("from 1e-6 to 1e4"), "{err}");
        let err = edited("rotor_stator.toml", "omega = 1.0", "omega = 1e300").unwrap_err();
        assert!(err.contains("key `rotor.omega`"), "{err}");
        let err = edited("pour.toml", "dt = 1e-3", "dt = 1e-300").unwrap_err();
        assert!(err.contains("key `time.dt`"), "{err}");
        let err = edited("pour.toml", "dt = 1e-3", "dt = 1e4").unwrap_err();
        assert!(err.contains("key `time.dt`") && err.contains("DEM sub-steps"), "{err}");
        let err = edited("pour.toml", "density = 2650.0", "density = 1e300").unwrap_err();
        assert!(err.contains("key `particles.materials.0.density`"), "{err}");
    }

    /// Merely unusual values pass with a warning naming the key.
    #[test]
    fn unusual_values_are_warned_about() {
        let case = edited("pour.toml", "steps_per_collision = 12", "steps_per_collision = 800").unwrap();
        let warnings = crate::case::unusual::warnings(&case);
        assert!(warnings.iter().any(|w| w.starts_with("particles.steps_per_collision = 800")), "{warnings:?}");
        let case = edited("verification/fluid/poiseuille_inlet_outlet.toml", "velocity = [1.0, 0.0, 0.0]", "velocity = [100.0, 0.0, 0.0]").unwrap();
        let warnings = crate::case::unusual::warnings(&case);
        assert!(warnings.iter().any(|w| w.starts_with("boundary.x_min.velocity")), "{warnings:?}");
        assert!(crate::case::unusual::warnings(&edited("pour.toml", "", "").unwrap()).is_empty());
    }
}
