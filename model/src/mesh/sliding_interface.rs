//! Geometry of a cylindrical sliding interface between a rotor and a stator zone, and the
//! conservative area-weighted face mapping across it (spec fluid-dem-model.md §4.2, T3.33–T3.36;
//! spillage-and-flow-verification.md §3.6).
//!
//! Both sides share the z layers, so the overlap of a rotor face and a stator face in one layer
//! is a 1-D overlap of their θ intervals; area fractions equal angle fractions. The two sides
//! are polygons with different numbers of chord faces inscribed in one circle, so they are not
//! geometrically identical surfaces (as with OpenFOAM's AMI on a curved interface); the mapping
//! is defined on θ, where both sides cover exactly 2π.

use super::{MeshError, Vec3};
use std::f64::consts::TAU;

/// A cylindrical sliding interface about the z axis.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SlidingInterface {
    pub name: String,
    /// Zone whose cells rotate (index into `Mesh::zones`).
    pub rotor_zone: usize,
    pub stator_zone: usize,
    /// Radius of the circle the face vertices lie on.
    pub radius: f64,
    /// Edges of the shared z layers (`n_layers + 1` values, ascending).
    pub z_edges: Vec<f64>,
    pub n_theta_rotor: usize,
    pub n_theta_stator: usize,
    /// θ edges of the rotor faces at rotor angle 0 (`n_theta_rotor + 1` values, the last
    /// 2π beyond the first).
    pub rotor_theta_edges: Vec<f64>,
    /// θ edges of the stator faces (`n_theta_stator + 1` values, the last 2π beyond the first).
    pub stator_theta_edges: Vec<f64>,
    /// Mesh faces of the rotor side, `rotor_faces[layer * n_theta_rotor + j]` for θ index j.
    pub rotor_faces: Vec<usize>,
    /// Mesh faces of the stator side, `stator_faces[layer * n_theta_stator + j]`.
    pub stator_faces: Vec<usize>,
}

/// One rotor face / stator face pair that overlap.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Overlap {
    /// Mesh face on the rotor side.
    pub rotor_face: usize,
    /// Mesh face on the stator side.
    pub stator_face: usize,
    /// Overlap / rotor face width: weight of the stator value in the rotor face value.
    pub rotor_fraction: f64,
    /// Overlap / stator face width: weight of the rotor value in the stator face value.
    pub stator_fraction: f64,
    /// Shared z layer of the two faces (index into the layers of `z_edges`).
    pub layer: usize,
    /// θ bounds of the overlap (rad, in the stator's frame: the rotor's edges turned by the
    /// rotor angle), `theta_lo < theta_hi`; they may lie up to 2π beyond the stator's first edge
    /// (the sweep runs from the turned rotor's first edge around once).
    pub theta_lo: f64,
    pub theta_hi: f64,
}

/// Overlap of source interval `source` and target interval `target` of a 1-D interface.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Overlap1d {
    pub source: usize,
    pub target: usize,
    /// Overlap length |A_s ∩ A_t|.
    pub length: f64,
    /// m^(st) = |A_s ∩ A_t| / |A_s| (reverse map weight).
    pub source_fraction: f64,
    /// m_ts = |A_s ∩ A_t| / |A_t| (T3.36).
    pub target_fraction: f64,
}

fn check_edges(name: &str, edges: &[f64]) -> Result<(), MeshError> {
    if edges.len() < 2 {
        return Err(MeshError::input(name, format!("{edges:?}"), "need at least 2 edges"));
    }
    if !edges.iter().all(|e| e.is_finite()) || edges.windows(2).any(|w| w[1] <= w[0]) {
        return Err(MeshError::input(name, format!("{edges:?}"), "edges must be finite and strictly increasing"));
    }
    Ok(())
}

