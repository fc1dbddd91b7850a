//! The eccentric, stationary suction mouth of a back-plate head (spillage-and-flow-verification.md
//! §4.1 b, §4.5, §4.6; §6.5 item 17 recommends it).
//!
//! On a real cutter head the ring, blades and hub turn while the back plate with the suction
//! mouth belongs to the ladder and stands still; the thesis joined the two with a planar
//! sliding-mesh plane at the back plate (§4.5). Here the back plate and the pipe above it are a
//! stationary housing of blocked rotor cells (r < the ring's inner radius, z > 0). The rotor
//! cells under the plate turn past it, and each of their top faces takes, as a boundary
//! condition, the share of its area that lies over the mouth at the current rotor angle: there
//! the water leaves normal to the plate, elsewhere it meets a wall at rest. The mouth is an
//! annular sector (a kidney) fixed in the world frame, so the faces' shares change smoothly as
//! they turn under it and, because a polar grid tiles the sector exactly, their sum stays the
//! mouth's area at every angle, without a second mesh zone or an interface to weld.
//!
//! The condition on a plate face with share s of the mouth:
//! - **flux** s·A·U normal to the plate. No boundary fixes the pressure, so the step's speed U
//!   is the one that balances continuity ([`balancing_speed`]): Q_m without particles, to
//!   round-off at every rotor angle.
//! - **momentum**: the water leaves with the cell's velocity (zero gradient, its swirl goes
//!   with it as it would into the pipe; a fixed outflow velocity kept the angular momentum in
//!   and spun a 13 m/s vortex up under the mouth); the rest, 1 − s of the face, is a no-slip
//!   wall at rest (both fluid solvers' momentum assembly and the torque budget).
//! - **velocity gradient, wall functions**: the face's fixed velocity s·U·n̂ (the plate's
//!   no-slip in the tangential directions, also over the mouth's share).
//!
//! What this leaves out: the flow inside the pipe (its pressure and swirl downstream of the
//! mouth); the kidney's rounded ends (an annular sector).

use std::f64::consts::{PI, TAU};

use crate::mesh::Vec3;

/// The mouth's shape in the world frame: an annular sector of the back plate (z = 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EccentricMouth {
    /// Azimuth of the sector's centre line [rad], world frame.
    pub angle: f64,
    /// Half the sector's opening angle [rad] (at most π/2).
    pub half_width: f64,
    /// Inner and outer radius [m].
    pub radii: [f64; 2],
}

impl EccentricMouth {
    /// Area of the opening [m²]: ½ · 2w · (r₂² − r₁²).
    pub fn area(&self) -> f64 {
        self.half_width * (self.radii[1].powi(2) - self.radii[0].powi(2))
    }

    /// Whether a world-frame point (x, y) lies over the opening.
    pub fn contains(&self, x: f64, y: f64) -> bool {
        let r = x.hypot(y);
        r > self.radii[0] && r < self.radii[1] && wrap(y.atan2(x) - self.angle).abs() < self.half_width
    }

    /// The share of the polar cell r ∈ [r_a, r_b], θ ∈ [θ_c − Δ/2, θ_c + Δ/2] (Δ ≤ 2π/3) that lies
    /// over the opening, by area in polar measure (r dr dθ): the product of the radial share in
    /// r² and the angular share.
    pub fn share(&self, r: [f64; 2], theta_centre: f64, delta: f64) -> f64 {
        let r2 = |a: f64| a * a;
        let radial = (r2(r[1].min(self.radii[1])) - r2(r[0].max(self.radii[0]))).max(0.0) / (r2(r[1]) - r2(r[0]));
        // the sector spans at most π, the cell at most 2π/3: only the nearest copy can overlap
        let d = wrap(theta_centre - self.angle);
        let angular = ((d + 0.5 * delta).min(self.half_width) - (d - 0.5 * delta).max(-self.half_width)).max(0.0) / delta;
        radial * angular
    }
}

/// An angle wrapped into (−π, π].
fn wrap(angle: f64) -> f64 {
    let a = angle - TAU * (angle / TAU).round();
    if a <= -PI {
        a + TAU
    } else {
        a
    }
}

