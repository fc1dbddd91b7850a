//! Fast vs reference DEM, step by step (issue 19): every shipped case with particles, at the
//! level of its case file, runs with both particle phases from the same initial state; after
//! every step the whole states agree to 1e-10 of each field's scale with the same contacts,
//! for at least 100 DEM sub-steps. And the fast DEM gives the same bits on 1 and 2 threads.

use std::path::PathBuf;

use spillage::verify::particle_equivalence::{compare_particle_phases, fast_run, MIN_SUBSTEPS, PARTICLE_TOLERANCE};
use spillage_model::case::Case;
use spillage_model::state_diff::diff;

fn case(path: &str) -> Case {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases").join(path);
    Case::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// Compares `path` over at least [`MIN_SUBSTEPS`] sub-steps (at most `max_steps` steps).
fn compare(path: &str, max_steps: u64) {
    compare_over(path, MIN_SUBSTEPS, max_steps);
}

fn compare_over(path: &str, min_substeps: u64, max_steps: u64) {
    let c = case(path);
    let e = compare_particle_phases(&c, min_substeps, max_steps).unwrap_or_else(|e| panic!("{e:#}"));
    eprintln!(
        "{path}: {} steps, {} sub-steps, worst {:.3e} in {} at step {}; reference {:.3} s, fast {:.3} s",
        e.steps, e.substeps, e.worst, e.worst_field, e.worst_step, e.reference_seconds, e.fast_seconds
    );
    assert!(e.substeps >= min_substeps, "{path}: only {} sub-steps in {max_steps} steps", e.substeps);
    assert!(e.worst <= PARTICLE_TOLERANCE, "{path}: step {}: {} differs by {:e} of its scale", e.worst_step, e.worst_field, e.worst);
}

#[test]
fn dem_verification_cases() {
    for name in [
        "dry_restitution",
        "hertz_sphere_sphere",
        "hertz_sphere_wall",
        "moving_wall_blade",
        "moving_wall_disc",
        "oblique_pair",
        "oblique_wall",
        "tessellated_plane",
        "wet_restitution",
    ] {
        compare(&format!("verification/dem/{name}.toml"), 400);
    }
}

#[test]
fn pile_of_a_thousand_polydisperse_spheres() {
    compare("verification/dem/pile.toml", 30);
}

#[test]
fn pour() {
    compare("pour.toml", 30);
}

#[test]
fn coupled_cases() {
    for path in [
        "verification/coupling/settling_single.toml",
        "verification/coupling/hindered_settling.toml",
        // held particles (`[particles] motion = "held"`): no kick, no drift, the same load
        "verification/coupling/hydrostatic_held.toml",
        "coupling/one_way_cavity.toml",
        "coupling/interface_crossing.toml",
    ] {
        compare(path, 120);
    }
}

#[test]
fn rotating_frame_and_rotor_cases() {
    for path in ["verification/rotating_frame/free_particle.toml", "verification/rotating_frame/settling.toml", "coupling/one_way_rotor.toml"] {
        compare(path, 120);
    }
}

#[test]
fn wear_cases() {
    for path in ["verification/wear/stream_plate.toml", "verification/wear/coriolis_garnet.toml"] {
        compare(path, 10);
    }
}

/// The cutter head fed with rock takes one sub-step per step at ≈ 0.4 s a step per phase:
/// 20 steps (the feed places its first pieces, which hit the turning blades) instead of 100.
#[test]
fn fed_cutter_head() {
    compare_over("cutter_head_feed.toml", 20, 20);
}

/// The same bits on 1 and 2 threads: every sum is taken in a fixed order. The pile (contacts
/// in a box) and the hindered-settling cloud (two-way coupled: the fast DEM with the kernel
/// stencils built in parallel).
#[test]
fn fast_particle_path_gives_the_same_bits_on_one_and_two_threads() {
    for (path, steps) in [("verification/dem/pile.toml", 20), ("verification/coupling/hindered_settling.toml", 5)] {
        let c = case(path);
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut run = fast_run(&c).unwrap();
                for _ in 0..steps {
                    run.step().unwrap();
                }
                run.state().clone()
            })
        };
        let (one, two) = (run(1), run(2));
        let d = diff(&one, &two);
        assert!(d.mismatches.is_empty() && d.worst_relative() == 0.0, "{path}: 1 vs 2 threads:\n{}", d.report());
    }
}
