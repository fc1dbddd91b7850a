//! The evaluators of `spillage analytic`: one function per solution of the table in the parent
//! module, turning its parameters into a [`Report`] by calling `spillage-analytic`.

use super::*;

pub(super) fn run_spillage(params: &Params) -> Result<Report, String> {
    use an::spillage_model::{onset_omega, rpm_to_omega, solve, CutterProfile, SpillageInputs};
    let rpms = params.list("rpm", Spacing::Linear(20))?;
    let discharges = params.list("discharge", Spacing::Linear(5))?;
    let profile = match params.text("head") {
        "lab" => CutterProfile::illustrative_lab_head(),
        "cylinder" => CutterProfile::cylinder(params.number("radius")?, params.number("blade-angle")?.to_radians(), params.number("height")?).map_err(err)?,
        other => return Err(format!("--head = `{other}`: allowed values are `lab` and `cylinder`")),
    };
    let mut report = Report::new("spillage", params, &["rpm", "discharge_m3s", "omega_rad_s", "w1_m", "Q1_m3s", "u_rad1_m_s", "spillage_%", "production_%"]);
    let mut curves = Vec::new();
    for &qm in &discharges {
        let mut inputs = SpillageInputs::calibrated_water(profile.clone(), 0.0, qm);
        inputs.flow_factor = params.number("alpha")?;
        inputs.pressure_coefficient = params.number("beta")?;
        inputs.density_top = params.number("rho1")?;
        inputs.density_bottom = params.number("rho2")?;
        let onset = onset_omega(&inputs).map_err(err)?;
        report.summary(&format!("outflow onset at Q_m = {qm}"), onset * 60.0 / (2.0 * std::f64::consts::PI), "rpm");
        let mut points = Vec::new();
        for &rpm in &rpms {
            inputs.omega = rpm_to_omega(rpm);
            let s = solve(&inputs).map_err(err)?;
            report.rows.push(vec![
                rpm,
                qm,
                inputs.omega,
                s.outflow_height,
                s.outflow_discharge,
                s.outflow_velocity,
                100.0 * s.spillage_fraction,
                100.0 * s.production_fraction,
            ]);
            points.push((rpm, 100.0 * s.spillage_fraction));
        }
        curves.push(Curve { label: format!("Q_m = {qm} m3/s"), points });
    }
    report.summary("head height H", profile.height(), "m");
    if params.text("head") == "lab" {
        report.notes.push("`lab` is an illustrative 1:4 head (the thesis geometry is only in drawings); see CutterProfile::illustrative_lab_head".into());
    }
    report.plot = plot_spec("Analytical spillage model (Eq. 4.55)", "rotation speed [rpm]", "spillage S [%]", false, curves);
    Ok(report)
}

pub(super) fn run_settling(params: &Params) -> Result<Report, String> {
    use an::drag_laws::DragLaw;
    use an::settling::SettlingSphere;
    let law = DragLaw::from_name(params.text("drag"))
        .ok_or_else(|| format!("--drag = `{}`: allowed values are stokes, schiller-naumann, brown-lawler, dallavalle", params.text("drag")))?;
    let sphere = SettlingSphere::new(
        params.number("d")?,
        params.number("rho-p")?,
        params.number("rho-f")?,
        params.number("nu")?,
        params.number("g")?,
        params.number("cam")?,
    )
    .map_err(err)?;
    let terminal = sphere.terminal_velocity(law).map_err(err)?;
    let (t99, x99) = sphere.time_and_distance_to_speed(law, 0.99 * terminal.velocity).map_err(err)?;
    let times = if params.text("t") == "auto" { (0..=30).map(|i| 1.5 * t99 * i as f64 / 30.0).collect() } else { params.list("t", Spacing::Linear(30))? };
    let samples = sphere.transient(law, &times).map_err(err)?;
    let mut report = Report::new("settling", params, &["t_s", "u_m_s", "x_m"]);
    report.summary("terminal velocity", terminal.velocity, "m/s");
    report.summary("Reynolds number at terminal velocity", terminal.reynolds, "-");
    report.summary("drag coefficient at terminal velocity", terminal.drag_coefficient, "-");
    report.summary("initial acceleration", sphere.initial_acceleration(), "m/s2");
    report.summary("time to 99 % of terminal velocity", t99, "s");
    report.summary("distance to 99 % of terminal velocity", x99, "m");
    report.rows = samples.iter().map(|s| vec![s.time, s.velocity, s.distance]).collect();
    let points = samples.iter().map(|s| (s.time, s.velocity)).collect();
    report.plot = plot_spec("Settling from rest", "time [s]", "settling velocity [m/s]", false, vec![Curve { label: law.name().into(), points }]);
    Ok(report)
}

