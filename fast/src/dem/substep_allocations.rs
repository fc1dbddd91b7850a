//! The DEM sub-steps allocate nothing once their buffers have grown (issue 19: "DEM sub-steps
//! without allocation"), on one thread and on two: pairs, walls, the pass, the segments'
//! balance and the team's parts, counted by the tests' allocator
//! ([`crate::counting_allocator`]). A sub-step that builds a new neighbour list is left out (a
//! build, every hundred sub-steps or so in a settling bed, may grow its pieces' buffers and the
//! list's arrays), and so is one that cuts the segments anew (it sizes the buffers of the
//! contributions set aside for the cuts). A particle's per-wall buffers (its near triangles, its contact history) grow at
//! its first approach to a wall, which the warm-up covers.
//!
//! It found, and so holds off: a Vec made at every look at the segments' balance; a wall
//! impact logged in its particle's own list, whose first impact allocated (now one list per
//! block of the pass); and wall histories swapped with the pass's scratch buffer, which handed
//! a particle that had never touched a wall (no capacity) to the next one.

use std::path::Path;

use spillage_model::case::Case;
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::step::{Coupled, StepContext};

use super::FastDem;
use crate::counting_allocator::{count_during, mark_this_thread};
use crate::team::with_team;

/// Steps of 50 sub-steps before the count: the buffers grow (every particle at a wall has
/// touched it), the wall candidates are marked.
const WARM_UP_STEPS: usize = 10;

/// Sub-steps counted one by one, after the warm-up: past three windows of the segments'
/// balance ([`super::segments::BALANCE_WINDOW`]).
const COUNTED: usize = 120;

#[test]
fn sub_steps_allocate_nothing_once_their_buffers_have_grown() {
    // the 10⁴ settling bed cut to its lowest 4 cm: 2 000 spheres, which come to rest
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/bench/settle_box_10k.toml");
    let text = std::fs::read_to_string(&path).expect("the bed's case");
    let tops = ["0.235940108] }", "0.2417136107] }"];
    assert!(tops.iter().all(|top| text.contains(top)), "the bed's lattice regions end at {tops:?}");
    let text = tops.iter().fold(text, |text, top| text.replace(top, "0.04] }"));
    let case = Case::from_toml(&text, &path).unwrap_or_else(|e| panic!("{e}"));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).start_handler(|_| mark_this_thread()).build().expect("pool");
        pool.install(|| {
            let mut state = State::default();
            let dem = FastDem::new(&case, &mut state).expect("fast DEM");
            let mut run = Coupled::particles_only(&case, state, dem).expect("run");
            // the buffers grow, the wall candidates are marked
            for _ in 0..WARM_UP_STEPS {
                run.step().expect("step");
            }
            let (_, dem, state) = run.parts_mut();
            let dem = dem.expect("particle phase");
            let walls = state.walls.as_mut().expect("the bed's box");
            let dt = case.particles.as_ref().and_then(|p| p.substep).expect("[particles] substep");
            let mut impacts = Vec::with_capacity(1 << 16);
            let (mut quiet, mut allocating) = (0, Vec::new());
            with_team(|team| {
                for k in 0..=COUNTED {
                    let ctx = StepContext::new(state.step + 1 + k as u64, state.time + k as f64 * dt, dt, dt, Default::default(), None);
                    let plans = (dem.list.builds, dem.list.segments.cuts);
                    let (result, allocations) = count_during(|| dem.substeps(&ctx, walls, &[], 1, false, &mut impacts, team));
                    assert!(result.is_ok(), "sub-step {k} failed");
                    // the first call grows what a call of its own needs; a new list or a re-cut
                    // of the segments may grow their buffers
                    if k > 0 && (dem.list.builds, dem.list.segments.cuts) == plans {
                        quiet += 1;
                        if allocations > 0 {
                            allocating.push((k, allocations));
                        }
                    }
                }
            });
            assert!(quiet >= COUNTED / 2, "{threads} threads: only {quiet} of {COUNTED} sub-steps built no list and cut no segments");
            assert!(allocating.is_empty(), "{threads} threads: (sub-step, allocations) {allocating:?} of {quiet} sub-steps without a build");
        });
    }
}
