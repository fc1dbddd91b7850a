//! Wear (issue 17) through the whole step: the stream, Coriolis and jet checks of the ladder at
//! their coarse level, restarts bit-for-bit with worn walls, the DEM colliding with the worn
//! shape, a clear error instead of a tangled wall, and a cutter head wearing its blades.

use std::path::Path;

use spillage_model::case::Case;
use spillage_model::particles::state::Vec3;
use spillage_model::particles::Particle;
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::step::Coupled;
use spillage_reference::dem::ReferenceDem;
use spillage_reference::wear::ReferenceWear;

fn stream_case(edit: impl Fn(&mut toml::Table)) -> Case {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/verification/wear/stream_plate.toml");
    let mut table: toml::Table = std::fs::read_to_string(&path).unwrap().parse().unwrap();
    edit(&mut table);
    Case::from_toml(&toml::to_string(&table).unwrap(), &path).unwrap_or_else(|e| panic!("{e}"))
}

fn run(case: &Case, state: State) -> Coupled<spillage_model::step::Absent, ReferenceDem> {
    let mut state = state;
    let dem = ReferenceDem::new(case, &mut state).unwrap();
    let wear = ReferenceWear::new(case, &mut state).unwrap();
    Coupled::particles_only(case, state, dem).unwrap().with_wear(Box::new(wear)).unwrap()
}

#[test]
fn the_stream_check_passes_at_its_coarse_level() {
    let case = stream_case(|_| {});
    let rows = spillage::verify::run_case(&case, false).unwrap();
    let failed: Vec<_> = rows.iter().filter(|r| !r.pass).collect();
    assert!(failed.is_empty(), "{failed:#?}");
    assert!(rows.len() >= 2 * 8 + 4, "{} rows", rows.len());
    // volumes and rates to 3 significant digits: a change that moves a verified number shows
    let summary: Vec<(String, String, bool)> = rows.iter().map(|r| (r.quantity.clone(), format!("{:.2e}", r.value), r.pass)).collect();
    insta::with_settings!({ snapshot_path => "../golden", prepend_module_to_snapshot => false }, {
        insta::assert_json_snapshot!("wear_stream_plate", summary);
    });
}

/// Runs a wear case of the ladder at its coarse level: every row passes, and the rows (values to
/// 3 significant digits) match the golden snapshot `snapshot`.
fn coarse_level_matches_its_golden(file: &str, snapshot: &str) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/verification/wear").join(file);
    let case = Case::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let rows = spillage::verify::run_case(&case, false).unwrap();
    for r in &rows {
        eprintln!("{:<80} value {:>12.5e} ref {:>10.3e} tol {:>10.3e} {}", r.quantity, r.value, r.reference, r.tolerance, if r.pass { "ok" } else { "FAIL" });
    }
    let failed: Vec<_> = rows.iter().filter(|r| !r.pass).collect();
    assert!(failed.is_empty(), "{failed:#?}");
    let summary: Vec<(String, String, bool)> = rows.iter().map(|r| (r.quantity.clone(), format!("{:.2e}", r.value), r.pass)).collect();
    insta::with_settings!({ snapshot_path => "../golden", prepend_module_to_snapshot => false }, {
        insta::assert_json_snapshot!(snapshot, summary);
    });
}

#[test]
fn the_coriolis_tester_lands_its_garnet_a_centimetre_after_the_step() {
    coarse_level_matches_its_golden("coriolis_garnet.toml", "wear_coriolis_garnet");
}

#[test]
fn the_jet_wears_a_receding_plate_as_a_still_one_at_first_impact() {
    coarse_level_matches_its_golden("jet_impingement.toml", "wear_jet_impingement");
}

