//! Profiling rig for issue 19: N steps of P3 fine (`cases/bench/hindered_settling_fine.toml`),
//! or of another coupled case (e.g. `cases/cutter_head.toml`, run to its own end), with the
//! whole fast solver on 2 threads, for `perf record -g`; `PROFILE_COUNTS=1` prints each step's
//! linear-solver iterations and times.
//!
//! `cargo run --release --example profile_coupled_fine -- [steps] [kernel|diffusion] [threads] [case]`

use std::path::Path;
use std::time::Instant;

use spillage_fast::dem::FastDem;
use spillage_fast::fluid::FastFluid;
use spillage_model::case::Case;
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::step::Coupled;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let steps: usize = args.get(1).map_or(20, |s| s.parse().expect("steps"));
    let method = args.get(2).map_or("kernel", String::as_str);
    let threads: usize = args.get(3).map_or(2, |s| s.parse().expect("threads"));
    let path = args.get(4).map_or(Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/bench/hindered_settling_fine.toml"), std::path::PathBuf::from);
    let mut case = Case::load(&path).expect("case");
    if case.cutter_head.is_none() {
        case.time.end_time = Some(1.0);
    }
    if method == "diffusion" {
        let coupling = case.coupling.as_mut().expect("[coupling]");
        coupling.method = spillage_model::coupling::MappingMethod::Diffusion;
        coupling.distance_factor = 3.0;
    }
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("pool");
    pool.install(|| {
        spillage_fast::team::keep_awake(|| {
            let mut state = State::default();
            let fluid = FastFluid::new(&case, spillage::verify::fluid::build_mesh(&case).expect("mesh"), &mut state).expect("fast fluid");
            let dem = FastDem::new(&case, &mut state).expect("fast DEM");
            let mut run = Coupled::new(&case, state, Some(fluid), Some(dem)).expect("run").with_mapping_solvers(spillage_fast::coupling::MAPPING_SOLVERS);
            run.step().expect("step");
            let t = Instant::now();
            for _ in 0..steps {
                let report = run.step().expect("step");
                if std::env::var_os("PROFILE_COUNTS").is_some() {
                    let c = run.fluid_phase().expect("fluid").last_counts();
                    let outer = report.values.iter().find(|v| v.0 == "outer_iterations").map_or(0.0, |v| v.1);
                    eprintln!(
                    "outer {outer} pressure solves {} its {} {:?} momentum its {}; amg setup {:.4} s, pressure {:.4} s, momentum {:.4} s, fluid step {:.4} s",
                    c.pressure_solves,
                    c.pressure_iterations,
                    c.pressure_per_solve,
                    c.momentum_iterations,
                    c.amg_setup_seconds,
                    c.pressure_seconds,
                    c.momentum_seconds,
                    c.step_seconds
                );
                }
            }
            if std::env::var_os("PROFILE_COUNTS").is_some() {
                eprintln!("pressure levels (rows, off-diagonals, colours): {:?}", run.fluid_phase().expect("fluid").pressure_levels());
            }
            println!("{method}, {threads} threads: {:.4} s per step", t.elapsed().as_secs_f64() / steps as f64);
        })
    });
}
