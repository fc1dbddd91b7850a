//! A fluid mesh that follows a receding wall (`[wear.fluid_mesh]`, wear-model.md §7.4;
//! spillage_model::wear::fluid_mesh, spillage_model::mesh::deform) in both fluid solvers.
//!
//! The piston: a channel closed at x = L by a plane wall that recedes at speed W, fed at
//! x = 0 at the same speed, slip walls on the sides (a closed volume: a reference cell fixes
//! the pressure level; an open end would be a pressure outlet taking inflow, which the
//! zero-gradient velocity of our pressure outlets does not hold steady). The mesh stretches with the wall (each point
//! takes x/L of the recession), and the exact solution is the water following the wall at the
//! uniform speed W (continuity in one dimension): the discrete one too, since with the swept
//! volumes balancing the volume change (GCL) a uniform field stays uniform on a moving mesh.

use std::path::Path;

use spillage_fast::fluid::FastFluid;
use spillage_model::case::Case;
use spillage_model::fluid::settings::TimeScheme;
use spillage_model::mesh::{self, Vec3};
use spillage_model::solver::StepReport;
use spillage_model::state::State;
use spillage_model::step::{FluidPhase, StepContext};
use spillage_reference::fluid::ReferenceFluid;

const LENGTH: f64 = 1.0;
const SPEED: f64 = 0.05;
const DT: f64 = 0.02;

fn piston_case(scheme: &str) -> Case {
    case_fed_at(scheme, SPEED)
}

/// The channel fed at `inflow` m/s.
fn case_fed_at(scheme: &str, inflow: f64) -> Case {
    Case::from_toml(&piston_text(scheme, inflow), Path::new("piston.toml")).unwrap_or_else(|e| panic!("{e}"))
}

fn piston_text(scheme: &str, inflow: f64) -> String {
    format!(
        r#"
[case]
name = "piston"
description = "a channel whose end wall recedes at constant speed: the water follows it uniformly"
[time]
dt = {DT}
steps = 10
[fluid]
density = 1000.0
kinematic_viscosity = 1e-3
[mesh]
generator = "box"
min = [0.0, 0.0, 0.0]
max = [{LENGTH}, 0.2, 0.1]
cells = [10, 4, 2]
grading = [0.3, 1.0, 1.0]
[boundary.x_min]
type = "velocity_inlet"
velocity = [{inflow}, 0.0, 0.0]
[boundary.x_max]
type = "symmetry"
[boundary.y_min]
type = "symmetry"
[boundary.y_max]
type = "symmetry"
[boundary.z_min]
type = "symmetry"
[boundary.z_max]
type = "symmetry"
[numerics]
time_scheme = "{scheme}"
linear_tolerance = 1e-13
max_outer_iterations = 30
p_initial_residual = 1e-11
[particles]
[[particles.materials]]
name = "steel"
density = 7800.0
youngs_modulus = 200e9
poisson_ratio = 0.3
restitution = 0.9
friction = 0.3
[[walls]]
name = "end"
material = "steel"
shape = {{ type = "plane", centre = [{LENGTH}, 0.1, 0.05], normal = [-1.0, 0.0, 0.0], size = [0.4, 0.3], divisions = [4, 3], u_axis = [0.0, 1.0, 0.0] }}
[wear]
law = "arabnejad"
[wear.material]
preset = "carbon_steel_1018"
[wear.fluid_mesh]
wall = "end"
patch = "x_max"
"#
    )
}

fn start(case: &Case) -> (ReferenceFluid, State) {
    let mut state = State { walls: Some(mesh_walls(case)), ..State::default() };
    let mesh = mesh::for_case(case).expect("a mesh section").unwrap();
    let fluid = ReferenceFluid::new(case, mesh, &mut state).unwrap_or_else(|e| panic!("{e}"));
    (fluid, state)
}

fn start_fast(case: &Case) -> (FastFluid, State) {
    let mut state = State { walls: Some(mesh_walls(case)), ..State::default() };
    let mesh = mesh::for_case(case).expect("a mesh section").unwrap();
    let fluid = FastFluid::new(case, mesh, &mut state).unwrap_or_else(|e| panic!("{e}"));
    (fluid, state)
}

fn mesh_walls(case: &Case) -> spillage_model::walls::state::WallState {
    spillage_model::walls::build(case, Path::new(".")).unwrap()
}

