//! 1 → 2 thread scaling of one multicolour Gauss–Seidel sweep (f32 5-point grid, the shape of
//! the multigrid levels of a 2-D case) over grid sizes, run by a gang of threads as in a solve
//! (`fast/src/linear/gang.rs`; issue #6). Prints µs per sweep and ns per row.
//!
//! usage: cargo run --release -p spillage-fast --example sweep_scaling

use spillage_fast::linear::gang::{self, Slot};
use spillage_fast::linear::smoother::{inverse_diagonal, sweep, Colouring};
use spillage_fast::linear::Csr;
use std::time::Instant;
/// 5-point Laplacian-like matrix on an n × n grid (diagonal 4.5).
fn grid(n: usize) -> Csr<f32> {
    let mut a: Csr<f32> = Csr { n: n * n, row_start: vec![0], ..Default::default() };
    for j in 0..n {
        for i in 0..n {
            for (di, dj) in [(0i64, -1i64), (-1, 0), (1, 0), (0, 1)] {
                let (ii, jj) = (i as i64 + di, j as i64 + dj);
                if ii >= 0 && jj >= 0 && (ii as usize) < n && (jj as usize) < n {
                    a.col.push((jj as usize * n + ii as usize) as u32);
                    a.val.push(-1.0);
                }
            }
            a.diag.push(4.5);
            a.row_start.push(a.col.len() as u32);
        }
    }
    a
}
fn main() {
    for n in [64usize, 96, 128, 160, 192, 256, 320, 384, 512] {
        let a = grid(n);
        let mut c = Colouring::default();
        c.build(&a);
        let mut inv = Vec::new();
        inverse_diagonal(&a, &mut inv);
        let mut b: Vec<f32> = (0..a.n).map(|i| (i as f32 * 0.1).sin()).collect();
        let mut partials = Vec::new();
        let mut line = format!("n {n}² ({} rows):", a.n);
        for t in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(t).build().unwrap();
            let mut x = vec![0.0f32; a.n];
            let reps = (400_000_000 / a.n).max(2);
            let best = pool.install(|| {
                let (b, x) = (Slot::from_mut_slice(&mut b), Slot::from_mut_slice(&mut x));
                let mut best = f64::INFINITY;
                for _ in 0..5 {
                    let t0 = Instant::now();
                    // SAFETY: b and x are this gang's alone, b is not x, and every member runs
                    // the same sweeps
                    gang::run(a.n, &mut partials, |crew| {
                        for r in 0..reps / 5 {
                            unsafe { sweep(crew, &a, &inv, &c, b, x, r % 2 == 0) };
                        }
                    });
                    best = best.min(t0.elapsed().as_secs_f64() / (reps / 5) as f64);
                }
                best
            });
            line += &format!("  {t}t {:.1} µs/sweep {:.2} ns/row", best * 1e6, best * 1e9 / a.n as f64);
        }
        println!("{line}");
    }
}
