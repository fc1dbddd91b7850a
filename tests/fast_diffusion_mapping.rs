//! The diffusion mapping on the fast linear solvers (issue 19: "the diffusion mapping via the
//! fast linear solvers"), held to the reference's on the shipped cases that verify the
//! diffusion method: P1 (`settling_single`, diffusion γ = 3), P3 (`hindered_settling`,
//! diffusion γ = 3, its `--full` mapping) and the held suspension (`hydrostatic_held`, γ = 1
//! and 3), each with its `[coupling] method` set to diffusion as `spillage verify` sets it.
//!
//! Every step of a fast run, the particle → mesh deposit and the mesh → particle sample are
//! taken from the same state with the reference mapping (stencils in order, smoothing by
//! `Diffusion::smooth`) and the fast one (stencils in parallel, smoothing by
//! `spillage_fast::coupling::smooth_in_parallel`), and compared.

use std::path::PathBuf;

use spillage_fast::dem::FastDem;
use spillage_fast::fluid::FastFluid;
use spillage_model::case::Case;
use spillage_model::coupling::{CellLoad, MappingMethod, MappingSolvers, ParticleMeshMap};
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::state_diff::diff;
use spillage_model::step::{Coupled, FluidPhase};

/// Per step, fast vs reference, as a fraction of each field's largest magnitude. Both smoothings
/// solve the same matrix from the same guess and stop once their residual is 1e-13 (reference,
/// relative 2-norm) or 1e-14 (fast, normalised 1-norm) of the right-hand side; the matrix is the
/// mass matrix plus a Laplacian (smallest eigenvalue the cell volume), so each answer is within
/// ~1e-13 of the field's size of the exact one, and the folded-back residuals are smaller
/// still. Measured: 0.8–2.9e-13 (the largest on P3's cloud); 1e-12 is two
/// such errors with room, and two orders inside the 1e-10 for whole states.
const MAPPING_TOLERANCE: f64 = 1e-12;

/// Σ α_p V = Σ V_p, Σ C = Σ K, Σ F = Σ F_n after the fast smoothing, relative: round-off of sums
/// over the cells (the model's own bound, `every_method_conserves_volume_drag_and_force`).
const CONSERVATION_TOLERANCE: f64 = 1e-13;

fn diffusion_case(path: &str, gamma: f64) -> Case {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases/verification/coupling").join(path);
    let mut case = Case::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let coupling = case.coupling.as_mut().expect("a coupled case");
    coupling.method = MappingMethod::Diffusion;
    coupling.distance_factor = gamma;
    coupling.validate().expect("a valid diffusion mapping");
    case
}

/// The whole fast solver (fluid, DEM, stencils and smoothing).
fn fast_run(case: &Case) -> Coupled<FastFluid, FastDem> {
    let mut state = State::default();
    let mesh = spillage_model::mesh::for_case(case).expect("a mesh").expect("mesh");
    let fluid = FastFluid::new(case, mesh, &mut state).expect("fast fluid");
    let dem = FastDem::new(case, &mut state).expect("fast DEM");
    Coupled::new(case, state, Some(fluid), Some(dem)).expect("run").with_mapping_solvers(spillage_fast::coupling::MAPPING_SOLVERS)
}

/// Largest |a − b| over the largest |b| (0 for two zero fields).
fn relative(a: impl Iterator<Item = f64>, b: impl Iterator<Item = f64> + Clone) -> f64 {
    let scale = b.clone().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = a.zip(b).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    if worst == 0.0 {
        0.0
    } else {
        worst / scale
    }
}