/// Steps `steps` times from the state's step, the end wall receding to W t at each step's
/// end: the plate overhangs the channel by one row of triangles, whose rim stays put (as a
/// worn wall's pinned rim), and its nodes over the channel recede together.
fn run(fluid: &mut impl FluidPhase, state: &mut State, steps: usize) {
    run_receding(fluid, state, steps, |_| 1.0);
}

/// As [`run`], the plate's nodes over the channel receding at `share(y)` W.
fn run_receding(fluid: &mut impl FluidPhase, state: &mut State, steps: usize, share: impl Fn(f64) -> f64) {
    let built = mesh_walls(&piston_case("euler"));
    for _ in 0..steps {
        let ctx = StepContext::new(state.step + 1, state.time, DT, state.dt, TimeScheme::Euler, None);
        let walls = state.walls.as_mut().unwrap();
        for (v, v0) in walls.walls[0].vertices.iter_mut().zip(&built.walls[0].vertices) {
            let over_channel = (-1e-9..=0.2 + 1e-9).contains(&v0.y) && (-1e-9..=0.1 + 1e-9).contains(&v0.z);
            *v = if over_channel { v0 + Vec3::new(share(v0.y) * SPEED * ctx.time_end(), 0.0, 0.0) } else { *v0 };
        }
        fluid.follow_walls(&ctx, walls, state.fluid.as_ref().unwrap()).unwrap_or_else(|e| panic!("{e}"));
        let mut report = StepReport::default();
        fluid.advance(&ctx, state.fluid.as_mut().unwrap(), None, &mut report).unwrap_or_else(|e| panic!("{e}"));
        state.step += 1;
        state.time = ctx.time_end();
        state.dt = DT;
    }
}

/// The water follows the wall at W in every cell (to 1e-11 W: the outer loops converged to a
/// pressure residual of 1e-11 and the linear solvers to 1e-13; measured 6.0e-14 m/s in the
/// reference, 2.3e-13 m/s in the fast solver; at four outer iterations a step it was 4.4e-4 m/s
/// without the slip wall's normal speed, 8e-7 with it), the end wall
/// has moved to L + W t, and the volume of the water grew by W t A: in both solvers.
#[test]
fn the_water_follows_a_receding_wall_at_its_speed() {
    let case = piston_case("euler");
    let (mut reference, mut reference_state) = start(&case);
    let (mut fast, mut fast_state) = start_fast(&case);
    check_piston(&mut reference, &mut reference_state, "reference");
    check_piston(&mut fast, &mut fast_state, "fast");
}

fn check_piston(fluid: &mut impl FluidPhase, state: &mut State, solver: &str) {
    let volume_before: f64 = fluid.mesh().cell_volumes.iter().sum();
    run(fluid, state, 10);
    let u = &state.fluid.as_ref().unwrap().velocity;
    let worst = u.iter().map(|v| (Vec3::from(*v) - Vec3::new(SPEED, 0.0, 0.0)).norm()).fold(0.0, f64::max);
    eprintln!("{solver}: largest deviation from the wall speed {worst:e} m/s");
    assert!(worst <= 1e-11 * SPEED, "{solver}: largest deviation from the wall speed: {worst:e} m/s");
    let mesh = fluid.mesh();
    let x_max = mesh.points.iter().map(|p| p.x).fold(f64::MIN, f64::max);
    let moved = SPEED * state.time;
    assert!((x_max - (LENGTH + moved)).abs() <= 1e-12, "{solver}: end wall at {x_max} m, expected {}", LENGTH + moved);
    let volume_after: f64 = mesh.cell_volumes.iter().sum();
    let grown = moved * 0.2 * 0.1;
    // 1e-12: round-off of a sum of 80 fan volumes
    assert!(
        ((volume_after - volume_before) - grown).abs() <= 1e-12 * volume_before,
        "{solver}: volume grew by {:e} m³, expected {grown:e}",
        volume_after - volume_before
    );
    // the water leaves through the receding wall as fast as the wall sweeps: the absolute
    // flux there is the mesh flux, W A (1e-12: round-off of the swept volumes)
    let through_wall: f64 = mesh.patch("x_max").unwrap().faces().map(|f| state.fluid.as_ref().unwrap().flux[f]).sum();
    assert!((through_wall - SPEED * 0.2 * 0.1).abs() <= 1e-12 * SPEED * 0.02, "{solver}: flux through the wall {through_wall:e} m³/s");
}

