//! The KTGF solids pressure of `spillage-model` (wear-model.md §4) against the independent
//! referee `spillage-analytic::granular`: Eq. 2.25–2.26 over a grid of α_p and Θ, A33, and the
//! granular temperature of Eq. 2.19 (A34) from velocity sets.

use spillage_analytic::granular as referee;
use spillage_model::closure::solids_pressure::{solids_pressure, VelocityMoments, PACKING_LIMIT, RESTITUTION};

#[test]
fn solids_pressure_matches_the_referee_below_the_packing_limit() {
    // the same closed form written twice (cbrt against powf(1/3), another order of products):
    // round-off of a few operations, amplified near α_max by g₀'s 1/(1 − (α/α_max)^⅓), whose
    // cancellation costs log10(g₀) digits (g₀ ≤ 360 on this grid): 1e-12 leaves a factor 10
    for i in 0..=119 {
        let alpha = i as f64 * 0.005;
        for theta in [0.0, 1e-4, 0.01, 1.0, 25.0] {
            let model = solids_pressure(alpha, 2500.0, theta, RESTITUTION, PACKING_LIMIT);
            let exact = referee::solids_pressure(alpha, 2500.0, theta, RESTITUTION, PACKING_LIMIT).unwrap();
            let scale = model.abs().max(exact.abs());
            assert!(model == exact || (model - exact).abs() <= 1e-12 * scale, "α_p {alpha}, Θ {theta}: {model} vs {exact}");
        }
    }
    // A33 (wear-model.md §15): 4.7126905 Pa to the printed digits
    let a33 = solids_pressure(0.1, 2500.0, 0.01, 0.99, 0.6);
    assert!((a33 / 4.7126905 - 1.0).abs() < 1e-7, "{a33}");
}

#[test]
fn granular_temperature_matches_the_referee() {
    // the model accumulates Σ(u − u₁) and Σ|u − u₁|² (one pass, as particles are binned) and
    // subtracts: cancellation of |c − u₁|²/Θ, of order 1 for any mean (u₁ the first velocity),
    // times a few round-offs of 1e-16 per particle summed: 1e-13 relative leaves a factor 10
    // at n = 100
    let mut seed = 12345_u64;
    let mut next = || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    for n in [2, 3, 10, 100] {
        for (mean, spread) in [(0.0, 1.0), (10.0, 0.1), (-3.0, 5.0)] {
            let velocities: Vec<[f64; 3]> =
                (0..n).map(|_| [mean + spread * (next() - 0.5), 0.5 * mean + spread * (next() - 0.5), spread * (next() - 0.5)]).collect();
            let mut moments = VelocityMoments::default();
            for v in &velocities {
                moments.add(*v, 1.0);
            }
            let exact = referee::granular_temperature(&velocities);
            let model = moments.granular_temperature();
            assert!((model - exact).abs() <= 1e-13 * exact, "n {n}, mean {mean}, spread {spread}: {model} vs {exact}");
        }
    }
    // A34
    let mut two = VelocityMoments::default();
    two.add([1.0, 0.0, 0.0], 1.0);
    two.add([-1.0, 0.0, 0.0], 1.0);
    assert!((two.granular_temperature() - referee::granular_temperature(&[[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]])).abs() <= 1e-15);
}

/// The fine-sand Coriolis arm as the thesis represents it (7.2e5 grains/s, each counting 100)
/// for its first steps, with and without `[particles.solids_pressure]`: with it every step
/// reports the stage (the case section reaches the step), the stage's α_p* after the
/// correction stays below α_max, and the grains' cells end less packed than without it,
/// where they pass α_max within the 20 steps (measured 0.47 against 0.89).
#[test]
fn the_solids_pressure_keeps_the_thesis_fine_sand_below_packing() {
    use spillage_fast::dem::FastDem;
    use spillage_fast::fluid::FastFluid;
    use spillage_fast::wear::FastWear;
    use spillage_model::case::Case;
    use spillage_model::particles::solids_pressure::SolidsPressure;
    use spillage_model::solver::Solver;
    use spillage_model::state::State;
    use spillage_model::step::Coupled;

    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases/wear/coriolis_fine_sand.toml");
    let text = std::fs::read_to_string(&path).unwrap().replace("rate = 7200.0", "rate = 7.2e5").replace("end_time = 0.025", "end_time = 0.0005");
    assert!(text.contains("rate = 7.2e5"));
    let with = Case::from_toml(&format!("{text}\n[particles.solids_pressure]\n"), &path).unwrap_or_else(|e| panic!("{e}"));
    let without = Case::from_toml(&text, &path).unwrap_or_else(|e| panic!("{e}"));
    let largest_binned = |case: &Case| {
        let mut state = State::default();
        let fluid = FastFluid::new(case, spillage::verify::fluid::build_mesh(case).unwrap(), &mut state).unwrap();
        let dem = FastDem::new(case, &mut state).unwrap();
        let wear = FastWear::new(case, &mut state).unwrap();
        let mut run = Coupled::new(case, state, Some(fluid), Some(dem)).unwrap().with_wear(Box::new(wear)).unwrap();
        let mut after = Vec::new();
        for _ in 0..20 {
            let report = run.step().unwrap();
            let value = |key: &str| report.values.iter().find(|(k, _)| *k == key).map(|(_, v)| *v);
            after.push(value("solids_fraction_max_after"));
        }
        // α_p of the particles where they ended, binned as the stage bins them
        let mut stage = SolidsPressure::default();
        let mut particles = run.state().particles.as_ref().unwrap().particles.clone();
        stage.correct(run.mesh().unwrap(), &mut particles, case.particle_modifier(), 1e-9).unwrap();
        (stage.fraction.iter().cloned().fold(0.0, f64::max), after)
    };
    let (packed_without, none) = largest_binned(&without);
    let (packed_with, after) = largest_binned(&with);
    assert!(none.iter().all(Option::is_none), "a case without the section reported the stage");
    let after: Vec<f64> = after.iter().map(|a| a.expect("every step reports the stage")).collect();
    let worst = after.iter().cloned().fold(0.0, f64::max);
    eprintln!("largest α_p after 20 steps: {packed_without:.3} without, {packed_with:.3} with the solids pressure; largest α_p* of a step {worst:.3}");
    assert!(worst < 0.6, "α_p* per step {after:?}");
    assert!(packed_without > 0.6, "without the solids pressure the grains did not pack: {packed_without}");
    assert!(packed_with < packed_without, "{packed_with} vs {packed_without}");
}

/// A bad value of `[particles.solids_pressure]` names its key and what is allowed.
#[test]
fn the_solids_pressure_section_is_checked() {
    use spillage_model::case::Case;
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases/wear/coriolis_fine_sand.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let error = Case::from_toml(&format!("{text}\n[particles.solids_pressure]\npacking_limit = 1.5\n"), &path).unwrap_err().to_string();
    assert!(error.contains("particles.solids_pressure.packing_limit") && error.contains("1.5"), "{error}");
    let error = Case::from_toml(&format!("{text}\n[particles.solids_pressure]\ntreatment = \"sometimes\"\n"), &path).unwrap_err().to_string();
    assert!(error.contains("sometimes") && error.contains("implicit"), "{error}");
}
