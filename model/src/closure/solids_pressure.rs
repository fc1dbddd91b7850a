//! The solids (granular) pressure of the kinetic theory of granular flow, as the thesis' wear
//! model uses it (spec wear-model.md §4): the granular temperature from the particle velocities
//! of a control volume (Eq. 2.19, §4.1), the radial distribution function (Eq. 2.26) and the
//! solids pressure (Eq. 2.25, §4.3). The stress is reduced to −p_p I (§4.3), and its force on a
//! particle is −∇p_p/(α_p ρ_p) (§4.4, the printed sign and the missing 1/α_p corrected, §13 row
//! 11). [`crate::particles::solids_pressure`] applies it.

/// α_max of Eq. 2.26 (Ding & Gidaspow 1990; wear-model.md §4.3, §9 item 3).
pub const PACKING_LIMIT: f64 = 0.6;

/// The particle–particle restitution e of Eq. 2.25: the thesis gives none, so the wall value
/// 0.99 (wear-model.md §4.3 [R], §13 row 13).
pub const RESTITUTION: f64 = 0.99;

/// How close to α_max Eq. 2.26 is evaluated: α_p is clamped to α_max (1 − 10⁻⁶) inside g₀, so
/// it stays finite (wear-model.md §4.3 [R]).
const CLAMP: f64 = 1.0e-6;

/// The radial distribution function g₀ = [1 − (α_p/α_max)^{1/3}]⁻¹ (Eq. 2.26).
pub fn radial_distribution(alpha_p: f64, packing_limit: f64) -> f64 {
    let ratio = clamped(alpha_p, packing_limit) / packing_limit;
    1.0 / (1.0 - ratio.cbrt())
}

/// dg₀/dα_p of Eq. 2.26, at α_p clamped like g₀ (so it is held beyond the clamp). It grows as
/// α_p^{−2/3} toward α_p = 0, where it is returned as 0: it only enters multiplied by α_p².
pub fn radial_distribution_slope(alpha_p: f64, packing_limit: f64) -> f64 {
    let alpha = clamped(alpha_p, packing_limit);
    if alpha <= 0.0 {
        return 0.0;
    }
    let g0 = radial_distribution(alpha, packing_limit);
    g0 * g0 * (alpha / packing_limit).cbrt() / (3.0 * alpha)
}

/// p_p = α_p ρ_p Θ + 2 ρ_p (1 + e) α_p² g₀ Θ (Eq. 2.25) [Pa].
pub fn solids_pressure(alpha_p: f64, density: f64, temperature: f64, restitution: f64, packing_limit: f64) -> f64 {
    let g0 = radial_distribution(alpha_p, packing_limit);
    alpha_p * density * temperature + 2.0 * density * (1.0 + restitution) * alpha_p * alpha_p * g0 * temperature
}

/// (∂p_p/∂α_p)/ρ_p at fixed Θ [m²/s²]: Θ [1 + 2 (1 + e)(2 α_p g₀ + α_p² dg₀/dα_p)], from Eq. 2.25;
/// ρ_p cancels, so a cell needs no particle density for it.
///
/// [R] Beyond the clamp of g₀ (α_p ≥ α_max (1 − 10⁻⁶)) the slope is held at its value there
/// (≈ 10¹³ Θ), as if p_p went on linearly. The clamped Eq. 2.25 itself would only grow as α_p²
/// there, with a slope a million times smaller: an over-packed cell would then resist less
/// than one just below α_max, the reverse of what the clamp is for.
pub fn solids_pressure_slope_per_density(alpha_p: f64, temperature: f64, restitution: f64, packing_limit: f64) -> f64 {
    let alpha = clamped(alpha_p, packing_limit);
    let g0 = radial_distribution(alpha, packing_limit);
    let dg0 = radial_distribution_slope(alpha, packing_limit);
    temperature * (1.0 + 2.0 * (1.0 + restitution) * (2.0 * alpha * g0 + alpha * alpha * dg0))
}

fn clamped(alpha_p: f64, packing_limit: f64) -> f64 {
    // max/min rather than clamp, which panics on a negative limit
    alpha_p.min(packing_limit * (1.0 - CLAMP)).max(0.0)
}

