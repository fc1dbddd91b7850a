//! Wear state: what the walls have lost so far, part of [`crate::state::State`] so checkpoints
//! carry it and a restart continues bit-for-bit.
//!
//! Volumes here are *deposited* volumes: the law's volume per real particle times the
//! representative-particle modifier and the acceleration factor (wear-model.md §7.1, §8), i.e.
//! the volume the wall geometry actually loses in the simulation.

use serde::{Deserialize, Serialize};

/// Impact-angle histogram bins: 9 bins of 10° from grazing to head-on.
pub const ANGLE_BINS: usize = 9;
/// Impact-speed histogram bins: 10 equal bins up to `[wear] histogram_max_speed`.
pub const SPEED_BINS: usize = 10;

/// The wear of one eroding wall.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WallWear {
    /// Index of the wall in [`crate::walls::state::WallState`].
    pub wall: usize,
    pub name: String,
    /// Node of each wall vertex ([`super::surface::WearSurface::node_of_vertex`]): output maps
    /// node values to the wall's vertices and triangles with it.
    pub node_of_vertex: Vec<u32>,
    /// Per triangle: deposited volume [m³], impacts, and the histograms (row-major,
    /// `ANGLE_BINS` / `SPEED_BINS` per triangle).
    pub triangle_volume: Vec<f64>,
    pub triangle_impacts: Vec<u64>,
    pub angle_histogram: Vec<u32>,
    pub speed_histogram: Vec<u32>,
    /// Per node of the wear surface: the smoothed wear rate w (recession speed, m/s, already
    /// accelerated) and the depth receded so far [m].
    pub node_rate: Vec<f64>,
    pub node_depth: Vec<f64>,
    /// +1 or −1: which side of the triangles' winding is wall material (the side particles hit
    /// from is not); 0 until known (open walls learn it from their first impact).
    pub material_side: f64,
    /// Σ deposited volume [m³], its law parts (per real particle, unscaled) and the volume the
    /// geometry has receded by [m³].
    pub deposited: f64,
    pub law_cutting: f64,
    pub law_deformation: f64,
    /// The part of `deposited` that sliding wear booked (`super::sliding`) [m³].
    #[serde(default)]
    pub sliding_deposited: f64,
    pub receded: f64,
    /// Volume deposited but not yet receded because it fell only on pinned rim nodes [m³].
    pub pending: f64,
    /// The wall's cone volume at the start (about `volume_origin`): the geometric measure of
    /// the removed volume is its change ([`super::surface::WearSurface::cone_volume`]).
    pub initial_volume: f64,
    pub volume_origin: [f64; 3],
}

impl WallWear {
    pub fn new(wall: usize, name: String, n_triangles: usize, node_of_vertex: Vec<u32>, n_nodes: usize) -> Self {
        WallWear {
            wall,
            name,
            node_of_vertex,
            triangle_volume: vec![0.0; n_triangles],
            triangle_impacts: vec![0; n_triangles],
            angle_histogram: vec![0; n_triangles * ANGLE_BINS],
            speed_histogram: vec![0; n_triangles * SPEED_BINS],
            node_rate: vec![0.0; n_nodes],
            node_depth: vec![0.0; n_nodes],
            ..WallWear::default()
        }
    }

    /// A node field at the wall's vertices.
    pub fn at_vertices(&self, node_values: &[f64]) -> Vec<f64> {
        self.node_of_vertex.iter().map(|&n| node_values[n as usize]).collect()
    }

    /// A node field averaged over each triangle's corners (`triangles` in vertex indices).
    pub fn on_triangles(&self, node_values: &[f64], triangles: &[[u32; 3]]) -> Vec<f64> {
        triangles.iter().map(|t| t.iter().map(|&v| node_values[self.node_of_vertex[v as usize] as usize]).sum::<f64>() / 3.0).collect()
    }

    /// Volume still being smoothed: ∫w dA / λ (wear-model.md §7.3, conservation identity), with
    /// the lumped node areas.
    pub fn in_flight(&self, node_area: &[f64], damping: Option<f64>) -> f64 {
        match damping {
            Some(lambda) => self.node_rate.iter().zip(node_area).map(|(w, a)| w * a).sum::<f64>() / lambda,
            None => 0.0,
        }
    }
}

/// Every eroding wall's wear, and the total number of impacts seen on them.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct WearState {
    pub walls: Vec<WallWear>,
    pub impacts: u64,
}
