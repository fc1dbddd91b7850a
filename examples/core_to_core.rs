//! How long two threads take to hand a cache line to each other: the price of every barrier of
//! a gang (`fast/src/linear/gang.rs`) and of every row a gang's members share at their blocks'
//! edges. On the project's 2-core VM it is 26–45 ns in some periods and 176–260 ns in others
//! (2026-11-28); a solve's speed on two threads follows it (docs/performance.md, "A gang or one thread, by the
//! clock"), so a benchmark run is best read together with it.
//!
//! `cargo run --release --example core_to_core -- [rounds]`: prints the median of `rounds`
//! (default 5) timings of 100 000 round trips, in ns per one-way hand-off.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// The line the two threads hand over, alone on its cache lines.
#[repr(align(128))]
struct Ball(AtomicU64);

const ROUND_TRIPS: u64 = 100_000;

/// Nanoseconds per one-way hand-off over `ROUND_TRIPS` round trips.
fn hand_off_ns() -> f64 {
    let ball = Arc::new(Ball(AtomicU64::new(0)));
    let other = {
        let ball = Arc::clone(&ball);
        std::thread::spawn(move || {
            for k in 0..ROUND_TRIPS {
                while ball.0.load(Ordering::Acquire) != 2 * k + 1 {
                    std::hint::spin_loop();
                }
                ball.0.store(2 * k + 2, Ordering::Release);
            }
        })
    };
    let start = Instant::now();
    for k in 0..ROUND_TRIPS {
        ball.0.store(2 * k + 1, Ordering::Release);
        while ball.0.load(Ordering::Acquire) != 2 * k + 2 {
            std::hint::spin_loop();
        }
    }
    let elapsed = start.elapsed();
    other.join().expect("the other thread");
    elapsed.as_secs_f64() * 1e9 / (2 * ROUND_TRIPS) as f64
}

fn main() {
    let rounds = match std::env::args().nth(1).map(|a| a.parse::<usize>()) {
        None => 5,
        Some(Ok(n)) if n > 0 => n,
        Some(_) => {
            eprintln!("core_to_core: the argument is the number of rounds, a whole number from 1 up");
            std::process::exit(2);
        }
    };
    let mut ns: Vec<f64> = (0..rounds).map(|_| hand_off_ns()).collect();
    ns.sort_by(f64::total_cmp);
    println!("{:.0} ns per hand-off between two threads (median of {rounds}; each round {ROUND_TRIPS} round trips)", ns[rounds / 2]);
}
