//! Golden snapshots of the analytic referee (insta, stored in golden/).
//!
//! The numbers here come from `spillage-analytic`; they were checked by hand against the spec
//! before the snapshots were accepted (see the report of the `analytic` branch). Values are
//! rounded to 6 significant digits so that round-off never churns the files.

use serde_json::{json, Value};
use spillage_analytic::couette::CircularCouette;
use spillage_analytic::drag_laws::DragLaw;
use spillage_analytic::hindered_settling::{cloud_settling_velocity, CloudReconstruction};
use spillage_analytic::restitution::legendre_wet_restitution;
use spillage_analytic::settling::SettlingSphere;
use spillage_analytic::spillage_model::{solve, CutterProfile, SpillageInputs, MIXTURE_DENSITY_TOP};

/// Rounds to `digits` significant digits.
fn sig(value: f64, digits: i32) -> f64 {
    if value == 0.0 || !value.is_finite() {
        return value;
    }
    let scale = 10f64.powi(digits - 1 - value.abs().log10().floor() as i32);
    (value * scale).round() / scale
}

fn spillage_point(rpm: f64, discharge: f64, density_top: f64) -> Value {
    let mut inputs = SpillageInputs::calibrated_water(CutterProfile::illustrative_lab_head(), rpm, discharge);
    inputs.density_top = density_top;
    let s = solve(&inputs).expect("calibrated inputs are valid");
    json!({
        "rpm": rpm,
        "discharge_m3s": discharge,
        "w1_m": sig(s.outflow_height, 6),
        "q1_m3s": sig(s.outflow_discharge, 6),
        "spillage_fraction": sig(s.spillage_fraction, 6),
        "production_fraction": sig(s.production_fraction, 6),
        "pressure_fraction": sig(s.pressure_fraction, 6),
    })
}

/// The calibrated analytical spillage model (Tab. 8.1/8.2/8.5 operating points, α = 0.375,
/// β = 0.774) on the illustrative 1:4 head.
#[test]
fn calibrated_spillage_curves() {
    let rpms = [20.0, 30.0, 45.0, 60.0, 75.0, 90.0];
    let water_012: Vec<Value> = rpms.iter().map(|&n| spillage_point(n, 0.12, 998.2)).collect();
    let water_006: Vec<Value> = rpms.iter().map(|&n| spillage_point(n, 0.06, 998.2)).collect();
    let suction_60rpm: Vec<Value> = [0.03, 0.06, 0.09, 0.12, 0.15].iter().map(|&q| spillage_point(60.0, q, 998.2)).collect();
    let mixture_012: Vec<Value> = rpms.iter().map(|&n| spillage_point(n, 0.12, MIXTURE_DENSITY_TOP)).collect();
    let snapshot = json!({
        "geometry": "CutterProfile::illustrative_lab_head (not the thesis geometry)",
        "alpha": 0.375,
        "beta": 0.774,
        "calibration_water_0.12": water_012,
        "water_0.06": water_006,
        "varying_suction_60rpm": suction_60rpm,
        "mixture_rho1_1254_0.12": mixture_012,
    });
    insta::with_settings!({snapshot_path => "../golden", prepend_module_to_snapshot => false}, {
        insta::assert_json_snapshot!("analytic_spillage_calibrated", snapshot);
    });
}

/// Case P1 settling transient and the P3 cloud velocities (particle-verification.md §2, §4).
#[test]
fn settling_tables() {
    let sphere = SettlingSphere::case_p1();
    let terminal = sphere.terminal_velocity(DragLaw::BrownLawler).unwrap();
    let times = [0.05, 0.1, 0.2, 0.3, 0.5, 1.0];
    let transient: Vec<Value> = sphere
        .transient(DragLaw::BrownLawler, &times)
        .unwrap()
        .iter()
        .map(|s| json!({"t_s": s.time, "u_m_s": sig(s.velocity, 6), "x_m": sig(s.distance, 6)}))
        .collect();
    let cloud: Vec<Value> = [0.027, 0.05, 0.1, 0.208, 0.308]
        .iter()
        .map(|&phi| {
            let a = cloud_settling_velocity(&sphere, phi, CloudReconstruction::SlipVelocity).unwrap();
            let b = cloud_settling_velocity(&sphere, phi, CloudReconstruction::ParticleVelocity).unwrap();
            json!({"phi": phi, "u_p_A_m_s": sig(a.particle_velocity, 6), "u_p_B_m_s": sig(b.particle_velocity, 6)})
        })
        .collect();
    let snapshot = json!({
        "terminal_velocity_m_s": sig(terminal.velocity, 6),
        "terminal_reynolds": sig(terminal.reynolds, 6),
        "transient": transient,
        "cloud": cloud,
    });
    insta::with_settings!({snapshot_path => "../golden", prepend_module_to_snapshot => false}, {
        insta::assert_json_snapshot!("analytic_settling", snapshot);
    });
}

/// Wet restitution and Couette reference tables.
#[test]
fn restitution_and_couette_tables() {
    let restitution: Vec<Value> = [10.0, 35.0, 100.0, 152.0, 360.0, 1000.0, 1e4]
        .iter()
        .map(|&st| json!({"st": st, "e_wet": sig(legendre_wet_restitution(0.97, st).unwrap(), 6)}))
        .collect();
    let cell = CircularCouette::thesis_case();
    let couette: Vec<Value> = [1.0, 1.125, 1.25, 1.5, 1.75, 2.0]
        .iter()
        .map(|&r| {
            let p = cell.point(r).unwrap();
            json!({
                "r": r,
                "u_theta": sig(p.tangential_velocity, 6),
                "dp_dr_over_rho": sig(p.kinematic_pressure_gradient, 6),
                "p_rise_over_rho": sig(p.kinematic_pressure_rise, 6),
            })
        })
        .collect();
    let snapshot = json!({"legendre_e_dry_0.97": restitution, "couette_ri1_ro2_omega1": couette});
    insta::with_settings!({snapshot_path => "../golden", prepend_module_to_snapshot => false}, {
        insta::assert_json_snapshot!("analytic_restitution_couette", snapshot);
    });
}
