//! Benchmark workloads shared by `benches/fluid_step.rs` and the fast crate's `step_driver`
//! example (issue #6): Couette flow with a sliding interface, a 3-D rotor/stator cylinder and a
//! lid-driven cavity, all with the same PIMPLE settings (2 outer, 2 PISO, 1 non-orthogonal
//! corrector, linear convection, BDF2).

use std::path::Path;

use spillage_model::case::Case;

pub const NUMERICS: &str = r#"
[numerics]
convection = "linear"
time_scheme = "backward"
pressure_wall = "fixed_flux_extrapolated"
max_outer_iterations = 2
p_initial_residual = 1e-300
piso_correctors = 2
non_orthogonal_correctors = 1
relax_velocity = 1.0
relax_pressure = 1.0
"#;

/// Couette flow with a sliding interface, n_θ × n_r cells (half the rings rotor, stator 5/4 n_θ
/// in θ so the interface is non-conformal), Δt = half a rotor cell per step.
pub fn couette(n_theta: usize, n_r: usize) -> Case {
    let dt = 0.5 * std::f64::consts::TAU / n_theta as f64;
    let text = format!(
        r#"[case]
name = "bench_couette_{n_theta}x{n_r}"
[time]
dt = {dt}
end_time = 1.0
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
n_r_rotor = {}
n_r_stator = {}
n_theta_rotor = {n_theta}
n_theta_stator = {}
two_d = true
[rotor]
omega = 1.0
[boundary.inner]
type = "wall"
rotating = true
[boundary.outer]
type = "wall"
{NUMERICS}"#,
        n_r / 2,
        n_r - n_r / 2,
        n_theta * 5 / 4
    );
    Case::from_toml(&text, Path::new("bench_couette.toml")).expect("bench case")
}

/// 3-D rotor/stator cylinder: rotor wall inside, static outer wall, walls top and bottom.
pub fn rotor3d(n_theta: usize, n_r: usize, n_z: usize) -> Case {
    let dt = 0.5 * std::f64::consts::TAU / n_theta as f64;
    let text = format!(
        r#"[case]
name = "bench_rotor3d"
[time]
dt = {dt}
end_time = 1.0
[fluid]
density = 1000.0
kinematic_viscosity = 0.01
[mesh]
generator = "rotor_stator"
r_inner = 0.5
r_interface = 1.0
r_outer = 1.5
z_min = 0.0
z_max = 1.0
n_r_rotor = {}
n_r_stator = {}
n_theta_rotor = {n_theta}
n_theta_stator = {}
n_z = {n_z}
two_d = false
[rotor]
omega = 1.0
[boundary.inner]
type = "wall"
rotating = true
[boundary.outer]
type = "wall"
[boundary.z_min]
type = "wall"
[boundary.z_max]
type = "wall"
{NUMERICS}"#,
        n_r / 2,
        n_r - n_r / 2,
        n_theta * 5 / 4
    );
    Case::from_toml(&text, Path::new("bench_rotor3d.toml")).expect("bench case")
}

/// 2-D lid-driven square cavity, n × n cells, Re = 100.
pub fn lid(n: usize) -> Case {
    let dt = 0.5 / n as f64;
    let text = format!(
        r#"[case]
name = "bench_lid_{n}"
[time]
dt = {dt}
end_time = 1.0
[fluid]
density = 1000.0
kinematic_viscosity = 0.01
[mesh]
generator = "box"
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 0.1]
cells = [{n}, {n}, 1]
two_d = true
[boundary.x_min]
type = "wall"
[boundary.x_max]
type = "wall"
[boundary.y_min]
type = "wall"
[boundary.y_max]
type = "wall"
velocity = [1.0, 0.0, 0.0]
{NUMERICS}"#
    );
    Case::from_toml(&text, Path::new("bench_lid.toml")).expect("bench case")
}
