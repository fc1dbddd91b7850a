//! The cutter head's shape in its body frame: contour R(z), blade angle φ(z), helical blades,
//! ring or back plate, hub, suction pipe (spillage-and-flow-verification.md §2.3, §2.8, §2.11).
//!
//! One description serves both consumers: the fluid mesh asks which cells a solid touches
//! ([`CutterHead::touches_solid`]), the DEM gets the same solids as triangle meshes
//! (`super::walls`), and the spillage bookkeeping asks whether a point is inside the contour
//! hull ([`CutterHead::inside_hull`]).
//!
//! A blade's cross-section at height z is a logarithmic spiral, which makes the same angle
//! φ(z) with every circle it crosses (the angle of §2.3 at the outer edge, where the analytical
//! model reads it): θ_k(r, z) = θ_k + τ(z) ± ln(R(z)/r) / tan φ(z), with τ(z) the helical
//! twist, linear from 0 at the ring to `blade_twist` at the hub. With `blade_sweep =
//! "backward"` (the default, + above) the inner part of a blade leads its outer edge in the direction of
//! rotation (a backward-swept impeller); with `"forward"` (−) it trails (the outer edge leads, as
//! a cutter's teeth do). Its thickness t is measured normal to the blade, so along a circle it
//! spans t / sin φ.

use std::f64::consts::TAU;

use super::mouth::EccentricMouth;
use super::settings::{BladeSweep, CutterHeadSection};

/// The solid parts, named in errors and outputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    Blade(usize),
    Ring,
    Hub,
    Pipe,
    /// The stationary back plate and the pipe housing above it (an eccentric mouth's head).
    BackPlate,
}

/// The validated geometry of `[cutter_head]`, SI units and radians.
#[derive(Clone, Debug)]
pub struct CutterHead {
    /// Contour points (s, R, φ), s from the ring toward the hub.
    contour: Vec<(f64, f64, f64)>,
    pub blades: usize,
    pub blade_thickness: f64,
    pub blade_depth: f64,
    /// τ at the hub [rad].
    pub blade_twist: f64,
    pub blade_sweep: BladeSweep,
    /// The inner radius of the ring (axial suction) or of the mouth in the back plate.
    pub opening_radius: f64,
    pub ring_thickness: f64,
    pub hub_thickness: f64,
    /// Outer radius of the hub plate (R(H) unless the case makes it smaller).
    pub hub_radius: f64,
    pub shaft_radius: f64,
    pub pipe_length: f64,
    pub pipe_wall: f64,
    pub capture_height: f64,
    pub suction_discharge: f64,
    /// The eccentric, stationary mouth in a back plate at rest, if the head has one.
    pub mouth: Option<EccentricMouth>,
}

fn overlaps(a0: f64, a1: f64, b0: f64, b1: f64) -> bool {
    a0 < b1 && b0 < a1
}

impl CutterHead {
    /// From a validated section.
    pub fn new(section: &CutterHeadSection) -> CutterHead {
        CutterHead {
            contour: section.contour.iter().map(|p| (p[0], p[1], p[2].to_radians())).collect(),
            blades: section.blades,
            blade_thickness: section.blade_thickness,
            blade_depth: section.blade_depth,
            blade_twist: section.blade_twist.to_radians(),
            blade_sweep: section.blade_sweep,
            opening_radius: section.opening_radius(),
            ring_thickness: section.ring_thickness,
            hub_thickness: section.hub_thickness,
            hub_radius: section.hub_radius.unwrap_or(section.contour.last().expect("≥ 2 points")[1]),
            shaft_radius: section.shaft_radius,
            pipe_length: section.pipe_length,
            pipe_wall: section.pipe_wall,
            capture_height: section.capture_height,
            suction_discharge: section.suction_discharge,
            mouth: section.eccentric_mouth(),
        }
    }

    /// H, ring to hub [m].
    pub fn height(&self) -> f64 {
        self.contour.last().expect("≥ 2 points").0
    }

    /// The contour points (s, R, φ [rad]).
    pub fn contour(&self) -> &[(f64, f64, f64)] {
        &self.contour
    }