/// A trough: only the plate's middle row of nodes (y = 0.1 m) recedes, so the end wall becomes
/// a V whose water the inflow (W/2, the V's mean speed) fills: a flow without a closed form,
/// in which the two solvers agree step by step (velocities to 1e-10 W, outer loops converged
/// to 1e-11 and linear solves to 1e-13; measured 9.7e-14 m/s, 1.9e-12 W), and each keeps every
/// cell's absolute fluxes balanced to round-off while its volume changes (the GCL: 1e-12 of
/// the inflow W A/2).
#[test]
fn the_solvers_agree_on_a_mesh_bending_into_a_trough() {
    let case = case_fed_at("euler", 0.5 * SPEED);
    let trough = |y: f64| if (y - 0.1).abs() < 1e-9 { 1.0 } else { 0.0 };
    let (mut reference, mut reference_state) = start(&case);
    let (mut fast, mut fast_state) = start_fast(&case);
    let mut largest = 0.0f64;
    for _ in 0..10 {
        run_receding(&mut reference, &mut reference_state, 1, trough);
        run_receding(&mut fast, &mut fast_state, 1, trough);
        let (r, f) = (reference_state.fluid.as_ref().unwrap(), fast_state.fluid.as_ref().unwrap());
        for (a, b) in r.velocity.iter().zip(&f.velocity) {
            largest = largest.max((Vec3::from(*a) - Vec3::from(*b)).norm());
        }
        assert_eq!(r.mesh_displacement, f.mesh_displacement, "the same mesh");
    }
    eprintln!("largest velocity difference fast − reference {largest:e} m/s");
    assert!(largest <= 1e-10 * SPEED, "largest velocity difference fast − reference: {largest:e} m/s");
    for (solver, fluid, state) in [("reference", reference.mesh(), &reference_state), ("fast", fast.mesh(), &fast_state)] {
        let flux = &state.fluid.as_ref().unwrap().flux;
        let mut net = vec![0.0; fluid.n_cells()];
        for (f, phi) in flux.iter().enumerate() {
            net[fluid.face_owner[f]] += phi;
            if f < fluid.n_internal_faces {
                net[fluid.face_neighbour[f]] -= phi;
            }
        }
        let worst = net.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        assert!(worst <= 1e-12 * 0.5 * SPEED * 0.02, "{solver}: largest net absolute flux of a cell {worst:e} m³/s");
    }
    // the end wall's points sit on the worn plate: the hat 1 − |y − 0.1|/0.1 times W t, the
    // plate's triangles interpolated linearly (1e-12 m: round-off of the barycentric weights)
    let recession = SPEED * reference_state.time;
    for mesh in [reference.mesh(), fast.mesh()] {
        for f in mesh.patch("x_max").unwrap().faces() {
            for &p in &mesh.face_points[f] {
                let (x0, x) = (mesh.reference_points[p], mesh.points[p]);
                let expected = LENGTH + recession * (1.0 - (x0.y - 0.1).abs() / 0.1).max(0.0);
                assert!((x.x - expected).abs() <= 1e-12, "wall point at y = {} z = {}: x = {} m, expected {expected}", x0.y, x0.z, x.x);
            }
        }
    }
    // the flow is not uniform: the water turns into the trough
    let u = &reference_state.fluid.as_ref().unwrap().velocity;
    let spread = u.iter().map(|v| v[1].abs()).fold(0.0, f64::max);
    // 1e-3 W: ten orders above the solvers' agreement, so the trough does turn the water
    assert!(spread > 1e-3 * SPEED, "largest sideways speed {spread:e} m/s");
}

/// A run restarted from the state after 4 of 8 steps (mesh rebuilt from the stored
/// displacement) ends with the same bits as the run straight through, in both solvers.
#[test]
fn a_restarted_following_mesh_continues_bit_for_bit() {
    let case = piston_case("euler");
    restart_continues_bit_for_bit(&case, "reference", |case, state| ReferenceFluid::new(case, mesh::for_case(case).unwrap().unwrap(), state).unwrap());
    restart_continues_bit_for_bit(&case, "fast", |case, state| FastFluid::new(case, mesh::for_case(case).unwrap().unwrap(), state).unwrap());
}

/// A fresh run of `case` with the fluid phase `build` makes, and its state.
fn started<F: FluidPhase>(case: &Case, build: &impl Fn(&Case, &mut State) -> F) -> (F, State) {
    let mut state = State { walls: Some(mesh_walls(case)), ..State::default() };
    (build(case, &mut state), state)
}