#[test]
fn a_restart_with_worn_walls_continues_bit_for_bit() {
    let case = stream_case(|_| {});
    let mut straight = run(&case, State::default());
    for _ in 0..40 {
        straight.step().unwrap();
    }
    let mut first = run(&case, State::default());
    for _ in 0..25 {
        first.step().unwrap();
    }
    let wear = first.state().wear.as_ref().unwrap();
    assert!(wear.walls[0].receded > 0.0, "the plate must have receded before the checkpoint");
    let path = std::env::temp_dir().join(format!("spillage-wear-restart-{}.chk", std::process::id()));
    spillage_model::checkpoint::write(&path, &case, first.state()).unwrap();
    let restored = spillage_model::checkpoint::read(&path, &case).unwrap();
    std::fs::remove_file(&path).ok();
    let mut second = run(&case, restored);
    for _ in 0..15 {
        second.step().unwrap();
    }
    assert_eq!(second.state(), straight.state());
}

#[test]
fn the_dem_collides_with_the_worn_shape_of_a_receding_wall() {
    let case = stream_case(|_| {});
    let mut state = State::default();
    let mut dem = ReferenceDem::new(&case, &mut state).unwrap();
    let particles = state.particles.as_mut().unwrap();
    let material = 0;
    // a 2 mm sphere 0.5 mm into the plate's original surface
    particles.particles.push(Particle {
        id: 0,
        material,
        diameter: 0.002,
        density: 2500.0,
        position: Vec3::new(0.0, 0.0, 0.0005),
        velocity: Vec3::zeros(),
        spin: Vec3::zeros(),
        contact_force: Vec3::zeros(),
        contact_torque: Vec3::zeros(),
        contacts: 0,
    });
    let contacts_after_substep = |dem: &mut ReferenceDem, state: &mut State| {
        let (particles, walls) = (state.particles.as_mut().unwrap(), state.walls.as_mut().unwrap());
        dem.refresh_wall_meshes(walls).unwrap();
        dem.substep(particles, walls, 1e-9, 1e-9, None, &|_, _| None);
        particles.particles[0].contacts
    };
    assert_eq!(contacts_after_substep(&mut dem, &mut state), 1);
    // the whole plate worn 1 mm deep: the sphere is clear of it
    let walls = state.walls.as_mut().unwrap();
    for v in &mut walls.walls[0].vertices {
        v.z -= 0.001;
    }
    walls.walls[0].revision += 1;
    assert_eq!(contacts_after_substep(&mut dem, &mut state), 0);
}

#[test]
fn wear_deeper_than_the_triangles_is_a_clear_error() {
    let case = stream_case(|t| {
        t["wear"]["acceleration"] = toml::Value::Float(1e6);
        t["wear"].as_table_mut().unwrap().remove("smoothing");
    });
    let mut run = run(&case, State::default());
    let error = loop {
        match run.step() {
            Ok(_) => assert!(run.state().time < 0.03, "no error although every impact removes millimetres"),
            Err(e) => break e.to_string(),
        }
    };
    assert!(error.contains("wall `plate` would turn inside out") && error.contains("acceleration"), "{error}");
}

#[test]
fn a_cutter_head_wears_its_blades_with_one_wear_section() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/cutter_head.toml");
    let mut text = std::fs::read_to_string(&path).unwrap();
    text.push_str(
        "\n[wear]\nlaw = \"arabnejad\"\nwalls = [\"blade_1\", \"blade_2\", \"blade_3\", \"blade_4\", \"blade_5\", \"blade_6\"]\n\
         [wear.material]\npreset = \"carbon_steel_1018\"\nvickers_hardness = 1.31e9\n",
    );
    let case = Case::from_toml(&text, &path).unwrap_or_else(|e| panic!("{e}"));
    let mut state = State::default();
    let _dem = ReferenceDem::new(&case, &mut state).unwrap();
    let wear = ReferenceWear::new(&case, &mut state).unwrap();
    let walls = state.walls.as_ref().unwrap();
    let wear_state = state.wear.as_ref().unwrap();
    assert_eq!(wear_state.walls.len(), 6);
    for (w, surface) in wear_state.walls.iter().zip(wear.surfaces()) {
        // a blade is a closed solid: no rim, and its material is inside its winding
        assert!(surface.closed, "{} is open", w.name);
        assert!(w.material_side != 0.0 && w.initial_volume != 0.0, "{}", w.name);
        assert_eq!(walls.walls[w.wall].name, w.name);
    }
}