pub(super) fn run_hindered(params: &Params) -> Result<Report, String> {
    use an::hindered_settling::{cloud_settling_velocity, richardson_zaki_velocity, rowe_exponent, CloudReconstruction};
    use an::settling::SettlingSphere;
    let sphere =
        SettlingSphere::new(params.number("d")?, params.number("rho-p")?, params.number("rho-f")?, params.number("nu")?, an::GRAVITY, 0.5).map_err(err)?;
    let single = sphere.terminal_velocity(an::drag_laws::DragLaw::BrownLawler).map_err(err)?;
    let n = rowe_exponent(single.reynolds).map_err(err)?;
    let mut report = Report::new("hindered", params, &["phi_p", "u_p_A_m_s", "u_p_B_m_s", "u_RZ_m_s", "beta_DiFelice_A"]);
    report.summary("single-particle terminal velocity", single.velocity, "m/s");
    report.summary("Rowe exponent n", n, "-");
    let (mut a, mut b, mut rz) = (Vec::new(), Vec::new(), Vec::new());
    for phi in params.list("phi", Spacing::Linear(12))? {
        let sa = cloud_settling_velocity(&sphere, phi, CloudReconstruction::SlipVelocity).map_err(err)?;
        let sb = cloud_settling_velocity(&sphere, phi, CloudReconstruction::ParticleVelocity).map_err(err)?;
        let u_rz = richardson_zaki_velocity(single.velocity, phi, n, 0.0).map_err(err)?;
        report.rows.push(vec![phi, sa.particle_velocity, sb.particle_velocity, u_rz, sa.di_felice_exponent]);
        a.push((phi, sa.particle_velocity));
        b.push((phi, sb.particle_velocity));
        rz.push((phi, u_rz));
    }
    report.plot = plot_spec(
        "Hindered settling velocity",
        "particle volume fraction [-]",
        "settling velocity [m/s]",
        false,
        vec![
            Curve { label: "Di Felice (A)".into(), points: a },
            Curve { label: "Di Felice (B)".into(), points: b },
            Curve { label: "Richardson-Zaki (Rowe n)".into(), points: rz },
        ],
    );
    Ok(report)
}

pub(super) fn run_restitution(params: &Params) -> Result<Report, String> {
    use an::restitution::{legendre_wet_restitution, lubrication_restitution};
    let e_dry = params.number("e-dry")?;
    let log_gap = params.number("log-gap")?;
    let mut report = Report::new("restitution", params, &["St_AM", "e_wet", "e_wet/e_dry", "e_lubrication"]);
    let (mut legendre, mut lubrication) = (Vec::new(), Vec::new());
    for st in params.list("st", Spacing::Log(40))? {
        let e = legendre_wet_restitution(e_dry, st).map_err(err)?;
        let l = lubrication_restitution(e_dry, st, log_gap).map_err(err)?.restitution;
        report.rows.push(vec![st, e, if e_dry > 0.0 { e / e_dry } else { 0.0 }, l]);
        legendre.push((st, e));
        lubrication.push((st, l));
    }
    report.plot = plot_spec(
        "Wet restitution",
        "Stokes number St_AM [-]",
        "restitution [-]",
        true,
        vec![
            Curve { label: "Legendre e_dry exp(-35/St)".into(), points: legendre },
            Curve { label: format!("lubrication only, ln(h0/hr) = {log_gap}"), points: lubrication },
        ],
    );
    Ok(report)
}

