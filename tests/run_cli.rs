//! The `spillage` program as a user runs it: results folders that ParaView and scripts can read,
//! restarts that continue bit-for-bit, results independent of the thread count, and bad input
//! that gets a clear error instead of a panic.

use std::path::{Path, PathBuf};
use std::process::Command;

use spillage_model::output::series::read_series;
use spillage_model::output::summary::Summary;
use spillage_model::output::vtk::{read_pvd, read_vtk};

mod common;
use common::{scratch, spillage};

/// [`fluid_case`] with `[numerics]` settings (TOML lines).
fn fluid_case_with_numerics(dir: &Path, steps: u64, numerics: &str) -> PathBuf {
    let case = fluid_case(dir, steps);
    let text = std::fs::read_to_string(&case).unwrap().replace("[output]", &format!("[numerics]\n{numerics}\n[output]"));
    std::fs::write(&case, text).unwrap();
    case
}

/// A small rotor/stator case (sliding interface, BDF2) of `steps` steps.
fn fluid_case(dir: &Path, steps: u64) -> PathBuf {
    let text = format!(
        r#"
[case]
name = "small_rotor"
[time]
dt = 0.1
steps = {steps}
write_every = 2
[fluid]
density = 1000.0
kinematic_viscosity = 0.02
[mesh]
generator = "rotor_stator"
r_inner = 1.0
r_interface = 1.5
r_outer = 2.0
z_min = 0.0
z_max = 0.1
n_r_rotor = 3
n_r_stator = 3
n_theta_rotor = 16
n_theta_stator = 20
two_d = true
[rotor]
omega = 1.0
[boundary.inner]
type = "wall"
rotating = true
[boundary.outer]
type = "wall"
[output]
checkpoint_every = 3
plots = false
"#
    );
    let path = dir.join("small_rotor.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// A small pour of spheres into a box (particles only).
fn particle_case(dir: &Path, steps: u64) -> PathBuf {
    let text = format!(
        r#"
[case]
name = "small_pour"
[time]
dt = 1e-3
steps = {steps}
write_every = 20
[particles]
domain = {{ min = [-0.1, -0.1, -0.1], max = [0.3, 0.3, 0.7] }}
[[particles.materials]]
name = "rock"
density = 2650.0
youngs_modulus = 60e9
poisson_ratio = 0.24
softening = 6000.0
restitution = 0.5
friction = 0.5
[[particles.feed]]
material = "rock"
diameter = {{ min = 0.015, max = 0.02 }}
region = {{ min = [0.02, 0.02, 0.05], max = [0.18, 0.18, 0.2] }}
rate = 2000.0
end = 0.05
seed = 3
[[walls]]
name = "box"
material = "rock"
shape = {{ type = "box", min = [0.0, 0.0, 0.0], max = [0.2, 0.2, 0.6], divisions = 2, open = ["+z"] }}
[output]
checkpoint_every = 60
plots = false
"#
    );
    let path = dir.join("small_pour.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// One rock settling in a small 2-D box of water, two-way coupled (`[coupling]`).
fn settling_case(dir: &Path) -> PathBuf {
    let text = r#"
[case]
name = "small_settling"
[physics]
gravity = [0.0, -9.81, 0.0]
[time]
dt = 0.001
end_time = 0.01
write_every = 5
[fluid]
density = 998.2
kinematic_viscosity = 1.0034e-6
[mesh]
generator = "box"
min = [0.0, 0.0, 0.0]
max = [0.1, 0.2, 0.02]
cells = [5, 10, 1]
two_d = true
[boundary.x_min]
type = "wall"
[boundary.x_max]
type = "wall"
[boundary.y_min]
type = "wall"
[boundary.y_max]
type = "wall"
[coupling]
method = "kernel"
[particles]
substep = 0.001
[[particles.materials]]
name = "rock"
density = 2650.0
youngs_modulus = 1e7
poisson_ratio = 0.25
restitution = 0.5
friction = 0.3
[[particles.groups]]
placement = "list"
material = "rock"
diameter = 0.01
positions = [[0.05, 0.15, 0.01]]
[output]
plots = false
"#;
    let path = dir.join("small_settling.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn run_ok(args: &[&str]) {
    let out = spillage(args);
    assert!(out.status.success(), "spillage {args:?} failed:\n{}", String::from_utf8_lossy(&out.stderr));
}

fn checkpoint(dir: &Path, step: u64) -> Vec<u8> {
    std::fs::read(dir.join("checkpoints").join(format!("step_{step:08}.ckpt"))).expect("checkpoint written")
}

#[test]
fn a_fluid_run_writes_files_paraview_and_scripts_can_read() {
    let dir = scratch("fluid-files");
    let case = fluid_case(&dir, 4);
    let out = dir.join("out");
    run_ok(&["run", case.to_str().unwrap(), "--out", out.to_str().unwrap()]);

    let frames = read_pvd(&out.join("fluid.pvd")).unwrap();
    assert_eq!(frames.iter().map(|f| f.time).collect::<Vec<_>>().len(), 3, "frames at steps 0, 2, 4");
    let first = read_vtk(&out.join(&frames[0].file)).unwrap();
    let last = read_vtk(&out.join(&frames[2].file)).unwrap();
    let velocity = first.cell_field("velocity").and_then(|f| f.as_vectors()).expect("velocity vectors");
    assert_eq!(velocity.len(), 3 * (16 + 20), "one velocity per cell");
    // The rotor turned by ω·t = 0.4 rad between the first and the last frame: its points moved,
    // the stator's did not.
    let moved = first.points.iter().zip(&last.points).filter(|(a, b)| a != b).count();
    assert!(moved > 0 && moved < first.points.len(), "{moved} of {} points moved", first.points.len());

    let series = read_series(&out.join("series.csv")).unwrap();
    assert_eq!(series.rows.len(), 4);
    assert_eq!(&series.columns[..3], &["step", "time", "dt"]);
    let imbalance = series.column("interface_imbalance").expect("interface column");
    assert!(imbalance.iter().all(|v| *v <= 1e-12), "interface flux imbalance {imbalance:?}");

    let summary = Summary::read(&out.join("summary.json")).unwrap();
    assert_eq!(summary.details["status"], "completed");
    assert_eq!(summary.results["final_step"], 4.0);
    assert!(summary.results["microseconds_per_cell_step"] > 0.0);
}

#[test]
fn a_restarted_fluid_run_continues_bit_for_bit_with_either_solver() {
    let dir = scratch("fluid-restart");
    let case = fluid_case(&dir, 6);
    for solver in ["fast", "reference"] {
        let (whole, resumed) = (dir.join(format!("whole-{solver}")), dir.join(format!("resumed-{solver}")));
        run_ok(&["run", case.to_str().unwrap(), "--solver", solver, "--out", whole.to_str().unwrap()]);
        let mid = whole.join("checkpoints").join("step_00000003.ckpt");
        run_ok(&["run", case.to_str().unwrap(), "--solver", solver, "--out", resumed.to_str().unwrap(), "--restart", mid.to_str().unwrap()]);
        assert!(checkpoint(&whole, 6) == checkpoint(&resumed, 6), "{solver}: restart from step 3 diverged from the uninterrupted run");
        let summary = Summary::read(&resumed.join("summary.json")).unwrap();
        assert_eq!(summary.solver, solver);
    }
}

/// Restarting into the results folder of the interrupted run keeps its series up to the restart
/// step and continues it: one row per step, steps 1…N in order, the rows after the restart
/// recomputed (issue 14, item 1: the step column used to be compared with the restart time, so
/// most rows were dropped).
#[test]
fn a_restart_into_the_same_folder_keeps_the_series() {
    let dir = scratch("series-restart");
    let case = fluid_case(&dir, 6);
    let (whole, same) = (dir.join("whole"), dir.join("same"));
    run_ok(&["run", case.to_str().unwrap(), "--out", whole.to_str().unwrap()]);
    run_ok(&["run", case.to_str().unwrap(), "--out", same.to_str().unwrap()]);
    let mid = same.join("checkpoints").join("step_00000003.ckpt");
    run_ok(&["run", case.to_str().unwrap(), "--out", same.to_str().unwrap(), "--restart", mid.to_str().unwrap()]);
    let (a, b) = (read_series(&whole.join("series.csv")).unwrap(), read_series(&same.join("series.csv")).unwrap());
    assert_eq!(b.column("step").unwrap(), vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    assert_eq!(a.column("time").unwrap(), b.column("time").unwrap());
    assert_eq!(a.column("kinetic_energy").unwrap(), b.column("kinetic_energy").unwrap(), "the continued series differs from the uninterrupted one");
}

/// `--threads` above the machine's cores is capped with a note (issue 15, item 7: 99 999 worker
/// threads were started).
#[test]
fn more_threads_than_cores_are_capped_with_a_note() {
    let dir = scratch("threads");
    let case = fluid_case(&dir, 1);
    let out = spillage(&["run", case.to_str().unwrap(), "--out", dir.join("o").to_str().unwrap(), "--threads", "99999"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("more than the"), "no note: {}", String::from_utf8_lossy(&out.stderr));
    let summary = Summary::read(&dir.join("o").join("summary.json")).unwrap();
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    assert_eq!(summary.details["threads"], cores as u64);
}

#[test]
fn a_restarted_particle_run_continues_bit_for_bit_with_its_contacts() {
    let dir = scratch("dem-restart");
    let case = particle_case(&dir, 180);
    let (whole, resumed) = (dir.join("whole"), dir.join("resumed"));
    run_ok(&["run", case.to_str().unwrap(), "--out", whole.to_str().unwrap()]);
    let mid = whole.join("checkpoints").join("step_00000120.ckpt");
    run_ok(&["run", case.to_str().unwrap(), "--out", resumed.to_str().unwrap(), "--restart", mid.to_str().unwrap()]);
    assert!(checkpoint(&whole, 180) == checkpoint(&resumed, 180), "restart from step 120 diverged");
    let series = read_series(&whole.join("series.csv")).unwrap();
    let contacts = series.column("contacts").unwrap();
    assert!(contacts[119] > 0.0, "the restart must happen with contacts open to test their history");
    let frames = read_pvd(&whole.join("particles.pvd")).unwrap();
    let last = read_vtk(&whole.join(&frames.last().unwrap().file)).unwrap();
    for field in ["id", "diameter", "velocity", "angular_velocity", "contacts"] {
        assert!(last.point_field(field).is_some(), "particle field {field} missing");
    }
    // a fast DEM run names the pair kernel this processor took (its speed depends on it)
    let summary = Summary::read(&whole.join("summary.json")).unwrap();
    let kernel = summary.details["dem_pair_kernel"].as_str().expect("dem_pair_kernel in the summary");
    assert!(["AVX-512, eight pairs a group", "AVX, four pairs a group", "portable lanes, four pairs a group"].contains(&kernel), "{kernel}");
    // particles without a fluid take no drag law, so no drag lanes are named
    assert!(!summary.details.contains_key("dem_drag_kernel"), "a dry run names drag lanes");
}

/// A two-way coupled run writes what the phases exchange (issue 13, output): α_c and the
/// particles' force density per cell, the fluid velocity, drag and slip Reynolds number per
/// particle, and the settling velocity in the series.
#[test]
fn a_two_way_coupled_run_writes_the_coupling_fields() {
    let dir = scratch("two-way");
    let case = settling_case(&dir);
    let out = dir.join("out");
    let run = spillage(&["run", case.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    assert!(!stderr.contains("one-way coupling"), "a case with [coupling] is two-way coupled: {stderr}");
    assert!(!stderr.contains("α_c was held"), "a lone sphere (α_p ≤ 0.07) leaves the fluid room: {stderr}");

    let last_frame = |pvd: &str| {
        let frames = read_pvd(&out.join(pvd)).unwrap();
        assert_eq!(frames.len(), 3, "{pvd}: frames at steps 0, 5, 10");
        read_vtk(&out.join(&frames.last().unwrap().file)).unwrap()
    };
    let fluid = last_frame("fluid.pvd");
    let finite = |name: &str, values: &[f64], n: usize| {
        assert_eq!(values.len(), n, "{name}: {} values, expected {n}", values.len());
        assert!(values.iter().all(|v| v.is_finite()), "{name}: {values:?}");
    };
    let cell_field = |name: &str| fluid.cell_field(name).unwrap_or_else(|| panic!("fluid field {name} missing")).values.as_f64().unwrap().to_vec();
    let alpha_c = cell_field("alpha_c");
    finite("alpha_c", &alpha_c, 50);
    assert!(alpha_c.iter().all(|a| *a > 0.0 && *a <= 1.0) && alpha_c.iter().any(|a| *a < 1.0), "α_c {alpha_c:?}");
    let force_density = cell_field("particle_force_density");
    finite("particle_force_density", &force_density, 3 * 50);
    let on_fluid_y: f64 = force_density.iter().skip(1).step_by(3).sum();
    assert!(on_fluid_y < 0.0, "the settling particle pushes the water down: Σ f_y = {on_fluid_y}");

    let particles = last_frame("particles.pvd");
    let point_field = |name: &str| particles.point_field(name).unwrap_or_else(|| panic!("particle field {name} missing")).values.as_f64().unwrap().to_vec();
    finite("fluid_velocity", &point_field("fluid_velocity"), 3);
    let drag = point_field("drag_force");
    finite("drag_force", &drag, 3);
    assert!(drag[1] > 0.0, "the drag on a settling particle points up: {drag:?}");
    let reynolds = point_field("slip_reynolds");
    finite("slip_reynolds", &reynolds, 1);
    assert!(reynolds[0] > 0.0, "slip Reynolds number {reynolds:?}");

    let series = read_series(&out.join("series.csv")).unwrap();
    let settling = series.column("settling_velocity").expect("settling_velocity column");
    assert_eq!(settling.len(), 10);
    assert!(settling.iter().all(|v| v.is_finite()) && *settling.last().unwrap() > 0.0, "settling velocity {settling:?}");
    for column in ["particles", "escaped", "alpha_p_max", "alpha_c_clamped", "particle_volume"] {
        assert!(series.column(column).is_some(), "series column {column} missing");
    }
    // a fast coupled run names the lanes its drag laws took (its speed depends on them)
    let summary = Summary::read(&out.join("summary.json")).unwrap();
    let kernel = summary.details["dem_drag_kernel"].as_str().expect("dem_drag_kernel in the summary");
    assert_eq!(kernel, spillage_fast::dem::drag_lanes::LaneWidth::detect().describe());
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    // The fluid case runs the default (fast, multi-threaded) solver.
    let dir = scratch("thread-count");
    for (case, last) in [(fluid_case(&dir, 3), 3), (particle_case(&dir, 60), 60)] {
        let (one, two) = (dir.join(format!("one-{last}")), dir.join(format!("two-{last}")));
        run_ok(&["run", case.to_str().unwrap(), "--out", one.to_str().unwrap(), "--threads", "1"]);
        run_ok(&["run", case.to_str().unwrap(), "--out", two.to_str().unwrap(), "--threads", "2"]);
        assert!(checkpoint(&one, last) == checkpoint(&two, last), "{}: 1 and 2 threads differ", case.display());
    }
}

#[test]
fn a_bad_case_gets_a_located_error_and_status_2() {
    let dir = scratch("bad");
    let case = fluid_case(&dir, 2);
    let text = std::fs::read_to_string(&case).unwrap().replace("kinematic_viscosity = 0.02", "kinematic_viscosity = -0.02");
    std::fs::write(&case, text).unwrap();
    for command in ["check", "run"] {
        let out = spillage(&[command, case.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2), "{command}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("small_rotor.toml:10:23") && err.contains("fluid.kinematic_viscosity") && err.contains("-0.02"), "{command}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn restarting_from_a_foreign_or_damaged_checkpoint_is_refused() {
    let dir = scratch("foreign");
    let case = fluid_case(&dir, 3);
    let bogus = dir.join("bogus.ckpt");
    std::fs::write(&bogus, b"not a checkpoint\n").unwrap();
    let out = spillage(&["run", case.to_str().unwrap(), "--restart", bogus.to_str().unwrap(), "--out", dir.join("o").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("not a spillage checkpoint"));
}

/// Issue 14 item 2: a DEM checkpoint ran as a fluid case of the same name (and the other way
/// round); now the run stops before any step, naming the phase that differs.
#[test]
fn a_checkpoint_of_another_phase_is_refused_before_any_step() {
    let dir = scratch("other_phase");
    let particles = particle_case(&dir, 2);
    let fluid = fluid_case(&dir, 3);
    // the fluid case under the particle case's name
    let text = std::fs::read_to_string(&fluid).unwrap().replace("name = \"small_rotor\"", "name = \"small_pour\"");
    std::fs::write(&fluid, text).unwrap();
    let (p_out, f_out) = (dir.join("p"), dir.join("f"));
    run_ok(&["run", particles.to_str().unwrap(), "--out", p_out.to_str().unwrap()]);
    run_ok(&["run", fluid.to_str().unwrap(), "--out", f_out.to_str().unwrap()]);
    let cases = [(&fluid, p_out.join("checkpoints/step_00000002.ckpt"), "particle"), (&particles, f_out.join("checkpoints/step_00000003.ckpt"), "fluid")];
    for (case, ckpt, phase) in cases {
        let out = spillage(&["run", case.to_str().unwrap(), "--restart", ckpt.to_str().unwrap(), "--out", dir.join("again").to_str().unwrap()]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains(&format!("the checkpoint has a {phase} phase but the case has none")), "{err}");
        assert!(!dir.join("again/series.csv").exists(), "a step was taken: {err}");
    }
}

#[test]
fn check_prints_the_derived_numbers() {
    let dir = scratch("check");
    let case = fluid_case(&dir, 2);
    let out = spillage(&["check", case.to_str().unwrap()]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in ["cells        108", "Courant", "Reynolds", "memory"] {
        assert!(text.contains(needle), "missing {needle:?} in\n{text}");
    }
}

#[test]
fn an_unconverged_linear_solve_stops_the_run_with_a_clear_error_and_a_summary() {
    let dir = scratch("unconverged");
    let case = fluid_case_with_numerics(&dir, 3, "max_linear_iterations = 1");
    let out_dir = dir.join("out");
    let out = spillage(&["run", case.to_str().unwrap(), "--out", out_dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("did not converge in 1 iterations") && err.contains("max_linear_iterations"), "{err}");
    assert!(err.contains("step 1, t = "), "the error names the step: {err}");
    let summary = Summary::read(&out_dir.join("summary.json")).unwrap();
    let status = summary.details["status"].as_str().unwrap().to_string();
    assert!(status.starts_with("failed:") && status.contains("did not converge"), "{status}");
    assert!(read_pvd(&out_dir.join("fluid.pvd")).unwrap().len() == 1, "the initial frame stays readable");
}

/// `spillage verify` outside the repository says where it looked and what to do (issue 15).
#[test]
fn verify_outside_the_repository_says_what_to_do() {
    let dir = std::env::temp_dir().join(format!("spillage-verify-elsewhere-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_spillage")).arg("verify").current_dir(&dir).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("no cases/verification folder") && stderr.contains("repository root"), "{stderr}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A run owns its results folder (issue 14 item 3): a second, shorter run into another run's
/// folder is refused, and with `--force` leaves none of the old run's checkpoints behind (a
/// restart from "the newest" would have loaded the other run's state); a restart drops the
/// checkpoints after its step and the `.tmp` files of a killed run.
#[test]
fn a_run_owns_its_results_folder() {
    let dir = scratch("owns-folder");
    let (long, short) = (fluid_case(&dir, 6), dir.join("short.toml"));
    std::fs::write(&short, std::fs::read_to_string(&long).unwrap().replace("steps = 6", "steps = 2")).unwrap();
    let out = dir.join("out");
    run_ok(&["run", long.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let refused = spillage(&["run", short.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let message = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{message}");
    assert!(message.contains("holds another run's results") && message.contains("--force"), "{message}");
    run_ok(&["run", short.to_str().unwrap(), "--out", out.to_str().unwrap(), "--force"]);
    let mut left: Vec<String> = std::fs::read_dir(out.join("checkpoints")).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    left.sort();
    assert!(left.iter().all(|n| n.as_str() <= "step_00000002.ckpt"), "old checkpoints left: {left:?}");
    assert_eq!(read_series(&out.join("series.csv")).unwrap().column("step").unwrap(), vec![1.0, 2.0]);

    // a restart into the folder: later checkpoints and a killed run's .tmp go
    run_ok(&["run", long.to_str().unwrap(), "--out", out.to_str().unwrap(), "--force"]);
    std::fs::write(out.join("checkpoints").join("step_00000007.tmp"), b"half a checkpoint").unwrap();
    let mid = out.join("checkpoints").join("step_00000003.ckpt");
    let saved = dir.join("step_3.ckpt");
    std::fs::copy(&mid, &saved).unwrap();
    assert!(out.join("checkpoints").join("step_00000006.ckpt").exists());
    let short_restart = dir.join("restart.toml");
    std::fs::write(&short_restart, std::fs::read_to_string(&long).unwrap().replace("steps = 6", "steps = 4")).unwrap();
    run_ok(&["run", short_restart.to_str().unwrap(), "--out", out.to_str().unwrap(), "--restart", saved.to_str().unwrap()]);
    let names: Vec<String> = std::fs::read_dir(out.join("checkpoints")).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert!(!names.iter().any(|n| n.ends_with(".tmp") || n.as_str() > "step_00000004.ckpt"), "{names:?}");

    // without --out, a second run takes the next free default folder
    let first = Command::new(env!("CARGO_BIN_EXE_spillage")).current_dir(&dir).args(["run", short.to_str().unwrap()]).output().unwrap();
    assert!(first.status.success(), "{}", String::from_utf8_lossy(&first.stderr));
    let second = Command::new(env!("CARGO_BIN_EXE_spillage")).current_dir(&dir).args(["run", short.to_str().unwrap()]).output().unwrap();
    assert!(second.status.success(), "{}", String::from_utf8_lossy(&second.stderr));
    assert!(String::from_utf8_lossy(&second.stderr).contains("small_rotor-2"), "{}", String::from_utf8_lossy(&second.stderr));
    assert!(dir.join("results/small_rotor/summary.json").exists() && dir.join("results/small_rotor-2/summary.json").exists());
}

/// Steps that stop at the outer-loop cap unconverged are reported (issue 15 item 1: a run
/// "completed" with every step capped and no warning).
#[test]
fn steps_capped_by_the_outer_loop_are_reported() {
    let dir = scratch("outer-cap");
    let case = fluid_case_with_numerics(&dir, 3, "max_outer_iterations = 1\np_initial_residual = 1e-14");
    let out_dir = dir.join("out");
    let out = spillage(&["run", case.to_str().unwrap(), "--out", out_dir.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("warning: the outer loop stopped at its cap of 1 iterations in 3 of 3 steps"), "{err}");
    let summary = Summary::read(&out_dir.join("summary.json")).unwrap();
    assert_eq!(summary.results["outer_loop_capped_steps"], 3.0);

    // a converged run says nothing of the kind
    let quiet = fluid_case(&dir, 2);
    let out = spillage(&["run", quiet.to_str().unwrap(), "--out", dir.join("quiet").to_str().unwrap()]);
    assert!(!String::from_utf8_lossy(&out.stderr).contains("outer loop stopped"));
}

/// A particle standing for more volume than its cells hold (here one sphere counting 100 times:
/// α_p ≈ 6.5 in its 2 cm cells) holds α_c at its floor; the run says so at the end instead of
/// finishing as if the water had seen it all.
#[test]
fn cells_held_at_the_fluid_fraction_floor_are_reported() {
    let dir = scratch("packed");
    let case = settling_case(&dir);
    let text = std::fs::read_to_string(&case).unwrap().replace("[particles]\n", "[particles]\nmodifier = 100.0\n");
    std::fs::write(&case, text).unwrap();
    let out = spillage(&["run", case.to_str().unwrap(), "--out", dir.join("out").to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("warning: α_c was held at its floor [coupling] min_fluid_fraction = 0.05"), "{err}");
    assert!(err.contains("in 10 of 10 steps") && err.contains("counting 100 times"), "{err}");
}