/// Compares the two mappings after each of `steps` steps; returns the worst relative difference.
fn compare(path: &str, gamma: f64, steps: usize) -> f64 {
    let case = diffusion_case(path, gamma);
    let section = case.coupling.as_ref().expect("coupled");
    let mut reference = ParticleMeshMap::new(section);
    reference.solvers = MappingSolvers::IN_ORDER;
    let mut fast = ParticleMeshMap::new(section);
    fast.solvers = spillage_fast::coupling::MAPPING_SOLVERS;
    let mut run = fast_run(&case);
    let mut worst = 0.0f64;
    for step in 1..=steps {
        run.step().unwrap_or_else(|e| panic!("{path}: step {step}: {e}"));
        let (phase, state) = (run.fluid_phase().expect("fluid"), run.state());
        let (mesh, particles) = (phase.mesh(), &state.particles.as_ref().expect("particles").particles);
        let load = run.particle_load().expect("a two-way coupled step returns its load");
        let (mut r, mut f) = (CellLoad::default(), CellLoad::default());
        reference.deposit(mesh, particles, load, &mut r);
        fast.deposit(mesh, particles, load, &mut f);
        let component = |c: &CellLoad, k: usize| c.explicit_force.iter().map(move |v| v[k]).collect::<Vec<f64>>();
        let mut differences = vec![
            ("α_p", relative(f.particle_fraction.iter().copied(), r.particle_fraction.iter().copied())),
            ("C", relative(f.implicit_drag.iter().copied(), r.implicit_drag.iter().copied())),
        ];
        for k in 0..3 {
            differences.push(("F", relative(component(&f, k).into_iter(), component(&r, k).into_iter())));
        }
        assert_eq!(f.masked, r.masked, "{path}: step {step}: the interface mask");
        // conservation of the fast deposit
        let volume: f64 = f.particle_fraction.iter().zip(&mesh.cell_volumes).map(|(a, v)| a * v).sum();
        let exact: f64 = load.volume.iter().sum();
        assert!((volume - exact).abs() <= CONSERVATION_TOLERANCE * exact, "{path}: step {step}: Σ α_p V = {volume:e}, Σ V_p = {exact:e}");
        let (drag, exact_drag): (f64, f64) = (f.implicit_drag.iter().sum(), load.implicit_drag.iter().sum());
        assert!((drag - exact_drag).abs() <= CONSERVATION_TOLERANCE * exact_drag.abs().max(1e-300), "{path}: step {step}: Σ C = {drag:e} vs {exact_drag:e}");
        let force: spillage_model::mesh::Vec3 = f.explicit_force.iter().sum();
        let exact_force: spillage_model::mesh::Vec3 = load.explicit_force.iter().map(|v| spillage_model::mesh::Vec3::from(*v)).sum();
        let force_scale = load.explicit_force.iter().map(|v| spillage_model::mesh::Vec3::from(*v).norm()).sum::<f64>();
        assert!((force - exact_force).norm() <= CONSERVATION_TOLERANCE * force_scale.max(1e-300), "{path}: step {step}: Σ F = {force} vs {exact_force}");
        // the fluid the particles see
        let fluid = state.fluid.as_ref().expect("fluid state");
        let (mut rs, mut fs) = (Vec::new(), Vec::new());
        reference.sample(&phase.sample_source(fluid), particles, &mut rs);
        fast.sample(&phase.sample_source(fluid), particles, &mut fs);
        let seen = |s: &[Option<spillage_model::closure::drag::FluidAtParticle>], what: usize| -> Vec<f64> {
            s.iter()
                .flat_map(|a| {
                    let a = a.as_ref().expect("inside the mesh");
                    match what {
                        0 => a.velocity.iter().copied().collect::<Vec<f64>>(),
                        1 => a.material_acceleration.iter().copied().collect(),
                        _ => vec![a.fluid_fraction],
                    }
                })
                .collect()
        };
        for (name, what) in [("u seen", 0), ("Du/Dt seen", 1), ("α_c seen", 2)] {
            differences.push((name, relative(seen(&fs, what).into_iter(), seen(&rs, what).into_iter())));
        }
        for (name, d) in differences {
            assert!(d <= MAPPING_TOLERANCE, "{path} (diffusion γ = {gamma}): step {step}: {name} differs by {d:e} of its scale");
            worst = worst.max(d);
        }
    }
    eprintln!("{path} (diffusion γ = {gamma}): {steps} steps, worst fast vs reference mapping difference {worst:.2e} of the field's scale");
    worst
}

#[test]
fn single_particle_settling() {
    compare("settling_single.toml", 3.0, 20);
}

#[test]
fn hindered_settling_cloud() {
    compare("hindered_settling.toml", 3.0, 10);
}

#[test]
fn held_suspension() {
    for gamma in [1.0, 3.0] {
        compare("hydrostatic_held.toml", gamma, 5);
    }
}

/// The whole fast run with the diffusion mapping gives the same bits on 1 and 2 threads (the
/// smoothing's sums in fixed chunks, one task per field).
#[test]
fn fast_diffusion_run_gives_the_same_bits_on_one_and_two_threads() {
    let case = diffusion_case("hindered_settling.toml", 3.0);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut run = fast_run(&case);
            for _ in 0..5 {
                run.step().unwrap();
            }
            run.state().clone()
        })
    };
    let (one, two) = (run(1), run(2));
    let d = diff(&one, &two);
    assert!(d.mismatches.is_empty() && d.worst_relative() == 0.0, "1 vs 2 threads:\n{}", d.report());
}