/// Overlaps of two partitions of one interval by a merge sweep (O(n_s + n_t)).
///
/// Both edge lists must be strictly increasing with the same first and last value (to 1e-12 of
/// the span, the round-off of edges built by summation).
pub fn overlap_1d(source_edges: &[f64], target_edges: &[f64]) -> Result<Vec<Overlap1d>, MeshError> {
    check_edges("source_edges", source_edges)?;
    check_edges("target_edges", target_edges)?;
    let (n_s, n_t) = (source_edges.len() - 1, target_edges.len() - 1);
    let span = source_edges[n_s] - source_edges[0];
    let tolerance = 1e-12 * span;
    if (source_edges[0] - target_edges[0]).abs() > tolerance || (source_edges[n_s] - target_edges[n_t]).abs() > tolerance {
        return Err(MeshError::input(
            "target_edges",
            format!("[{}, {}]", target_edges[0], target_edges[n_t]),
            &format!("must span the source interval [{}, {}]", source_edges[0], source_edges[n_s]),
        ));
    }
    let mut overlaps = Vec::with_capacity(n_s + n_t);
    let (mut i, mut j) = (0, 0);
    let mut current = source_edges[0].max(target_edges[0]);
    while i < n_s && j < n_t {
        let (source_end, target_end) = (source_edges[i + 1], target_edges[j + 1]);
        let end = source_end.min(target_end);
        let length = end - current;
        if length > 0.0 {
            overlaps.push(Overlap1d {
                source: i,
                target: j,
                length,
                source_fraction: length / (source_end - source_edges[i]),
                target_fraction: length / (target_end - target_edges[j]),
            });
        }
        current = current.max(end);
        if source_end <= target_end {
            i += 1;
        }
        if target_end <= source_end {
            j += 1;
        }
    }
    Ok(overlaps)
}

/// Target face values from source face values, q_t^j = Σ_i m_ji q_s^i (T3.33).
pub fn map_to_target(overlaps: &[Overlap1d], source_values: &[f64], n_target: usize) -> Vec<f64> {
    let mut target = vec![0.0; n_target];
    for o in overlaps {
        target[o.target] += o.target_fraction * source_values[o.source];
    }
    target
}

/// Source face values from target face values with the reverse weights |A_s ∩ A_t|/|A_s|.
pub fn map_to_source(overlaps: &[Overlap1d], target_values: &[f64], n_source: usize) -> Vec<f64> {
    let mut source = vec![0.0; n_source];
    for o in overlaps {
        source[o.source] += o.source_fraction * target_values[o.target];
    }
    source
}

/// Merge sweep of two periodic partitions of the circle, the rotor one turned by `angle`.
/// Calls `emit(rotor index, stator index, rotor_fraction, stator_fraction, θ_lo, θ_hi)` for
/// every overlap of positive length, in order of increasing θ starting at the rotor's first edge.
fn periodic_sweep(rotor_edges: &[f64], stator_edges: &[f64], angle: f64, mut emit: impl FnMut(usize, usize, f64, f64, f64, f64)) {
    let (n_r, n_s) = (rotor_edges.len() - 1, stator_edges.len() - 1);
    // Reduce the angle so values stay within a few 2π (their round-off bounds the error).
    let shift = angle.rem_euclid(TAU);
    let rotor = |i: usize| rotor_edges[i] + shift;
    // Stator edges unrolled over the real line: edge m lies in turn m div n_s.
    let stator = |m: i64| {
        let n = n_s as i64;
        stator_edges[m.rem_euclid(n) as usize] + TAU * m.div_euclid(n) as f64
    };
    let start = rotor(0);
    let mut m = ((start - stator_edges[0]) / TAU).floor() as i64 * n_s as i64;
    while stator(m) > start {
        m -= 1;
    }
    while stator(m + 1) <= start {
        m += 1;
    }
    let mut i = 0;
    let mut current = start;
    loop {
        let (rotor_end, stator_end) = (rotor(i + 1), stator(m + 1));
        let end = rotor_end.min(stator_end);
        let length = end - current;
        if length > 0.0 {
            let rotor_width = rotor_end - rotor(i);
            let stator_width = stator_end - stator(m);
            let j = m.rem_euclid(n_s as i64) as usize;
            emit(i, j, length / rotor_width, length / stator_width, current, end);
        }
        current = current.max(end);
        if stator_end <= rotor_end {
            m += 1;
        }
        if rotor_end <= stator_end {
            i += 1;
            if i == n_r {
                break;
            }
        }
    }
}

