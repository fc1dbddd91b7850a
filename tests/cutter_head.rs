//! The cutter head (issue 16) on a coarse copy of the shipped case: the fast fluid held to the
//! reference fluid at every step, the hull's net flux equal to the suction discharge, the
//! particles accounted for at every step, restarts bit-for-bit.

use std::path::Path;

use spillage_fast::fluid::FastFluid;
use spillage_model::case::Case;
use spillage_model::solver::{Solver, StepReport};
use spillage_model::state::State;
use spillage_model::step::{Coupled, FluidPhase};
use spillage_reference::dem::ReferenceDem;
use spillage_reference::fluid::ReferenceFluid;

/// The shipped head at 5 cm cells in a 0.8 m tank, `steps` steps of 2 ms;
/// `particles = false` drops everything from `[coupling]` on (fluid only).
fn coarse_head(particles: bool, steps: u64) -> Case {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/cutter_head.toml")).unwrap();
    let text = if particles { text } else { text[..text.find("[coupling]").unwrap()].to_string() };
    let mut table: toml::Table = text.parse().unwrap();
    let set = |table: &mut toml::Table, path: &[&str], value: toml::Value| {
        let (last, parents) = path.split_last().unwrap();
        let mut t = table;
        for p in parents {
            t = t.get_mut(*p).unwrap().as_table_mut().unwrap();
        }
        t.insert(last.to_string(), value);
    };
    let time: toml::Table = format!("dt = 0.002\nsteps = {steps}\nwrite_every = 0").parse().unwrap();
    table.insert("time".into(), toml::Value::Table(time));
    set(&mut table, &["cutter_head", "mesh", "cell_size"], 0.05.into());
    set(&mut table, &["cutter_head", "mesh", "outer_cell_size"], 0.15.into());
    set(&mut table, &["cutter_head", "tank", "radius"], 0.8.into());
    set(&mut table, &["cutter_head", "tank", "below_hub"], 0.16.into());
    if !particles {
        table["cutter_head"].as_table_mut().unwrap().remove("material");
    }
    Case::from_toml(&toml::to_string(&table).unwrap(), Path::new("cutter_head_coarse.toml")).unwrap_or_else(|e| panic!("{e}"))
}

fn fluid_only<F: FluidPhase>(case: &Case, make: impl FnOnce(&Case, &mut State) -> F) -> Coupled<F> {
    let mut state = State::default();
    let fluid = make(case, &mut state);
    Coupled::fluid_only(case, state, fluid).unwrap()
}

fn coupled<F: FluidPhase>(case: &Case, state: Option<State>, make: impl FnOnce(&Case, &mut State) -> F) -> Coupled<F, ReferenceDem> {
    let mut state = state.unwrap_or_default();
    let fluid = make(case, &mut state);
    let dem = ReferenceDem::new(case, &mut state).unwrap();
    Coupled::new(case, state, Some(fluid), Some(dem)).unwrap()
}

fn mesh(case: &Case) -> spillage_model::mesh::Mesh {
    spillage::verify::fluid::build_mesh(case).unwrap()
}

fn value(report: &StepReport, name: &str) -> f64 {
    report.values.iter().find(|(n, _)| *n == name).unwrap_or_else(|| panic!("no {name} in the report")).1
}

/// Fast and reference fluid on the head (rotor with blocked cells, rotating head walls, the
/// floor's inflow, the pipe's outlet, the sliding interface) agree within 1e-8 of the field
/// scale after every step (the bound of tests/fast_equivalence.rs).
#[test]
fn fast_fluid_matches_the_reference_fluid_on_the_head() {
    let case = coarse_head(false, 12);
    let mut reference = fluid_only(&case, |c, s| ReferenceFluid::new(c, mesh(c), s).unwrap());
    let mut fast = fluid_only(&case, |c, s| FastFluid::new(c, mesh(c), s).unwrap());
    let mut worst = 0.0f64;
    for step in 1..=12 {
        let (a, b) = (reference.step().unwrap(), fast.step().unwrap());
        let diff = spillage_model::state_diff::diff(reference.state(), fast.state());
        let error = spillage::verify::equivalence_error(reference.state(), &diff);
        worst = worst.max(error);
        assert!(error <= 1e-8, "step {step}: {}", diff.report());
        // the hull fluxes are computed from each solver's own face fluxes
        assert!((value(&a, "hull_outflow") - value(&b, "hull_outflow")).abs() <= 1e-8 * case.cutter_head.as_ref().unwrap().suction_discharge);
        // and the contour surface's from each solver's own cell velocities
        assert!((value(&a, "contour_outflow") - value(&b, "contour_outflow")).abs() <= 1e-8 * case.cutter_head.as_ref().unwrap().suction_discharge);
    }
    eprintln!("head, fluid only: 12 steps, worst relative difference {worst:.3e}, {} cells", reference.mesh().unwrap().n_cells());
}

