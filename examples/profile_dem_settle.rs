//! Profiling rig for issue 19: the fast DEM alone on the settling bed of `cargo bench --bench
//! dem_settle` (`cases/bench/settle_box_10k.toml` or `settle_box_100k.toml`), N outer steps on
//! T threads after one warm-up step, for `perf record`; prints particle sub-steps per second.
//! Several thread counts (`1,2,1,2`) run the bed afresh one after another in one process.
//!
//! `cargo run --release --example profile_dem_settle -- [steps] [threads[,threads…]] [10k|100k]`

use std::path::Path;
use std::time::Instant;

use spillage_fast::dem::FastDem;
use spillage_model::case::Case;
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::step::Coupled;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let steps: usize = args.get(1).map_or(8, |s| s.parse().expect("steps"));
    let threads: Vec<usize> = args.get(2).map_or(vec![2], |s| s.split(',').map(|t| t.parse().expect("threads")).collect());
    let size = args.get(3).map_or("10k", String::as_str);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("cases/bench/settle_box_{size}.toml"));
    let case = Case::load(&path).expect("case");
    for threads in threads {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("pool");
        pool.install(|| {
            let mut state = State::default();
            let dem = FastDem::new(&case, &mut state).expect("fast DEM");
            let mut run = Coupled::particles_only(&case, state, dem).expect("run");
            run.step().expect("step");
            let (started, mut work) = (Instant::now(), 0.0);
            for _ in 0..steps {
                let report = run.step().expect("step");
                let substeps = report.values.iter().find(|v| v.0 == "substeps").map_or(0.0, |v| v.1);
                work += substeps * run.state().particles.as_ref().map_or(0, |p| p.particles.len()) as f64;
            }
            let seconds = started.elapsed().as_secs_f64();
            println!("{size} on {threads} threads: {:.3e} particle-steps/s ({seconds:.3} s for {steps} steps)", work / seconds);
        });
    }
}
