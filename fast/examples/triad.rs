//! STREAM-like triad a = b + 3·c on 1 and 2 threads (same kernel as the bench in
//! `benches/fluid_step.rs`), for judging the solver's 1 → 2 thread scaling against what the
//! machine's memory system allows (issue #6). Prints GB/s (STREAM's count: 3 arrays) per
//! thread count and the ratio.
//!
//! usage: cargo run --release -p spillage-fast --example triad -- [n (default 20 000 000)] [repeats]

#[path = "../../benches/common/triad.rs"]
mod triad;
use triad::triad;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(20_000_000);
    let repeats: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(10);
    let bw1 = triad(1, n, repeats);
    let bw2 = triad(2, n, repeats);
    println!("triad {n}: {:.2} GB/s (1 thread), {:.2} GB/s (2 threads), 1→2 scaling {:.2}×", bw1 / 1e9, bw2 / 1e9, bw2 / bw1);
}
