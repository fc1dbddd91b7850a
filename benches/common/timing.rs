//! Wall time per step of a solver, shared by the benches.

use std::time::Instant;

use spillage_model::solver::Solver;

/// Seconds per step over `steps` steps after 2 warm-up steps.
pub fn seconds_per_step(s: &mut dyn Solver, steps: usize) -> f64 {
    for _ in 0..2 {
        s.step().expect("step");
    }
    seconds_per_next_steps(s, steps)
}

/// Seconds per step over the next `steps` steps, without warming up.
#[allow(dead_code)] // not every bench that includes this file takes turns between solvers
pub fn seconds_per_next_steps(s: &mut dyn Solver, steps: usize) -> f64 {
    let t = Instant::now();
    for _ in 0..steps {
        s.step().expect("step");
    }
    t.elapsed().as_secs_f64() / steps as f64
}