/// The mouth as the boundary condition of the plate's faces: the faces are the tops of the rotor
/// cells under the plate, trapezoids of a polar grid (radial edges `ring_edges`, n_θ equal
/// sectors of Δ = 2π/n_θ) at z = `plate_z`, turned by the rotor.
#[derive(Clone, Debug, PartialEq)]
pub struct SuctionWindow {
    pub mouth: EccentricMouth,
    pub plate_z: f64,
    ring_edges: Vec<f64>,
    /// Per ring: the distance of its trapezoid's centroid from the axis (how a face centre
    /// tells its ring).
    ring_centroids: Vec<f64>,
    delta: f64,
    /// Speed normal to the plate through a face wholly over the mouth [m/s].
    speed: f64,
}

impl SuctionWindow {
    /// The window of `mouth` over the plate faces of a rotor grid, carrying `discharge` [m³/s].
    ///
    /// A trapezoid face has area ½ sin Δ (r_b² − r_a²), sin Δ / Δ of its polar cell's, so faces
    /// whose polar cells tile the mouth (every rotor cell under it open, which the mesh
    /// generator checks) have Σ share · area = (sin Δ / Δ) · mouth area at every angle, and
    /// the speed below makes their fluxes sum to `discharge`.
    pub fn new(mouth: EccentricMouth, plate_z: f64, ring_edges: Vec<f64>, n_theta: usize, discharge: f64) -> SuctionWindow {
        let delta = TAU / n_theta as f64;
        let (c, s) = ((0.5 * delta).cos(), (0.5 * delta).sin());
        let ring_centroids = ring_edges
            .windows(2)
            .map(|e| {
                // parallel sides 2 r sin(Δ/2) at distances r cos(Δ/2): the trapezoid's centroid
                let (ha, hb, a, b) = (e[0] * c, e[1] * c, e[0] * s, e[1] * s);
                ha + (hb - ha) * (a + 2.0 * b) / (3.0 * (a + b))
            })
            .collect();
        let speed = discharge / (mouth.area() * delta.sin() / delta);
        SuctionWindow { mouth, plate_z, ring_edges, ring_centroids, delta, speed }
    }

    /// The share of the face centred at `centre` (world frame) that lies over the mouth; 0 off
    /// the plate.
    pub fn share(&self, centre: &Vec3) -> f64 {
        let r = centre.x.hypot(centre.y);
        let ring = self.ring_centroids.iter().enumerate().min_by(|a, b| (a.1 - r).abs().total_cmp(&(b.1 - r).abs())).map(|(i, _)| i).expect("≥ 1 ring");
        let radii = [self.ring_edges[ring], self.ring_edges[ring + 1]];
        if (centre.z - self.plate_z).abs() > 1e-6 * (radii[1] - radii[0]) {
            return 0.0;
        }
        self.mouth.share(radii, centre.y.atan2(centre.x), self.delta)
    }

    /// The velocity of the water at the face centred at `centre`: out of the head through the
    /// plate (+z) in proportion to the face's share of the mouth, at rest elsewhere.
    pub fn velocity(&self, centre: &Vec3) -> Vec3 {
        Vec3::new(0.0, 0.0, self.speed * self.share(centre))
    }

    /// Speed normal to the plate through a face wholly over the mouth [m/s].
    pub fn speed(&self) -> f64 {
        self.speed
    }

    /// Sets the speed of a step ([`balancing_speed`]).
    pub fn set_speed(&mut self, speed: f64) {
        self.speed = speed;
    }
}

