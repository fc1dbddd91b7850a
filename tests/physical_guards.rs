//! Physical guards of a run (issue 14 item 4): blow-ups stop with an error naming the step, the
//! time and the particle or cell with its position, instead of finishing as `completed`; the
//! initial placements that cause them are refused by `check` and `run`.

use std::path::Path;

use spillage_model::case::Case;
use spillage_model::particles::state::Vec3;
use spillage_model::solver::{Solver, SolverError};
use spillage_model::state::State;
use spillage_model::step::{Absent, Coupled};
use spillage_reference::dem::ReferenceDem;
use spillage_reference::fluid::ReferenceFluid;

/// Glass spheres (d = 1 cm) at `positions` above a plate, no gravity.
fn spheres(positions: &str) -> String {
    format!(
        r#"
[case]
name = "guards"
[physics]
gravity = [0.0, 0.0, 0.0]
[time]
dt = 1e-4
steps = 20
[particles]
steps_per_collision = 20
[[particles.materials]]
name = "glass"
density = 2540.0
youngs_modulus = 60e9
poisson_ratio = 0.23
restitution = 0.9
friction = 0.15
[[particles.groups]]
placement = "list"
material = "glass"
diameter = 0.01
positions = {positions}
[[walls]]
name = "plate"
material = "glass"
shape = {{ type = "plane", centre = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0], size = [0.1, 0.1], divisions = [4, 4] }}
"#
    )
}

fn case(text: &str) -> Case {
    Case::from_toml(text, Path::new("guards.toml")).unwrap_or_else(|e| panic!("{e}"))
}

fn dem_run(case: &Case, edit: impl FnOnce(&mut State)) -> Coupled<Absent, ReferenceDem> {
    let mut state = State::default();
    let dem = ReferenceDem::new(case, &mut state).unwrap();
    edit(&mut state);
    Coupled::particles_only(case, state, dem).unwrap()
}

/// The error of the first failing step among `steps`.
fn first_error(run: &mut dyn Solver, steps: usize) -> SolverError {
    for _ in 0..steps {
        if let Err(e) = run.step() {
            return e;
        }
    }
    panic!("{steps} steps ran without an error")
}

/// Reproduced first: a sphere with its centre on the plate went from 6.6e-4 J to 2 005 J in
/// the first step and the run finished. `check` and `run` refuse the placement; a state that
/// gets there anyway stops at the sub-step that meets it.
#[test]
fn a_sphere_started_on_a_wall_is_refused_and_stops_a_run() {
    let on_wall = case(&spheres("[[0.0, 0.0, 0.0]]"));
    let err = spillage_model::particles::placement::check_initial_placement(&on_wall, Path::new(".")).unwrap_err();
    assert_eq!(err.key, "particles.groups.0.positions.0");
    assert!(err.value.contains("wall `plate`"), "{err:?}");

    // a sphere just above the plate, moved onto it (and 0.1 mm above it, overlapping 80 %)
    let above = case(&spheres("[[0.0, 0.0, 0.0051]]"));
    assert!(spillage_model::particles::placement::check_initial_placement(&above, Path::new(".")).is_ok());
    for (z, expected) in [(0.0, "has its centre on wall `plate`"), (0.001, "overlaps wall `plate` by 0.800 of its radius")] {
        let mut run = dem_run(&above, |s| s.particles.as_mut().unwrap().particles[0].position.z = z);
        let err = first_error(&mut run, 3);
        let text = err.to_string();
        assert!(matches!(err, SolverError::Diverged { step: 1, .. }), "{text}");
        assert!(text.contains(expected) && text.contains("particle 0 at [0e0, 0e0,"), "{text}");
        assert!(text.contains("DEM sub-step 1 of"), "{text}");
    }
}

/// Reproduced first: two spheres at one position ran 200 steps with 0 contacts.
#[test]
fn two_spheres_at_one_position_are_refused_and_stop_a_run() {
    let same = case(&spheres("[[0.0, 0.0, 0.05], [0.0, 0.0, 0.05]]"));
    let err = spillage_model::particles::placement::check_initial_placement(&same, Path::new(".")).unwrap_err();
    assert_eq!(err.key, "particles.groups.0.positions.0");
    assert!(err.value.contains("at the same position as particle 1") && err.value.contains("particles.groups.0.positions.1"), "{err:?}");
    let apart = case(&spheres("[[0.0, 0.0, 0.05], [0.0, 0.0, 0.07]]"));
    let mut run = dem_run(&apart, |s| s.particles.as_mut().unwrap().particles[1].position.z = 0.05);
    let err = first_error(&mut run, 3).to_string();
    assert!(err.contains("step 1") && err.contains("particles 0 and 1 have their centres at the same point [0e0, 0e0, 5e-2] m"), "{err}");
    // nearly coincident: an overlap of almost two radii
    let mut run = dem_run(&apart, |s| s.particles.as_mut().unwrap().particles[1].position.z = 0.0501);
    let err = first_error(&mut run, 3).to_string();
    assert!(err.contains("overlaps particle") && err.contains("of its radius"), "{err}");
}

/// Energy from nowhere (a forged stored contact force of 1 kN on a free sphere) stops the step
/// that gains it, naming the particle.
#[test]
fn kinetic_energy_beyond_what_gravity_and_walls_supply_stops_the_run() {
    let free = case(&spheres("[[0.0, 0.0, 0.05]]"));
    let mut run = dem_run(&free, |_| {});
    run.step().unwrap();
    run.parts_mut().2.particles.as_mut().unwrap().particles[0].contact_force = Vec3::new(1e3, 0.0, 0.0);
    let err = run.step().unwrap_err().to_string();
    assert!(err.contains("at step 2") && err.contains("kinetic energy grew") && err.contains("particle 0 at ["), "{err}");
    // the same sphere falling onto the plate and bouncing: gravity's work, no error
    let falling = case(&spheres("[[0.0, 0.0, 0.0051]]").replace("gravity = [0.0, 0.0, 0.0]", "gravity = [0.0, 0.0, -9.81]"));
    let mut run = dem_run(&falling, |_| {});
    for _ in 0..200 {
        run.step().unwrap();
    }
}

/// A non-finite fluid value names the field, the cell and its centre.
#[test]
fn a_non_finite_fluid_value_names_the_field_and_the_cell() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/verification/fluid/poiseuille_inlet_outlet.toml");
    let case = Case::load(&path).unwrap();
    let mut state = State::default();
    let mesh = spillage_model::mesh::for_case(&case).unwrap().unwrap();
    let fluid = ReferenceFluid::new(&case, mesh, &mut state).unwrap();
    let mut run = Coupled::fluid_only(&case, state, fluid).unwrap();
    run.parts_mut().2.fluid.as_mut().unwrap().pressure[3] = f64::NAN;
    let err = run.step().unwrap_err().to_string();
    assert!(err.contains("step 1") && err.contains("the fluid pressure of cell 3 at [") && err.contains("is NaN"), "{err}");
}