    /// (R, φ) at axial distance s from the ring (clamped to [0, H]), linear between points.
    fn at(&self, s: f64) -> (f64, f64) {
        let s = s.clamp(0.0, self.height());
        let i = self.contour.partition_point(|p| p.0 <= s).clamp(1, self.contour.len() - 1);
        let (a, b) = (self.contour[i - 1], self.contour[i]);
        let t = (s - a.0) / (b.0 - a.0);
        (a.1 + t * (b.1 - a.1), a.2 + t * (b.2 - a.2))
    }

    /// Contour radius R at height z (z = 0 at the ring, −H at the hub).
    pub fn radius_at(&self, z: f64) -> f64 {
        self.at(-z).0
    }

    /// Blade angle φ at height z [rad].
    pub fn blade_angle_at(&self, z: f64) -> f64 {
        self.at(-z).1
    }

    /// Top of the ring (or back plate) [m].
    pub fn ring_top(&self) -> f64 {
        self.ring_thickness
    }

    /// Top of the domain: the end of the suction pipe [m].
    pub fn pipe_top(&self) -> f64 {
        self.ring_thickness + self.pipe_length
    }

    /// Bottom of the hub plate [m].
    pub fn hub_bottom(&self) -> f64 {
        -self.height() - self.hub_thickness
    }

    /// Innermost radius of the blades at height z.
    pub fn blade_inner_radius(&self, z: f64) -> f64 {
        (self.radius_at(z) - self.blade_depth).max(self.shaft_radius)
    }

    /// Azimuth of blade `k`'s centre surface at radius r and height z (body frame, radians,
    /// not wrapped), leaning as `blade_sweep` says.
    pub fn blade_azimuth(&self, k: usize, r: f64, z: f64) -> f64 {
        let (radius, phi) = self.at(-z);
        let inner_part_lead_sign = match self.blade_sweep {
            BladeSweep::Backward => 1.0,
            BladeSweep::Forward => -1.0,
        };
        TAU * k as f64 / self.blades as f64 + self.blade_twist * (-z / self.height()) + inner_part_lead_sign * (radius / r).ln() / phi.tan()
    }

    /// Half the angular width of a blade at radius r and height z (thickness t normal to the
    /// blade spans t / sin φ along the circle).
    pub fn blade_half_angle(&self, r: f64, z: f64) -> f64 {
        0.5 * self.blade_thickness / (r * self.blade_angle_at(z).sin())
    }

    /// The axisymmetric plates: (part, r range, z range). With an eccentric mouth the third is
    /// the stationary back plate, solid from the shaft to the ring and from the ring's
    /// underside to the domain's top (the mouth is a boundary condition on its underside).
    pub fn plates(&self) -> [(Part, [f64; 2], [f64; 2]); 3] {
        let h = self.height();
        let above_ring = match self.mouth {
            None => (Part::Pipe, [self.opening_radius, self.opening_radius + self.pipe_wall], [self.ring_top(), self.pipe_top()]),
            Some(_) => (Part::BackPlate, [self.shaft_radius, self.opening_radius], [0.0, self.pipe_top()]),
        };
        [
            (Part::Hub, [self.shaft_radius, self.hub_radius], [self.hub_bottom(), -h]),
            (Part::Ring, [self.opening_radius, self.radius_at(0.0)], [0.0, self.ring_top()]),
            above_ring,
        ]
    }

    /// The plate a cylindrical cell r ∈ [r0, r1], z ∈ [z0, z1] overlaps, if any (at every θ: the
    /// plates are axisymmetric).
    pub fn touches_plate(&self, r: [f64; 2], z: [f64; 2]) -> Option<Part> {
        self.plates().into_iter().find(|(_, pr, pz)| overlaps(r[0], r[1], pr[0], pr[1]) && overlaps(z[0], z[1], pz[0], pz[1])).map(|(part, _, _)| part)
    }

