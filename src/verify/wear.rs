//! Wear checks (wear-model.md §6, §7, §15): a stream of identical particles against a plate,
//! run through the whole step (DEM impacts → erosion law → deposit → smoothing → receding
//! wall) and compared with the erosion law of the `analytic` crate and with the volume
//! bookkeeping; the Coriolis tester's wear profile (§12.4); and, in `jet.rs`, a jet on a
//! receding plate against a still one (§12.3).

use std::path::Path;

use anyhow::{anyhow, bail, Context, Result};
use spillage_analytic::erosion::{arabnejad_wear, AngleFunction, ArabnejadMaterial, ArabnejadOptions};
use spillage_fast::fluid::FastFluid;
use spillage_model::case::Case;
use spillage_model::output::plot::{write_png, Plot, Series};
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::step::{reached_end_time, Coupled};
use spillage_model::walls::state::Vec3;
use spillage_model::wear::profile::{wear_profile, UnwornWalls};
use spillage_model::wear::settings::{AngleFunctionForm, ErosionLawName};
use spillage_model::wear::surface::WearSurface;
use spillage_reference::dem::ReferenceDem;
use spillage_reference::wear::ReferenceWear;

use super::CheckRow;

mod jet;

/// Checks implemented here.
pub const CHECKS: &[&str] = &["wear_stream", "wear_profile", "wear_jet"];

pub fn run_check(case: &Case, check: &str, full: bool, plots: Option<&Path>) -> Result<Vec<CheckRow>> {
    match check {
        "wear_stream" => stream(case, full, plots),
        "wear_profile" => profile(case, full, plots),
        "wear_jet" => jet::jet(case, full, plots),
        other => bail!("unknown wear check `{other}`; known: {}", CHECKS.join(", ")),
    }
}

const SOLVER: &str = "reference";

fn params(case: &Case) -> Result<&toml::Table> {
    case.verify.as_ref().map(|v| &v.params).ok_or_else(|| anyhow!("{}: no [verify] section", case.path.display()))
}

fn number(case: &Case, key: &str) -> Result<f64> {
    let v = params(case)?.get(key).ok_or_else(|| anyhow!("{}: [verify.params] needs `{key}`", case.path.display()))?;
    v.as_float().or_else(|| v.as_integer().map(|i| i as f64)).ok_or_else(|| anyhow!("verify.params.{key}: {v} is not a number"))
}

fn numbers(case: &Case, key: &str) -> Result<Vec<f64>> {
    let value = params(case)?.get(key).ok_or_else(|| anyhow!("{}: [verify.params] needs `{key}`", case.path.display()))?;
    let array = value.as_array().ok_or_else(|| anyhow!("{}: verify.params.{key} must be a list of numbers", case.path.display()))?;
    array.iter().map(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)).ok_or_else(|| anyhow!("verify.params.{key}: {v} is not a number"))).collect()
}

/// Runs a wear case to its end time with the reference DEM and wear phase (and the fast fluid
/// when the case has one).
pub fn run_to_end(case: &Case) -> Result<State> {
    run_sampling(case, |_| Ok(()))
}

/// [`run_to_end`], handing the state to `sample` at the start and after every step.
fn run_sampling(case: &Case, mut sample: impl FnMut(&State) -> Result<()>) -> Result<State> {
    let end = case.time.end_time.ok_or_else(|| anyhow!("{}: wear checks need [time] end_time", case.path.display()))?;
    let mut run = start(case)?;
    sample(run.state())?;
    while !reached_end_time(run.state().time, end) {
        run.step().with_context(|| format!("case {}", case.case.name))?;
        sample(run.state())?;
    }
    Ok(run.state().clone())
}

/// The run of a wear case as the checks step it: the reference DEM and wear phase, and the
/// fast fluid when the case has one.
fn start(case: &Case) -> Result<Box<dyn Solver>> {
    let mut state = State::default();
    Ok(if case.fluid.is_some() {
        let mesh = super::fluid::build_mesh(case)?;
        let fluid = FastFluid::new(case, mesh, &mut state)?;
        let dem = ReferenceDem::new(case, &mut state)?;
        let wear = ReferenceWear::new(case, &mut state)?;
        Box::new(Coupled::new(case, state, Some(fluid), Some(dem))?.with_wear(Box::new(wear))?)
    } else {
        let dem = ReferenceDem::new(case, &mut state)?;
        let wear = ReferenceWear::new(case, &mut state)?;
        Box::new(Coupled::particles_only(case, state, dem)?.with_wear(Box::new(wear))?)
    })
}