/// Cylindrical frame of a sliding interface about `axis` through `origin`: θ is measured from
/// `e1` towards `e2 = axis × e1` [R, our construction; spec fluid-dem-model.md §4.1 only fixes
/// the axis]. Both solvers build their overlap links with it ([`InterfaceFrame::overlap_link`]),
/// so the geometry they discretise is one definition.
#[derive(Clone, Debug)]
pub struct InterfaceFrame {
    pub origin: Vec3,
    /// Unit rotation axis.
    pub axis: Vec3,
    pub e1: Vec3,
    pub e2: Vec3,
}

/// Geometry of the link of one rotor/stator overlap (owner = rotor cell, neighbour = stator
/// cell), the quantities the finite-volume schemes need (spec fluid-dem-model.md §4.2, §8.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverlapLinkGeometry {
    /// Area vector S of the overlap, out of the rotor cell: the chord of the *true* circle
    /// between the overlap's θ bounds times its axial extent.
    pub area: Vec3,
    /// Centre x_f of the overlap: the chord midpoint at the mid z.
    pub centre: Vec3,
    /// d = x_N − x_P, rotor cell centre to stator cell centre.
    pub delta: Vec3,
    /// Owner weight w = d_N/(d_P + d_N) of linear interpolation, from the normal distances of
    /// the two centres to the overlap plane.
    pub weight: f64,
    /// Skewness vector k = x_f − (w x_P + (1 − w) x_N): from the point on the line P–N where
    /// linear interpolation gives its value (it lies in the overlap plane) to the overlap centre.
    pub skew: Vec3,
}

impl InterfaceFrame {
    pub fn new(origin: Vec3, axis: Vec3) -> InterfaceFrame {
        let axis = axis.normalize();
        let trial = if axis.x.abs() < 0.9 { Vec3::x() } else { Vec3::y() };
        let e1 = (trial - axis * trial.dot(&axis)).normalize();
        let e2 = axis.cross(&e1);
        InterfaceFrame { origin, axis, e1, e2 }
    }

    /// (θ in (−π, π], axial coordinate, distance from the axis) of point `p`.
    pub fn theta_z_r(&self, p: &Vec3) -> (f64, f64, f64) {
        let rel = p - self.origin;
        let z = rel.dot(&self.axis);
        let (a, b) = (rel.dot(&self.e1), rel.dot(&self.e2));
        (b.atan2(a), z, (a * a + b * b).sqrt())
    }

    /// Point at angle `theta` on the circle of `radius` in the plane through `origin`.
    pub fn circle_point(&self, radius: f64, theta: f64) -> Vec3 {
        self.origin + (self.e1 * theta.cos() + self.e2 * theta.sin()) * radius
    }

