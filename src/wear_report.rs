//! What `spillage run` tells a user at the end of a run with `[wear]`: the volume and mass the
//! walls lost, the deepest point, the bookkeeping (impacts → smoothing → geometry), and with
//! `[wear.profile]` the wear profile as `wear_profile.csv` and `plots/wear_profile.png`.

use std::fmt::Write as _;
use std::path::Path;

use spillage_model::case::Case;
use spillage_model::output::plot::{write_png, Plot, Series};
use spillage_model::state::State;
use spillage_model::wear::profile::{wear_profile, UnwornWalls};

/// Writes the profile files and returns the lines to print; empty without `[wear]`.
pub fn report(case: &Case, state: &State, out: &Path) -> anyhow::Result<Vec<String>> {
    let (Some(section), Some(wear)) = (&case.wear, &state.wear) else { return Ok(Vec::new()) };
    let density = section.material.density.or_else(|| section.material.constants().ok().map(|c| c.density)).unwrap_or(f64::NAN);
    let mut lines = Vec::new();
    for w in &wear.walls {
        let impacts: u64 = w.triangle_impacts.iter().sum();
        let max_depth = w.node_depth.iter().fold(0.0, |m: f64, d| m.max(*d));
        let sliding = if section.sliding {
            format!(" ({:.1} % of it by sliding)", 100.0 * w.sliding_deposited / w.deposited.max(f64::MIN_POSITIVE))
        } else {
            String::new()
        };
        lines.push(format!(
            "wear {:<12} {impacts} impacts, {:.4e} m³ removed{sliding} ({:.4e} kg at {density} kg/m³), deepest {:.4e} m{}",
            w.name,
            w.deposited,
            w.deposited * density,
            max_depth,
            if section.receding { "" } else { " (static wall: depth as it would recede)" }
        ));
    }
    let deposited: f64 = wear.walls.iter().map(|w| w.deposited).sum();
    let receded: f64 = wear.walls.iter().map(|w| w.receded).sum();
    lines.push(format!(
        "wear bookkeeping  deposited {deposited:.6e} m³ = receded {receded:.6e} m³ + still smoothing {:.6e} m³ (× [particles] modifier {} × [wear] acceleration {})",
        deposited - receded,
        case.particle_modifier(),
        section.acceleration
    ));
    if let Some(profile) = &section.profile {
        let bins = wear_profile(profile, &UnwornWalls::of_case(case)?, wear);
        let mut csv = String::from("distance_m,depth_m,rate_m_per_s,volume_m3,impacts,area_m2\n");
        for b in &bins {
            writeln!(csv, "{},{},{},{},{},{}", b.distance, b.depth, b.rate, b.volume, b.impacts, b.area)?;
        }
        std::fs::write(out.join("wear_profile.csv"), csv)?;
        let covered: Vec<(f64, f64)> = bins.iter().filter(|b| b.area > 0.0).map(|b| (1e3 * b.distance, 1e6 * b.depth)).collect();
        if !covered.is_empty() {
            let plots = out.join("plots");
            std::fs::create_dir_all(&plots)?;
            let title = format!("{}: wear depth along the profile line (t = {:.4} s)", case.case.name, state.time);
            let x_label = format!("distance from ({}, {}, {}) m [mm]", profile.from[0], profile.from[1], profile.from[2]);
            write_png(
                &Plot {
                    title: &title,
                    x_label: &x_label,
                    y_label: "depth receded [µm]",
                    log_x: false,
                    log_y: false,
                    series: vec![Series { label: "wear depth", points: &covered }],
                },
                &plots.join("wear_profile.png"),
            )?;
            lines.push(format!("wear profile      {} (and plots/wear_profile.png)", out.join("wear_profile.csv").display()));
        } else {
            lines.push(format!(
                "wear profile      {}: every bin empty, the line passes over no triangle of the eroding walls (no plot; `spillage check` warns of it)",
                out.join("wear_profile.csv").display()
            ));
        }
    }
    Ok(lines)
}
