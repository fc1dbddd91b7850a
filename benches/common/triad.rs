//! STREAM triad a = b + 3·c (issue #6): the machine's memory bandwidth, measured beside the
//! solver so its bandwidth fraction and 1 → 2 thread scaling are judged against the same minute.
//! Shared by `benches/fluid_step.rs` and `fast/examples/triad.rs`.

use std::time::Instant;

/// Best of `repeats` triads over `n` doubles on `threads` threads: bytes moved per second
/// (3 arrays, STREAM's count).
pub fn triad(threads: usize, n: usize, repeats: usize) -> f64 {
    use rayon::prelude::*;
    let b = vec![1.0f64; n];
    let c = vec![2.0f64; n];
    let mut a = vec![0.0f64; n];
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
    pool.install(|| {
        let mut best = f64::INFINITY;
        for _ in 0..repeats {
            let t = Instant::now();
            a.par_chunks_mut(1 << 16).enumerate().for_each(|(k, ch)| {
                let o = k << 16;
                for (i, x) in ch.iter_mut().enumerate() {
                    *x = b[o + i] + 3.0 * c[o + i];
                }
            });
            best = best.min(t.elapsed().as_secs_f64());
        }
        std::hint::black_box(&a);
        3.0 * 8.0 * n as f64 / best
    })
}