pub(super) fn run_couette(params: &Params) -> Result<Report, String> {
    use an::couette::CircularCouette;
    let cell = CircularCouette::new(params.number("ri")?, params.number("ro")?, params.number("omega-i")?, params.number("omega-o")?).map_err(err)?;
    let rho = params.number("rho")?;
    let radii = if params.text("r") == "auto" {
        (0..=8).map(|i| cell.inner_radius + (cell.outer_radius - cell.inner_radius) * i as f64 / 8.0).collect()
    } else {
        params.list("r", Spacing::Linear(8))?
    };
    let (a, b) = cell.coefficients();
    let mut report = Report::new("couette", params, &["r_m", "u_theta_m_s", "dp_dr_Pa_m", "p_minus_p_Ri_Pa"]);
    report.summary("A in u = A r + B/r", a, "1/s");
    report.summary("B in u = A r + B/r", b, "m2/s");
    let mut points = Vec::new();
    for r in radii {
        let point = cell.point(r).map_err(err)?;
        report.rows.push(vec![r, point.tangential_velocity, rho * point.kinematic_pressure_gradient, rho * point.kinematic_pressure_rise]);
        points.push((r, point.tangential_velocity));
    }
    report.notes.push("dp/dr = +rho u^2/r (sign erratum of thesis Eq. 5.1 corrected)".into());
    report.plot = plot_spec("Circular Couette flow", "radius [m]", "u_theta [m/s]", false, vec![Curve { label: "exact".into(), points }]);
    Ok(report)
}

pub(super) fn run_hertz(params: &Params) -> Result<Report, String> {
    use an::hertz::{collision_time, hertz_damping_coefficient, openfoam_collision_constant, ContactPair, ElasticMaterial};
    let material = ElasticMaterial::new(params.number("e")?, params.number("poisson")?, params.number("rho")?).map_err(err)?;
    let radius = 0.5 * params.number("d")?;
    let pair = match params.text("partner") {
        "wall" => ContactPair::sphere_rigid_wall(&material, radius),
        "sphere" => ContactPair::sphere_sphere(&material, radius, &material, radius),
        other => return Err(format!("--partner = `{other}`: allowed values are `wall` and `sphere`")),
    }
    .map_err(err)?;
    let alpha = hertz_damping_coefficient(params.number("restitution")?).map_err(err)?;
    let mut report = Report::new("hertz", params, &["u_m_s", "max_overlap_m", "max_force_N", "contact_time_s", "t_col_openfoam_s"]);
    report.summary("effective radius R*", pair.effective_radius, "m");
    report.summary("effective mass M*", pair.effective_mass, "kg");
    report.summary("effective modulus E*", pair.effective_modulus, "Pa");
    report.summary("normal stiffness k_n", pair.normal_stiffness(), "N/m^1.5");
    report.summary("tangential stiffness k_t", pair.tangential_stiffness(), "N/m^1.5");
    report.summary("damping coefficient alpha_eta (Eq. 3.101)", alpha, "-");
    let mut points = Vec::new();
    for u in params.list("u", Spacing::Log(10))? {
        let impact = pair.elastic_impact(u).map_err(err)?;
        let t_col = collision_time(openfoam_collision_constant(), material.density, pair.effective_modulus, radius, u).map_err(err)?;
        report.rows.push(vec![u, impact.max_overlap, impact.max_force, impact.contact_time, t_col]);
        points.push((u, impact.contact_time));
    }
    report.plot = plot_spec("Undamped Hertz contact time", "impact speed [m/s]", "contact time [s]", true, vec![Curve { label: "exact".into(), points }]);
    Ok(report)
}

pub(super) fn run_walton(params: &Params) -> Result<Report, String> {
    use an::oblique_impact::{ImpactRegime, WaltonModel, SOLID_SPHERE_INERTIA_FACTOR};
    let model = WaltonModel::new(params.number("mu")?, params.number("e-n")?, params.number("e-t")?, SOLID_SPHERE_INERTIA_FACTOR).map_err(err)?;
    let mut report = Report::new("walton", params, &["psi_in", "psi_out", "slip(1)/stick(0)"]);
    report.summary("critical psi*", model.critical_psi(), "-");
    report.summary("slip offset 3.5 mu (1 + e_n)", model.slip_offset(), "-");
    let mut points = Vec::new();
    for psi in params.list("psi", Spacing::Linear(22))? {
        let r = model.rebound(psi).map_err(err)?;
        report.rows.push(vec![psi, r.psi_out, if r.regime == ImpactRegime::Slip { 1.0 } else { 0.0 }]);
        points.push((psi, r.psi_out));
    }
    report.plot = plot_spec("Walton oblique impact", "psi_in [-]", "psi_out [-]", false, vec![Curve { label: "Eq. 2.13".into(), points }]);
    Ok(report)
}

