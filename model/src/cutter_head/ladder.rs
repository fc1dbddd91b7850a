//! Which way gravity pulls along the head's axis: the orientation of the ladder.
//!
//! The thesis represents its 45° ladder by "tilting the gravity vector 45° from the rotation
//! axis" (spillage-and-flow-verification.md §5.4, Fig. 8.5) without saying which way along the
//! axis. The head's axis here is +z, from the hub (z = −H) to the ring (z = 0), the rotation
//! vector of a positive rpm. Read literally, gravity 45° from +z pulls toward the ring: the ring
//! lies lowest. On a dredger the ladder hangs the head nose down, so the hub lies lowest and
//! gravity pulls toward the hub (135° from +z). Both are a `[physics] gravity` away; which one
//! a case runs decides where its rock leaves (README, "Where the rock leaves"), so `spillage
//! check` and `spillage run` name it.

/// Where gravity's component along the head's axis pulls.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AxialPull {
    /// +z: the ring lies lowest (the literal reading of the thesis' tilt).
    TowardRing,
    /// −z: the hub lies lowest (a dredger's ladder).
    TowardHub,
    /// No axial part: the axis is horizontal (or there is no gravity).
    Across,
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

/// Axial parts below this fraction of |g| count as none (a horizontal axis written with
/// rounded components).
const ACROSS: f64 = 1e-9;

impl LadderTilt {
    pub fn of(gravity: [f64; 3]) -> Self {
        let magnitude = gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
        if magnitude == 0.0 {
            return Self { magnitude, angle_to_axis: 90.0, pull: AxialPull::Across };
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

    /// A short name for summaries: "toward the ring", "toward the hub" or "across the axis".
    pub fn pull_name(&self) -> &'static str {
        match self.pull {
            AxialPull::TowardRing => "toward the ring",
            AxialPull::TowardHub => "toward the hub",
            AxialPull::Across => "across the axis",
        }
    }

    /// One sentence for `spillage check`: the angle, the pull and what it means for the head.
    pub fn describe(&self) -> String {
        if self.magnitude == 0.0 {
            return "gravity 0".to_string();
        }
        let what = match self.pull {
            AxialPull::TowardRing => "the ring lies lowest, as the thesis' spillage results imply; a dredger's ladder has the hub lowest (gravity's z < 0)",
            AxialPull::TowardHub => "the hub lies lowest, as on a dredger's ladder; the thesis' spillage results imply the ring lowest (gravity's z > 0)",
            AxialPull::Across => "the axis is horizontal",
        };
        format!("gravity {:.3} m/s², {:.1}° from the axis +z (hub → ring), its axial part {}: {what}", self.magnitude, self.angle_to_axis, self.pull_name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shipped head's 45° tilts either way, a horizontal axis and no gravity.
    #[test]
    fn the_pull_and_angle_follow_the_sign_of_gravitys_axial_part() {
        let g = 9.81 / 2f64.sqrt();
        let ring = LadderTilt::of([-g, 0.0, g]);
        assert_eq!(ring.pull, AxialPull::TowardRing);
        assert!((ring.angle_to_axis - 45.0).abs() < 1e-12, "{}", ring.angle_to_axis);
        assert!((ring.magnitude - 9.81).abs() < 1e-12);
        let hub = LadderTilt::of([-g, 0.0, -g]);
        assert_eq!(hub.pull, AxialPull::TowardHub);
        assert!((hub.angle_to_axis - 135.0).abs() < 1e-12, "{}", hub.angle_to_axis);
        assert_eq!(LadderTilt::of([-9.81, 0.0, 0.0]).pull, AxialPull::Across);
        assert_eq!(LadderTilt::of([0.0; 3]).describe(), "gravity 0");
        assert!(ring.describe().contains("45.0° from the axis") && ring.describe().contains("toward the ring: the ring lies lowest"), "{}", ring.describe());
        assert!(hub.describe().contains("135.0°") && hub.describe().contains("the hub lies lowest"), "{}", hub.describe());
    }
}
