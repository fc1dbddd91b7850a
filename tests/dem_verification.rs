//! The DEM verification ladder (issue #5) at its coarse levels: every row must pass its
//! tolerance (stated next to each check in src/verify/dem.rs), and the rounded summary must match
//! its reviewed golden snapshot. The 1000-sphere pile runs with `spillage verify --full` only
//! (here: its first 150 spheres).

use std::path::Path;

use spillage::verify::{dem, CheckRow};
use spillage_model::case::Case;

fn run(file: &str) -> Vec<CheckRow> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/verification/dem").join(file);
    let case = Case::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let check = case.verify.as_ref().expect("a verification case").check.clone();
    let rows = dem::run_check(&case, &check, false, None).unwrap_or_else(|e| panic!("{file}: {e:#}"));
    assert!(!rows.is_empty(), "{file}: no rows");
    for row in &rows {
        assert!(row.pass, "{file}: {} = {} vs {} (error {:e} > tolerance {:e})", row.quantity, row.value, row.reference, row.error, row.tolerance);
    }
    rows
}

/// Values rounded to a tenth of their tolerance (relative to the reference where it is not
/// zero), so the snapshot changes only when a result moves by a visible fraction of it.
fn summary(rows: &[CheckRow]) -> Vec<(String, String, bool)> {
    rows.iter()
        .map(|r| {
            let quantum =
                if r.tolerance > 0.0 { 0.1 * r.tolerance * if r.reference != 0.0 && r.tolerance < 1.0 { r.reference.abs() } else { 1.0 } } else { 0.0 };
            let value = if quantum > 0.0 { (r.value / quantum).round() * quantum } else { r.value };
            let digits = if quantum > 0.0 { ((value.abs().max(quantum) / quantum).log10().ceil() as usize).clamp(1, 12) } else { 12 };
            (r.quantity.clone(), format!("{value:.*e}", digits.saturating_sub(1)), r.pass)
        })
        .collect()
}

fn golden(name: &str, rows: &[CheckRow]) {
    insta::with_settings!({ snapshot_path => "../golden", prepend_module_to_snapshot => false }, {
        insta::assert_json_snapshot!(name, summary(rows));
    });
}

#[test]
fn hertz_elastic_sphere_wall() {
    golden("dem_hertz_sphere_wall", &run("hertz_sphere_wall.toml"));
}

#[test]
fn hertz_elastic_sphere_sphere() {
    golden("dem_hertz_sphere_sphere", &run("hertz_sphere_sphere.toml"));
}

#[test]
fn dry_restitution_is_speed_independent() {
    golden("dem_dry_restitution", &run("dry_restitution.toml"));
}

#[test]
fn wet_restitution_follows_legendre() {
    golden("dem_wet_restitution", &run("wet_restitution.toml"));
}

#[test]
fn oblique_sphere_wall_against_walton() {
    golden("dem_oblique_wall", &run("oblique_wall.toml"));
}

#[test]
fn oblique_sphere_sphere_against_walton() {
    golden("dem_oblique_pair", &run("oblique_pair.toml"));
}

#[test]
fn rotating_disc_carries_a_resting_sphere() {
    golden("dem_moving_wall_disc", &run("moving_wall_disc.toml"));
}

#[test]
fn rotating_blade_hits_a_sphere() {
    golden("dem_moving_wall_blade", &run("moving_wall_blade.toml"));
}

#[test]
fn tessellated_plane_equals_flat_plane() {
    golden("dem_tessellated_plane", &run("tessellated_plane.toml"));
}

#[test]
fn pile_comes_to_rest_in_the_box() {
    golden("dem_pile_coarse", &run("pile.toml"));
}

/// A checkpoint round trip (serde JSON) of a mid-run DEM state continues bit for bit,
/// including the tangential contact history.
#[test]
fn checkpoint_restart_is_bit_exact() {
    use spillage_model::solver::Solver;
    use spillage_model::state::State;
    use spillage_model::step::Coupled;
    use spillage_reference::dem::ReferenceDem;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/verification/dem/tessellated_plane.toml");
    let case = Case::load(&path).unwrap();
    let mut state = State::default();
    let dem = ReferenceDem::new(&case, &mut state).unwrap();
    let mut a = Coupled::particles_only(&case, state, dem).unwrap();
    for _ in 0..50 {
        a.step().unwrap();
    }
    assert!(!a.state().particles.as_ref().unwrap().contacts.is_empty(), "the check needs a live contact history");
    let text = serde_json::to_string(a.state()).unwrap();
    let restored: State = serde_json::from_str(&text).unwrap();
    assert_eq!(&restored, a.state());
    let mut restored = restored;
    let dem = ReferenceDem::new(&case, &mut restored).unwrap();
    let mut b = Coupled::particles_only(&case, restored, dem).unwrap();
    for _ in 0..50 {
        a.step().unwrap();
        b.step().unwrap();
    }
    assert_eq!(a.state(), b.state());
}