pub(super) fn run_erosion(params: &Params) -> Result<Report, String> {
    use an::erosion::*;
    let material = match params.text("material") {
        "cs1018" => CARBON_STEEL_1018,
        "ss316" => STAINLESS_STEEL_316,
        other => return Err(format!("--material = `{other}`: allowed values are cs1018 and ss316")),
    };
    let angle_function = match params.text("angle-function") {
        "literal" => AngleFunction::ThesisLiteral,
        "continuous" => AngleFunction::Continuous,
        other => return Err(format!("--angle-function = `{other}`: allowed values are literal and continuous")),
    };
    let include_c = match params.text("include-c") {
        "true" => true,
        "false" => false,
        other => return Err(format!("--include-c = `{other}`: allowed values are true and false")),
    };
    let options = ArabnejadOptions { include_cutting_coefficient: include_c, angle_function, ..ArabnejadOptions::default() };
    let (speed, d, rho_p) = (params.number("u")?, params.number("d")?, params.number("rho-p")?);
    if !(d > 0.0 && rho_p > 0.0) {
        return Err(format!("--d and --rho-p must be > 0 (got {d}, {rho_p})"));
    }
    let mass = rho_p * std::f64::consts::PI * d.powi(3) / 6.0;
    let mut report = Report::new("erosion", params, &["angle_deg", "W_arabnejad", "W_cutting", "W_deformation", "mass_arabnejad_kg", "mass_dnv_kg", "ER_ecrc"]);
    report.summary("particle mass", mass, "kg");
    report.summary("critical angle atan K", critical_angle(material.contact_ratio).to_degrees(), "deg");
    let mut points = Vec::new();
    for deg in params.list("angle", Spacing::Linear(18))? {
        let angle = deg.to_radians().min(std::f64::consts::FRAC_PI_2);
        let w = arabnejad_wear(&material, &options, mass, rho_p, speed, angle).map_err(err)?;
        let dnv = dnv_removed_mass(DNV_STEEL_K, DNV_STEEL_N, mass, speed, angle).map_err(err)?;
        let ecrc = ecrc_erosion_ratio(ECRC_STEEL_C, ECRC_STEEL_N, 120.0, material.sharpness, speed, angle).map_err(err)?;
        report.rows.push(vec![deg, w.volume, w.cutting_volume, w.deformation_volume, w.mass, dnv, ecrc]);
        points.push((deg, w.volume));
    }
    report.notes.push(
        "W in the printed (Table 4.1/5.2) units, see wear-model.md §6.7; DNV and E/CRC use literature constants for steel (E/CRC with Brinell 120)".into(),
    );
    report.plot = plot_spec(
        "Erosion per impact (Arabnejad)",
        "impact angle [deg]",
        "removed volume W",
        false,
        vec![Curve { label: params.text("material").into(), points }],
    );
    Ok(report)
}

pub(super) fn run_interface(params: &Params) -> Result<Report, String> {
    use an::sliding_interface::{map_values, overlap_weights};
    let source = params.list("source", Spacing::Linear(1))?;
    let targets = params.number("targets")?;
    if !(targets >= 1.0 && targets.fract() == 0.0 && targets <= 10_000.0) {
        return Err(format!("--targets = {targets}: must be a whole number in [1, 10000]"));
    }
    let n_s = source.len();
    let source_edges: Vec<f64> = (0..=n_s).map(|i| 2.0 * i as f64 / n_s as f64).collect();
    let target_edges: Vec<f64> = (0..=targets as usize).map(|j| 2.0 * j as f64 / targets).collect();
    let weights = overlap_weights(&source_edges, &target_edges).map_err(err)?;
    let mapped = map_values(&weights, &source).map_err(err)?;
    let mut report = Report::new("interface", params, &["target_face", "q_target", "weight_row_sum"]);
    for (j, (q, row)) in mapped.iter().zip(&weights).enumerate() {
        report.rows.push(vec![j as f64 + 1.0, *q, row.iter().sum()]);
    }
    let area_s: f64 = source.iter().map(|q| q * 2.0 / n_s as f64).sum();
    let area_t: f64 = mapped.iter().map(|q| q * 2.0 / targets).sum();
    report.summary("sum A q (source)", area_s, "");
    report.summary("sum A q (target)", area_t, "");
    report.notes.push("thesis example prints [3, 5, 8, 9]; its own weights give [3, 5, 7, 9] (erratum)".into());
    Ok(report)
}
