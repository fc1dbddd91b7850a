//! The parts of the receding-wall step (wear-model.md §7.4) both wear phases share: how far the
//! nodes move so the swept volume is the volume removed, and the words for a wall that would
//! fold.

use crate::walls::state::Vec3;

/// The scale s of a displacement field whose swept volume is `side`·(c₀ s + c₁ s² + c₂ s³)
/// (`coefficients` from [`super::surface::WearSurface::swept_volume_coefficients`]) such that
/// it equals `target` > 0, by Newton's method from the linear estimate; `Ok(None)` when the
/// field sweeps nothing to first order (only rim nodes were hit: the volume waits for a step
/// that moves an inner node). `wall` names the wall in the error.
pub fn displacement_scale(coefficients: [f64; 3], side: f64, target: f64, wall: &str) -> Result<Option<f64>, String> {
    let c = coefficients;
    let removed = |s: f64| side * (c[0] * s + c[1] * s * s + c[2] * s * s * s);
    let slope = |s: f64| side * (c[0] + 2.0 * c[1] * s + 3.0 * c[2] * s * s);
    if !(side != 0.0 && slope(0.0) > 0.0) {
        return Ok(None);
    }
    let mut s = target / slope(0.0);
    for _ in 0..50 {
        let step = (removed(s) - target) / slope(s);
        s -= step;
        if step.abs() <= 1e-15 * s.abs() {
            break;
        }
    }
    if !(s.is_finite() && s > 0.0 && (removed(s) - target).abs() <= 1e-12 * target) {
        return Err(format!("wall `{wall}`: the receding wall's volume equation has no solution (removed volume {target:e} m³)"));
    }
    Ok(Some(s))
}

/// The error of a wall whose nodes would move more than half their shortest edge in one step
/// (its triangles would fold), near `centre` (body frame).
pub fn inside_out(wall: &str, centre: Vec3) -> String {
    format!(
        "wall `{wall}` would turn inside out near ({:.4}, {:.4}, {:.4}) m (body frame): the wear of one step is deeper than its triangles are wide; lower [wear] acceleration or [particles] modifier, or widen [wear.smoothing]",
        centre.x, centre.y, centre.z
    )
}