    /// Link geometry of the overlap [θ_lo, θ_hi] × [z_lo, z_hi] of a rotor face (area vector
    /// `rotor_face_area`, out of its cell whose centre is `rotor_centre`) and a stator face of
    /// the cell centred at `stator_centre`, on the interface circle of `radius`.
    ///
    /// [R, our construction] (spec fluid-dem-model.md §4.2 gives only the area weights
    /// T3.33–T3.36): the area is the chord of the true circle between θ_lo and θ_hi, so the
    /// overlaps of a face telescope to the face's own chord and both cells stay closed (free-
    /// stream preservation, a rigid rotation sweeps no volume); the centre is the chord midpoint.
    /// The rotor and stator cell centres are not on one ray, so d is not parallel to S: the
    /// schemes split S over d (over-relaxed, |S|²/(d·S)) with an explicit non-orthogonal
    /// remainder, and linear interpolation with weight w gives the value at the point
    /// x_f − `skew` on the line P–N, O(h) beside the overlap centre along the interface; the
    /// solvers add (k·∇)φ_f where that first-order error would otherwise enter (issue 12).
    #[allow(clippy::too_many_arguments)]
    pub fn overlap_link(
        &self,
        radius: f64,
        theta_lo: f64,
        theta_hi: f64,
        z_lo: f64,
        z_hi: f64,
        rotor_face_area: &Vec3,
        rotor_centre: &Vec3,
        stator_centre: &Vec3,
    ) -> OverlapLinkGeometry {
        let a = self.circle_point(radius, theta_lo);
        let b = self.circle_point(radius, theta_hi);
        let mut area = (b - a).cross(&self.axis) * (z_hi - z_lo);
        if area.dot(rotor_face_area) < 0.0 {
            area = -area; // out of the rotor cell
        }
        let centre = (a + b) * 0.5 + self.axis * (0.5 * (z_lo + z_hi));
        let (xp, xn) = (rotor_centre, stator_centre);
        let n = area.normalize();
        let dp = (centre - xp).dot(&n).abs();
        let dn = (xn - centre).dot(&n).abs();
        let weight = dn / (dp + dn);
        let skew = centre - (xp * weight + xn * (1.0 - weight));
        OverlapLinkGeometry { area, centre, delta: xn - xp, weight, skew }
    }
}

impl SlidingInterface {
    pub fn n_layers(&self) -> usize {
        self.z_edges.len() - 1
    }

    /// Overlapping rotor/stator face pairs with the rotor turned by `rotor_angle` (rad,
    /// counter-clockwise about +z, any value: it is reduced modulo 2π).
    pub fn overlaps(&self, rotor_angle: f64) -> Vec<Overlap> {
        let mut out = Vec::new();
        self.overlaps_into(rotor_angle, &mut out);
        out
    }