/// The stream case with its particles aimed at `angle` (from the plate) at the same speed.
fn aimed(base: &Case, angle_deg: f64) -> Result<Case> {
    let mut case = base.clone();
    let feed =
        case.particles.as_mut().and_then(|p| p.feed.first_mut()).ok_or_else(|| anyhow!("{}: the stream needs a [[particles.feed]]", base.path.display()))?;
    let speed = feed.velocity.iter().map(|v| v * v).sum::<f64>().sqrt();
    let a = angle_deg.to_radians();
    feed.velocity = [speed * a.cos(), 0.0, -speed * a.sin()];
    feed.rate = number(base, "sweep_rate")?;
    feed.end = Some(number(base, "sweep_feed_end")?);
    case.time.end_time = Some(number(base, "sweep_end_time")?);
    Ok(case)
}

/// `wear_stream`: (1) at each angle of `angles_deg`, the removed volume per unit mass of the
/// particles that hit equals the analytic law at that speed and angle, and the angle of the
/// largest wear is the law's; (2) the full stream: Σ per-impact volumes = Σ deposited on the
/// triangles = receded + still smoothing, and the receded volume = the wall's geometric
/// volume change.
fn stream(base: &Case, full: bool, plots: Option<&Path>) -> Result<Vec<CheckRow>> {
    let name = base.case.name.as_str();
    let section = base.wear.as_ref().ok_or_else(|| anyhow!("{}: the wear checks need [wear]", base.path.display()))?;
    if section.law != ErosionLawName::Arabnejad {
        bail!("{}: wear_stream compares with the Arabnejad law; the case has {:?}", base.path.display(), section.law);
    }
    let c = section.material.constants().map_err(|e| anyhow!("{}: {} = {}: {}", base.path.display(), e.key, e.value, e.allowed))?;
    let material = ArabnejadMaterial {
        density: c.density,
        cutting_coefficient: c.cutting_coefficient,
        vickers_hardness: c.vickers_hardness,
        sharpness: c.sharpness,
        contact_ratio: c.contact_ratio,
        deformation_factor: c.deformation_factor,
        threshold_velocity: c.threshold_velocity,
    };
    let options = ArabnejadOptions {
        angle_function: match section.angle_function {
            AngleFunctionForm::ThesisLiteral => AngleFunction::ThesisLiteral,
            AngleFunctionForm::Continuous => AngleFunction::Continuous,
        },
        ..ArabnejadOptions::default()
    };
    let feed = base.particles.as_ref().and_then(|p| p.feed.first()).ok_or_else(|| anyhow!("no feed"))?;
    let material_name = &feed.material;
    let particle = base.particles.as_ref().and_then(|p| p.materials.iter().find(|m| &m.name == material_name)).ok_or_else(|| anyhow!("no feed material"))?;
    let diameter = feed.diameter.largest();
    let mass = particle.density * std::f64::consts::PI * diameter.powi(3) / 6.0;
    let speed = feed.velocity.iter().map(|v| v * v).sum::<f64>().sqrt();
    let scale = base.particle_modifier() * section.acceleration;

    let mut rows = Vec::new();
    let (mut measured, mut exact) = (Vec::new(), Vec::new());
    for angle in numbers(base, "angles_deg")? {
        let case = aimed(base, angle)?;
        let state = run_to_end(&case)?;
        let wear = state.wear.as_ref().ok_or_else(|| anyhow!("no wear state"))?;
        let impacts: u64 = wear.walls.iter().flat_map(|w| &w.triangle_impacts).sum();
        if impacts == 0 {
            bail!("{name}: no particle hit the plate at {angle}°");
        }
        let deposited: f64 = wear.walls.iter().map(|w| w.deposited).sum();
        let created = state.particles.as_ref().map_or(0, |p| p.counts.created);
        // one particle per angle: a stream would rebound into its own incoming particles
        rows.push(CheckRow::absolute(name, format!("impacts of the one particle at {angle}°"), SOLVER, impacts as f64, created as f64, 0.0));
        let per_mass = deposited / scale / (impacts as f64 * mass);
        let law = arabnejad_wear(&material, &options, mass, particle.density, speed, angle.to_radians()).map_err(|e| anyhow!("analytic: {e}"))?;
        let reference = law.volume / mass;
        // identical particles at first touch: the DEM sees the feed velocity exactly, so only
        // round-off separates the two codes' evaluations of the law
        rows.push(CheckRow::relative(name, format!("removed volume per particle mass [m³/kg] at {angle}°, {speed} m/s"), SOLVER, per_mass, reference, 1e-10));
        measured.push((angle, per_mass));
        exact.push((angle, reference));
    }
    let argmax = |v: &[(f64, f64)]| v.iter().copied().fold((f64::NAN, f64::NEG_INFINITY), |best, p| if p.1 > best.1 { p } else { best }).0;
    rows.push(CheckRow::absolute(name, "angle of the largest wear rate among the angles run [°]", SOLVER, argmax(&measured), argmax(&exact), 0.0));
    if let Some(dir) = plots {
        std::fs::create_dir_all(dir)?;
        let dense: Vec<(f64, f64)> = (0..=180)
            .map(|k| 0.5 * k as f64)
            .filter_map(|a| arabnejad_wear(&material, &options, mass, particle.density, speed, a.to_radians()).ok().map(|w| (a, w.volume / mass)))
            .collect();
        let title = format!("{name}: wear per particle mass at {speed} m/s");
        write_png(
            &Plot {
                title: &title,
                x_label: "impact angle from the surface [°]",
                y_label: "removed wall volume per particle mass [m³/kg]",
                log_x: false,
                log_y: false,
                series: vec![Series { label: "analytic (Arabnejad, §6.4)", points: &dense }, Series { label: "simulated stream", points: &measured }],
            },
            &dir.join(format!("{name}_angle.png")),
        )?;
    }

    // the stream as the case gives it (coarse: the first part of it)
    let mut case = base.clone();
    if !full {
        case.time.end_time = Some(number(base, "coarse_end_time")?);
    }
    let state = run_to_end(&case)?;
    let wear = state.wear.as_ref().ok_or_else(|| anyhow!("no wear state"))?;
    let impacts: u64 = wear.walls.iter().flat_map(|w| &w.triangle_impacts).sum();
    let law_total: f64 = wear.walls.iter().map(|w| scale * (w.law_cutting + w.law_deformation)).sum();
    let on_triangles: f64 = wear.walls.iter().flat_map(|w| &w.triangle_volume).sum();
    let minimum = number(base, if full { "full_min_impacts" } else { "coarse_min_impacts" })?;
    rows.push(CheckRow::at_least(name, "impacts on the plate (the stream)", SOLVER, impacts as f64, minimum));
    // sums of the same numbers in different orders: round-off of a sum of n terms
    rows.push(CheckRow::relative(name, "Σ deposited on the triangles vs Σ per-impact volumes (relative)", SOLVER, on_triangles, law_total, 1e-12));
    rows.extend(budget_rows(name, &case, &state)?);
    if let (Some(dir), Some(line)) = (plots, section.profile.as_ref()) {
        let depth: Vec<(f64, f64)> =
            wear_profile(line, &UnwornWalls::of_case(&case)?, wear).iter().filter(|b| b.area > 0.0).map(|b| (b.distance, b.depth)).collect();
        draw_profile(dir, name, &state, &depth, None)?;
    }
    Ok(rows)
}