fn restart_continues_bit_for_bit<F: FluidPhase>(case: &Case, solver: &str, build: impl Fn(&Case, &mut State) -> F) {
    let start = || started(case, &build);
    let (mut straight, mut straight_state) = start();
    run(&mut straight, &mut straight_state, 8);
    let (mut first, mut state) = start();
    run(&mut first, &mut state, 4);
    let mut restarted_state = state.clone();
    let mut restarted = build(case, &mut restarted_state);
    assert_eq!(restarted.mesh().points, first.mesh().points, "{solver}: the restarted mesh is where the run left it");
    run(&mut restarted, &mut restarted_state, 4);
    assert_eq!(restarted_state.fluid, straight_state.fluid, "{solver}");
    assert_eq!(restarted.mesh().points, straight.mesh().points, "{solver}");
}

/// A rejected step leaves no trace: the mesh moved and the fluid stepped, the driver put the
/// state back and rewound the phase, and the step taken again gives the bits of a run that took
/// it once, in both solvers.
#[test]
fn a_rejected_step_leaves_the_mesh_where_it_was() {
    let case = piston_case("euler");
    rejected_step_leaves_no_trace(&case, "reference", |case, state| ReferenceFluid::new(case, mesh::for_case(case).unwrap().unwrap(), state).unwrap());
    rejected_step_leaves_no_trace(&case, "fast", |case, state| FastFluid::new(case, mesh::for_case(case).unwrap().unwrap(), state).unwrap());
}

fn rejected_step_leaves_no_trace<F: FluidPhase>(case: &Case, solver: &str, build: impl Fn(&Case, &mut State) -> F) {
    let start = || started(case, &build);
    let (mut direct, mut direct_state) = start();
    run(&mut direct, &mut direct_state, 4);
    let (mut retried, mut state) = start();
    run(&mut retried, &mut state, 3);
    let (saved, points) = (state.clone(), retried.mesh().points.clone());
    run(&mut retried, &mut state, 1);
    assert_ne!(retried.mesh().points, points, "{solver}: the rejected step moved the mesh");
    state = saved;
    retried.rewind(state.dt);
    assert_eq!(retried.mesh().points, points, "{solver}: the mesh is back where the step began");
    run(&mut retried, &mut state, 1);
    assert_eq!(state.fluid, direct_state.fluid, "{solver}");
    assert_eq!(retried.mesh().points, direct.mesh().points, "{solver}");
}

/// What a following mesh needs of the case is refused when the case is read, naming the key:
/// implicit Euler (its swept volumes balance Euler's volume change), a slip patch, laminar flow,
/// a box without periodic directions. A wall that does not cover the patch is refused by both
/// solvers, naming the point.
#[test]
fn a_following_mesh_names_what_it_needs() {
    let refused = |text: String, key: &str| {
        let error = Case::from_toml(&text, Path::new("piston.toml")).err().expect("refused").to_string();
        assert!(error.contains(key), "{error}");
    };
    let text = || toml::to_string(&toml::from_str::<toml::Table>(&piston_text("euler", SPEED)).unwrap()).unwrap();
    refused(piston_text("backward", SPEED), "numerics.time_scheme` = \"backward\"");
    refused(text().replace("[boundary.x_max]\ntype = \"symmetry\"", "[boundary.x_max]\ntype = \"wall\""), "wear.fluid_mesh.patch` = \"x_max\"");
    refused(piston_text("euler", SPEED).replace("[numerics]", "[turbulence]\nmodel = \"realizable-k-epsilon\"\n[numerics]"), "turbulence.model");
    let mut periodic: toml::Table = toml::from_str(&piston_text("euler", SPEED)).unwrap();
    periodic["mesh"].as_table_mut().unwrap().insert("periodic".into(), toml::Value::Array(vec!["z".into()]));
    for side in ["z_min", "z_max"] {
        periodic["boundary"].as_table_mut().unwrap().remove(side);
    }
    refused(toml::to_string(&periodic).unwrap(), "a mesh without periodic directions");
    // the plate moved off the channel's end by 0.15 m along y: the patch's corner lies beyond it
    let case = Case::from_toml(&piston_text("euler", SPEED).replace("centre = [1, 0.1, 0.05]", "centre = [1, 0.25, 0.05]"), Path::new("piston.toml")).unwrap();
    for solver in ["reference", "fast"] {
        let mut state = State { walls: Some(mesh_walls(&case)), ..State::default() };
        let mesh = mesh::for_case(&case).unwrap().unwrap();
        let error = match solver {
            "reference" => ReferenceFluid::new(&case, mesh, &mut state).err().map(|e| e.to_string()),
            _ => FastFluid::new(&case, mesh, &mut state).err().map(|e| e.to_string()),
        }
        .expect("refused");
        assert!(error.contains("lies outside wall \"end\""), "{solver}: {error}");
    }
}

