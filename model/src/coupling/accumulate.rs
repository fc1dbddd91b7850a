//! The particles' loads summed into the cells through their deposit weights (fluid-dem-model.md
//! §6.8, particle → mesh): α_p V_j = Σ_n w_j,n V_p,n, C_j = Σ_n w_j,n K_n, F_j = Σ_n w_j,n F_n.
//!
//! Each cell's sums run over the particles in particle order, each term `w × load`, starting from
//! zero: that fixes every cell's bits. The reference adds particle after particle
//! ([`accumulate_in_order`]); a solver may split the work over the cells (never over the
//! particles, which would regroup a cell's sum) and gets the same bits.

use super::kernel::Stencil;
use crate::step::ParticleLoad;

/// The cell sums of a deposit before they become per-volume fields: Σ w V_p [m³], Σ w K [kg/s]
/// and each component of Σ w F [N], one entry per cell.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CellSums {
    pub volume: Vec<f64>,
    pub drag: Vec<f64>,
    pub force: [Vec<f64>; 3],
}

impl CellSums {
    /// Zero sums on `n` cells.
    pub fn zeros(n: usize) -> Self {
        CellSums { volume: vec![0.0; n], drag: vec![0.0; n], force: [vec![0.0; n], vec![0.0; n], vec![0.0; n]] }
    }

    /// Adds particle `i`'s load with weight `w` to the sums of the cell at `index` (the
    /// reference's term, as every accumulator forms it).
    #[inline(always)]
    pub fn add(volume: &mut f64, drag: &mut f64, force: [&mut f64; 3], w: f64, load: &ParticleLoad, i: usize) {
        *volume += w * load.volume[i];
        *drag += w * load.implicit_drag[i];
        for (k, f) in force.into_iter().enumerate() {
            *f += w * load.explicit_force[i][k];
        }
    }
}

/// Adds every particle's load (particle `i` through `stencils[i].deposit`) to `sums`, which hold
/// zeros on entry. Any accumulator must give each cell the sum [`accumulate_in_order`] gives.
pub type Accumulator = fn(stencils: &[Stencil], load: &ParticleLoad, sums: &mut CellSums);

/// Particle after particle, each stencil's cells in its order.
pub fn accumulate_in_order(stencils: &[Stencil], load: &ParticleLoad, sums: &mut CellSums) {
    let CellSums { volume, drag, force: [fx, fy, fz] } = sums;
    for (i, s) in stencils.iter().enumerate() {
        for (&c, &w) in s.cells.iter().zip(&s.deposit) {
            CellSums::add(&mut volume[c], &mut drag[c], [&mut fx[c], &mut fy[c], &mut fz[c]], w, load, i);
        }
    }
}