/// The volume budget at the end of a run, measured on the geometry independently of the wear
/// phase's own bookkeeping (the walls as the case builds them, unworn, against the walls at the
/// end): deposited = receded + still smoothing (§7.3 identity), and the receded volume = the
/// walls' geometric volume change.
fn budget_rows(name: &str, case: &Case, state: &State) -> Result<Vec<CheckRow>> {
    let wear = state.wear.as_ref().ok_or_else(|| anyhow!("no wear state"))?;
    let walls = state.walls.as_ref().ok_or_else(|| anyhow!("no walls"))?;
    let damping = case.wear.as_ref().and_then(|w| w.smoothing.as_ref()).map(|s| s.damping);
    let dir = case.path.parent().map(|p| p.to_path_buf()).unwrap_or_default();
    let unworn = spillage_model::walls::build(case, &dir)?;
    let (mut in_flight, mut geometric, mut representable) = (0.0, 0.0, 0.0);
    for w in &wear.walls {
        let before = &unworn.walls[w.wall];
        let surface = WearSurface::new(&before.vertices, &before.triangles);
        in_flight += w.in_flight(&surface.node_area, damping);
        let (nodes_before, nodes_after) = (surface.nodes(&before.vertices), surface.nodes(&walls.walls[w.wall].vertices));
        let origin = nodes_before.iter().fold(Vec3::zeros(), |a, p| a + p) / nodes_before.len() as f64;
        geometric += w.material_side * (surface.cone_volume(&nodes_after, origin) - surface.cone_volume(&nodes_before, origin));
        // a vertex moves in steps of its coordinates' ulp: the wall's volume is known only to a
        // sheet that thin over its area (9e-21 m³ on the Coriolis coupon, x ≤ 0.147 m)
        let extent = nodes_after.iter().flat_map(|p| p.iter()).fold(0.0f64, |m, c| m.max(c.abs()));
        representable += f64::EPSILON * extent * surface.node_area.iter().sum::<f64>();
    }
    let deposited: f64 = wear.walls.iter().map(|w| w.deposited).sum();
    let receded: f64 = wear.walls.iter().map(|w| w.receded).sum();
    let pending: f64 = wear.walls.iter().map(|w| w.pending).sum();
    Ok(vec![
        // the discrete identity holds to the direct solves' round-off
        CheckRow::relative(name, "receded + still smoothing vs deposited (relative; §7.3 identity)", SOLVER, receded + pending + in_flight, deposited, 1e-12),
        // the bound: each step's recession is solved to 1e-12 of its volume; plus what
        // the vertex coordinates can represent, which only matters for a wall worn by a few
        // nanometres (the fine sand's 15 ms: 2.3e-14 m³ over the coupon, 5e-9 relative)
        CheckRow::relative(
            name,
            "wall geometric volume change vs receded volume (relative)",
            SOLVER,
            geometric,
            receded,
            1e-9 + if receded > 0.0 { representable / receded } else { 0.0 },
        ),
    ])
}

