//! Pressure-solve driver for A/B comparisons of the AMG-preconditioned CG (issue #6): builds a
//! Neumann Laplacian with one pinned cell (the lid-driven cavity's pressure matrix shape) on an
//! n × n (2-D) or n × n × n (3-D) grid, solves it to a normalised residual of 1e-7 several times
//! and prints iterations and times. Deterministic, so callgrind instruction counts compare.
//!
//! usage: cargo run --release -p spillage-fast --example pressure_solve -- [2d|3d] [n] [repeats]

use std::time::Instant;

use spillage_fast::linear::{amg::Amg, pcg::Pcg, Csr, Tolerance};

fn neumann(dims: &[usize]) -> Csr {
    let n: usize = dims.iter().product();
    let mut a = Csr { n, row_start: vec![0], ..Default::default() };
    let stride: Vec<usize> = (0..dims.len()).map(|d| dims[..d].iter().product()).collect();
    for c in 0..n {
        let mut d = 0.0;
        let mut nb = Vec::new();
        for (k, &s) in stride.iter().enumerate() {
            let i = (c / s) % dims[k];
            if i > 0 {
                nb.push(c - s);
            }
            if i + 1 < dims[k] {
                nb.push(c + s);
            }
        }
        nb.sort_unstable();
        for j in nb {
            a.col.push(j as u32);
            a.val.push(-1.0);
            d += 1.0;
        }
        a.diag.push(d);
        a.row_start.push(a.col.len() as u32);
    }
    a.diag[0] *= 2.0;
    a
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let three_d = args.get(1).is_some_and(|s| s == "3d");
    let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(256);
    let dims = if three_d { vec![n, n, n] } else { vec![n, n] };
    let a = neumann(&dims);
    // a smooth solution plus a rough part, shifted to zero mean right-hand side
    let x_true: Vec<f64> = (0..a.n).map(|i| ((i as f64) * 0.001).sin() + ((i * 7919) % 101) as f64 * 1e-3).collect();
    let mut b = vec![0.0; a.n];
    a.multiply(&x_true, &mut b);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(std::env::var("THREADS").ok().and_then(|s| s.parse().ok()).unwrap_or(1)).build().expect("pool");
    pool.install(|| spillage_fast::team::keep_awake(|| run(&a, &b)));
}

fn run(a: &Csr, b: &[f64]) {
    let args: Vec<String> = std::env::args().collect();
    let repeats: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(4);
    let tol = Tolerance { tolerance: 1e-7, max_iterations: 1000 };
    let mut amg = Amg::default();
    let t = Instant::now();
    amg.setup(a);
    let setup = t.elapsed().as_secs_f64();
    let mut pcg = Pcg::default();
    let mut total = 0.0;
    let mut solving = 0.0;
    let mut iterations = 0;
    for r in 0..repeats {
        let mut x = vec![0.0; a.n];
        let t = Instant::now();
        if r > 0 {
            amg.setup(a);
        }
        let solve_start = Instant::now();
        let s = pcg.solve(a, b, &mut x, &mut amg, tol);
        solving += solve_start.elapsed().as_secs_f64();
        let dt = t.elapsed().as_secs_f64();
        total += dt;
        iterations += s.iterations;
        eprintln!("solve {r}: {} iterations, residual {:.2e}, {:.2} ms", s.iterations, s.final_residual, dt * 1e3);
    }
    eprintln!("levels (rows, off-diagonals, colours): {:?}", amg.level_sizes());
    println!(
        "{} cells, {} levels, first setup {:.2} ms, mean setup+solve {:.2} ms, {:.1} iterations, {:.1} ns per cell-iteration ({:.1} in the solve alone)",
        a.n,
        amg.levels(),
        setup * 1e3,
        total / repeats as f64 * 1e3,
        iterations as f64 / repeats as f64,
        total / iterations as f64 / a.n as f64 * 1e9,
        solving / iterations as f64 / a.n as f64 * 1e9
    );
}