    /// The blade whose centre surface separates two body-frame points a and b (cylindrical
    /// [r, θ, z]), if any: its azimuth offset θ − θ_blade(r, z) changes sign between them (not
    /// across the half-turn away from the blade) and the crossing, interpolated linearly in that
    /// offset, lies within the blade's extent (between the hub and the ring, from the blade's
    /// inner edge to the contour R(z)). For two neighbouring cell centres this makes their
    /// common face the blade's wall: every face path between the blade's two sides crosses one.
    pub fn blade_between(&self, a: [f64; 3], b: [f64; 3]) -> Option<usize> {
        let wrap = |angle: f64| angle - TAU * (angle / TAU).round();
        (0..self.blades).find(|&k| {
            let (da, db) = (wrap(a[1] - self.blade_azimuth(k, a[0], a[2])), wrap(b[1] - self.blade_azimuth(k, b[0], b[2])));
            if (da < 0.0) == (db < 0.0) || (da - db).abs() >= std::f64::consts::PI {
                return false;
            }
            let t = da / (da - db);
            let (r, z) = (a[0] + t * (b[0] - a[0]), a[2] + t * (b[2] - a[2]));
            z >= -self.height() && z <= 0.0 && r >= self.blade_inner_radius(z) && r <= self.radius_at(z)
        })
    }

    /// Heights in [z0, z1] where the blade's extent can be extreme: the ends and the contour
    /// points in between (R and φ are linear between them).
    fn blade_heights(&self, z0: f64, z1: f64) -> Vec<f64> {
        let mut zs = vec![z0, z1];
        zs.extend(self.contour.iter().map(|p| -p.0).filter(|&z| z > z0 && z < z1));
        zs
    }

    /// The solid a cylindrical cell r ∈ [r0, r1], θ ∈ [θ0, θ1] (body frame), z ∈ [z0, z1]
    /// overlaps, if any. Conservative: a solid thinner than a cell still takes the whole cell,
    /// so blades and plates stay watertight on any mesh (a staircase that converges to the
    /// true shape as the cells shrink).
    pub fn touches_solid(&self, r: [f64; 2], theta: [f64; 2], z: [f64; 2]) -> Option<Part> {
        if let Some(part) = self.touches_plate(r, z) {
            return Some(part);
        }
        let h = self.height();
        let (z0, z1) = (z[0].max(-h), z[1].min(0.0));
        if z0 >= z1 {
            return None;
        }
        let heights = self.blade_heights(z0, z1);
        let reaches = heights.iter().any(|&zz| overlaps(r[0], r[1], self.blade_inner_radius(zz), self.radius_at(zz)));
        if !reaches {
            return None;
        }
        for k in 0..self.blades {
            // the azimuths the blade takes over the cell's corners (monotone in r; in z between
            // the sampled heights)
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for &zz in &heights {
                let (rin, rout) = (r[0].max(self.blade_inner_radius(zz)), r[1].min(self.radius_at(zz)));
                if rin > rout {
                    continue;
                }
                for rr in [rin, rout] {
                    let a = self.blade_azimuth(k, rr, zz);
                    let w = self.blade_half_angle(rr, zz);
                    lo = lo.min(a - w);
                    hi = hi.max(a + w);
                }
            }
            if lo > hi {
                continue;
            }
            // shift the cell's θ interval next to the blade's and test both neighbours of the wrap
            let shift = TAU * ((lo - theta[0]) / TAU).floor();
            for s in [shift, shift + TAU] {
                if overlaps(theta[0] + s, theta[1] + s, lo, hi) {
                    return Some(Part::Blade(k));
                }
            }
        }
        None
    }

    /// Whether a body-frame point is inside the contour hull: between the hub and the ring and
    /// within R(z) of the axis (the surface Eq. 8.1–8.4 and Eq. 8.6 refer to).
    pub fn inside_hull(&self, r: f64, z: f64) -> bool {
        z >= -self.height() && z <= 0.0 && r < self.radius_at(z)
    }

    /// Whether a point is in the suction pipe, `capture_height` above its entrance; with an
    /// eccentric mouth, through the back plate (only the mouth lets a particle there).
    pub fn sucked(&self, r: f64, z: f64) -> bool {
        match self.mouth {
            None => r < self.opening_radius && z >= self.ring_top() + self.capture_height,
            Some(_) => r < self.opening_radius && z > 0.0,
        }
    }

