//! Sliding wear (wear-model.md §14 item 12, `spillage_model::wear::sliding`): a sphere pressed
//! onto a plate while it slides along it wears the plate at the closed-form rate of
//! `analytic::erosion::arabnejad_sliding_wear_rate`, in both particle phases, which agree step
//! by step; without `sliding` the same contact wears nothing (one impact at zero angle).

use std::path::Path;

use spillage::verify::particle_equivalence::{compare_particle_phases, reference_run, MIN_SUBSTEPS, PARTICLE_TOLERANCE};
use spillage_analytic::erosion::{arabnejad_sliding_wear_rate, ArabnejadMaterial, CARBON_STEEL_1018};
use spillage_analytic::hertz::{ContactPair, ElasticMaterial};
use spillage_model::case::Case;
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::step::{Absent, Coupled};
use spillage_reference::dem::ReferenceDem;
use spillage_reference::wear::ReferenceWear;

const DIAMETER: f64 = 0.002;
const DENSITY: f64 = 2500.0;
const YOUNGS: f64 = 1e8;
const POISSON: f64 = 0.25;
const RESTITUTION: f64 = 0.9;
/// The push onto the plate [m/s²]: of the order of the Coriolis tester's 2Ωu.
const PUSH: f64 = 1000.0;
const SPEED: f64 = 2.0;
const HARDNESS: f64 = 1.31e9;
const STEPS: usize = 40;
const DT: f64 = 1e-3;

fn mass() -> f64 {
    DENSITY * std::f64::consts::PI / 6.0 * DIAMETER.powi(3)
}

/// The sphere starts at rest on the plate at the overlap where Hertz's force carries its
/// weight, sliding at `SPEED` without friction: the plate pushes back with m·PUSH all along.
fn sliding_case(sliding: bool, substep: f64) -> Case {
    let material = ElasticMaterial::new(YOUNGS, POISSON, DENSITY).unwrap();
    let pair = ContactPair::sphere_wall(&material, DIAMETER / 2.0, &material).unwrap();
    let overlap = (mass() * PUSH / pair.normal_stiffness()).powf(2.0 / 3.0);
    let text = format!(
        r#"
[case]
name = "sliding_sphere"
description = "a sphere pressed onto a plate sliding along it (sliding wear)"
[physics]
gravity = [0.0, 0.0, -{PUSH}]
[time]
dt = {DT}
steps = {STEPS}
[particles]
substep = {substep}
[[particles.materials]]
name = "glass"
density = {DENSITY}
youngs_modulus = {YOUNGS}
poisson_ratio = {POISSON}
restitution = {RESTITUTION}
friction = 0.0
[[particles.groups]]
placement = "list"
material = "glass"
diameter = {DIAMETER}
# mid-row: clear of the line where the two rows of triangles meet
positions = [[-0.04, 0.005, {z}]]
velocities = [[{SPEED}, 0.0, 0.0]]
[[walls]]
name = "plate"
material = "glass"
shape = {{ type = "plane", centre = [0.0, 0.0, 0.0], normal = [0.0, 0.0, 1.0], size = [0.2, 0.02], divisions = [20, 2] }}
[wear]
law = "arabnejad"
sliding = {sliding}
receding = false
[wear.material]
preset = "carbon_steel_1018"
vickers_hardness = {HARDNESS}
"#,
        z = DIAMETER / 2.0 - overlap,
    );
    Case::from_toml(&text, Path::new("sliding_sphere.toml")).unwrap_or_else(|e| panic!("{e}"))
}

/// The reference DEM and wear phase from `state` (a restart when it is not empty).
fn run_from(case: &Case, mut state: State) -> Coupled<Absent, ReferenceDem> {
    let dem = ReferenceDem::new(case, &mut state).unwrap();
    let wear = ReferenceWear::new(case, &mut state).unwrap();
    Coupled::particles_only(case, state, dem).unwrap().with_wear(Box::new(wear)).unwrap()
}

fn deposited_after_the_run(case: &Case) -> (f64, f64, u64) {
    let mut run = reference_run(case).unwrap();
    for _ in 0..STEPS {
        run.step().unwrap();
    }
    let state = run.state();
    let wall = &state.wear.as_ref().unwrap().walls[0];
    (wall.deposited, wall.sliding_deposited, state.particles.as_ref().unwrap().counts.impacts)
}