/// The shipped wet jet (`cases/wear/jet_impingement_wet.toml`) made cheap: grains fed 1.5 mm from
/// the plate, straight at it, and a wear acceleration that lets a few impacts bend the mesh.
fn wet_jet_close_up() -> Case {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/wear/jet_impingement_wet.toml");
    let mut table: toml::Table = std::fs::read_to_string(&path).unwrap().parse().unwrap();
    let feed = table["particles"]["feed"][0].as_table().unwrap().clone();
    let mut feed = feed;
    feed.remove("velocity_profile");
    feed.insert("region".into(), toml::from_str::<toml::Table>("r = { min = [0.198, 0.2, 0.0005], max = [0.1985, 0.22, 0.0245] }").unwrap()["r"].clone());
    table["particles"]["feed"].as_array_mut().unwrap()[0] = toml::Value::Table(feed);
    table["wear"].as_table_mut().unwrap().insert("acceleration".into(), toml::Value::Float(2e8));
    Case::from_toml(&toml::to_string(&table).unwrap(), &path).unwrap_or_else(|e| panic!("{e}"))
}

fn wet_run(case: &Case, state: State) -> spillage_model::step::Coupled<FastFluid, spillage_fast::dem::FastDem> {
    let mut state = state;
    let mesh = mesh::for_case(case).unwrap().unwrap();
    let fluid = FastFluid::new(case, mesh, &mut state).unwrap_or_else(|e| panic!("{e}"));
    let dem = spillage_fast::dem::FastDem::new(case, &mut state).unwrap();
    let wear = spillage_fast::wear::FastWear::new(case, &mut state).unwrap();
    spillage_model::step::Coupled::new(case, state, Some(fluid), Some(dem)).unwrap().with_wear(Box::new(wear)).unwrap()
}

/// The whole step (grains, water, wear) with the mesh following the plate: a run restarted
/// from a checkpoint written once the mesh has bent continues bit for bit.
#[test]
fn a_wet_jet_with_a_following_mesh_restarts_bit_for_bit() {
    use spillage_model::solver::Solver;
    let case = wet_jet_close_up();
    let mut straight = wet_run(&case, State::default());
    for _ in 0..24 {
        straight.step().unwrap();
    }
    let mut first = wet_run(&case, State::default());
    for _ in 0..14 {
        first.step().unwrap();
    }
    let bent = first.state().fluid.as_ref().unwrap().mesh_displacement.iter().fold(0.0f64, |a, d| a.max(*d));
    let impacts = first.state().wear.as_ref().unwrap().impacts;
    // 10 µm: thousands of times the round-off of the points' coordinates, so the restart
    // rebuilds a bent mesh
    assert!(bent > 1e-5, "the mesh must have bent before the checkpoint: {bent:e} m after {impacts} impacts");
    // the 2-D mesh stays 2-D: the two points of a column across its one layer move alike
    let mesh = first.fluid_phase().expect("a fluid").mesh();
    let displacement = &first.state().fluid.as_ref().unwrap().mesh_displacement;
    let mut by_column = std::collections::HashMap::new();
    for (p, d) in mesh.reference_points.iter().zip(displacement) {
        if let Some(other) = by_column.insert((p.x.to_bits(), p.y.to_bits()), *d) {
            assert_eq!(other, *d, "points over ({}, {}) moved apart across the layer", p.x, p.y);
        }
    }
    let path = std::env::temp_dir().join(format!("spillage-following-restart-{}.ckpt", std::process::id()));
    spillage_model::checkpoint::write(&path, &case, first.state()).unwrap();
    let restored = spillage_model::checkpoint::read(&path, &case).unwrap();
    std::fs::remove_file(&path).ok();
    let mut second = wet_run(&case, restored);
    for _ in 0..10 {
        second.step().unwrap();
    }
    assert!(second.state() == straight.state(), "{}", spillage_model::state_diff::diff(straight.state(), second.state()).report());
}
