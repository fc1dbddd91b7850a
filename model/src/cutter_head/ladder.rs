//! Which way gravity pulls along the head's axis: the orientation of the ladder.
//!
//! The thesis represents its 45° ladder by "tilting the gravity vector 45° from the rotation
//! axis" (spillage-and-flow-verification.md §5.4, Fig. 8.5) without saying which way along the
//! axis. The head's axis here is +z, from the hub (z = −H) to the ring (z = 0), the rotation
//! vector of a positive rpm. Taken from that vector, gravity 45° from +z pulls toward the ring:
//! the ring lies lowest, and only then do the thesis' reported spillage results come out
//! (README, "Which way the ladder leans"). On a dredger the ladder hangs the head nose down, so
//! the hub lies lowest and gravity pulls toward the hub (135° from +z); the thesis' own words,
//! "top" for the ring side (§0), fit that. Both are a `[physics] gravity` away; which one a case
//! runs decides where its rock leaves, so `spillage check` and `spillage run` name it.

/// Where gravity's component along the head's axis pulls.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AxialPull {
    /// +z: the ring lies lowest (the thesis' tilt taken from the rotation vector).
    TowardRing,
    /// −z: the hub lies lowest (a dredger's ladder).
    TowardHub,
    /// No axial part: the axis is horizontal.
    Across,
    /// No gravity at all.
    None,
}

/// Gravity relative to the head's axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LadderTilt {
    /// |g| [m/s²].
    pub magnitude: f64,
    /// Angle between g and the axis +z (hub → ring) [deg]: 0 pulls straight at the ring.
    pub angle_to_axis: f64,
    pub pull: AxialPull,
}

/// Axial parts below this fraction of |g| count as none: a horizontal axis whose gravity was
/// written with rounded components (six digits leave ~1e-7 of |g|).
const ACROSS: f64 = 1e-6;

impl LadderTilt {
    pub fn of(gravity: [f64; 3]) -> Self {
        let magnitude = gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
        if magnitude == 0.0 {
            return Self { magnitude, angle_to_axis: 90.0, pull: AxialPull::None };
        }
        let cosine = (gravity[2] / magnitude).clamp(-1.0, 1.0);
        let pull = if cosine > ACROSS {
            AxialPull::TowardRing
        } else if cosine < -ACROSS {
            AxialPull::TowardHub
        } else {
            AxialPull::Across
        };
        Self { magnitude, angle_to_axis: cosine.acos().to_degrees(), pull }
    }

    /// The ladder angle: between the axis and the horizontal plane (normal to g), so 45° with
    /// either end lowest, 0° for a horizontal axis [deg].
    pub fn ladder_angle(&self) -> f64 {
        (90.0 - self.angle_to_axis).abs()
    }

    /// A short name for summaries: "toward the ring", "toward the hub", "across the axis" or
    /// "nowhere" (no gravity).
    pub fn pull_name(&self) -> &'static str {
        match self.pull {
            AxialPull::TowardRing => "toward the ring",
            AxialPull::TowardHub => "toward the hub",
            AxialPull::Across => "across the axis",
            AxialPull::None => "nowhere",
        }
    }

    /// One sentence for `spillage check`: the angles, the pull and what it means for the head.
    pub fn describe(&self) -> String {
        let what = match self.pull {
            AxialPull::None => return "gravity 0".to_string(),
            AxialPull::Across => return format!("gravity {:.3} m/s², across the axis: the axis is horizontal", self.magnitude),
            AxialPull::TowardRing => "pulls toward the ring, which lies lowest: the orientation the thesis' spillage results need; a dredger's ladder has the hub lowest (set gravity's z < 0)",
            AxialPull::TowardHub => "pulls toward the hub, which lies lowest, as on a dredger's ladder; the thesis' spillage results need the ring lowest (set gravity's z > 0)",
        };
        format!(
            "gravity {:.3} m/s², ladder angle {:.1}° ({:.1}° from the axis +z, hub → ring): its axial part {what}",
            self.magnitude,
            self.ladder_angle(),
            self.angle_to_axis
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shipped head's 45° tilts either way, a horizontal axis (also with gravity rounded to
    /// six digits) and no gravity.
    #[test]
    fn the_pull_and_angle_follow_the_sign_of_gravitys_axial_part() {
        let g = 9.81 / 2f64.sqrt();
        let ring = LadderTilt::of([-g, 0.0, g]);
        assert_eq!(ring.pull, AxialPull::TowardRing);
        assert!((ring.angle_to_axis - 45.0).abs() < 1e-12, "{}", ring.angle_to_axis);
        assert!((ring.ladder_angle() - 45.0).abs() < 1e-12 && (ring.magnitude - 9.81).abs() < 1e-12);
        let hub = LadderTilt::of([-g, 0.0, -g]);
        assert_eq!(hub.pull, AxialPull::TowardHub);
        assert!((hub.angle_to_axis - 135.0).abs() < 1e-12, "{}", hub.angle_to_axis);
        assert!((hub.ladder_angle() - 45.0).abs() < 1e-12, "{}", hub.ladder_angle());
        assert!((LadderTilt::of([-9.81 * 0.5, 0.0, -9.81 * 0.75f64.sqrt()]).ladder_angle() - 60.0).abs() < 1e-9);
        let level = LadderTilt::of([-9.81, 0.0, 4e-7]);
        assert_eq!(level.pull, AxialPull::Across);
        assert!(level.ladder_angle() < 1e-5);
        assert_eq!(level.describe(), "gravity 9.810 m/s², across the axis: the axis is horizontal");
        assert_eq!(LadderTilt::of([0.0; 3]).pull_name(), "nowhere");
        assert_eq!(LadderTilt::of([0.0; 3]).describe(), "gravity 0");
        assert!(
            ring.describe().contains("ladder angle 45.0° (45.0° from the axis +z") && ring.describe().contains("pulls toward the ring, which lies lowest"),
            "{}",
            ring.describe()
        );
        assert!(
            hub.describe().contains("ladder angle 45.0° (135.0°") && hub.describe().contains("pulls toward the hub, which lies lowest"),
            "{}",
            hub.describe()
        );
    }
}