/// The wear law's sliding volume per unit normal impulse, at the sub-step's grazing angle,
/// relative to its limit: f(θ)/(θ/K) = 1 − θ/(2K) + O(θ²) with θ = PUSH·Δt_s/((1 + e)·U).
fn first_order_bias(substep: f64) -> f64 {
    let theta = PUSH * substep / ((1.0 + RESTITUTION) * SPEED);
    theta / (2.0 * CARBON_STEEL_1018.contact_ratio)
}

#[test]
fn a_sliding_sphere_wears_the_plate_at_the_closed_form_rate() {
    let material = ArabnejadMaterial { vickers_hardness: HARDNESS, ..CARBON_STEEL_1018 };
    let expected = arabnejad_sliding_wear_rate(&material, RESTITUTION, mass() * PUSH, SPEED).unwrap() * STEPS as f64 * DT;
    let mut errors = Vec::new();
    for substep in [2e-6, 1e-6] {
        let (deposited, sliding, impacts) = deposited_after_the_run(&sliding_case(true, substep));
        let error = deposited / expected - 1.0;
        eprintln!("sub-step {substep:.0e} s: deposited {deposited:.6e} m³ ({sliding:.6e} sliding), closed form {expected:.6e} m³, relative error {error:.3e}, bias {:.3e}", first_order_bias(substep));
        assert_eq!(impacts, 1, "sustained contact's equivalent impacts are not impacts");
        // the first touch (normal speed PUSH·Δt_s after the first sub-step) wore for the
        // collision's impulse, the rest is sliding wear
        assert!(sliding > 0.999 * deposited && sliding < deposited);
        // Tolerance: the law's first-order departure from its slope, θ/(2K) (5e-4 and 3e-4
        // here), and the few sub-steps' worth of impulse of the starting transient
        // (the sphere starts at the overlap of the analytic Hertz stiffness, its oscillation
        // damps out in 20 ms): the error must be the bias to within 10 %
        assert!((error + first_order_bias(substep)).abs() < 0.1 * first_order_bias(substep), "relative error {error:.3e}");
        errors.push(error);
    }
    // the sub-step's error is first order: halving it halves the error (order 1 ± 0.1)
    let order = (errors[0] / errors[1]).log2();
    assert!((order - 1.0).abs() < 0.1, "observed order {order:.3}");
}

#[test]
fn without_sliding_wear_the_same_contact_wears_nothing() {
    let (with, _, _) = deposited_after_the_run(&sliding_case(true, 1e-6));
    let (deposited, sliding, impacts) = deposited_after_the_run(&sliding_case(false, 1e-6));
    // one impact, at the normal speed one sub-step of the push gives: 2e-5 of the sliding wear
    assert_eq!((sliding, impacts), (0.0, 1));
    assert!(deposited < 1e-4 * with, "{deposited:.3e} of {with:.3e}");
}

#[test]
fn the_fast_particle_phase_books_the_same_sliding_wear() {
    let case = sliding_case(true, 1e-6);
    // 20 steps of 1 000 sub-steps (Δt_s = 1 µs): the contact slides through 20 of them
    let out = compare_particle_phases(&case, 20_000, STEPS as u64).unwrap();
    eprintln!("{} steps, {} sub-steps, worst {:.2e} in {} at step {}", out.steps, out.substeps, out.worst, out.worst_field, out.worst_step);
    assert!(out.substeps >= MIN_SUBSTEPS);
    assert!(out.worst <= PARTICLE_TOLERANCE, "worst {:.3e} in {}", out.worst, out.worst_field);
}

#[test]
fn a_restart_mid_slide_continues_bit_for_bit() {
    // the contact's normal impulse so far lives in the checkpoint: without it the restarted
    // contact would book its first (1 + e)·m·v_n again as collision, not as sliding wear
    let case = sliding_case(true, 1e-6);
    let mut straight = run_from(&case, State::default());
    for _ in 0..20 {
        straight.step().unwrap();
    }
    let mut first = run_from(&case, State::default());
    for _ in 0..10 {
        first.step().unwrap();
    }
    assert!(first.state().particles.as_ref().unwrap().contacts[0].normal_impulse > 0.0);
    let path = std::env::temp_dir().join(format!("spillage-sliding-restart-{}.chk", std::process::id()));
    spillage_model::checkpoint::write(&path, &case, first.state()).unwrap();
    let restored = spillage_model::checkpoint::read(&path, &case).unwrap();
    std::fs::remove_file(&path).ok();
    let mut second = run_from(&case, restored);
    for _ in 0..10 {
        second.step().unwrap();
    }
    assert_eq!(second.state(), straight.state());
}
