//! Step 1 of wear: impacts → removed volume on the triangle hit and its nodes
//! (wear-model.md §5.3, §6, §7.1, §7.3 "per-face accumulation").

use spillage_model::particles::ImpactRecord;
use spillage_model::walls::state::Vec3;
use spillage_model::wear::laws::{ErosionLaw, ImpactInput};
use spillage_model::wear::state::{WallWear, ANGLE_BINS, SPEED_BINS};
use spillage_model::wear::surface::{barycentric_weights, WearSurface};

/// What one wall received this step.
pub struct Booked {
    pub impacts: u64,
    /// Deposited volume per node [m³] (Σ_i modifier·A·W_i φ_j(x_i)).
    pub node_volume: Vec<f64>,
}

/// Books the impacts on wall `w` (the others are skipped). The impact speed is the particle
/// centre's speed relative to the wall surface and the angle is measured from the surface
/// (§5.3): both taken at first touch by the DEM.
pub fn deposit(law: &ErosionLaw, scale: f64, max_speed: f64, surface: &WearSurface, nodes: &[Vec3], impacts: &[ImpactRecord], w: &mut WallWear) -> Booked {
    let mut booked = Booked { impacts: 0, node_volume: vec![0.0; surface.n_nodes] };
    for impact in impacts.iter().filter(|i| i.wall as usize == w.wall) {
        let t = impact.triangle as usize;
        let [a, b, c] = surface.triangles[t].map(|n| nodes[n as usize]);
        if w.material_side == 0.0 {
            // an open wall: the material is on the side the particles move into
            let side = impact.normal.dot(&(b - a).cross(&(c - a)));
            w.material_side = if side < 0.0 { -1.0 } else { 1.0 };
        }
        let speed = impact.normal_speed.hypot(impact.tangential_speed);
        let angle = impact.angle.clamp(0.0, std::f64::consts::FRAC_PI_2);
        let removed = law.removed_volume(&ImpactInput { speed, angle, mass: impact.mass, diameter: impact.diameter, density: impact.density });
        let volume = scale * removed.total();
        w.law_cutting += removed.cutting;
        w.law_deformation += removed.deformation;
        w.deposited += volume;
        w.triangle_volume[t] += volume;
        for (n, phi) in surface.triangles[t].iter().zip(barycentric_weights(a, b, c, impact.point)) {
            booked.node_volume[*n as usize] += volume * phi;
        }
        if impact.sliding {
            // sliding wear's equivalent impact (`spillage_model::wear::sliding`): not an impact
            w.sliding_deposited += volume;
            continue;
        }
        w.triangle_impacts[t] += 1;
        let angle_bin = ((angle / std::f64::consts::FRAC_PI_2 * ANGLE_BINS as f64) as usize).min(ANGLE_BINS - 1);
        let speed_bin = ((speed / max_speed * SPEED_BINS as f64) as usize).min(SPEED_BINS - 1);
        w.angle_histogram[t * ANGLE_BINS + angle_bin] += 1;
        w.speed_histogram[t * SPEED_BINS + speed_bin] += 1;
        booked.impacts += 1;
    }
    booked
}
