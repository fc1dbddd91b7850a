//! The whole-domain rotating reference frame (issue 17; wear-model.md §2.6 [R], §15 A39–A40):
//! the coarse levels of `cases/verification/rotating_frame` (`spillage verify --full` adds the
//! fine ones), each row asserted and snapshotted. (Bad `[physics.rotating_frame]` sections:
//! model/tests/case_errors.rs.)

use std::path::PathBuf;

use spillage::verify::{run_case, CheckRow};
use spillage_model::case::Case;

fn case(name: &str) -> Case {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases/verification/rotating_frame").join(name);
    Case::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// Runs the coarse levels, asserts every row and snapshots the rows (3 significant digits).
fn check(name: &str) -> Vec<CheckRow> {
    let rows = run_case(&case(name), false).unwrap_or_else(|e| panic!("{name}: {e:#}"));
    for r in &rows {
        eprintln!(
            "{:<66} {:<9} value {:>12.5e} ref {:>12.5e} tol {:>10.3e} {}",
            r.quantity,
            r.solver,
            r.value,
            r.reference,
            r.tolerance,
            if r.pass { "ok" } else { "FAIL" }
        );
    }
    for r in &rows {
        assert!(r.pass, "{name}: {} ({}) = {} fails (reference {}, tolerance {})", r.quantity, r.solver, r.value, r.reference, r.tolerance);
    }
    let summary: Vec<(String, String, String, bool)> =
        rows.iter().map(|r| (r.quantity.clone(), r.solver.clone(), format!("{:.2e}", r.value), r.pass)).collect();
    insta::with_settings!({ snapshot_path => "../golden", prepend_module_to_snapshot => false }, {
        insta::assert_json_snapshot!(format!("rotating_frame_{}", name.trim_end_matches(".toml")), summary);
    });
    rows
}

/// (a) A39, and A40 on the reference DEM: second order in Δt.
#[test]
fn free_particle() {
    check("free_particle.toml");
}

/// (b) Water at rest in the frame: no motion, centrifugal pressure, both fluid solvers.
#[test]
fn fluid_at_rest() {
    check("fluid_at_rest.toml");
}

/// (b) The same in a closed annulus about the axis: the pressure error is second order in Δr.
#[test]
fn fluid_at_rest_annulus() {
    check("fluid_at_rest_annulus.toml");
}

/// (c) Fast vs reference fluid ≤ 1e-8 at every step with the Coriolis force acting.
#[test]
fn fast_fluid_matches_the_reference_fluid_with_coriolis() {
    check("channel.toml");
}

/// (d) A grain drifting outwards through water at rest in the frame.
#[test]
fn settling_grain_drifts_at_the_centrifugal_terminal_velocity() {
    check("settling.toml");
}
