//! The cutter head's part of `spillage check`: the operating point in the thesis'
//! dimensionless numbers, the haul, which way gravity pulls along the axis, and the
//! Euler-turbine model's out-flowing flux on the case's own contour.

use spillage_model::case::Case;

use crate::verify::head_model::HeadModel;

/// The head's operating point in the thesis' dimensionless numbers (spillage-and-flow-
/// verification.md §2.11) and the Euler-turbine model's prediction on its contour (§2).
pub(super) fn head_lines(case: &Case) -> Vec<String> {
    let (Some(head), Some(rotor)) = (&case.cutter_head, &case.rotor) else { return Vec::new() };
    let omega = rotor.angular_velocity().abs();
    let rpm = omega * 60.0 / std::f64::consts::TAU;
    let r_c = head.contour[0][1];
    let pipe_area = match head.eccentric_mouth() {
        Some(mouth) => mouth.area(),
        None => std::f64::consts::PI * (head.opening_radius().powi(2) - head.shaft_radius.powi(2)),
    };
    let v_m = head.suction_discharge / pipe_area;
    let mut lines = vec![
        format!("head         {} blades, R_c {r_c} m, H {} m, {rpm:.1} rpm, Q_m {} m³/s", head.blades, head.height(), head.suction_discharge),
        format!(
            "             tip speed ω R_c {:.3} m/s, suction velocity v_m {v_m:.3} m/s, ω R_c / v_m {:.3}, θ_c = Q_m/(ω R_c³) {:.3}",
            omega * r_c,
            omega * r_c / v_m,
            head.suction_discharge / (omega * r_c.powi(3))
        ),
    ];
    lines.push(haul_line(head, omega * r_c));
    lines.push(format!("             {}", spillage_model::cutter_head::ladder::LadderTilt::of(case.physics.gravity).describe()));
    // the model on the case's own contour, as `spillage sweep` and `spillage verify` evaluate it
    if let Some(Ok(model)) = HeadModel::of_case(case) {
        if let Ok(answer) = model.answer_at_case() {
            lines.push(format!(
                "             Euler-turbine model ({}, water): out-flowing flux {:.4} m³/s = {:.3} Q_m{}",
                model.coefficients_label(),
                answer.outflow_water,
                answer.outflow_water / head.suction_discharge,
                lean_caveat(head.blade_sweep)
            ));
        }
    }
    lines
}

/// The Euler-turbine model has one velocity triangle (spec §2.4, Eqs. 4.67–4.70) and reads φ
/// the same whichever way the blades lean (`cutter_head.blade_sweep`); with the non-default
/// lean the check says so beside the flux it prints.
fn lean_caveat(sweep: spillage_model::cutter_head::BladeSweep) -> &'static str {
    match sweep {
        spillage_model::cutter_head::BladeSweep::Backward => "",
        spillage_model::cutter_head::BladeSweep::Forward => " (the model does not see the blades' forward lean: one velocity triangle, §2.4)",
    }
}

/// The head's haul velocity (the current past it, `cutter_head::current`) as `spillage check`
/// and `spillage run` print it.
pub fn haul_line(head: &spillage_model::cutter_head::CutterHeadSection, tip_speed: f64) -> String {
    let u = head.haul_velocity;
    let speed = u.iter().map(|v| v * v).sum::<f64>().sqrt();
    if speed == 0.0 {
        return "             haul velocity 0 (still water; the tank wall is [boundary.tank])".to_string();
    }
    let ratio = if tip_speed > 0.0 { format!(", {:.3} of the tip speed", speed / tip_speed) } else { String::new() };
    format!(
        "             haul velocity [{}, {}, {}] m/s ({speed:.3} m/s{ratio}): a current past the head, imposed on the tank's side and floor (far field, tank radius {} m = {:.2} R_c)",
        u[0],
        u[1],
        u[2],
        head.tank.radius,
        head.tank.radius / head.contour[0][1]
    )
}
