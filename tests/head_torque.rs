//! The rotor's torque balance (issue 16 check 3; spillage_model::cutter_head::torque): the
//! terms of the angular-momentum budget on a case with a known answer (circular Couette flow
//! through the sliding interface) and on the coarse head.

use std::path::Path;

use spillage_fast::fluid::FastFluid;
use spillage_model::case::Case;
use spillage_model::solver::{Solver, StepReport};
use spillage_model::state::State;
use spillage_model::step::Coupled;

fn value(report: &StepReport, name: &str) -> f64 {
    report.values.iter().find(|(n, _)| *n == name).unwrap_or_else(|| panic!("no {name} in the report")).1
}

fn run(case: &Case, steps: usize, mut each: impl FnMut(usize, &StepReport)) {
    let mut state = State::default();
    let mesh = spillage::verify::fluid::build_mesh(case).unwrap();
    let fluid = FastFluid::new(case, mesh, &mut state).unwrap();
    let mut run = Coupled::fluid_only(case, state, fluid).unwrap();
    for step in 1..=steps {
        let report = run.step().unwrap();
        each(step, &report);
    }
}

fn couette(n_r: usize, n_theta: usize, dt: f64) -> Case {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/verification/fluid/couette_sliding.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text
        .replace("dt = 0.2\n", &format!("dt = {dt}\n"))
        .replace("n_r_rotor = 4", &format!("n_r_rotor = {}", n_r / 2))
        .replace("n_r_stator = 4", &format!("n_r_stator = {}", n_r / 2))
        .replace("n_theta_rotor = 32", &format!("n_theta_rotor = {n_theta}"))
        .replace("n_theta_stator = 40", &format!("n_theta_stator = {}", n_theta * 5 / 4));
    Case::from_toml(&text, &path).unwrap()
}

/// Circular Couette flow through the sliding interface (cases/verification/fluid/
/// couette_sliding.toml: rotor zone turning with the inner wall, non-conformal interface) run to
/// near steady state (45 s, e^{−9} of the spin-up left): the inner wall's torque on the water
/// is the exact 4πμL R₁²R₂²ω/(R₂² − R₁²) (spillage-and-flow-verification.md §3.2) to the
/// discretisation error, the outer wall's is its opposite, and the budget's imbalance R is the
/// truncation error of angular momentum, falling with the mesh.
///
/// Measured (inner torque error, |T_in + T_out|/T, |R|/T): 8×32: 1.51e-2, 4.0e-3, 3.6e-3;
/// 12×48: 7.6e-3, 4.8e-4, 1.8e-4; 16×64: 4.5e-3, 7e-5, 2.2e-4; 32×128: 1.1e-3, 1.1e-4, 1.7e-4 (the
/// outer loop's p_initial_residual 1e-5 bounds it there).
#[test]
fn couette_torque_matches_the_exact_one_and_the_budget_closes() {
    let mut previous = (f64::INFINITY, f64::INFINITY);
    for (n_r, n_theta, dt) in [(8, 32, 0.2), (12, 48, 0.2 * 2.0 / 3.0)] {
        let case = couette(n_r, n_theta, dt);
        let f = case.fluid.as_ref().unwrap();
        let (r1, r2, omega, length) = (1.0f64, 2.0f64, 1.0, 0.1);
        let exact = 4.0 * std::f64::consts::PI * f.density * f.kinematic_viscosity * length * r1 * r1 * r2 * r2 * omega / (r2 * r2 - r1 * r1);
        let steps = (45.0 / dt).round() as usize;
        let mut last = (0.0, 0.0, 0.0, 0.0);
        run(&case, steps, |step, r| {
            if step == steps {
                last = (value(r, "head_torque"), value(r, "static_wall_torque"), value(r, "torque_imbalance"), value(r, "angular_momentum_rate"));
            }
            // nothing crosses the walls, and the tank has no open boundary
            assert_eq!((value(r, "boundary_angular_momentum_outflow"), value(r, "open_boundary_torque")), (0.0, 0.0));
        });
        let (inner, outer, imbalance, rate) = last;
        let error = (inner - exact).abs() / exact;
        let opposite = (inner + outer).abs() / exact;
        let relative = imbalance.abs() / exact;
        eprintln!("Couette {n_r}×{n_theta}: inner {inner:.5} (exact {exact:.5}, error {error:.2e}), outer {outer:.5}, |sum|/T {opposite:.2e}, dL/dt {rate:.3e}, |R|/T {relative:.2e}");
        // the wall torque is second order: 1.5 % at 8×32 (the Couette check's velocity error is
        // of the same size); 2 % fails for a missing explicit stress or a wrong wall distance
        assert!(error <= 0.02, "{n_r}×{n_theta}: inner torque {inner} vs exact {exact}");
        // the spin-up's remaining dL/dt plus R: 4.0e-3 at 8×32
        assert!(opposite <= 6e-3, "{n_r}×{n_theta}: inner {inner}, outer {outer}");
        // truncation error of angular momentum: 3.6e-3 at 8×32
        assert!(relative <= 5e-3, "{n_r}×{n_theta}: R = {imbalance}");
        assert!(error < previous.0 && relative < previous.1, "{n_r}×{n_theta}: no convergence: {error} and {relative} after {previous:?}");
        previous = (error, relative);
    }
}
