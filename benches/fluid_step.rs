//! Fast vs reference fluid solver (issue #6): per-step time and µs per cell-step on the Couette
//! sliding-interface case (2-D), a 3-D rotor/stator cylinder and a lid-driven box; pressure-solve
//! throughput against a STREAM-like triad measured in the same run; 1 → 2 thread scaling.
//!
//! `cargo bench --bench fluid_step` runs the default sizes (a few minutes on 2 cores);
//! `SPILLAGE_BENCH_LARGE=1` adds the large sizes (Couette 512×128, 3-D 10⁵–10⁶ cells).
//! Numbers are also written to `target/spillage-bench/summary.json`.
//!
//! Settings of every run: PIMPLE with 2 outer correctors (no early exit), 2 PISO correctors,
//! 1 non-orthogonal corrector, linear convection, BDF2; fast linear solves to a normalised
//! residual of 1e-7 (OpenFOAM's definition and a typical OpenFOAM tolerance); the reference
//! solves exactly (sparse LU).

use std::path::Path;
use std::time::Instant;

use criterion::{criterion_group, Criterion};
use spillage_fast::fluid::{FastFluid, FastSettings};
use spillage_fast::linear::{amg::Amg, pcg::Pcg, Csr, Tolerance};
use spillage_model::case::Case;
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::step::{Coupled, FluidOnly};
use spillage_reference::fluid::ReferenceFluid;

#[path = "common/timing.rs"]
mod timing;
use timing::seconds_per_step;

#[path = "common/triad.rs"]
mod triad;
use triad::triad;
#[path = "common/cases.rs"]
mod bench_cases;
use bench_cases::{couette, lid, rotor3d};

fn settings() -> FastSettings {
    let t = Tolerance { tolerance: 1e-7, max_iterations: 1000 };
    FastSettings { pressure: t, momentum: t }
}

fn large() -> bool {
    std::env::var("SPILLAGE_BENCH_LARGE").is_ok_and(|v| v != "0")
}

fn fast_solver(case: &Case) -> FluidOnly<FastFluid> {
    let mesh = spillage::verify::fluid::build_mesh(case).expect("mesh");
    let mut state = State::default();
    let fluid = FastFluid::new(case, mesh, &mut state).expect("fast solver").with_settings(settings());
    Coupled::fluid_only(case, state, fluid).expect("fast run")
}

fn reference_solver(case: &Case) -> FluidOnly<ReferenceFluid> {
    let mesh = spillage::verify::fluid::build_mesh(case).expect("mesh");
    let mut state = State::default();
    let fluid = ReferenceFluid::new(case, mesh, &mut state).expect("reference solver");
    Coupled::fluid_only(case, state, fluid).expect("reference run")
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool")
}

fn n_cells(case: &Case) -> usize {
    spillage::verify::fluid::build_mesh(case).expect("mesh").n_cells()
}

/// 7-point Laplacian on an n³ grid (diagonal 6 everywhere: Dirichlet walls), the pressure
/// matrix shape of a 3-D hexahedral mesh.
fn laplacian3d(n: usize) -> Csr {
    let idx = |i: usize, j: usize, k: usize| (k * n + j) * n + i;
    let mut a = Csr { n: n * n * n, row_start: vec![0], ..Default::default() };
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                for (di, dj, dk) in [(0i64, 0i64, -1i64), (0, -1, 0), (-1, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                    let (ii, jj, kk) = (i as i64 + di, j as i64 + dj, k as i64 + dk);
                    if ii >= 0 && jj >= 0 && kk >= 0 && (ii as usize) < n && (jj as usize) < n && (kk as usize) < n {
                        a.col.push(idx(ii as usize, jj as usize, kk as usize) as u32);
                        a.val.push(-1.0);
                    }
                }
                a.diag.push(6.0);
                a.row_start.push(a.col.len() as u32);
            }
        }
    }
    a
}