    /// As [`Self::overlaps`], reusing `out` (cleared first; no allocation once it is large
    /// enough, at most `n_layers · (n_theta_rotor + n_theta_stator + 1)` entries). Ordered by
    /// layer, then by θ from the rotor's first edge.
    pub fn overlaps_into(&self, rotor_angle: f64, out: &mut Vec<Overlap>) {
        out.clear();
        for layer in 0..self.n_layers() {
            let rotor_faces = &self.rotor_faces[layer * self.n_theta_rotor..][..self.n_theta_rotor];
            let stator_faces = &self.stator_faces[layer * self.n_theta_stator..][..self.n_theta_stator];
            periodic_sweep(&self.rotor_theta_edges, &self.stator_theta_edges, rotor_angle, |i, j, rotor_fraction, stator_fraction, theta_lo, theta_hi| {
                out.push(Overlap { rotor_face: rotor_faces[i], stator_face: stator_faces[j], rotor_fraction, stator_fraction, layer, theta_lo, theta_hi })
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Spec fluid-dem-model.md §4.2 worked example; the thesis misprints q_t^3 = 8, its own
    /// weights give 7 (erratum, spillage-and-flow-verification.md §3.6).
    #[test]
    fn spec_worked_example_three_to_four_faces() {
        let source = [0.0, 2.0 / 3.0, 4.0 / 3.0, 2.0];
        let target = [0.0, 0.5, 1.0, 1.5, 2.0];
        let overlaps = overlap_1d(&source, &target).unwrap();
        let weights: Vec<(usize, usize, f64)> = overlaps.iter().map(|o| (o.target, o.source, o.target_fraction)).collect();
        let expected = [(0, 0, 1.0), (1, 0, 1.0 / 3.0), (1, 1, 2.0 / 3.0), (2, 1, 2.0 / 3.0), (2, 2, 1.0 / 3.0), (3, 2, 1.0)];
        assert_eq!(weights.len(), expected.len());
        for (got, want) in weights.iter().zip(&expected) {
            assert_eq!((got.0, got.1), (want.0, want.1));
            // Edges 2/3, 4/3 carry one rounding each.
            assert!((got.2 - want.2).abs() < 1e-15, "{got:?} vs {want:?}");
        }
        let q_t = map_to_target(&overlaps, &[3.0, 6.0, 9.0], 4);
        for (got, want) in q_t.iter().zip([3.0, 5.0, 7.0, 9.0]) {
            assert!((got - want).abs() < 1e-14, "{q_t:?}");
        }
        // Integral conserved: 0.5 (3 + 5 + 7 + 9) = 12 = (2/3)(3 + 6 + 9).
        let integral: f64 = q_t.iter().map(|q| 0.5 * q).sum();
        assert!((integral - 12.0).abs() < 1e-14);
        // Reverse map sends a constant to the same constant.
        let back = map_to_source(&overlaps, &[1.0; 4], 3);
        assert!(back.iter().all(|b| (b - 1.0).abs() < 1e-15), "{back:?}");
    }

    /// The shared overlap-link construction: area = chord of the true circle out of the rotor
    /// cell, centre = chord midpoint, the interpolation point w x_P + (1 − w) x_N lies in the
    /// overlap plane (k·n = 0), and k vanishes when both centres lie on the overlap's ray.
    #[test]
    fn overlap_link_geometry() {
        let frame = InterfaceFrame::new(Vec3::zeros(), Vec3::z());
        let (radius, lo, hi) = (1.5, 0.1, 0.3);
        let mid = 0.2f64;
        let ray = Vec3::new(mid.cos(), mid.sin(), 0.0);
        let outward = ray; // a rotor face area pointing outward (rotor inside)
                           // on the ray: no skew; inner centre 0.1 inside the chord, outer 0.2 outside
        let chord_r = radius * (0.1f64).cos();
        let (xp, xn) = (ray * (chord_r - 0.1) + Vec3::z() * 0.05, ray * (chord_r + 0.2) + Vec3::z() * 0.05);
        let g = frame.overlap_link(radius, lo, hi, 0.0, 0.1, &outward, &xp, &xn);
        let chord = 2.0 * radius * (0.1f64).sin() * 0.1;
        // round-off of O(1) trigonometry: 1e-14
        assert!((g.area - ray * chord).norm() < 1e-14, "{:?}", g.area);
        assert!((g.centre - (ray * chord_r + Vec3::z() * 0.05)).norm() < 1e-14);
        assert!((g.weight - 2.0 / 3.0).abs() < 1e-13 && g.skew.norm() < 1e-14, "{g:?}");
        assert_eq!(g.delta, xn - xp);
        // stator centre turned by 0.15 rad: k is tangential (in the overlap plane), O(h)
        let turned = Vec3::new((mid + 0.15).cos(), (mid + 0.15).sin(), 0.0) * (chord_r + 0.2) + Vec3::z() * 0.05;
        let g = frame.overlap_link(radius, lo, hi, 0.0, 0.1, &outward, &xp, &turned);
        assert!(g.skew.dot(&g.area.normalize()).abs() < 1e-14, "{g:?}");
        assert!(g.skew.norm() > 0.01, "{g:?}");
        let point = xp * g.weight + turned * (1.0 - g.weight);
        assert!((point + g.skew - g.centre).norm() < 1e-14);
        // the area points out of the rotor cell whichever way the face area is given
        let g = frame.overlap_link(radius, lo, hi, 0.0, 0.1, &(-outward), &xn, &xp);
        assert!(g.area.dot(&ray) < 0.0);
    }

    #[test]
    fn overlap_1d_rejects_bad_edges() {
        assert!(overlap_1d(&[0.0, 1.0, 0.5], &[0.0, 0.5]).unwrap_err().to_string().contains("source_edges"));
        assert!(overlap_1d(&[0.0, 1.0], &[0.0, 0.9]).unwrap_err().to_string().contains("target_edges"));
        assert!(overlap_1d(&[0.0], &[0.0, 1.0]).is_err());
    }

    fn uniform_edges(n: usize, start: f64) -> Vec<f64> {
        (0..=n).map(|k| start + TAU * k as f64 / n as f64).collect()
    }

    fn interface(n_rotor: usize, n_stator: usize, layers: usize) -> SlidingInterface {
        SlidingInterface {
            name: "test".into(),
            rotor_zone: 0,
            stator_zone: 1,
            radius: 1.0,
            z_edges: (0..=layers).map(|k| k as f64).collect(),
            n_theta_rotor: n_rotor,
            n_theta_stator: n_stator,
            rotor_theta_edges: uniform_edges(n_rotor, 0.0),
            stator_theta_edges: uniform_edges(n_stator, 0.0),
            rotor_faces: (0..layers * n_rotor).collect(),
            stator_faces: (1000..1000 + layers * n_stator).collect(),
        }
    }

    /// Largest deviation from 1 of Σ fractions per face, both sides, and of the total overlap
    /// angle per layer from 2π.
    fn fraction_errors(i: &SlidingInterface, angle: f64, out: &mut Vec<Overlap>) -> (f64, f64) {
        i.overlaps_into(angle, out);
        let mut rotor_sum = vec![0.0; i.rotor_faces.len()];
        let mut stator_sum = vec![0.0; i.stator_faces.len()];
        let mut covered = vec![0.0; i.n_layers()];
        for o in out.iter() {
            rotor_sum[o.rotor_face] += o.rotor_fraction;
            stator_sum[o.stator_face - 1000] += o.stator_fraction;
            covered[o.rotor_face / i.n_theta_rotor] += o.rotor_fraction * TAU / i.n_theta_rotor as f64;
        }
        let fraction_error = rotor_sum.iter().chain(&stator_sum).map(|s| (s - 1.0).abs()).fold(0.0, f64::max);
        let cover_error = covered.iter().map(|c| (c - TAU).abs()).fold(0.0, f64::max);
        (fraction_error, cover_error)
    }

    /// The θ bounds of each layer's overlaps tile one full turn from the turned rotor's first
    /// edge, each overlap's width equals its fractions times its faces' widths, and each bound
    /// lies inside both faces' θ intervals (taken modulo 2π).
    #[test]
    fn theta_bounds_tile_the_turn_and_match_the_fractions() {
        let mut out = Vec::new();
        for (n_rotor, n_stator) in [(32, 48), (7, 5)] {
            let i = interface(n_rotor, n_stator, 2);
            let (w_r, w_s) = (TAU / n_rotor as f64, TAU / n_stator as f64);
            for angle in [0.0, 0.3, -1.7, 12.345] {
                i.overlaps_into(angle, &mut out);
                let start = angle.rem_euclid(TAU);
                for layer in out.chunk_by(|a, b| a.layer == b.layer) {
                    assert_eq!(layer[0].rotor_face / n_rotor, layer[0].layer);
                    // round-off of the breakpoints (magnitude ≤ 4π): a few ε·4π
                    let eps = 1e-13;
                    assert!((layer[0].theta_lo - start).abs() < eps);
                    assert!((layer[layer.len() - 1].theta_hi - (start + TAU)).abs() < eps);
                    for w in layer.windows(2) {
                        assert_eq!(w[0].theta_hi, w[1].theta_lo, "overlaps are contiguous");
                    }
                    for o in layer {
                        let width = o.theta_hi - o.theta_lo;
                        assert!(width > 0.0);
                        assert!((width - o.rotor_fraction * w_r).abs() < eps, "{o:?}");
                        assert!((width - o.stator_fraction * w_s).abs() < eps, "{o:?}");
                        if width < 1e-9 {
                            continue; // a round-off sliver at coinciding edges: its midpoint
                                      // sits on a face edge, so the index test is ambiguous
                        }
                        let mid = 0.5 * (o.theta_lo + o.theta_hi);
                        let j_s = (mid.rem_euclid(TAU) / w_s) as usize;
                        let j_r = ((mid - angle).rem_euclid(TAU) / w_r) as usize;
                        assert_eq!(o.stator_face - 1000, (o.stator_face - 1000) / n_stator * n_stator + j_s);
                        assert_eq!(o.rotor_face, o.rotor_face / n_rotor * n_rotor + j_r);
                    }
                }
            }
        }
    }

    #[test]
    fn fractions_sum_to_one_for_all_angles() {
        let mut out = Vec::new();
        for (n_rotor, n_stator) in [(32, 32), (32, 48), (7, 5), (256, 100)] {
            let i = interface(n_rotor, n_stator, 2);
            let mut worst = (0.0f64, 0.0f64);
            let sweep = (0..1000).map(|k| -2.0 * TAU + 5.0 * TAU * k as f64 / 999.0);
            for angle in sweep.chain([1234.5678, -98765.4321]) {
                let (fraction, cover) = fraction_errors(&i, angle, &mut out);
                worst = (worst.0.max(fraction), worst.1.max(cover));
                assert!(out.len() <= 2 * (n_rotor + n_stator + 1));
            }
            // Breakpoints of magnitude ≤ 4π carry round-off ~ε·4π each; relative to a face
            // width 2π/n that is ~2nε per piece, so 1e-12 covers n ≤ 256 with margin.
            assert!(worst.0 < 1e-12 && worst.1 < 1e-12, "{n_rotor}/{n_stator}: {worst:?}");
        }
    }

    #[test]
    fn many_turns_and_exact_coincidence() {
        let i = interface(8, 4, 1);
        let mut out = Vec::new();
        // Aligned: rotor face 2j and 2j+1 lie wholly in stator face j.
        // Multiples of 2π by powers of two are exact in floating point, so the edges coincide
        // exactly (other multiples leave harmless slivers ~1e-15 long).
        for turns in [-8.0, -1.0, 0.0, 1.0, 2.0, 64.0] {
            i.overlaps_into(turns * TAU, &mut out);
            assert_eq!(out.len(), 8, "turns {turns}");
            for o in &out {
                assert_eq!(o.stator_face - 1000, o.rotor_face / 2);
                assert!((o.rotor_fraction - 1.0).abs() < 1e-12 && (o.stator_fraction - 0.5).abs() < 1e-12);
            }
        }
        // Rotor turned by a quarter rotor face (π/16): rotor face 0 spans [π/16, 5π/16],
        // stator face 0 spans [0, π/2]: fully inside.
        let overlaps = i.overlaps(TAU / 32.0);
        assert_eq!(overlaps[0].rotor_face, 0);
        assert_eq!(overlaps[0].stator_face, 1000);
        // Rotor face 1 spans [5π/16, 9π/16]: 3/4 in stator face 0, 1/4 in stator face 1.
        let face1: Vec<&Overlap> = overlaps.iter().filter(|o| o.rotor_face == 1).collect();
        assert_eq!(face1.len(), 2);
        assert!((face1[0].rotor_fraction - 0.75).abs() < 1e-14 && face1[0].stator_face == 1000);
        assert!((face1[1].rotor_fraction - 0.25).abs() < 1e-14 && face1[1].stator_face == 1001);
        // Negative angle: −π/16 puts rotor face 0 at [−π/16, 3π/16]: 1/4 in the last stator face.
        let back = i.overlaps(-TAU / 32.0);
        let face0: Vec<&Overlap> = back.iter().filter(|o| o.rotor_face == 0).collect();
        assert_eq!(face0.len(), 2);
        assert_eq!(face0[0].stator_face, 1003);
        assert!((face0[0].rotor_fraction - 0.25).abs() < 1e-14);
        // Overlap π/16 of the stator face width π/2.
        assert!((face0[0].stator_fraction - 0.125).abs() < 1e-14);
    }
}
