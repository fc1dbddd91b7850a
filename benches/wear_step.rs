//! The wear phase alone, fast vs reference (issue 19): the stream on a plate
//! (`cases/verification/wear/stream_plate.toml`, the largest eroding surface of the wear cases:
//! 1 600 triangles over 861 nodes, smoothing on, receding) at its coarse level, driven by the
//! reference DEM. Each run times only its wear phase's `advance` (a wrapper around it), so the
//! DEM does not dilute the ratio.
//!
//! `cargo bench --bench wear_step`. The ratio is printed and written to
//! `target/spillage-bench/wear_step.json`; criterion then times one recorded busy step of the
//! fast phase.

use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use criterion::{BatchSize, Criterion};
use spillage_fast::wear::FastWear;
use spillage_model::case::Case;
use spillage_model::particles::ImpactRecord;
use spillage_model::solver::{Solver, SolverError, StepReport};
use spillage_model::state::State;
use spillage_model::step::{Coupled, StepContext, WearPhase};
use spillage_model::walls::state::WallState;
use spillage_model::wear::state::WearState;
use spillage_reference::dem::ReferenceDem;
use spillage_reference::wear::ReferenceWear;

fn stream() -> Case {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/verification/wear/stream_plate.toml");
    let mut case = Case::load(&path).expect("case");
    // the coarse level, as `spillage verify` runs it
    case.time.end_time = Some(0.012);
    case
}

/// The busiest step seen: its context, impacts and the wear and walls before it.
type Recorded = (StepContext, Vec<ImpactRecord>, WearState, WallState);

/// Seconds spent in the wrapped phase, the calls, and the busiest step.
#[derive(Default)]
struct Clock {
    seconds: f64,
    calls: u64,
    busiest: Option<Recorded>,
}

struct Timed {
    inner: Box<dyn WearPhase + Send>,
    clock: Arc<Mutex<Clock>>,
}

impl WearPhase for Timed {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn advance(
        &mut self,
        ctx: &StepContext,
        impacts: &[ImpactRecord],
        wear: &mut WearState,
        walls: &mut WallState,
        report: &mut StepReport,
    ) -> Result<(), SolverError> {
        let mut clock = self.clock.lock().expect("clock");
        if clock.busiest.as_ref().is_none_or(|b| b.1.len() < impacts.len()) {
            clock.busiest = Some((ctx.clone(), impacts.to_vec(), wear.clone(), walls.clone()));
        }
        let t = Instant::now();
        let result = self.inner.advance(ctx, impacts, wear, walls, report);
        clock.seconds += t.elapsed().as_secs_f64();
        clock.calls += 1;
        result
    }
}

/// The coarse stream with the `fast` or reference wear phase: wear seconds per step.
fn wear_seconds_per_step(case: &Case, fast: bool) -> (f64, Clock) {
    let mut state = State::default();
    let dem = ReferenceDem::new(case, &mut state).expect("DEM");
    let inner: Box<dyn WearPhase + Send> = if fast {
        Box::new(FastWear::new(case, &mut state).expect("fast wear"))
    } else {
        Box::new(ReferenceWear::new(case, &mut state).expect("reference wear"))
    };
    let clock = Arc::new(Mutex::new(Clock::default()));
    let mut run = Coupled::particles_only(case, state, dem).expect("run").with_wear(Box::new(Timed { inner, clock: clock.clone() })).expect("wear");
    while run.state().time < case.time.end_time.expect("end") - 1e-12 {
        run.step().expect("step");
    }
    drop(run);
    let clock = Arc::try_unwrap(clock).ok().expect("one owner").into_inner().expect("clock");
    (clock.seconds / clock.calls as f64, clock)
}

fn ratio() -> Recorded {
    let case = stream();
    let (r, _) = wear_seconds_per_step(&case, false);
    let pool = |k: usize| rayon::ThreadPoolBuilder::new().num_threads(k).build().expect("pool");
    let (f1, clock) = pool(1).install(|| wear_seconds_per_step(&case, true));
    let (f2, _) = pool(2).install(|| wear_seconds_per_step(&case, true));
    println!(
        "stream plate (coarse, {} steps): wear phase per step: reference {r:.3e} s, fast {f1:.3e} s on 1 thread ({:.1}×), {f2:.3e} s on 2 threads ({:.1}×)",
        clock.calls,
        r / f1,
        r / f2
    );
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/spillage-bench");
    let _ = std::fs::create_dir_all(&dir);
    let json = format!(
        "{{\"case\": \"wear_stream_plate\", \"steps\": {}, \"reference_seconds_per_step\": {r}, \"fast_seconds_per_step_1_thread\": {f1}, \"fast_seconds_per_step_2_threads\": {f2}, \"ratio_1_thread\": {}, \"ratio_2_threads\": {}}}\n",
        clock.calls,
        r / f1,
        r / f2
    );
    let _ = std::fs::write(dir.join("wear_step.json"), json);
    clock.busiest.expect("a step")
}

fn bench(c: &mut Criterion, busiest: &Recorded) {
    let case = stream();
    let (ctx, impacts, wear, walls) = busiest;
    let mut state = State::default();
    let _dem = ReferenceDem::new(&case, &mut state).expect("DEM");
    let mut fast = FastWear::new(&case, &mut state).expect("fast wear");
    let mut reference = ReferenceWear::new(&case, &mut state).expect("reference wear");
    let mut group = c.benchmark_group("wear_step");
    group.sample_size(20);
    let name = format!("stream plate, busiest step ({} impacts)", impacts.len());
    for (label, phase) in [("fast", &mut fast as &mut dyn WearPhase), ("reference", &mut reference as &mut dyn WearPhase)] {
        group.bench_function(format!("{label}: {name}"), |b| {
            b.iter_batched(
                || (wear.clone(), walls.clone(), StepReport::default()),
                |(mut wear, mut walls, mut report)| phase.advance(ctx, impacts, &mut wear, &mut walls, &mut report).expect("wear step"),
                BatchSize::SmallInput,
            )
        });
    }
    group.finish();
}

fn main() {
    let busiest = ratio();
    let mut c = Criterion::default().configure_from_args();
    bench(&mut c, &busiest);
    c.final_summary();
}