/// Pressure-solve throughput: (cell-iterations per second, counted bytes per cell-iteration,
/// iterations, setup seconds, solve seconds). The bytes are those the executed CG and K-cycle
/// kernels stream, counted per pass from the sizes of the arrays each kernel touches
/// (`Pcg::bytes_streamed`, `Amg::bytes_streamed`), not a model.
fn pressure_throughput(threads: usize, n: usize) -> (f64, f64, usize, f64, f64) {
    let a = laplacian3d(n);
    let b: Vec<f64> = (0..a.n).map(|i| ((i * 7919) % 101) as f64 / 50.0 - 1.0).collect();
    pool(threads).install(|| {
        let mut amg = Amg::default();
        let t0 = Instant::now();
        amg.setup(&a);
        let setup = t0.elapsed().as_secs_f64();
        let mut pcg = Pcg::default();
        // the fastest of ROUNDS identical solves (see ROUNDS)
        let (mut solve, mut iterations) = (f64::INFINITY, 0);
        for _ in 0..ROUNDS {
            let mut x = vec![0.0; a.n];
            let t1 = Instant::now();
            let stats = pcg.solve(&a, &b, &mut x, &mut amg, Tolerance { tolerance: 1e-7, max_iterations: 500 });
            solve = solve.min(t1.elapsed().as_secs_f64());
            iterations = stats.iterations;
        }
        let bytes = (pcg.bytes_streamed() + amg.bytes_streamed()) / (a.n as f64 * (ROUNDS * iterations) as f64);
        (a.n as f64 * iterations as f64 / solve, bytes, iterations, setup, solve)
    })
}

struct Row {
    workload: String,
    cells: usize,
    fast_1: f64,
    fast_2: f64,
    reference: Option<f64>,
}

/// Rounds of the 1- and 2-thread timings, interleaved; each keeps its fastest round. The host
/// is shared (other guests' memory traffic shows up as 30–50 % swings between single runs), so
/// the fastest of interleaved rounds is the estimate that compares thread counts fairly.
const ROUNDS: usize = 3;

fn measure(name: String, case: &Case, steps: usize, with_reference: bool) -> Row {
    let cells = n_cells(case);
    let (pool_1, pool_2) = (pool(1), pool(2));
    let (mut solver_1, mut solver_2) = (fast_solver(case), fast_solver(case));
    let (mut fast_1, mut fast_2) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..ROUNDS {
        fast_1 = fast_1.min(pool_1.install(|| seconds_per_step(&mut solver_1, steps)));
        fast_2 = fast_2.min(pool_2.install(|| seconds_per_step(&mut solver_2, steps)));
    }
    let reference = with_reference.then(|| pool(2).install(|| seconds_per_step(&mut reference_solver(case), steps.min(5))));
    let r = Row { workload: name, cells, fast_1, fast_2, reference };
    eprintln!(
        "{:<28} {:>8} cells  fast 1t {:>9.3} ms ({:>6.2} µs/cell-step)  2t {:>9.3} ms (×{:.2})  reference {}",
        r.workload,
        cells,
        fast_1 * 1e3,
        fast_1 * 1e6 / cells as f64,
        fast_2 * 1e3,
        fast_1 / fast_2,
        r.reference.map_or("-".into(), |t| format!("{:.3} ms (fast 2t is {:.1}× faster)", t * 1e3, t / fast_2))
    );
    r
}

