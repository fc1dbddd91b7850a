//! Fast-solver step driver for profiling (issue #6): runs one benchmark workload of
//! `benches/fluid_step.rs` (same cases, same 1e-7 tolerances) for a few steps and prints the
//! time per step, µs per cell-step and the linear-solver iteration counts. Builds without the
//! reference solver and the application crate, so A/B rebuilds are quick; deterministic, so
//! callgrind instruction counts compare.
//!
//! usage: cargo run --release -p spillage-fast --example step_driver -- lid 256 [steps]
//!        … -- couette 256 [steps]   (n_θ × n_θ/4)   … -- rotor 40 [steps]   (n_θ × 16 × 16 · n_θ/40)

use std::time::Instant;

use spillage_fast::fluid::{FastFluid, FastSettings};
use spillage_fast::linear::Tolerance;
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::step::{Coupled, FluidOnly};

#[allow(dead_code)]
#[path = "../../benches/common/cases.rs"]
mod cases;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let kind = args.get(1).map_or("lid", |s| s.as_str());
    let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(128);
    let steps: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(5);
    let case = match kind {
        "lid" => cases::lid(n),
        "couette" => cases::couette(n, n / 4),
        "rotor" => cases::rotor3d(n, 16 * n / 40, 16 * n / 40),
        other => panic!("unknown workload {other} (lid, couette, rotor)"),
    };
    let mesh = spillage_model::mesh::build(case.mesh.as_ref().expect("mesh")).expect("mesh");
    let cells = mesh.n_cells();
    let t = Tolerance { tolerance: 1e-7, max_iterations: 1000 };
    let mut state = State::default();
    let fluid = FastFluid::new(&case, mesh, &mut state).expect("fast solver").with_settings(FastSettings { pressure: t, momentum: t });
    let mut solver = Coupled::new(&case, state, Some(fluid), None).expect("run");
    let threads: usize = std::env::var("THREADS").ok().and_then(|s| s.parse().ok()).unwrap_or(1);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("pool");
    // inside the pool, as the bench: parallel loops start on a worker, not by a cross-thread hand-off
    pool.install(|| run(kind, n, steps, cells, &mut solver));
}

fn run(kind: &str, n: usize, steps: usize, cells: usize, solver: &mut FluidOnly<FastFluid>) {
    let t0 = Instant::now();
    for _ in 0..2 {
        solver.step().expect("step");
    }
    let warm = t0.elapsed().as_secs_f64() / 2.0;
    let t1 = Instant::now();
    let mut p_it = 0;
    let mut m_it = 0;
    for _ in 0..steps {
        solver.step().expect("step");
        let c = solver.fluid_phase().expect("fluid").last_counts();
        p_it += c.pressure_iterations;
        m_it += c.momentum_iterations;
        eprintln!(
            "step {:.1} ms: pressure {:.1} ms ({} it {:?}), AMG setup {:.1} ms, momentum {:.1} ms ({} it), rest {:.1} ms",
            c.step_seconds * 1e3,
            c.pressure_seconds * 1e3,
            c.pressure_iterations,
            &c.pressure_per_solve[..c.pressure_solves.min(12)],
            c.amg_setup_seconds * 1e3,
            c.momentum_seconds * 1e3,
            c.momentum_iterations,
            (c.step_seconds - c.pressure_seconds - c.amg_setup_seconds - c.momentum_seconds) * 1e3
        );
    }
    eprintln!("pressure levels (rows, off-diagonals, colours): {:?}", solver.fluid_phase().expect("fluid").pressure_levels());
    let per = t1.elapsed().as_secs_f64() / steps as f64;
    println!(
        "{kind} {n}: {cells} cells, warm-up {:.1} ms/step, {:.2} ms/step = {:.2} µs/cell-step; per step {:.1} pressure and {:.1} momentum iterations",
        warm * 1e3,
        per * 1e3,
        per * 1e6 / cells as f64,
        p_it as f64 / steps as f64,
        m_it as f64 / steps as f64
    );
}
