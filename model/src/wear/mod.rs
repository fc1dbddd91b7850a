//! Erosive wear of the walls (spec wear-model.md). For now: the `[wear]` case section; the
//! erosion laws, smoothing and boundary recession follow in their own files.

pub mod settings;
