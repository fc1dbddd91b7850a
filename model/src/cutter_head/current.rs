//! The haul velocity: a uniform current past the cutter head (spillage-and-flow-verification.md
//! §6.1 item 3, "haul (swing) velocity, imposed as a flow past the head"; the thesis' runs had
//! none, §5.4 difference 3; the 1:4 model scale hauls at 0.05–0.1 m/s, Tab. 2.1 of §1.4).
//!
//! **Frame and sign.** The head stays put and the water streams past it: `haul_velocity` is the
//! water's velocity relative to the head, U = −v_swing. With gravity tilted in the x–z plane by
//! the ladder angle, "up" is toward +x (and toward the hub, −z, in the shipped cases, whose ring
//! lies lowest; toward the ring, +z, with a dredger's hub lowest: `ladder`), the head's top is on
//! the +x side and the swing is horizontal and normal to the ladder: along ±y. A head turning
//! with positive ω moves its top along +y, so U along −y (the head swings along +y, with its top)
//! is over-cutting and U along +y is under-cutting (§1.3). U has no z component: the tank's end
//! beyond the ring (`top`) is a lid.
//!
//! **Far field.** Open water around a swinging head is unbounded; the mesh ends at the tank. The
//! tank's side (r = R_T) and its floor get the current as a fixed velocity (Dirichlet, a
//! `velocity_inlet` whose flux points in on the upstream half and out on the downstream half):
//! the tank wall stands for water far enough from the head to be undisturbed by it. This is
//! exact only as R_T/R_c → ∞. A finite tank forces the head's blockage and wake back to the
//! uniform current at r = R_T: it speeds up the flow past the head (a solid cylinder of radius
//! a in a current U disturbs it by U a²/r² in potential flow, 14 % at the shipped tank's wall,
//! R_T = 1 m, a = R_c = 0.375 m; the porous turning head blocks less) and squeezes the wake into
//! a layer at the downstream wall. A larger current asks for a larger tank (README gives the
//! measured sensitivity of the out-flowing flux to R_T).
//!
//! **Mass.** The floor gets the current plus the suction's inflow, U + (Q_m / A_floor) ẑ, and
//! the side U. The side is a closed polygonal cylinder whose outward face normals sum to zero,
//! so Σ U·S over it vanishes to round-off: the current adds no net flux, and the pipe's end
//! (fixed pressure) still carries Q_m.
//!
//! **Start.** The water outside the head starts with the current, inside the contour hull and
//! the pipe with the case's `[fluid] initial` (solid-body rotation for the shipped head), so
//! the run starts without a shock at the tank wall ([`initial_velocity`]).

use super::geometry::CutterHead;
use super::settings::CutterHeadSection;
use crate::fluid::settings::BoundaryCondition;

/// The tank floor's condition: the current plus the upward velocity `inflow` = Q_m / A_floor.
/// Without a current this is the still tank's `[0, 0, inflow]`, bit for bit.
pub fn floor_condition(section: &CutterHeadSection, inflow: f64) -> BoundaryCondition {
    let u = section.haul_velocity;
    BoundaryCondition::VelocityInlet { velocity: [u[0], u[1], u[2] + inflow], profile: None }
}

/// The tank side's condition with a current (the far field); `None` in still water, where the
/// case file's `[boundary.tank]` holds.
pub fn tank_condition(section: &CutterHeadSection) -> Option<BoundaryCondition> {
    section.has_current().then_some(BoundaryCondition::VelocityInlet { velocity: section.haul_velocity, profile: None })
}

/// Whether the case file's `[boundary.tank]` may be replaced by the far field of a current: a
/// still tank's wall (no-slip at rest, or slip), which the current supersedes. A moving wall
/// or an inlet or outlet there would be another flow the current cannot silently replace.
pub fn still_tank(condition: &BoundaryCondition) -> bool {
    match condition {
        BoundaryCondition::Wall { velocity, rotating, angular_velocity, .. } => !rotating && *angular_velocity == 0.0 && velocity.iter().all(|v| *v == 0.0),
        BoundaryCondition::Symmetry => true,
        BoundaryCondition::VelocityInlet { .. } | BoundaryCondition::PressureOutlet { .. } => false,
    }
}

/// Whether a body-frame point is in the head: inside the contour hull, or in the suction pipe
/// (inside its outer wall above the ring; an eccentric mouth's housing holds no water).
pub fn in_head(head: &CutterHead, x: [f64; 3]) -> bool {
    let (r, z) = (x[0].hypot(x[1]), x[2]);
    let pipe = if head.mouth.is_some() { 0.0 } else { head.pipe_wall };
    head.inside_hull(r, z) || (z > 0.0 && r < head.opening_radius + pipe)
}

/// The initial velocity at `x`: `start` (the case's `[fluid] initial`) inside the head, the
/// current added outside it. At rest the head's body frame is the mesh frame (rotor angle 0).
pub fn initial_velocity(head: &CutterHead, current: [f64; 3], x: [f64; 3], start: [f64; 3]) -> [f64; 3] {
    if in_head(head, x) {
        start
    } else {
        [start[0] + current[0], start[1] + current[1], start[2] + current[2]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn section(current: [f64; 3]) -> CutterHeadSection {
        let mut s = crate::cutter_head::fluid_mesh::tests::section(0.05);
        s.haul_velocity = current;
        s
    }

    #[test]
    fn the_floor_adds_the_current_to_the_inflow_and_still_water_keeps_the_file_condition() {
        let still = section([0.0; 3]);
        assert_eq!(floor_condition(&still, 0.04), BoundaryCondition::VelocityInlet { velocity: [0.0, 0.0, 0.04], profile: None });
        assert_eq!(tank_condition(&still), None);
        let moving = section([0.1, -0.3, 0.0]);
        assert_eq!(floor_condition(&moving, 0.04), BoundaryCondition::VelocityInlet { velocity: [0.1, -0.3, 0.04], profile: None });
        assert_eq!(tank_condition(&moving), Some(BoundaryCondition::VelocityInlet { velocity: [0.1, -0.3, 0.0], profile: None }));
    }

    #[test]
    fn the_current_starts_outside_the_head_only() {
        let s = section([0.0, 0.3, 0.0]);
        let head = CutterHead::new(&s);
        let start = [0.5, 0.0, 0.0];
        // between the blades, in the pipe: the case's start
        assert_eq!(initial_velocity(&head, s.haul_velocity, [0.2, 0.0, -0.2], start), start);
        assert_eq!(initial_velocity(&head, s.haul_velocity, [0.1, 0.0, 0.1], start), start);
        // beside the head, under the hub, beside the pipe: start + current
        for x in [[0.6, 0.0, -0.2], [0.1, 0.0, -0.6], [0.0, 0.3, 0.1]] {
            assert_eq!(initial_velocity(&head, s.haul_velocity, x, start), [0.5, 0.3, 0.0], "{x:?}");
        }
    }

    #[test]
    fn only_a_still_tank_gives_way_to_the_current() {
        let wall = |velocity: [f64; 3], rotating: bool| BoundaryCondition::Wall {
            velocity,
            rotating,
            angular_velocity: 0.0,
            axis: [0.0, 0.0, 1.0],
            origin: [0.0; 3],
            suction: None,
        };
        assert!(still_tank(&wall([0.0; 3], false)));
        assert!(still_tank(&BoundaryCondition::Symmetry));
        assert!(!still_tank(&wall([0.1, 0.0, 0.0], false)));
        assert!(!still_tank(&wall([0.0; 3], true)));
        assert!(!still_tank(&BoundaryCondition::PressureOutlet { pressure: 0.0 }));
    }
}