/// Running sums of a control volume's particle velocities, for its granular temperature. The
/// sums are of the velocities less the first one added, so that Θ does not come from the
/// cancellation of |c|² against ⟨|u|²⟩ (grains carried at 10 m/s with a spread of 0.1 m/s
/// would lose five digits to it).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VelocityMoments {
    /// Σ w (weights: the real particles each simulated one stands for, §4.1 [R]).
    pub weight: f64,
    /// Number of simulated particles.
    pub count: u32,
    /// The first velocity added, subtracted from every one.
    pub shift: [f64; 3],
    /// Σ w (u − shift).
    pub sum: [f64; 3],
    /// Σ w |u − shift|².
    pub sum_of_squares: f64,
}

impl VelocityMoments {
    pub fn add(&mut self, velocity: [f64; 3], weight: f64) {
        if self.count == 0 {
            self.shift = velocity;
        }
        self.weight += weight;
        self.count += 1;
        let mut square = 0.0;
        for k in 0..3 {
            let v = velocity[k] - self.shift[k];
            self.sum[k] += weight * v;
            square += v * v;
        }
        self.sum_of_squares += weight * square;
    }

    /// The (weighted) mean velocity c; zero without particles.
    pub fn mean(&self) -> [f64; 3] {
        if self.weight > 0.0 {
            std::array::from_fn(|k| self.shift[k] + self.sum[k] / self.weight)
        } else {
            [0.0; 3]
        }
    }

    /// Θ = ⟨|c − u_p|²⟩/3 (Eq. 2.19), c the (weighted) mean velocity; 0 with fewer than two
    /// particles (§4.1 [R]). Computed as ⟨|u − s|²⟩ − |c − s|², s the first velocity, clipped
    /// at 0 against round-off.
    pub fn granular_temperature(&self) -> f64 {
        if self.count < 2 || self.weight <= 0.0 {
            return 0.0;
        }
        let mean_square: f64 = self.sum.iter().map(|s| (s / self.weight).powi(2)).sum();
        ((self.sum_of_squares / self.weight - mean_square) / 3.0).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn two_opposite_particles_have_a_third_and_equal_ones_none() {
        // spec wear-model.md §15 A34: (±1, 0, 0) m/s in one CV give Θ = 1/3; equal velocities 0.
        let mut m = VelocityMoments::default();
        m.add([1.0, 0.0, 0.0], 1.0);
        m.add([-1.0, 0.0, 0.0], 1.0);
        assert!((m.granular_temperature() - 1.0 / 3.0).abs() <= 1e-14);
        let mut same = VelocityMoments::default();
        same.add([0.3, -2.0, 1.0], 1.0);
        same.add([0.3, -2.0, 1.0], 1.0);
        assert!(same.granular_temperature().abs() <= 1e-14);
        let mut lone = VelocityMoments::default();
        lone.add([5.0, 0.0, 0.0], 1.0);
        assert_eq!(lone.granular_temperature(), 0.0);
    }

    #[test]
    fn slope_is_the_derivative_of_the_pressure() {
        // central differences of Eq. 2.25, step 1e-7: truncation up to ~1e-10 relative (at α_p
        // 0.59), round-off ~1e-9 relative at these magnitudes; 1e-6 leaves a factor 1000
        for alpha in [0.01, 0.1, 0.3, 0.5, 0.59] {
            let h = 1e-7;
            let numeric = (solids_pressure(alpha + h, 1.0, 0.7, RESTITUTION, PACKING_LIMIT) - solids_pressure(alpha - h, 1.0, 0.7, RESTITUTION, PACKING_LIMIT))
                / (2.0 * h);
            assert_relative_eq!(solids_pressure_slope_per_density(alpha, 0.7, RESTITUTION, PACKING_LIMIT), numeric, max_relative = 1e-6);
        }
    }

    #[test]
    fn pressure_stays_finite_at_and_beyond_the_packing_limit() {
        for alpha in [0.6, 0.7, 5.0] {
            let p = solids_pressure(alpha, 2500.0, 1.0, RESTITUTION, PACKING_LIMIT);
            assert!(p.is_finite() && p > 0.0, "α_p {alpha}: p_p {p}");
            assert!(solids_pressure_slope_per_density(alpha, 1.0, RESTITUTION, PACKING_LIMIT).is_finite());
        }
        assert_eq!(radial_distribution(0.0, PACKING_LIMIT), 1.0);
    }
}