    /// Whether a sphere of radius `a` centred at body-frame cylindrical (r, θ, z) is clear of
    /// every solid (used to place particles): the sphere's bounding cylindrical box touches no
    /// solid.
    pub fn sphere_is_clear(&self, r: f64, theta: f64, z: f64, a: f64) -> bool {
        if r - a <= self.shaft_radius {
            return false;
        }
        let half = (a / (r - a)).min(std::f64::consts::PI);
        self.touches_solid([r - a, r + a], [theta - half, theta + half], [z - a, z + a]).is_none()
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    pub(crate) fn head() -> CutterHead {
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../cases/cutter_head.toml")).unwrap();
        let case = crate::case::Case::from_toml(&text, std::path::Path::new("cutter_head.toml")).unwrap();
        CutterHead::new(case.cutter_head.as_ref().unwrap())
    }

    #[test]
    fn the_blade_makes_the_angle_phi_with_every_circle_it_crosses() {
        let head = head();
        for &(z, k) in &[(-0.1, 0), (-0.3, 3), (-0.4, 5)] {
            let phi = head.blade_angle_at(z);
            let r = head.radius_at(z) - 0.5 * head.blade_depth;
            let dr = 1e-5;
            // tan of the angle between the curve and the circle: dr / (r dθ), by a central
            // difference (truncation (dr/r)² ~ 1e-8)
            let dtheta = head.blade_azimuth(k, r + dr, z) - head.blade_azimuth(k, r - dr, z);
            let angle = (2.0 * dr / (r * dtheta.abs())).atan();
            assert!((angle - phi).abs() < 1e-7, "z = {z}: {angle} vs {phi}");
        }
    }

    #[test]
    fn a_forward_swept_blade_leads_with_its_outer_edge_at_the_same_angle_phi() {
        let backward = head();
        let mut forward = head();
        forward.blade_sweep = BladeSweep::Forward;
        for &(z, k) in &[(-0.1, 0), (-0.3, 3)] {
            let (outer, inner) = (backward.radius_at(z), backward.radius_at(z) - backward.blade_depth);
            // the outer edges coincide; the inner part lies ahead (backward sweep) or behind
            // (forward sweep) it by the same angle ln(R/r)/tan φ, to a few ulp of the ~4 rad
            // azimuths subtracted
            assert_eq!(forward.blade_azimuth(k, outer, z), backward.blade_azimuth(k, outer, z));
            let lead = |h: &CutterHead| h.blade_azimuth(k, inner, z) - h.blade_azimuth(k, outer, z);
            let expected = (outer / inner).ln() / backward.blade_angle_at(z).tan();
            assert!((lead(&backward) - expected).abs() < 1e-14 && (lead(&forward) + expected).abs() < 1e-14, "z = {z}");
            let r = outer - 0.5 * forward.blade_depth;
            let dr = 1e-5;
            // the angle to the circle by a central difference, as above (truncation (dr/r)² ~ 1e-8)
            let dtheta = forward.blade_azimuth(k, r + dr, z) - forward.blade_azimuth(k, r - dr, z);
            assert!(((2.0 * dr / (r * dtheta.abs())).atan() - forward.blade_angle_at(z)).abs() < 1e-7);
            // the solid follows the surface
            let a = forward.blade_azimuth(k, r, z);
            let cell = |t: f64| forward.touches_solid([r - 0.005, r + 0.005], [t - 0.01, t + 0.01], [z - 0.005, z + 0.005]);
            assert_eq!(cell(a), Some(Part::Blade(k)));
        }
    }

    #[test]
    fn a_cell_on_the_blade_touches_it_and_one_between_blades_does_not() {
        let head = head();
        let (z, r) = (-0.2, 0.3);
        let a = head.blade_azimuth(2, r, z);
        let cell = |t: f64| head.touches_solid([r - 0.005, r + 0.005], [t - 0.01, t + 0.01], [z - 0.005, z + 0.005]);
        assert_eq!(cell(a), Some(Part::Blade(2)));
        assert_eq!(cell(a + TAU), Some(Part::Blade(2)), "the azimuth wraps");
        assert_eq!(cell(a + 0.5 * TAU / head.blades as f64), None);
        // outside the contour and below the hub plate nothing is solid
        assert_eq!(head.touches_solid([0.5, 0.51], [0.0, 0.1], [-0.2, -0.19]), None);
        assert_eq!(head.touches_solid([0.1, 0.11], [0.0, 0.1], [head.hub_bottom() - 0.1, head.hub_bottom() - 0.05]), None);
        assert_eq!(head.touches_solid([0.1, 0.11], [0.0, 0.1], [head.hub_bottom() + 0.001, head.hub_bottom() + 0.002]), Some(Part::Hub));
    }

    #[test]
    fn a_small_hub_leaves_the_bottom_open_between_the_hub_and_the_contour() {
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../cases/cutter_head.toml")).unwrap();
        let bad = text.replace("hub_thickness = 0.03", "hub_thickness = 0.03\nhub_radius = 0.3");
        let error = crate::case::Case::from_toml(&bad, std::path::Path::new("cutter_head.toml")).unwrap_err().to_string();
        assert!(error.contains("cutter_head.hub_radius") && error.contains("0.3") && error.contains("R(H) = 0.25"), "{error}");
        let open = text.replace("hub_thickness = 0.03", "hub_thickness = 0.03\nhub_radius = 0.13");
        let case = crate::case::Case::from_toml(&open, std::path::Path::new("cutter_head.toml")).unwrap();
        let (closed, open) = (head(), CutterHead::new(case.cutter_head.as_ref().unwrap()));
        let plate = |head: &CutterHead, r: f64| head.touches_solid([r, r + 0.005], [1.0, 1.01], [head.hub_bottom() + 0.001, head.hub_bottom() + 0.002]);
        assert_eq!((plate(&closed, 0.1), plate(&closed, 0.2)), (Some(Part::Hub), Some(Part::Hub)));
        assert_eq!((plate(&open, 0.1), plate(&open, 0.2)), (Some(Part::Hub), None));
        // a rock that falls through the opening has left the hull
        assert!(open.inside_hull(0.2, -open.height() + 0.01) && !open.inside_hull(0.2, -open.height() - 0.01));
    }

    #[test]
    fn blade_between_finds_the_blade_two_points_straddle() {
        let head = head();
        let (r, z) = (0.32, -0.2);
        for k in 0..head.blades {
            let theta = head.blade_azimuth(k, r, z);
            let point = |dtheta: f64, r: f64| [r, theta + dtheta, z];
            assert_eq!(head.blade_between(point(-0.05, r), point(0.05, r)), Some(k));
            // the same offsets a turn apart (cell centres are in [0, 2π))
            assert_eq!(head.blade_between(point(-0.05 + TAU, r), point(0.05, r)), Some(k));
            assert_eq!(head.blade_between(point(0.05, r), point(0.1, r)), None, "one side");
            // beyond the contour R(z) (the tip) and inside the blade's inner edge: no blade
            let tip = head.radius_at(z) + 0.01;
            let (a, b) = ([tip, head.blade_azimuth(k, tip, z) - 0.05, z], [tip, head.blade_azimuth(k, tip, z) + 0.05, z]);
            assert_eq!(head.blade_between(a, b), None, "past the tip");
            let edge = head.blade_inner_radius(z) - 0.01;
            let (a, b) = ([edge, head.blade_azimuth(k, edge, z) - 0.05, z], [edge, head.blade_azimuth(k, edge, z) + 0.05, z]);
            assert_eq!(head.blade_between(a, b), None, "inside the inner edge");
        }
        // halfway between two blades: no blade
        let mid = head.blade_azimuth(0, r, z) + std::f64::consts::PI / head.blades as f64;
        assert_eq!(head.blade_between([r, mid - 0.01, z], [r, mid + 0.01, z]), None);
    }

    #[test]
    fn the_hull_follows_the_contour() {
        let head = head();
        let h = head.height();
        assert!(head.inside_hull(0.9 * head.radius_at(-0.1), -0.1));
        assert!(!head.inside_hull(1.01 * head.radius_at(-0.1), -0.1));
        assert!(!head.inside_hull(0.1, 0.01), "above the ring");
        assert!(!head.inside_hull(0.1, -h - 0.01), "below the hub");
    }
}
