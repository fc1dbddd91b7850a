//! The cutter head: one parametric description (`[cutter_head]`) that makes the fluid mesh
//! (a rotor zone with the head's solids removed as blocked cells, [`fluid_mesh`]), the DEM walls
//! (the same solids as triangle meshes turning with the rotor, [`walls`]) and the spillage
//! bookkeeping (the contour hull, the suction pipe, [`spillage`]), the fluxes through the hull
//! ([`fluxes`]: the solver's face fluxes and the thesis' interpolated surface, [`hull_surface`]),
//! the rotor's torque balance on the computed flow ([`torque`]), the haul velocity, a current
//! past the head ([`current`]), the thesis' eccentric suction mouth at rest in a back plate
//! ([`mouth`]), and which way gravity pulls along the axis ([`ladder`]).
//! spillage-and-flow-verification.md §2, §4, §5.

pub mod current;
pub mod fluid_mesh;
pub mod fluxes;
pub mod geometry;
pub mod hull_surface;
pub mod ladder;
pub mod mouth;
pub mod settings;
pub mod spillage;
pub mod torque;
pub mod walls;

pub use geometry::{CutterHead, Part};
pub use settings::{BladeCells, BladeSweep, CutterHeadSection, Suction};
