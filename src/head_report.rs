//! What `spillage run` tells a user at the end of a cutter-head run: production and spillage
//! fractions (Eq. 8.6), the out-flowing flux over Q_m averaged over the last revolution (the
//! thesis averaged the last one, §5.1), where the spilled particles left (Fig. 8.8), and the
//! plots that show it: `plots/spillage_heights.png`, `plots/fractions.png`,
//! `plots/hull_flux.png`. The histogram is also written as `spillage_heights.csv`.

use std::fmt::Write as _;
use std::path::Path;

use spillage_model::case::Case;
use spillage_model::cutter_head::spillage::{exit_height_histogram, steady_spillage, SpillageCounts, EXIT_BIN};
use spillage_model::cutter_head::CutterHead;
use spillage_model::output::plot::{write_png, Plot, Series};
use spillage_model::output::series::read_series;
use spillage_model::state::State;

use crate::sweep::table::{window_mean, WindowRule};

/// Writes the head's files and plots and returns the lines to print; empty without a head.
pub fn report(case: &Case, state: &State, out: &Path) -> anyhow::Result<Vec<String>> {
    let Some(section) = &case.cutter_head else { return Ok(Vec::new()) };
    let head = CutterHead::new(section);
    let mut lines = Vec::new();
    if section.has_current() {
        // the current past the head (cutter_head::current), as `spillage check` prints it
        let tip = case.rotor.as_ref().map_or(0.0, |r| r.angular_velocity().abs()) * section.contour[0][1];
        lines.push(format!("haul velocity     {}", spillage::check::haul_line(section, tip).trim_start().trim_start_matches("haul velocity ")));
    }
    let plots = out.join("plots");
    std::fs::create_dir_all(&plots)?;
    let series_path = out.join("series.csv");
    if series_path.exists() {
        let table = read_series(&series_path)?;
        if let (Some(time), Some(outflow)) = (table.column("time"), table.column("hull_outflow")) {
            let end = time.last().copied().unwrap_or(0.0);
            // the sweep's window and its time-weighted mean (the `_mean` columns): the
            // Courant-controlled step is not uniform
            let rule = WindowRule::for_case(case);
            let window = rule.window(end);
            let window_mean = |values: &[f64]| window_mean(&time, values, window).unwrap_or(f64::NAN);
            let mean = window_mean(&outflow);
            let window_text = match rule {
                WindowRule::LastRevolution { period } if end >= period => "the last revolution".to_string(),
                WindowRule::LastRevolution { period } => format!("the {:.2} revolutions run", end / period),
                WindowRule::LastTenth => "the last 10 % of the run (the rotor stands)".to_string(),
            };
            let q_m = head.suction_discharge;
            lines.push(format!(
                "out-flowing flux  {mean:.4} m³/s = {:.3} Q_m through the cells' hull (Eq. 8.4, mean over {window_text}; Q_m = {q_m} m³/s)",
                mean / q_m
            ));
            if let (Some(contour), Some(net)) = (table.column("contour_outflow"), table.column("contour_net_flux")) {
                // the thesis' measure: velocities interpolated onto r = R(z) (cutter_head::hull_surface)
                let (mean, net) = (window_mean(&contour), window_mean(&net));
                lines.push(format!(
                    "                  {mean:.4} m³/s = {:.3} Q_m through the contour R(z) (Eqs. 8.1–8.4, interpolated; net inflow {:.3} Q_m)",
                    mean / q_m,
                    -net / q_m
                ));
            }
            if let Some(torque) = table.column("head_torque") {
                // the rotor's torque on the water and the shaft power T ω (cutter_head::torque)
                let mean = window_mean(&torque);
                lines.push(format!(
                    "head torque       {mean:.2} N m, shaft power {:.1} W (mean over {window_text})",
                    mean * case.rotor.as_ref().map_or(0.0, |r| r.angular_velocity())
                ));
            }
            let q_m: Vec<(f64, f64)> = time.iter().map(|t| (*t, head.suction_discharge)).collect();
            let q_out: Vec<(f64, f64)> = time.iter().copied().zip(outflow.iter().copied()).collect();
            let mut series = vec![
                Series { label: "out-flowing flux Q_out through the cells' hull (Eq. 8.4)", points: &q_out },
                Series { label: "suction discharge Q_m", points: &q_m },
            ];
            let (net, contour): (Vec<(f64, f64)>, Vec<(f64, f64)>);
            if let Some(c) = table.column("contour_outflow") {
                contour = time.iter().copied().zip(c).collect();
                series.push(Series { label: "out-flowing flux through the contour R(z) (Eqs. 8.1–8.4)", points: &contour });
            }
            if let Some(n) = table.column("hull_net_flux") {
                net = time.iter().copied().zip(n.iter().map(|q| -q)).collect();
                series.push(Series { label: "net inflow through the hull", points: &net });
            }
            let title = format!("{}: flux through the contour hull", case.case.name);
            write_png(&Plot { title: &title, x_label: "time [s]", y_label: "flux [m³/s]", log_x: false, log_y: false, series }, &plots.join("hull_flux.png"))?;
        }
        if let (Some(time), Some(production), Some(spillage)) = (table.column("time"), table.column("production"), table.column("spillage")) {
            let p: Vec<(f64, f64)> = time.iter().copied().zip(production).collect();
            let s: Vec<(f64, f64)> = time.iter().copied().zip(spillage).collect();
            let title = format!("{}: production and spillage (Eq. 8.6)", case.case.name);
            let series = vec![Series { label: "production P = sucked / created", points: &p }, Series { label: "spillage S = spilled / created", points: &s }];
            write_png(
                &Plot { title: &title, x_label: "time [s]", y_label: "fraction of the particles [-]", log_x: false, log_y: false, series },
                &plots.join("fractions.png"),
            )?;
        }
    }
    if let Some(particles) = &state.particles {
        let counts = SpillageCounts::from_exits(&particles.exits);
        let created = particles.counts.created.max(1) as f64;
        lines.push(format!(
            "production        {:.1} % ({} of {} particles sucked)",
            100.0 * counts.sucked as f64 / created,
            counts.sucked,
            particles.counts.created
        ));
        lines.push(format!(
            "spillage          {:.1} % ({} spilled, {} still in the head)",
            100.0 * counts.spilled as f64 / created,
            counts.spilled,
            particles.particles.len()
        ));
        if case.particles.as_ref().is_some_and(|p| !p.feed.is_empty()) {
            // the feed's steady state: the second half of the run
            match steady_spillage(&particles.exits, 0.5 * state.time) {
                Some(s) => lines.push(format!(
                    "steady spillage   {:.1} % of the {} particles that left in the second half of the run (95 % interval {:.1}–{:.1} %)",
                    100.0 * s.fraction,
                    s.exits,
                    100.0 * s.low,
                    100.0 * s.high
                )),
                None => lines.push("steady spillage   no particle left in the second half of the run: run longer".to_string()),
            }
        }
        let bins = exit_height_histogram(&head, &particles.exits);
        let mut csv = String::from("bin_top_z_m,bin_bottom_z_m,spilled\n");
        for (top, n) in &bins {
            // + 0.0 turns the first bin's −0 into 0
            writeln!(csv, "{:.3},{:.3},{n}", top + 0.0, top - EXIT_BIN)?;
        }
        std::fs::write(out.join("spillage_heights.csv"), csv)?;
        if counts.spilled > 0 {
            let top_share = bins[0].1 as f64 / counts.spilled as f64;
            lines.push(format!(
                "where             {:.0} % of the spilled particles left 0–{:.0} cm under the ring (axially, toward the hub; spillage_heights.csv; gravity pulls {})",
                100.0 * top_share,
                100.0 * EXIT_BIN,
                spillage_model::cutter_head::ladder::LadderTilt::of(case.physics.gravity).pull_name()
            ));
            // a bar outline: count against the bin's height, the ring at the top (z = 0)
            let outline: Vec<(f64, f64)> = bins.iter().flat_map(|(top, n)| [(*n as f64, top * 100.0), (*n as f64, (top - EXIT_BIN) * 100.0)]).collect();
            let title = format!("{}: where the spilled particles left (Fig. 8.8)", case.case.name);
            let series = vec![Series { label: "spilled particles per 3 cm bin", points: &outline }];
            write_png(
                &Plot { title: &title, x_label: "spilled particles [-]", y_label: "height z [cm] (ring 0, hub −H)", log_x: false, log_y: false, series },
                &plots.join("spillage_heights.png"),
            )?;
        }
    }
    Ok(lines)
}
