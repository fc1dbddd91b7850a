//! Hertz collision time and the DEM sub-step (fluid-dem-model.md §7.6, T3.105–T3.106).

/// OpenFOAM's constant C_col = π^{7/5} (5/4)^{2/5} ≈ 5.4297 in (T3.105).
pub fn openfoam_collision_constant() -> f64 {
    std::f64::consts::PI.powf(1.4) * 1.25f64.powf(0.4)
}

/// Contact duration estimate t_col = C_col (ρ_p/E*)^{2/5} r / u^{1/5} [s] (T3.105).
pub fn collision_time(density: f64, effective_youngs: f64, radius: f64, speed: f64) -> f64 {
    openfoam_collision_constant() * (density / effective_youngs).powf(0.4) * radius / speed.powf(0.2)
}

/// Number of DEM sub-steps in a step of size `dt`: N_sub = ⌈Δt / Δt_col⌉ with
/// Δt_col = t_col / N_timeSteps (T3.106, OpenFOAM's sub-cycling of §7.6). At least 1.
pub fn substeps(dt: f64, collision_time: f64, steps_per_collision: f64) -> u64 {
    let dt_col = collision_time / steps_per_collision;
    // Shave round-off so an exact multiple (1e-3 / 1e-4 = 10.000000000000002) is not rounded up.
    let n = (dt / dt_col * (1.0 - 1e-12)).ceil();
    if n.is_finite() && n >= 1.0 {
        n as u64
    } else {
        1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// particle-verification.md §8 checks 21–22: glass d = 10 mm, E = 60 GPa, ν = 0.23, u = 1.
    #[test]
    fn glass_collision_times() {
        let e_star = |e: f64| e / (2.0 * (1.0 - 0.23f64 * 0.23));
        assert_relative_eq!(collision_time(2540.0, e_star(60e9), 0.005, 1.0), 3.939e-5, max_relative = 1e-3);
        assert_relative_eq!(collision_time(2540.0, e_star(10e6), 0.005, 1.0), 1.278e-3, max_relative = 1e-3);
        assert_relative_eq!(openfoam_collision_constant(), 5.429675, max_relative = 1e-6);
    }

    #[test]
    fn substep_count_rounds_up() {
        assert_eq!(substeps(1e-3, 1.2e-3, 12.0), 10);
        assert_eq!(substeps(1e-3, 1.2e-2, 12.0), 1);
        assert_eq!(substeps(1e-3, f64::INFINITY, 12.0), 1);
    }
}
