//! `spillage-model`: the one definition of the problem that both solvers solve.
//!
//! Case files → typed [`case::Case`]; face-addressed [`mesh::Mesh`] and its generators; wall
//! geometry; closure laws; the [`state::State`] both solvers read and write; the
//! [`solver::Solver`] trait; output writers.

pub mod case;
pub mod checkpoint;
pub mod closure;
pub mod coupling;
pub mod cutter_head;
pub mod fluid;
pub mod mesh;
pub mod output;
pub mod particles;
pub mod solver;
pub mod state;
pub mod state_diff;
pub mod step;
pub mod turbulence;
pub mod walls;
pub mod wear;
