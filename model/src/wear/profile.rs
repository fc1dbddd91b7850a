//! The wear profile along a line (`[wear.profile]`): what the thesis plots along its coupon
//! (wear-model.md §12.4) and what `wear_profile.csv` holds.

use super::settings::ProfileSection;
use super::state::WallWear;
use crate::walls::state::{Vec3, Wall};

/// One bin of the profile: triangles whose centroid projects into it, within `width`/2 of the
/// line, in the wall's body frame (its pose at t = 0).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ProfileBin {
    /// Distance of the bin centre from `from` [m].
    pub distance: f64,
    /// Area-weighted mean depth receded [m] and rate [m/s] of the bin's triangles.
    pub depth: f64,
    pub rate: f64,
    /// Volume deposited on the bin's triangles [m³] and their impacts.
    pub volume: f64,
    pub impacts: u64,
    /// Wall area the bin covers [m²] (0: no triangle there).
    pub area: f64,
}

/// The profile over the eroding walls `walls` (each with its wear).
pub fn wear_profile(section: &ProfileSection, walls: &[(&Wall, &WallWear)]) -> Vec<ProfileBin> {
    let (from, to) = (Vec3::from(section.from), Vec3::from(section.to));
    let length = (to - from).norm();
    let along = (to - from) / length;
    let n = section.bins;
    let mut bins: Vec<ProfileBin> = (0..n).map(|k| ProfileBin { distance: (k as f64 + 0.5) * length / n as f64, ..ProfileBin::default() }).collect();
    for (wall, wear) in walls {
        let depth = wear.on_triangles(&wear.node_depth, &wall.triangles);
        let rate = wear.on_triangles(&wear.node_rate, &wall.triangles);
        for (t, tri) in wall.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|v| wall.vertices[v as usize]);
            let centre = (a + b + c) / 3.0;
            let s = (centre - from).dot(&along);
            let off = (centre - from - s * along).norm();
            if !(0.0..length).contains(&s) || off > 0.5 * section.width {
                continue;
            }
            let area = 0.5 * (b - a).cross(&(c - a)).norm();
            let bin = &mut bins[((s / length * n as f64) as usize).min(n - 1)];
            bin.area += area;
            bin.depth += area * depth[t];
            bin.rate += area * rate[t];
            bin.volume += wear.triangle_volume[t];
            bin.impacts += wear.triangle_impacts[t];
        }
    }
    for bin in &mut bins {
        if bin.area > 0.0 {
            bin.depth /= bin.area;
            bin.rate /= bin.area;
        }
    }
    bins
}
