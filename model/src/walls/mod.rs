//! Wall geometry: triangle meshes (generated shapes or STL), rigid motion, per-triangle wear.
//! (Owned by the DEM work; placeholders for now.)

pub mod settings;
pub mod state;