/// Continuity through the head: what enters through the floor leaves through the pipe, and
/// the net flux into the contour hull is the flux out of its mouth, both to the solver's
/// continuity tolerance (1e-9 of Q_m; the pressure solve converges to 1e-12 normalised). The
/// out-flowing flux is never negative and, once the blades pump (by the tenth step), positive.
#[test]
fn the_hull_passes_the_suction_discharge() {
    let case = coarse_head(false, 10);
    let q_m = case.cutter_head.as_ref().unwrap().suction_discharge;
    let mut run = fluid_only(&case, |c, s| FastFluid::new(c, mesh(c), s).unwrap());
    let mut outflow = 0.0;
    for step in 1..=10 {
        let report = run.step().unwrap();
        let (net, suction) = (value(&report, "hull_net_flux"), value(&report, "suction_flux"));
        outflow = value(&report, "hull_outflow");
        assert!((suction - q_m).abs() <= 1e-9 * q_m, "step {step}: mouth flux {suction} vs Q_m {q_m}");
        assert!((net + suction).abs() <= 1e-9 * q_m, "step {step}: net hull flux {net} vs mouth {suction}");
        assert!((0.0..10.0 * q_m).contains(&outflow), "step {step}: out-flowing flux {outflow}");
        // the ratio is the same division done once in the driver: equal to round-off of one op
        assert!((value(&report, "outflow_ratio") - outflow / q_m).abs() < 1e-15);
        // the interpolated contour (Eqs. 8.1–8.4): its net flux is checked against Q_m on the
        // developed flow by `spillage verify` (cutter_head_flow); in these first steps from the
        // solid-body start it is 6–27 % off, so here only its sign and size
        let contour_net = value(&report, "contour_net_flux");
        assert!(contour_net < 0.0 && contour_net > -2.0 * q_m, "step {step}: net flux through the contour {contour_net}");
        assert!((0.0..10.0 * q_m).contains(&value(&report, "contour_outflow")));
    }
    assert!(outflow > 0.0, "no outflow after 10 steps");
}

/// With the batch: every particle is inside, sucked or spilled at every step (the driver also
/// refuses a step that loses one), the fractions are those counts over the batch (Eq. 8.6),
/// and both fluids give the same particles to 1e-8.
#[test]
fn every_particle_is_inside_sucked_or_spilled() {
    let case = coarse_head(true, 15);
    let mut reference = coupled(&case, None, |c, s| ReferenceFluid::new(c, mesh(c), s).unwrap());
    let mut fast = coupled(&case, None, |c, s| FastFluid::new(c, mesh(c), s).unwrap());
    let batch = fast.state().particles.as_ref().unwrap().particles.len() as f64;
    assert!(batch > 50.0, "the head lattice placed {batch} particles");
    for step in 1..=15 {
        let (a, report) = (reference.step().unwrap(), fast.step().unwrap());
        let inside = value(&report, "particles");
        let (sucked, spilled) = (value(&report, "sucked"), value(&report, "spilled"));
        assert_eq!(inside + sucked + spilled, batch, "step {step}");
        assert_eq!(value(&report, "production"), sucked / batch);
        assert_eq!(value(&report, "spillage"), spilled / batch);
        let diff = spillage_model::state_diff::diff(reference.state(), fast.state());
        let error = spillage::verify::equivalence_error(reference.state(), &diff);
        assert!(error <= 1e-8, "step {step}: {}", diff.report());
        assert_eq!(value(&a, "spilled"), spilled, "step {step}");
    }
}

/// A head run restarted from a checkpoint continues bit-for-bit (fluid, particles, walls,
/// exit log).
#[test]
fn a_head_run_restarts_bit_for_bit() {
    let case = coarse_head(true, 12);
    let make = |c: &Case, s: &mut State| FastFluid::new(c, mesh(c), s).unwrap();
    let mut straight = coupled(&case, None, make);
    for _ in 0..6 {
        straight.step().unwrap();
    }
    let path = std::env::temp_dir().join(format!("spillage-head-restart-{}.ckpt", std::process::id()));
    spillage_model::checkpoint::write(&path, &case, straight.state()).unwrap();
    let read = spillage_model::checkpoint::read(&path, &case).unwrap();
    std::fs::remove_file(&path).ok();
    let mut restarted = coupled(&case, Some(read), make);
    for step in 7..=12 {
        let (a, b) = (straight.step().unwrap(), restarted.step().unwrap());
        let bits = |r: &StepReport| r.values.iter().map(|v| v.1.to_bits()).collect::<Vec<u64>>();
        assert_eq!(bits(&a), bits(&b), "step {step}: reports differ after the restart");
    }
    assert!(straight.state() == restarted.state(), "states differ after the restart");
}

