//! Erosive wear of the walls (spec wear-model.md). For now: the `[wear]` case section and the
//! erosion laws; smoothing and boundary recession follow in their own files.

pub mod laws;
pub mod settings;