/// The mouth's speed for one step: the one that lets the water leave through the mouth what
/// continuity leaves for it, Σ_b α_P φ_b + Σ_c V_c ∂α_c/∂t = 0 over the prescribed-flux faces
/// and the cells (fluid-dem-model.md §2.2: the pressure equation's right-hand side must sum to
/// zero when no boundary fixes the pressure). `unit` is Σ α_P φ_b of the mouth's faces at unit
/// speed, `other` that of every other face less the particles' share of the boundary faces'
/// mesh fluxes (crate::fluid::moving_cells; the interior faces' shares cancel in the sum),
/// `volume_rate` the cells' Σ V ∂α/∂t.
///
/// Without particles this is the nominal speed (the floor's Q_m in, Q_m out) to round-off. With
/// them the mouth also takes the volume particles free or fill: their α lowers the water's
/// share of the flux through the mouth's cells, and a particle sucked through the plate leaves
/// its volume to the water at once. The mixture's discharge through the mouth is thus Q_m on
/// average, not at every step, as at the rotating mouth's fixed-pressure outlet.
pub fn balancing_speed(unit: f64, other: f64, volume_rate: f64) -> Result<f64, String> {
    let speed = -(other + volume_rate) / unit;
    if unit > 0.0 && speed.is_finite() {
        Ok(speed)
    } else {
        Err(format!("the suction mouth's balancing speed is {speed} (its faces carry {unit} m³/s per m/s): no open face under the mouth"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mouth() -> EccentricMouth {
        EccentricMouth { angle: 170f64.to_radians(), half_width: 50f64.to_radians(), radii: [0.08, 0.2] }
    }

    /// The faces of a polar grid turned by `turn`: (centre, area) of each trapezoid on z = 0.
    fn faces(edges: &[f64], n: usize, turn: f64) -> Vec<(Vec3, f64)> {
        let delta = TAU / n as f64;
        let mut out = Vec::new();
        for j in 0..n {
            let (t0, t1) = (turn + j as f64 * delta, turn + (j + 1) as f64 * delta);
            for e in edges.windows(2) {
                let p = [(e[0], t0), (e[1], t0), (e[1], t1), (e[0], t1)].map(|(r, t)| Vec3::new(r * t.cos(), r * t.sin(), 0.0));
                // centroid and area of the quadrilateral from its two triangles
                let (a1, a2) = ((p[1] - p[0]).cross(&(p[2] - p[0])).z * 0.5, (p[2] - p[0]).cross(&(p[3] - p[0])).z * 0.5);
                let centre = ((p[0] + p[1] + p[2]) * a1 + (p[0] + p[2] + p[3]) * a2) / (3.0 * (a1 + a2));
                out.push((centre, a1 + a2));
            }
        }
        out
    }

    #[test]
    fn the_faces_carry_the_discharge_at_every_rotor_angle() {
        let edges: Vec<f64> = (0..8).map(|i| 0.06 + 0.03 * i as f64).collect();
        let n = 40;
        let window = SuctionWindow::new(mouth(), 0.0, edges.clone(), n, 0.12);
        for turn in [0.0, 0.013, 0.5, 1.7, 3.1, 5.9] {
            let flux: f64 = faces(&edges, n, turn).iter().map(|(c, a)| window.velocity(c).z * a).sum();
            // round-off of a few hundred shares and areas
            assert!((flux - 0.12).abs() < 1e-13, "turn {turn}: Σ u·S = {flux}");
        }
    }

    #[test]
    fn a_face_knows_its_share_of_the_mouth() {
        let edges = vec![0.06, 0.1, 0.14, 0.18, 0.22];
        let n = 36;
        let window = SuctionWindow::new(mouth(), 0.0, edges.clone(), n, 0.12);
        let delta = TAU / n as f64;
        for (centre, _) in faces(&edges, n, 0.02) {
            let r = centre.x.hypot(centre.y);
            let i = edges.windows(2).position(|e| r > e[0] * (0.5 * delta).cos() && r < e[1]).unwrap();
            let expected = mouth().share([edges[i], edges[i + 1]], centre.y.atan2(centre.x), delta);
            assert_eq!(window.share(&centre), expected);
            // by sampling the polar cell
            let theta = centre.y.atan2(centre.x);
            let m = 200;
            let mut inside = 0.0;
            let mut total = 0.0;
            for a in 0..m {
                let rr = edges[i] + (edges[i + 1] - edges[i]) * (a as f64 + 0.5) / m as f64;
                for b in 0..m {
                    let t = theta - 0.5 * delta + delta * (b as f64 + 0.5) / m as f64;
                    total += rr;
                    if mouth().contains(rr * t.cos(), rr * t.sin()) {
                        inside += rr;
                    }
                }
            }
            // midpoint sampling of a cell with two straight cuts: error ~ 1/m
            assert!((inside / total - expected).abs() < 1.5 / m as f64, "sampled {} vs {expected}", inside / total);
        }
        assert_eq!(window.share(&Vec3::new(-0.12, 0.01, 0.05)), 0.0, "off the plate");
        assert_eq!(window.share(&Vec3::new(0.12, 0.0, 0.0)), 0.0, "on the plate, away from the mouth");
    }

    #[test]
    fn the_mouth_wraps_through_the_negative_axis() {
        let m = mouth();
        assert!(m.contains(-0.15, 0.0));
        assert!(m.contains(-0.15 * 0.9f64.cos(), -0.15 * 0.9f64.sin()) == (wrap(PI + 0.9 - m.angle).abs() < m.half_width));
        assert!(!m.contains(0.15, 0.0));
        assert!((m.area() - 50f64.to_radians() * (0.04 - 0.0064)).abs() < 1e-15);
    }
}
