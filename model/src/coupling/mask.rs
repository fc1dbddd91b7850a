//! The ∂α_c/∂t the pressure equation takes in the interface mask (T4.54, spec
//! fluid-dem-model.md §6.7), shared by both fluid phases so they apply the same rule.
//!
//! [R, deviation from the literal T4.54] The thesis sets ∂α_c/∂t to zero in the masked band.
//! In a closed domain (walls only) that makes the pressure equation's right-hand side
//! incompatible whenever particle volume enters or leaves the band: Σ_cells ∂α_c/∂t V is no
//! longer zero, and the mismatch lands in the one cell whose pressure is pinned (cell 0,
//! OpenFOAM's setReference), wherever that is — a point source of fluid volume far from the
//! particle. Measured on P2 at d_p/Δx = 5 (cases/coupling/interface_crossing_fine.toml):
//! 2.9e-2 V_p per step in that one cell, u_p Δt / (√(2π) σ) V_p, the rate at which the Gaussian
//! footprint crosses the band's edge; it was the largest single-cell continuity error of the run
//! (Table 6.4's "local" row; the thesis' 2.2e-2). With an open boundary the mismatch leaves
//! through it instead, as a flow across the whole domain.
//!
//! What the mask is for is the jump of the truncated footprint from one side of the interface
//! to the other, a redistribution of particle volume *inside* the band. So the band keeps its
//! net rate S = Σ_band ∂α_c/∂t V (the particle volume entering or leaving it) and drops only the
//! redistribution: S is spread over the band's cells in proportion to the particle volume they
//! hold at the three time levels of ∂α/∂t, i.e. where the particle is. Σ_cells of the pressure
//! equation's ∂α_c/∂t V is then the unmasked one (zero: compatible), and a crossing deep inside
//! the band is still masked (its S is only the footprint's tails beyond the band's edge).

/// The band's net rate and the weight it is spread by, for one step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BandRate {
    /// S = Σ_masked ∂α_c/∂t V [m³/s].
    pub net: f64,
    /// Σ_masked of the cells' weights (particle volume at the three time levels) [m³].
    pub weight: f64,
}

/// The weight of a cell in the band: its particle volume (1 − α_c) V at the current, old and
/// old-old time levels summed, so a cell the particle just left still takes its share.
#[inline]
pub fn band_weight(alpha: f64, alpha_old: f64, alpha_old_old: f64, volume: f64) -> f64 {
    ((1.0 - alpha) + (1.0 - alpha_old) + (1.0 - alpha_old_old)) * volume
}

impl BandRate {
    /// Sums over the cells in order (a fixed order: both fluid phases get the same bits):
    /// `rate_volume(c)` = ∂α_c/∂t V, `weight(c)` = [`band_weight`] of cell c.
    pub fn of(masked: &[bool], rate_volume: impl Fn(usize) -> f64, weight: impl Fn(usize) -> f64) -> Self {
        let mut out = BandRate::default();
        for (c, _) in masked.iter().enumerate().filter(|(_, m)| **m) {
            out.net += rate_volume(c);
            out.weight += weight(c);
        }
        out
    }

    /// ∂α_c/∂t V of a masked cell with weight `weight` and rate `own` as the pressure equation
    /// takes it: its share of the band's net rate; when no particle volume is in the band at any
    /// of the three levels there is no footprint to redistribute, and the cell keeps its own
    /// rate (zero but for the particles' share of a turning cell's mesh fluxes on faces it
    /// shares with cells outside the band, crate::fluid::moving_cells).
    #[inline]
    pub fn share(&self, weight: f64, own: f64) -> f64 {
        if self.weight > 0.0 {
            self.net * weight / self.weight
        } else {
            own
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A footprint that moves inside the band is masked; one that enters the band keeps its net
    /// rate, spread where the particle is; Σ of the pressure's rates equals Σ of the true rates
    /// (compatible), which zeroing the band (the literal T4.54) does not give.
    #[test]
    fn the_band_keeps_its_net_rate_and_drops_the_redistribution() {
        let volume = [1.0; 6];
        let masked = [false, false, true, true, true, false];
        let dt = 0.5;
        let rates = |now: &[f64; 6], old: &[f64; 6]| -> Vec<f64> { (0..6).map(|c| (now[c] - old[c]) * volume[c] / dt).collect() };
        let pressure = |now: &[f64; 6], old: &[f64; 6]| -> Vec<f64> {
            let r = rates(now, old);
            let band = BandRate::of(&masked, |c| r[c], |c| band_weight(now[c], old[c], old[c], volume[c]));
            (0..6).map(|c| if masked[c] { band.share(band_weight(now[c], old[c], old[c], volume[c]), r[c]) } else { r[c] }).collect()
        };
        // particle volume 0.2 moves from cell 2 to cell 4, both in the band: all masked
        let (old, now) = ([1.0, 1.0, 0.8, 1.0, 1.0, 1.0], [1.0, 1.0, 1.0, 1.0, 0.8, 1.0]);
        assert!(pressure(&now, &old).iter().all(|r| r.abs() < 1e-15), "{:?}", pressure(&now, &old));
        // half of it moves from cell 1 (outside) into cell 2 (inside)
        let (old, now) = ([1.0, 0.8, 1.0, 1.0, 1.0, 1.0], [1.0, 0.9, 0.9, 1.0, 1.0, 1.0]);
        let (p, r) = (pressure(&now, &old), rates(&now, &old));
        let sum = |v: &[f64]| v.iter().sum::<f64>();
        assert!(sum(&r).abs() < 1e-15 && sum(&p).abs() < 1e-15, "compatible: {r:?} {p:?}");
        assert!((p[2] - r[2]).abs() < 1e-15 && p[3] == 0.0 && p[4] == 0.0, "the entering volume stays where it is: {p:?}");
        // the literal mask (zero in the band) leaves −0.2 unbalanced
        let literal: f64 = (0..6).filter(|&c| !masked[c]).map(|c| r[c]).sum();
        assert!((literal - 0.2).abs() < 1e-12, "{literal}");
        // no particle volume in the band at any level: nothing to spread, a cell keeps its rate
        assert_eq!(BandRate::of(&masked, |_| 0.0, |_| 0.0).share(0.0, 0.0), 0.0);
        assert_eq!(BandRate::of(&masked, |_| 0.0, |_| 0.0).share(0.0, -0.3), -0.3);
    }
}