fn summary() {
    let mut rows = Vec::new();
    let mut couette_sizes = vec![(64, 16), (128, 32), (256, 64)];
    let mut rotor_sizes = vec![(40, 16, 16), (100, 32, 32)];
    let mut lid_sizes = vec![(64, true), (256, true), (384, false)];
    if large() {
        couette_sizes.push((512, 128));
        rotor_sizes.push((200, 64, 80));
        lid_sizes.push((512, false));
    }
    for (nt, nr) in couette_sizes {
        rows.push(measure(format!("couette_sliding {nt}x{nr}"), &couette(nt, nr), 10, true));
    }
    for (nt, nr, nz) in rotor_sizes {
        let case = rotor3d(nt, nr, nz);
        let cells = nt * nr * nz;
        rows.push(measure(format!("rotor_stator_3d {nt}x{nr}x{nz}"), &case, if cells > 200_000 { 3 } else { 5 }, cells <= 20_000));
    }
    for (n, with_ref) in lid_sizes {
        rows.push(measure(format!("lid_driven {n}x{n}"), &lid(n), 10, with_ref));
    }
    let triad_n = 20_000_000;
    let bw1 = triad(1, triad_n, 6);
    let bw2 = triad(2, triad_n, 6);
    let pn = if large() { 100 } else { 64 };
    let (cips1, bytes, iters, setup1, solve1) = pressure_throughput(1, pn);
    let (cips2, _, _, setup2, solve2) = pressure_throughput(2, pn);
    eprintln!("STREAM triad: {:.2} GB/s (1 thread), {:.2} GB/s (2 threads)", bw1 / 1e9, bw2 / 1e9);
    eprintln!(
        "pressure AMG-PCG {pn}³: {iters} iterations; 1t: setup {:.3} s solve {:.3} s, {:.3e} cell-it/s = {:.0}% of triad; 2t: setup {:.3} s solve {:.3} s, {:.3e} cell-it/s = {:.0}% of triad ({bytes:.0} B/cell-it counted)",
        setup1,
        solve1,
        cips1,
        100.0 * cips1 * bytes / bw1,
        setup2,
        solve2,
        cips2,
        100.0 * cips2 * bytes / bw2
    );
    let json_rows: Vec<serde_json::Value> = rows
        .iter()
        .map(|r| {
            serde_json::json!({
                "workload": r.workload, "cells": r.cells,
                "fast_1_thread_s_per_step": r.fast_1, "fast_2_threads_s_per_step": r.fast_2,
                "fast_1_thread_us_per_cell_step": r.fast_1 * 1e6 / r.cells as f64,
                "fast_2_threads_us_per_cell_step": r.fast_2 * 1e6 / r.cells as f64,
                "speedup_1_to_2_threads": r.fast_1 / r.fast_2,
                "reference_2_threads_s_per_step": r.reference,
                "reference_over_fast": r.reference.map(|t| t / r.fast_2),
            })
        })
        .collect();
    let json = serde_json::json!({
        "settings": "2 outer, 2 PISO, 1 non-orthogonal corrector; fast tolerances 1e-7 normalised; reference exact LU",
        "steps": json_rows,
        "stream_triad_bytes_per_s": {"1": bw1, "2": bw2},
        "pressure_solve": {
            "grid": format!("{pn}^3 7-point Laplacian"), "iterations": iters, "bytes_per_cell_iteration_counted": bytes,
            "cell_iterations_per_s": {"1": cips1, "2": cips2},
            "fraction_of_triad": {"1": cips1 * bytes / bw1, "2": cips2 * bytes / bw2},
            "setup_s": {"1": setup1, "2": setup2}, "solve_s": {"1": solve1, "2": solve2},
        },
    });
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/spillage-bench");
    let _ = std::fs::create_dir_all(&dir);
    let _ = std::fs::write(dir.join("summary.json"), serde_json::to_string_pretty(&json).expect("json"));
    eprintln!("wrote {}", dir.join("summary.json").display());
}

fn criterion_steps(c: &mut Criterion) {
    let mut g = c.benchmark_group("fluid_step");
    g.sample_size(10);
    for (name, case) in [("couette_sliding_128x32", couette(128, 32)), ("lid_driven_128x128", lid(128))] {
        let mut fast = fast_solver(&case);
        g.bench_function(format!("fast/{name}"), |b| b.iter(|| fast.step().expect("step")));
        let mut reference = reference_solver(&case);
        g.bench_function(format!("reference/{name}"), |b| b.iter(|| reference.step().expect("step")));
    }
    g.finish();
}

criterion_group!(benches, criterion_steps);

fn main() {
    // benches/peers/openfoam_lid.sh: time only the lid-driven cavity on 1 thread
    if let Ok(n) = std::env::var("SPILLAGE_PEER_LID") {
        let n: usize = n.parse().expect("SPILLAGE_PEER_LID = cells per side");
        let steps: usize = std::env::var("SPILLAGE_PEER_STEPS").ok().and_then(|s| s.parse().ok()).unwrap_or(20);
        let case = lid(n);
        let mut solver = fast_solver(&case);
        let t = pool(1).install(|| seconds_per_step(&mut solver, steps));
        eprintln!("{:?}", solver.fluid_phase().expect("fluid").last_counts());
        println!("fast_s_per_step {t:.6e} cells {}", n * n);
        return;
    }
    summary();
    benches();
    Criterion::default().configure_from_args().final_summary();
}