/// A continuous feed in a cutting region of the turning head, starting after two steps: the
/// particles created follow the requested rate to within one particle per step (the debt
/// carries the fraction), every new particle lies clear of the blades and of the other
/// particles when it appears, and the steps without particles report the same columns.
#[test]
fn the_feed_keeps_its_rate_and_clear_of_blades_and_particles() {
    let mut case = coarse_head(true, 10);
    let section = case.particles.as_mut().unwrap();
    section.groups.clear();
    let feed: spillage_model::particles::settings::FeedSection = toml::from_str(
        r#"material = "rock"
           diameter = 0.02
           region = { min = [-0.3, -0.3, -0.3], max = [-0.05, -0.05, -0.03] }
           rate = 2000.0
           start = 0.0041
           seed = 7"#,
    )
    .unwrap();
    section.feed.push(feed);
    case.finish().unwrap();
    let head = spillage_model::cutter_head::CutterHead::new(case.cutter_head.as_ref().unwrap());
    let mut run = coupled(&case, None, |c, s| FastFluid::new(c, mesh(c), s).unwrap());
    let mut known = 0u64;
    let mut columns: Option<Vec<&str>> = None;
    for step in 1..=10 {
        let report = run.step().unwrap();
        // series.csv has one header: every step reports the same columns, also the first,
        // before the feed has placed anything
        let names: Vec<&str> = report.values.iter().map(|v| v.0).collect();
        assert_eq!(columns.get_or_insert_with(|| names.clone()), &names, "step {step}");
        let state = run.state();
        let particles = state.particles.as_ref().unwrap();
        let owed = 2000.0 * (state.time - 0.0041).max(0.0);
        let created = particles.counts.created as f64;
        assert!(created <= owed + 1e-9 && created > owed - 1.0 - 1e-9, "step {step}: {created} created, {owed} owed");
        // new particles have moved at most ~g Δt² since they appeared: they keep 90 % of
        // their radius clear of the solids and of each other
        for p in particles.particles.iter().filter(|p| p.id >= known) {
            let (r, theta) = (p.position.x.hypot(p.position.y), p.position.y.atan2(p.position.x) - state.rotor_angle);
            assert!(head.sphere_is_clear(r, theta, p.position.z, 0.45 * p.diameter), "step {step}: particle {} in a solid", p.id);
            for q in particles.particles.iter().filter(|q| q.id != p.id) {
                assert!((p.position - q.position).norm() > 0.9 * 0.5 * (p.diameter + q.diameter), "step {step}: {} overlaps {}", p.id, q.id);
            }
        }
        known = particles.particles.iter().map(|p| p.id + 1).max().unwrap_or(known);
    }
    // 2000/s over the 15.9 ms after the start: 31 owed
    assert_eq!(run.state().particles.as_ref().unwrap().counts.created, 31);
}

/// The rotor's torque balance (issue 16 check 3, spillage_model::cutter_head::torque) on the
/// coarse head after the start-up (steps 5–20; the first steps carry the solid-body start's
/// torque spike): the whole water's angular momentum changes by the wall torques less what the
/// pipe carries out, and the hull's by its walls less what crosses hull and mouth (the Euler
/// turbine equation), both up to the imbalance R. The scheme conserves angular momentum only to
/// truncation error; measured here R/T ≤ 0.099 (whole) and ≤ 0.047 (hull) at 5 cm cells, falling
/// with the cell size (R 6.9 → 6.1 → 3.3 N m at 5, 4, 3.3 cm over steps 31–60). The bounds
/// 0.15 and 0.1 fail if a term is missing or has the wrong sign (the rate is ~T here), and the
/// hull's flux taken with linearly interpolated instead of the scheme's face values left
/// R_hull/T ≈ 0.5.
#[test]
fn the_head_torque_balances_the_angular_momentum_budget() {
    let case = coarse_head(false, 20);
    let mut run = fluid_only(&case, |c, s| FastFluid::new(c, mesh(c), s).unwrap());
    let (mut worst, mut worst_hull, mut outflow) = (0.0f64, 0.0f64, 0.0f64);
    for step in 1..=20 {
        let report = run.step().unwrap();
        let v = |n: &str| value(&report, n);
        let t = v("head_torque");
        // R is what is left of the budget: the driver's terms add up to it exactly
        let closed = v("angular_momentum_rate")
            - (t + v("static_wall_torque") + v("open_boundary_torque") + v("gravity_torque") - v("boundary_angular_momentum_outflow"));
        assert!((closed - v("torque_imbalance")).abs() <= 1e-9 * t.abs(), "step {step}");
        assert!((v("shaft_power") - t * case.rotor.as_ref().unwrap().angular_velocity()).abs() <= 1e-12 * t.abs());
        if step >= 5 {
            assert!(t > 0.0, "step {step}: the head drives the water along ω: T = {t}");
            worst = worst.max(v("torque_imbalance").abs() / t);
            worst_hull = worst_hull.max(v("hull_torque_imbalance").abs() / t);
            outflow = outflow.max(v("boundary_angular_momentum_outflow") / t);
        }
    }
    eprintln!("head torque budget, steps 5–20: worst |R|/T {worst:.4}, hull {worst_hull:.4}; pipe outflow up to {outflow:.3} T");
    assert!(worst <= 0.15, "whole water: |R|/T = {worst}");
    assert!(worst_hull <= 0.1, "hull: |R|/T = {worst_hull}");
}
