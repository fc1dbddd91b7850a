//! DEM alone (issue 19): a dense bed of 10⁴ and 10⁵ spheres settling in a closed box
//! (`cases/bench/settle_box_10k.toml`, `settle_box_100k.toml`: d = 10 mm, Hertz–Mindlin–Tsuji
//! with E softened to 1e7 Pa, e = 0.5, μ = 0.3, sub-step 1/21 of the collision time), in
//! particle sub-steps per second over the case's run after its first step (950 of its 1 000
//! sub-steps; the reference DEM over 100 at 10⁴): the fast DEM on 1 and 2 threads, the
//! reference DEM on 1, all measured in one run. One and two threads take turns, [`ROUNDS`]
//! times, each from the bed's start, and the ratio is the median of the rounds' ratios: the
//! machine's speed moves by a third from hour to hour (README, *Where it stands*), and one
//! stretch of each had compared two speeds of the machine as often as two thread counts.
//!
//! `cargo bench --bench dem_settle` prints the rates and ratios and writes them to
//! `target/spillage-bench/dem_settle.json`; LIGGGHTS' rate on the same bed comes from
//! `benches/peers/liggghts_settle/run.sh`.

use std::path::Path;
use std::time::Instant;

use criterion::{criterion_group, Criterion};
use spillage_fast::dem::FastDem;
use spillage_model::case::Case;
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::step::coupled::median::median;
use spillage_model::step::{Coupled, ParticlePhase};
use spillage_reference::dem::ReferenceDem;

/// Rounds of one thread then two.
const ROUNDS: usize = 3;

fn bed(name: &str) -> Case {
    Case::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/bench").join(name)).expect("benchmark case")
}

fn run<P: ParticlePhase>(case: &Case, make: fn(&Case, &mut State) -> P) -> Coupled<spillage_model::step::Absent, P> {
    let mut state = State::default();
    let dem = make(case, &mut state);
    Coupled::particles_only(case, state, dem).expect("run")
}

fn fast(case: &Case, state: &mut State) -> FastDem {
    FastDem::new(case, state).expect("fast DEM")
}

fn reference(case: &Case, state: &mut State) -> ReferenceDem {
    ReferenceDem::new(case, state).expect("reference DEM")
}

/// Particle sub-steps per second over `steps` outer steps (after one warm-up step), on
/// `threads` threads.
fn rate<S: Solver + Send>(solver: &mut S, steps: usize, threads: usize) -> f64 {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("pool");
    pool.install(|| {
        solver.step().expect("step");
        let (started, mut work) = (Instant::now(), 0.0);
        for _ in 0..steps {
            let report = solver.step().expect("step");
            let substeps = report.values.iter().find(|v| v.0 == "substeps").map_or(0.0, |v| v.1);
            work += substeps * solver.state().particles.as_ref().map_or(0, |p| p.particles.len()) as f64;
        }
        work / started.elapsed().as_secs_f64()
    })
}

fn rates() {
    let mut json = Vec::new();
    for (name, reference_steps) in [("settle_box_10k.toml", 2), ("settle_box_100k.toml", 0)] {
        let case = bed(name);
        // the case's whole run after its first step, as LIGGGHTS' rate is taken over the whole
        // run (`benches/peers/liggghts_settle/run.sh`): the bed's first steps, its lattice
        // collapsing with its contacts still closing, run faster and scale less
        let steps = case.time.steps.expect("the bed's [time] steps") as usize - 1;
        let rounds: Vec<(f64, f64)> = (0..ROUNDS).map(|_| (rate(&mut run(&case, fast), steps, 1), rate(&mut run(&case, fast), steps, 2))).collect();
        let (fast_1, fast_2) = (median(rounds.iter().map(|r| r.0).collect()), median(rounds.iter().map(|r| r.1).collect()));
        let scaling = median(rounds.iter().map(|(one, two)| two / one).collect());
        let each: Vec<String> = rounds.iter().map(|(one, two)| format!("{:.2}", two / one)).collect();
        let reference_1 = if reference_steps > 0 { rate(&mut run(&case, reference), reference_steps, 1) } else { f64::NAN };
        println!(
            "{name}: fast {fast_1:.3e} particle-steps/s on 1 thread, {fast_2:.3e} on 2 ({scaling:.2}x: the median of {ROUNDS} alternating rounds, {}); reference {reference_1:.3e} on 1 (fast/reference {:.1}x)",
            each.join(", "),
            fast_1 / reference_1
        );
        let number = |x: f64| if x.is_finite() { format!("{x}") } else { "null".to_string() };
        json.push(format!(
            "{{\"case\": \"{name}\", \"fast_1_thread\": {fast_1}, \"fast_2_threads\": {fast_2}, \"reference_1_thread\": {}, \"fast_over_reference\": {}, \"two_over_one_thread\": {}}}",
            number(reference_1),
            number(fast_1 / reference_1),
            scaling
        ));
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/spillage-bench");
    let _ = std::fs::create_dir_all(&dir);
    let _ = std::fs::write(dir.join("dem_settle.json"), format!("[{}]\n", json.join(",\n")));
}

fn bench(c: &mut Criterion) {
    let case = bed("settle_box_10k.toml");
    let mut group = c.benchmark_group("dem_settle");
    group.sample_size(10);
    let mut fast_run = run(&case, fast);
    group.bench_function("10k spheres, fast DEM, one outer step (50 sub-steps)", |b| b.iter(|| fast_run.step().expect("step")));
    group.finish();
}

criterion_group!(benches, bench);

fn main() {
    rates();
    benches();
    Criterion::default().configure_from_args().final_summary();
}
