//! The frozen-rotor (MRF) start-up (issue 16 "Start-up"; spillage_model::fluid::frozen_rotor,
//! spillage-and-flow-verification.md §4.2): its steady solution on the rotor–stator Couette case
//! against the exact Couette flow (analytic crate) and against the sliding-mesh run, the fast
//! fluid against the reference fluid at every step of a start-up and of the sliding steps after
//! it, restarts during and right after the start-up, and the case checks.

use std::path::{Path, PathBuf};

use spillage_analytic::couette::CircularCouette;
use spillage_fast::fluid::FastFluid;
use spillage_model::case::{Case, MeshSection};
use spillage_model::fluid::settings::InitialVelocity;
use spillage_model::mesh::Vec3;
use spillage_model::solver::{Solver, StepReport};
use spillage_model::state::State;
use spillage_model::step::Coupled;
use spillage_reference::fluid::ReferenceFluid;

use spillage::verify::equivalence::{step_by_step, TOLERANCE};

fn couette() -> Case {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases/verification/fluid/couette_sliding.toml");
    Case::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn frozen(mut case: Case, time: f64) -> Case {
    case.fluid.as_mut().unwrap().initial = InitialVelocity::FrozenRotor { time, from: None };
    case.finish().unwrap_or_else(|e| panic!("{e:?}"));
    case
}

/// The Couette case at (n_r, n_θ) of the rotor with Δt, the splits of the verify ladder
/// (rotor and stator rings in proportion to the gaps, 5/4 as many stator cells in θ).
fn level(case: &Case, n_r: usize, n_theta: usize, dt: f64) -> Case {
    let mut c = case.clone();
    if let Some(MeshSection::RotorStator { n_r_rotor, n_r_stator, n_theta_rotor, n_theta_stator, .. }) = c.mesh.as_mut() {
        (*n_r_rotor, *n_r_stator, *n_theta_rotor, *n_theta_stator) = (n_r / 2, n_r / 2, n_theta, n_theta * 5 / 4);
    }
    c.time.dt = Some(dt);
    c
}

fn mesh(case: &Case) -> spillage_model::mesh::Mesh {
    spillage::verify::fluid::build_mesh(case).unwrap()
}

fn reference(case: &Case, state: Option<State>) -> Coupled<ReferenceFluid> {
    let mut state = state.unwrap_or_default();
    let fluid = ReferenceFluid::new(case, mesh(case), &mut state).unwrap();
    Coupled::fluid_only(case, state, fluid).unwrap()
}

fn fast(case: &Case, state: Option<State>) -> Coupled<FastFluid> {
    let mut state = state.unwrap_or_default();
    let fluid = FastFluid::new(case, mesh(case), &mut state).unwrap();
    Coupled::fluid_only(case, state, fluid).unwrap()
}

/// rms errors of the ring-averaged u_θ and of the ring-averaged radial cell pressure gradient
/// against circular Couette flow, as `spillage verify`'s fluid_couette measures them.
fn couette_errors(run: &Coupled<ReferenceFluid>) -> (f64, f64) {
    let phase = run.fluid_phase().unwrap();
    let (mesh, fluid) = (phase.mesh(), run.state().fluid.as_ref().unwrap());
    let grad_p = phase.pressure_gradient(fluid);
    let exact = CircularCouette::thesis_case();
    let mut rows: Vec<(f64, f64, f64)> = (0..mesh.n_cells())
        .map(|c| {
            let x = mesh.cell_centres[c];
            let r = x.x.hypot(x.y);
            let (e_r, e_t) = (Vec3::new(x.x / r, x.y / r, 0.0), Vec3::new(-x.y / r, x.x / r, 0.0));
            (r, Vec3::from(fluid.velocity[c]).dot(&e_t), grad_p[c].dot(&e_r))
        })
        .collect();
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut rings: Vec<(f64, f64, f64, f64)> = Vec::new();
    for (r, u, g) in rows {
        match rings.last_mut() {
            Some(last) if (r - last.0 / last.3).abs() < 1e-9 => {
                *last = (last.0 + r, last.1 + u, last.2 + g, last.3 + 1.0);
            }
            _ => rings.push((r, u, g, 1.0)),
        }
    }
    let (mut su, mut sg) = (0.0, 0.0);
    for (r, u, g, k) in &rings {
        let r = r / k;
        su += (u / k - exact.tangential_velocity(r).unwrap()).powi(2);
        sg += (g / k - exact.kinematic_pressure_gradient(r).unwrap()).powi(2);
    }
    let n = rings.len() as f64;
    ((su / n).sqrt(), (sg / n).sqrt())
}

/// The frozen-rotor steady solution of the rotor–stator Couette case is the exact Couette flow
/// to the discretisation error of the sliding-mesh run on the same mesh and Δt (the flow is
/// axisymmetric, so freezing the rotor changes nothing but the frame): at each of two levels
/// both the u_θ and the dp/dr errors are at most 1.5× the sliding run's (the ratio the sliding
/// case itself is held to against the wall-velocity case, couette_sliding.toml), and they fall
/// at order ≥ 1.7 (the case's min_order_u) from one level to the next. The dp/dr check is the
/// one that sees the frame term: without −Ω×u the frozen balance is dP/dr = (u_θ − Ωr)u_θ/r, off
/// by Ω u_θ ≈ 0.3–1 m/s² against rms errors of 10⁻³. Both runs last 45 s (case file: the
/// start-up transient decays to ≈ 10⁻⁴ of it).
#[test]
fn the_frozen_rotor_solution_is_couette_flow_to_the_sliding_runs_error() {
    let base = couette();
    let mut errors = Vec::new();
    for (n_r, n_theta, dt) in [(8, 32, 0.2), (12, 48, 0.2 / 1.5)] {
        let sliding_case = level(&base, n_r, n_theta, dt);
        let mut sliding = reference(&sliding_case, None);
        while sliding.state().time < 45.0 - 0.5 * dt {
            sliding.step().unwrap();
        }
        let mut start_up = reference(&frozen(sliding_case, 45.0), None);
        assert_eq!(start_up.state().time, -45.0);
        let mut steps = 0;
        while start_up.state().time < 0.0 {
            let report = start_up.step().unwrap();
            assert_eq!(start_up.state().rotor_angle, 0.0, "the rotor stays during the start-up");
            assert!(report.values.iter().any(|(n, v)| *n == "outer_capped" && *v == 0.0), "step {steps}: outer loop not converged");
            steps += 1;
        }
        assert_eq!(start_up.state().time, 0.0, "the start-up lands on t = 0");
        let (s, f) = (couette_errors(&sliding), couette_errors(&start_up));
        eprintln!(
            "{n_theta}x{n_r}, dt {dt:.4}: sliding mesh ({} steps) u_θ rms {:.4e}, dp/dr rms {:.4e}; frozen rotor ({steps} steps) u_θ rms {:.4e}, dp/dr rms {:.4e}",
            sliding.state().step,
            s.0,
            s.1,
            f.0,
            f.1
        );
        assert!(f.0 <= 1.5 * s.0, "{n_theta}x{n_r}: frozen u_θ error {:e} vs sliding {:e}", f.0, s.0);
        assert!(f.1 <= 1.5 * s.1, "{n_theta}x{n_r}: frozen dp/dr error {:e} vs sliding {:e}", f.1, s.1);
        errors.push((n_r as f64, f));
    }
    let order = |e0: f64, e1: f64| (e0 / e1).ln() / (errors[1].0 / errors[0].0).ln();
    let (u_order, p_order) = (order(errors[0].1 .0, errors[1].1 .0), order(errors[0].1 .1, errors[1].1 .1));
    eprintln!("frozen rotor: observed order u_θ {u_order:.2}, dp/dr {p_order:.2}");
    assert!(u_order >= 1.7 && p_order >= 1.7, "orders u_θ {u_order}, dp/dr {p_order}");
}

/// Fast and reference fluids agree within 1e-8 of each field's scale after every step
/// (tests/fast_equivalence.rs's bound) through 25 frozen-rotor steps, the switch to the sliding
/// mesh at t = 0 and 25 sliding steps after it.
#[test]
fn fast_matches_reference_through_the_start_up_of_the_couette_case() {
    let case = frozen(couette(), 5.0);
    let (mut r, mut f) = (reference(&case, None), fast(&case, None));
    let e = step_by_step(&mut r, &mut f, 50).unwrap_or_else(|e| panic!("{e:#}"));
    assert!(r.state().time > 4.5, "about 25 steps of start-up, 25 after it: t = {}", r.state().time);
    assert!(e.worst <= TOLERANCE, "step {}: {:e}\n{}", e.worst_step, e.worst, e.worst_report);
    eprintln!("couette frozen rotor: 50 steps, largest relative difference {:.3e} (step {})", e.worst, e.worst_step);
}

/// The shipped head, water only, coarse (5 cm cells in a 0.8 m tank as tests/cutter_head.rs)
/// with a frozen-rotor start-up of 5 steps of 2 ms and 4 sliding steps: fast within 1e-8 of the
/// reference at every step, hull outflow included.
#[test]
fn fast_matches_reference_through_the_start_up_of_the_coarse_head() {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/verification/cutter_head/flow_60rpm.toml")).unwrap();
    let mut table: toml::Table = text.parse().unwrap();
    table.insert("time".into(), toml::Value::Table("dt = 0.002\nend_time = 0.008\nwrite_every = 0".parse().unwrap()));
    let head = table["cutter_head"].as_table_mut().unwrap();
    head["mesh"].as_table_mut().unwrap().insert("outer_cell_size".into(), 0.15.into());
    head["tank"].as_table_mut().unwrap().insert("radius".into(), 0.8.into());
    head["tank"].as_table_mut().unwrap().insert("below_hub".into(), 0.16.into());
    let initial = "type = \"frozen_rotor\"\ntime = 0.01\nfrom = { type = \"solid_body\", radius = 0.375, z = [-0.44, 0.0] }";
    table["fluid"].as_table_mut().unwrap().insert("initial".into(), toml::Value::Table(initial.parse().unwrap()));
    table.remove("verify");
    let case = Case::from_toml(&toml::to_string(&table).unwrap(), Path::new("head_frozen_coarse.toml")).unwrap_or_else(|e| panic!("{e}"));
    let (mut r, mut f) = (reference(&case, None), fast(&case, None));
    let value = |report: &StepReport, name: &str| report.values.iter().find(|(n, _)| *n == name).unwrap().1;
    let mut worst = 0.0f64;
    let mut step = 0;
    while r.state().time < 0.008 - 1e-12 {
        step += 1;
        let (a, b) = (r.step().unwrap(), f.step().unwrap());
        let diff = spillage_model::state_diff::diff(r.state(), f.state());
        let error = spillage::verify::equivalence_error(r.state(), &diff);
        worst = worst.max(error);
        assert!(error <= TOLERANCE, "step {step}: {}", diff.report());
        assert!((value(&a, "hull_outflow") - value(&b, "hull_outflow")).abs() <= TOLERANCE * 0.12, "step {step}");
        assert_eq!(r.state().rotor_angle == 0.0, r.state().time <= 0.0, "step {step}: the rotor turns after the start-up only");
    }
    assert!(step >= 9, "5 steps of start-up and 4 after it, {step} in all");
    eprintln!("head, frozen-rotor start: {step} steps, worst relative difference {worst:.3e}");
}

/// A run restarted from a checkpoint written during the start-up (t < 0), or at its end
/// (t = 0, before the first sliding step, which is an implicit-Euler step), continues
/// bit-for-bit through the switch to the sliding mesh.
#[test]
fn a_restart_during_or_after_the_start_up_continues_bit_for_bit() {
    let case = frozen(couette(), 2.0);
    let mut straight = fast(&case, None);
    let bits = |r: &StepReport| r.values.iter().map(|v| v.1.to_bits()).collect::<Vec<u64>>();
    let mut restarted = Vec::new();
    for step in 1..=16 {
        // before step 5 (t ≈ −1.2 s) and before the first sliding step (t = 0)
        if step == 5 || straight.state().time == 0.0 {
            let path = std::env::temp_dir().join(format!("spillage-frozen-restart-{}-{step}.ckpt", std::process::id()));
            spillage_model::checkpoint::write(&path, &case, straight.state()).unwrap();
            let read = spillage_model::checkpoint::read(&path, &case).unwrap();
            std::fs::remove_file(&path).ok();
            restarted.push(fast(&case, Some(read)));
        }
        let a = straight.step().unwrap();
        for run in restarted.iter_mut() {
            assert_eq!(bits(&a), bits(&run.step().unwrap()), "step {step}: reports differ after the restart");
            assert!(straight.state() == run.state(), "step {step}: states differ after the restart");
        }
    }
    assert_eq!(restarted.len(), 2);
    // the checkpoint of a start-up is refused by a case without one (its t < 0)
    let mut during = fast(&case, None);
    during.step().unwrap();
    let path = std::env::temp_dir().join(format!("spillage-frozen-refused-{}.ckpt", std::process::id()));
    spillage_model::checkpoint::write(&path, &case, during.state()).unwrap();
    let refused = spillage_model::checkpoint::read(&path, &couette());
    std::fs::remove_file(&path).ok();
    assert!(refused.unwrap_err().to_string().contains("time"));
}

/// Bad frozen-rotor starts are refused naming the key, the value and what is allowed.
#[test]
fn bad_frozen_rotor_starts_name_key_value_and_what_is_allowed() {
    let text = std::fs::read_to_string(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases/verification/fluid/couette_sliding.toml")).unwrap();
    let with = |initial: &str, edit: &dyn Fn(String) -> String| {
        let t = edit(text.replace("kinematic_viscosity = 0.02", &format!("kinematic_viscosity = 0.02\ninitial = {initial}")));
        Case::from_toml(&t, Path::new("frozen.toml")).map(|_| ()).map_err(|e| e.to_string())
    };
    let same = |t: String| t;
    assert!(with("{ type = \"frozen_rotor\", time = 2.0 }", &same).is_ok());
    assert!(with("{ type = \"frozen_rotor\", time = 2.0, from = { type = \"uniform\", velocity = [0.0, 0.0, 0.0] } }", &same).is_ok());
    let cases: [(&str, &dyn Fn(String) -> String, &str); 5] = [
        ("{ type = \"frozen_rotor\", time = -1.0 }", &same, "fluid.initial.time"),
        ("{ type = \"frozen_rotor\" }", &same, "time"),
        ("{ type = \"frozen_rotor\", time = 1.0, from = { type = \"frozen_rotor\", time = 1.0 } }", &same, "fluid.initial.from.type"),
        ("{ type = \"frozen_rotor\", time = 1.0 }", &|t: String| t.replace("end_time = 45.0", "steps = 10"), "time.steps"),
        ("{ type = \"frozen_rotor\", time = 1.0 }", &|t: String| t.replace("omega = 1.0", "omega = 0.0"), "fluid.initial.type"),
    ];
    for (initial, edit, key) in cases {
        let e = with(initial, edit).unwrap_err();
        assert!(e.contains(key), "{initial}: {e}");
    }
}