/// The wear profile of a case with `[wear.profile]` (the Coriolis tester, §12.4): its largest
/// peak `first_peak` m from the profile's start within `first_peak_tolerance`, then a dip and a
/// second region whose peak is `second_ratio[0]`…`[1]` of the first; with the bookkeeping rows.
/// The coarse level runs `coarse_end_time` with the feed thinned by `coarse_modifier` (each
/// particle then stands for that many more, `[particles] modifier`).
fn profile(base: &Case, full: bool, plots: Option<&Path>) -> Result<Vec<CheckRow>> {
    let name = base.case.name.as_str();
    let mut case = base.clone();
    if !full {
        case.time.end_time = Some(number(base, "coarse_end_time")?);
        let thinning = number(base, "coarse_modifier")?;
        if let Some(p) = case.particles.as_mut() {
            p.feed.iter_mut().for_each(|feed| feed.rate /= thinning);
            p.modifier *= thinning;
        }
    }
    let section = case.wear.clone().ok_or_else(|| anyhow!("{}: the wear checks need [wear]", base.path.display()))?;
    let line = section.profile.clone().ok_or_else(|| anyhow!("{}: wear_profile needs [wear.profile]", base.path.display()))?;
    let state = run_to_end(&case)?;
    let wear = state.wear.as_ref().ok_or_else(|| anyhow!("no wear state"))?;
    let bins = wear_profile(&line, &UnwornWalls::of_case(&case)?, wear);
    let depth: Vec<(f64, f64)> = bins.iter().filter(|b| b.area > 0.0).map(|b| (b.distance, b.depth)).collect();
    let peaks = profile_peaks(&depth);
    let mut rows = Vec::new();
    let impacts: u64 = wear.walls.iter().flat_map(|w| &w.triangle_impacts).sum();
    rows.push(CheckRow::at_least(
        name,
        "impacts on the eroding walls",
        SOLVER,
        impacts as f64,
        number(base, if full { "min_impacts" } else { "coarse_min_impacts" })?,
    ));
    rows.push(CheckRow::absolute(
        name,
        "distance of the deepest wear from the profile start [m]",
        SOLVER,
        peaks.first.0,
        number(base, "first_peak")?,
        number(base, "first_peak_tolerance")?,
    ));
    let second_region = params(base)?.get("second_region").and_then(|v| v.as_bool()).unwrap_or(true);
    if full && !second_region {
        // one broad region: no dip followed by a rise of a quarter (0 when there is none)
        let ratio = if peaks.second_ratio.is_nan() { 0.0 } else { peaks.second_ratio };
        rows.push(CheckRow::at_most(name, "second wear region after a dip: its peak over the first (none expected)", SOLVER, ratio, 0.0));
    } else if full {
        // the second region builds up from rebounds over the whole run (the thesis: it appears
        // at t = 0.01 s): the coarse level's 8 ms cannot show it
        let ratio = numbers(base, "second_ratio")?;
        let (lo, hi) = (ratio[0], ratio[1]);
        rows.push(CheckRow::absolute(
            name,
            "second wear region: its peak over the first (after a dip; NaN without one)",
            SOLVER,
            peaks.second_ratio,
            0.5 * (lo + hi),
            0.5 * (hi - lo),
        ));
    }
    rows.extend(budget_rows(name, &case, &state)?);
    if let Some(dir) = plots {
        draw_profile(dir, name, &state, &depth, Some(number(base, "first_peak")?))?;
    }
    Ok(rows)
}

