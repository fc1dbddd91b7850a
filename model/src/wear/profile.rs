//! The wear profile along a line (`[wear.profile]`): what the thesis plots along its coupon
//! (wear-model.md §12.4) and what `wear_profile.csv` holds.

use super::settings::ProfileSection;
use super::state::WearState;
use crate::case::Case;
use crate::walls::state::{Vec3, Wall, WallState};
use crate::walls::WallError;

/// One bin of the profile: triangles whose centroid, on the wall as built (unworn, in its body
/// frame, the pose at t = 0), projects into it within `width`/2 of the line.
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

/// The walls as the case builds them, before any wear: where [`wear_profile`] bins the
/// triangles. A type of its own so that the walls of a worn state cannot be passed instead.
pub struct UnwornWalls(WallState);

impl UnwornWalls {
    /// The walls `case` builds (STL paths relative to the case file's folder).
    pub fn of_case(case: &Case) -> Result<Self, WallError> {
        crate::walls::build(case, &case.path.parent().map(|p| p.to_path_buf()).unwrap_or_default()).map(UnwornWalls)
    }

    pub fn walls(&self) -> &WallState {
        &self.0
    }
}

/// The profile of `wear` over its eroding walls, binned on the walls as built. A bin keeps its
/// triangles and its area however deep the wall recedes. Binned where they are now, the
/// triangles would leave the band as the wall recedes: it is measured in 3-D, so a triangle
/// `z` off the line left it once the depth passed √((`width`/2)² − z²) (on the Coriolis coupon
/// the outer rows, 2.67 mm off, at 1.4 mm), and a bin then held only the crater's floor, or
/// nothing.
pub fn wear_profile(section: &ProfileSection, unworn: &UnwornWalls, wear: &WearState) -> Vec<ProfileBin> {
    let n = section.bins;
    let length = (Vec3::from(section.to) - Vec3::from(section.from)).norm();
    let mut bins: Vec<ProfileBin> = (0..n).map(|k| ProfileBin { distance: (k as f64 + 0.5) * length / n as f64, ..ProfileBin::default() }).collect();
    for wear in &wear.walls {
        let wall = &unworn.0.walls[wear.wall];
        debug_assert_eq!(wall.triangles.len(), wear.triangle_volume.len(), "{}: the wall as built has other triangles than its wear", wear.name);
        let depth = wear.on_triangles(&wear.node_depth, &wall.triangles);
        let rate = wear.on_triangles(&wear.node_rate, &wall.triangles);
        for (t, k, area) in binned_triangles(section, wall) {
            let bin = &mut bins[k];
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

/// How many of the profile's bins hold a triangle of the walls `eroding` (indices into the
/// walls as built): `spillage check` says so, and warns when none does (a line that misses the
/// eroding walls gives a profile of empty bins).
pub fn covered_bins(section: &ProfileSection, unworn: &UnwornWalls, eroding: &[usize]) -> usize {
    let mut covered = vec![false; section.bins];
    for &w in eroding {
        for (_, k, _) in binned_triangles(section, &unworn.0.walls[w]) {
            covered[k] = true;
        }
    }
    covered.iter().filter(|&&c| c).count()
}

/// (triangle, bin, area) of each triangle of `wall` whose centre projects into the profile
/// within `width`/2 of its line.
fn binned_triangles<'a>(section: &'a ProfileSection, wall: &'a Wall) -> impl Iterator<Item = (usize, usize, f64)> + 'a {
    let (from, to) = (Vec3::from(section.from), Vec3::from(section.to));
    let length = (to - from).norm();
    let along = (to - from) / length;
    let n = section.bins;
    wall.triangles.iter().enumerate().filter_map(move |(t, tri)| {
        let [a, b, c] = tri.map(|v| wall.vertices[v as usize]);
        let centre = (a + b + c) / 3.0;
        let s = (centre - from).dot(&along);
        let off = (centre - from - s * along).norm();
        if !(0.0..length).contains(&s) || off > 0.5 * section.width {
            return None;
        }
        Some((t, ((s / length * n as f64) as usize).min(n - 1), 0.5 * (b - a).cross(&(c - a)).norm()))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::walls::geometry::plane;
    use crate::walls::state::WallMotion;
    use crate::wear::state::WallWear;
    use crate::wear::surface::WearSurface;

    /// A 10 × 6 mm plate (normal +y) receded uniformly by 4 mm, deeper than the profile's
    /// half-width of 3 mm: binned on the plate as built, each of the ten bins keeps its
    /// 1 × 6 mm and reads the 4 mm. Binned on the worn plate (what the profile was given before
    /// [`UnwornWalls`]), the triangles are 4 mm off the line and every bin is empty.
    #[test]
    fn bins_keep_their_triangles_however_deep_the_wall_recedes() {
        let plate = coupon();
        let surface = WearSurface::new(&plate.vertices, &plate.triangles);
        let mut wall_wear = WallWear::new(0, "coupon".into(), plate.triangles.len(), surface.node_of_vertex.clone(), surface.n_nodes);
        let depth = 0.004;
        wall_wear.node_depth.iter_mut().for_each(|d| *d = depth);
        let wear = WearState { walls: vec![wall_wear], impacts: 0 };
        let mut worn = plate.clone();
        worn.vertices.iter_mut().for_each(|v| v.y -= depth);
        let line = ProfileSection { from: [-0.005, 0.0, 0.0], to: [0.005, 0.0, 0.0], width: 0.006, bins: 10 };

        let bins = wear_profile(&line, &UnwornWalls(WallState { walls: vec![plate] }), &wear);
        assert_eq!(bins.len(), 10);
        for (k, bin) in bins.iter().enumerate() {
            // sums of a bin's twelve triangle areas and depths: round-off
            assert!((bin.area - 6e-6).abs() < 1e-18, "bin {k}: area {}", bin.area);
            assert!((bin.depth - depth).abs() < 1e-15, "bin {k}: depth {}", bin.depth);
            assert!((bin.distance - (k as f64 + 0.5) * 1e-3).abs() < 1e-15);
        }
        let on_the_worn_plate = wear_profile(&line, &UnwornWalls(WallState { walls: vec![worn.clone()] }), &wear);
        assert!(on_the_worn_plate.iter().all(|b| b.area == 0.0), "the worn plate's triangles lie outside the band");
        // what `spillage check` counts: every bin over the plate, none over a plate 4 mm away
        assert_eq!(covered_bins(&line, &UnwornWalls(WallState { walls: vec![coupon()] }), &[0]), 10);
        assert_eq!(covered_bins(&line, &UnwornWalls(WallState { walls: vec![worn] }), &[0]), 0);
    }

    /// A 10 × 6 mm plate through the origin, normal +y, in 1 mm squares.
    fn coupon() -> Wall {
        crate::walls::wall("coupon".into(), 0, plane(Vec3::zeros(), Vec3::y(), [0.01, 0.006], [10, 6], Some(Vec3::x())), WallMotion::Static).unwrap()
    }
}