/// The wear profile normalised by its peak, with the expected position of the peak if given:
/// `DIR/<case>_profile.png`.
fn draw_profile(dir: &Path, name: &str, state: &State, depth: &[(f64, f64)], expected_peak: Option<f64>) -> Result<()> {
    std::fs::create_dir_all(dir)?;
    let top = depth.iter().map(|p| p.1).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    let normalised: Vec<(f64, f64)> = depth.iter().map(|(x, d)| (1e3 * x, d / top)).collect();
    let title = format!("{name}: wear depth / its peak (t = {:.4} s)", state.time);
    let mut series = vec![Series { label: "simulated", points: &normalised }];
    let (label, marker);
    if let Some(x) = expected_peak {
        label = format!("expected deepest wear ({:.0} mm)", 1e3 * x);
        marker = vec![(1e3 * x, 0.0), (1e3 * x, 1.0)];
        series.push(Series { label: &label, points: &marker });
    }
    let plot = Plot { title: &title, x_label: "distance along the profile line [mm]", y_label: "depth / peak depth [-]", log_x: false, log_y: false, series };
    write_png(&plot, &dir.join(format!("{name}_profile.png")))?;
    Ok(())
}

/// The largest peak of a profile and the ratio of the largest peak downstream of it, beyond
/// the deepest dip that follows, to it; NaN when the profile never rises again by a quarter
/// above that dip (a single wear region). An unworn profile has neither (NaN).
struct Peaks {
    first: (f64, f64),
    second_ratio: f64,
}

fn profile_peaks(profile: &[(f64, f64)]) -> Peaks {
    // an unworn profile has no peak (not the last of its equal zeros)
    let Some((k, &first)) = profile.iter().enumerate().filter(|(_, p)| p.1 > 0.0).max_by(|a, b| a.1 .1.total_cmp(&b.1 .1)) else {
        return Peaks { first: (f64::NAN, f64::NAN), second_ratio: f64::NAN };
    };
    let after = &profile[k..];
    // the deepest dip that has a rise after it: scan for the best (rise over the dip)
    let mut best: Option<(f64, f64)> = None;
    for (i, dip) in after.iter().enumerate() {
        let Some(rise) = after[i..].iter().map(|p| p.1).reduce(f64::max) else { continue };
        if rise > 1.25 * dip.1 && rise > 0.0 && best.is_none_or(|(_, r)| rise > r) {
            best = Some((dip.1, rise));
        }
    }
    Peaks { first, second_ratio: best.map_or(f64::NAN, |(_, rise)| rise / first.1) }
}

#[cfg(test)]
mod tests {
    use super::profile_peaks;

    #[test]
    fn peaks_of_a_profile() {
        // two regions: the second (0.5) after a dip (0.1) to half the first
        let two = [(0.0, 0.0), (1.0, 1.0), (2.0, 0.1), (3.0, 0.5), (4.0, 0.2)];
        let p = profile_peaks(&two);
        assert_eq!(p.first, (1.0, 1.0));
        assert_eq!(p.second_ratio, 0.5);
        // one region falling away: no second
        assert!(profile_peaks(&[(0.0, 0.2), (1.0, 1.0), (2.0, 0.6), (3.0, 0.55)]).second_ratio.is_nan());
        // unworn: no peak anywhere (not at the last bin)
        let none = profile_peaks(&[(0.0, 0.0), (1.0, 0.0), (2.0, 0.0)]);
        assert!(none.first.0.is_nan() && none.second_ratio.is_nan());
    }
}
