//! `spillage check`: validates a case file and prints the numbers derived from it, so a user
//! sees the cost and the stability margins before starting a run.

use std::path::Path;
use std::process::ExitCode;

use spillage_model::case::{Case, MeshSection};

mod head;
pub use head::haul_line;
use head::head_lines;

/// Derived numbers of a case, also used by the run summary.
#[derive(Debug, Default, serde::Serialize)]
pub struct Derived {
    pub cells: usize,
    /// Smallest cell edge [m].
    pub min_cell_size: Option<f64>,
    /// Largest velocity the boundary conditions impose [m/s].
    pub velocity_scale: Option<f64>,
    /// Courant number U·Δt/Δx_min from the imposed velocities (spec fluid-dem-model.md §8.9).
    pub courant_estimate: Option<f64>,
    /// Viscous diffusion number ν·Δt/Δx_min² (fixed Δt).
    pub diffusion_estimate: Option<f64>,
    /// Reynolds number U·L/ν with L the mesh's smallest extent.
    pub reynolds: Option<f64>,
    /// Fields and geometry in memory [bytes] (solver workspace not included).
    pub memory_estimate_bytes: usize,
}

pub fn derive(case: &Case) -> Derived {
    let mut d = Derived::default();
    if let Some(head) = &case.cutter_head {
        return derive_head(case, head).map_or(d, |d| with_diffusion(case, d));
    }
    let Some(mesh) = &case.mesh else { return d };
    d.cells = mesh.cell_count();
    let (min_size, extent, r_max) = match mesh {
        MeshSection::Box { min, max, cells, grading, two_d, .. } => {
            let mut smallest = f64::INFINITY;
            let mut extent = f64::INFINITY;
            // The single layer of a 2-D mesh limits neither the step nor the Reynolds number.
            for k in 0..if *two_d { 2 } else { 3 } {
                let len = max[k] - min[k];
                extent = extent.min(len);
                smallest = smallest.min(smallest_graded_cell(len, cells[k], grading[k]));
            }
            (smallest, extent, None)
        }
        MeshSection::Annulus { r_inner, r_outer, z_min, z_max, n_r, n_theta, n_z, radial_grading, two_d } => {
            let dr = smallest_graded_cell(r_outer - r_inner, *n_r, *radial_grading);
            let arc = r_inner * std::f64::consts::TAU / *n_theta as f64;
            let dz = if *two_d { f64::INFINITY } else { (z_max - z_min) / *n_z as f64 };
            (dr.min(arc).min(dz), r_outer - r_inner, Some(*r_outer))
        }
        // r_max: the rotor zone's outer radius (its fastest cells)
        MeshSection::RotorStator {
            r_inner,
            r_interface,
            r_outer,
            z_min,
            z_max,
            n_r_rotor,
            n_r_stator,
            n_theta_rotor,
            n_theta_stator,
            n_z,
            radial_grading,
            two_d,
        } => {
            let dr = smallest_graded_cell(r_interface - r_inner, *n_r_rotor, *radial_grading).min(smallest_graded_cell(
                r_outer - r_interface,
                *n_r_stator,
                *radial_grading,
            ));
            let arc = (r_inner * std::f64::consts::TAU / *n_theta_rotor as f64).min(r_interface * std::f64::consts::TAU / *n_theta_stator as f64);
            let dz = if *two_d { f64::INFINITY } else { (z_max - z_min) / *n_z as f64 };
            (dr.min(arc).min(dz), r_outer - r_inner, Some(*r_interface))
        }
    };
    d.min_cell_size = Some(min_size);
    // the fastest wall: a rotating boundary at its own radius (the inner circle at r_inner, the
    // outer one and the end walls out to r_outer), the rotor zone at its outer radius
    let (r_inner, r_outer) = match mesh {
        MeshSection::Annulus { r_inner, r_outer, .. } | MeshSection::RotorStator { r_inner, r_outer, .. } => (*r_inner, *r_outer),
        MeshSection::Box { .. } => (0.0, 0.0),
    };
    let mut speed: f64 = 0.0;
    for (name, bc) in &case.boundary {
        let radius = if name == "inner" { r_inner } else { r_outer };
        if let Some(u) = bc.imposed_speed(radius) {
            speed = speed.max(u);
        }
    }
    if let (Some(rotor), Some(r)) = (&case.rotor, r_max) {
        speed = speed.max(rotor.angular_velocity().abs() * r);
    }
    if speed > 0.0 {
        d.velocity_scale = Some(speed);
        if let Some(dt) = case.time.dt {
            d.courant_estimate = Some(speed * dt / min_size);
        }
        if let Some(fluid) = &case.fluid {
            d.reynolds = Some(speed * extent / fluid.kinematic_viscosity);
        }
    }
    // Per cell ≈ 20 f64 of cell fields with two old time levels; 3 faces per cell of ≈ 17 words
    // (points, centre, area vector, delta, weight, fluxes at three levels).
    d.memory_estimate_bytes = d.cells * (20 + 3 * 17) * 8;
    with_diffusion(case, d)
}

fn with_diffusion(case: &Case, mut d: Derived) -> Derived {
    if let (Some(dt), Some(fluid), Some(h)) = (case.time.dt, &case.fluid, d.min_cell_size) {
        d.diffusion_estimate = Some(fluid.kinematic_viscosity * dt / (h * h));
    }
    d
}

/// Above this diffusion number the PIMPLE outer loop with one PISO corrector and no
/// under-relaxation is likely not to converge (issue 15, measured on cases/rotor_stator.toml
/// refined to 16 and 32 radial cells: it diverges at 1.1 and 4.5, and at 0.56 leaves steps at a
/// pressure residual of 0.46; it converges at 0.28 on both, near the shipped 8-cell mesh's 0.26).
const PLAIN_PIMPLE_DIFFUSION_LIMIT: f64 = 0.3;

/// The notes on the Courant and diffusion numbers: when they are too large for the settings.
fn stability_notes(case: &Case, d: &Derived) -> Vec<String> {
    let mut lines = Vec::new();
    let n = &case.numerics;
    let plain = n.piso_correctors == 1 && n.relax_velocity == 1.0 && n.relax_pressure == 1.0;
    if let Some(co) = d.courant_estimate {
        let note = if co > 1.0 { "  (above 1: the implicit solver stays stable, but time accuracy suffers)" } else { "" };
        lines.push(format!("Courant      {co:.4} (estimate from the imposed velocity){note}"));
    }
    if let (Some(diffusion), Some(dt)) = (d.diffusion_estimate, case.time.dt) {
        lines.push(format!("diffusion    {diffusion:.4} (ν Δt/Δx_min²)"));
        if plain && diffusion > PLAIN_PIMPLE_DIFFUSION_LIMIT {
            lines.push(format!(
                "             too large for one PISO corrector without under-relaxation: the outer loop is likely not to converge (a refined rotor/stator diverges at 1.1 and 0.56 and converges at 0.28). \
                 dt = {:.3e} s keeps it at {PLAIN_PIMPLE_DIFFUSION_LIMIT}; or set [numerics] piso_correctors = 3, or relax_velocity = 0.7 with relax_pressure = 0.3. \
                 `spillage run` stops on the first step that diverges and names a Δt that converges",
                dt * PLAIN_PIMPLE_DIFFUSION_LIMIT / diffusion
            ));
        }
    }
    lines
}

/// A cutter head's cells (the open ones), its tip speed and the Courant number of the tip
/// over the smallest cell.
fn derive_head(case: &Case, head: &spillage_model::cutter_head::CutterHeadSection) -> Option<Derived> {
    let spec = spillage_model::cutter_head::fluid_mesh::blocked_rotor_stator(head).ok()?;
    let n_stator = (spec.stator_r.len() - 1) * spec.n_theta_stator * (spec.z_edges.len() - 1);
    let cells = spec.blocked.iter().filter(|b| !**b).count() + n_stator;
    let arc = spec.rotor_r[0] * std::f64::consts::TAU / spec.n_theta_rotor as f64;
    let dz = spec.z_edges.windows(2).map(|w| w[1] - w[0]).fold(f64::INFINITY, f64::min);
    let min_size = arc.min(dz).min(spec.rotor_r[1] - spec.rotor_r[0]);
    let tip = case.rotor.as_ref().map_or(0.0, |r| r.angular_velocity().abs()) * head.contour[0][1];
    Some(Derived {
        cells,
        min_cell_size: Some(min_size),
        velocity_scale: (tip > 0.0).then_some(tip),
        courant_estimate: case.time.dt.map(|dt| tip * dt / min_size),
        diffusion_estimate: None,
        reynolds: case.fluid.as_ref().map(|f| tip * 2.0 * head.contour[0][1] / f.kinematic_viscosity),
        memory_estimate_bytes: cells * (20 + 3 * 17) * 8,
    })
}

/// Smallest cell of `n` cells over `len` with geometric ratio `grading` of last to first.
fn smallest_graded_cell(len: f64, n: usize, grading: f64) -> f64 {
    if n <= 1 || (grading - 1.0).abs() < 1e-12 {
        return len / n as f64;
    }
    let r = grading.powf(1.0 / (n as f64 - 1.0));
    let first = len * (r - 1.0) / (r.powi(n as i32) - 1.0);
    first.min(first * grading)
}

pub fn check(path: &Path) -> anyhow::Result<ExitCode> {
    let bytes = std::fs::read(path).map_err(|e| anyhow::anyhow!("{}: cannot read the case file: {e}", path.display()))?;
    let report = inspect(&bytes, path)?;
    for line in &report.lines {
        println!("{line}");
    }
    for warning in &report.warnings {
        eprintln!("warning: {warning}");
    }
    println!("ok: the case is valid");
    Ok(ExitCode::SUCCESS)
}

/// What `spillage check` finds in a case file's bytes: the validated case's derived numbers
/// and its warnings, or the first error (located in the file, naming the key).
#[derive(Debug)]
pub struct Report {
    pub case: Case,
    pub lines: Vec<String>,
    /// Values that are allowed but unusual (printed after the numbers).
    pub warnings: Vec<String>,
}

/// `spillage check` without printing: the path is used in messages only.
pub fn inspect(bytes: &[u8], path: &Path) -> Result<Report, spillage_model::case::CaseError> {
    let case = Case::from_bytes(bytes, path)?;
    let d = derive(&case);
    let mut lines = Vec::new();
    let placement = spillage_model::particles::placement::check_initial_placement(&case, path.parent().unwrap_or(Path::new("")))
        .map_err(|field| Case::located(&String::from_utf8_lossy(bytes), path, field))?;
    // a following fluid mesh's patch and wall must meet as the solvers need (the run checks it
    // too); on meshes and plane walls small enough to build here in a moment (a mutated case may
    // ask for billions of cells)
    let following = case.wear.as_ref().and_then(|w| w.fluid_mesh.as_ref()).filter(|f| {
        let wall = case.walls.iter().find(|w| w.name == f.wall);
        let small_wall = matches!(wall.map(|w| &w.shape), Some(spillage_model::walls::settings::ShapeSection::Plane { divisions, .. }) if (divisions[0] as u64) * (divisions[1] as u64) <= 200_000);
        small_wall && case.mesh.as_ref().is_some_and(|m| m.cell_count() <= 200_000)
    });
    if let (Some(section), Some(Ok(mesh))) = (following, following.and_then(|_| spillage_model::mesh::for_case(&case))) {
        spillage_model::wear::fluid_mesh::WallFollower::from_case(&case, &mesh, None).map_err(|why| {
            Case::located(
                &String::from_utf8_lossy(bytes),
                path,
                spillage_model::case::error::FieldError::new("wear.fluid_mesh.wall", format!("{:?}", section.wall), why),
            )
        })?;
    }
    let mut push = |line: String| lines.push(line);

    push(format!("case         {} ({})", case.case.name, path.display()));
    if !case.case.description.is_empty() {
        push(format!("             {}", case.case.description));
    }
    if case.mesh.is_some() || case.cutter_head.is_some() {
        push(format!("cells        {}", d.cells));
    }
    for line in head_lines(&case) {
        push(line);
    }
    if let Some(h) = d.min_cell_size {
        push(format!("min cell     {h:.4e} m"));
    }
    if let Some(u) = d.velocity_scale {
        push(format!("velocity     {u:.4e} m/s (largest imposed)"));
    }
    for line in stability_notes(&case, &d) {
        push(line);
    }
    if let Some(re) = d.reynolds {
        push(format!("Reynolds     {re:.4e}"));
    }
    match (case.time.dt, case.time.steps, case.time.end_time) {
        (Some(dt), Some(n), _) => push(format!("time         {n} steps of {dt:e} s = {:.4e} s", dt * n as f64)),
        (Some(dt), None, Some(t)) => push(format!("time         {} steps of {dt:e} s to t = {t:e} s", (t / dt).ceil())),
        (None, _, Some(t)) if case.time.revolutions.is_some() => push(format!(
            "time         {} revolutions = {t:.4e} s, Δt from max Courant number {}",
            case.time.revolutions.unwrap_or(0.0),
            case.time.max_courant.unwrap_or(f64::NAN)
        )),
        (None, _, _) => push(format!("time         Δt from max Courant number {}", case.time.max_courant.unwrap_or(f64::NAN))),
        _ => {}
    }
    for line in turbulence_lines(&case, &d) {
        push(line);
    }
    for line in particle_lines(&case) {
        push(line);
    }
    for line in wear_lines(&case) {
        push(line);
    }
    if let Some((line, _)) = profile_coverage(&case) {
        push(line);
    }
    if case.mesh.is_some() || case.cutter_head.is_some() {
        push(format!("memory       ≈ {:.1} MB (fields and geometry)", d.memory_estimate_bytes as f64 / 1e6));
    }
    match placement {
        Some(0) => {}
        Some(n) => push(format!("placement    {n} initial particles clear of the walls and of each other")),
        None => push(format!(
            "placement    not checked: about {:.0} initial particles (more than {})",
            spillage_model::particles::placement::estimated_count(&case),
            spillage_model::particles::placement::CHECKED_MAX
        )),
    }
    let later = spillage_model::particles::batch::later_batches(&case).map_err(|field| Case::located(&String::from_utf8_lossy(bytes), path, field))?;
    for batch in later {
        let revolutions = batch.revolutions;
        let end = case.time.end_time.or(case.time.dt.zip(case.time.steps).map(|(dt, n)| dt * n as f64));
        let end = end.filter(|&end| end <= batch.time).map_or(String::new(), |end| format!("; the run ends first, at t = {end:.4e} s"));
        push(format!(
            "batch        particles.groups.{} placed after {revolutions} revolution{} of water alone, at t = {:.4e} s (spillage-and-flow-verification.md §5.4){end}",
            batch.group,
            if revolutions == 1.0 { "" } else { "s" },
            batch.time
        ));
    }
    let warnings = warnings(&case);
    Ok(Report { case, lines, warnings })
}

/// DEM sub-step and Stokes numbers, from the smallest and largest particles the case makes.
/// What `[wear]` will do: the law and the walls, the scaling, the smoothing's length and time,
/// and what one impact of the fed particles removes, so absurd constants show before a run
/// (wear-model.md §6.7: the printed constants remove hundreds of particle volumes per impact).
fn wear_lines(case: &Case) -> Vec<String> {
    use spillage_model::wear::laws::{ErosionLaw, ImpactInput};
    let Some(wear) = &case.wear else { return Vec::new() };
    let walls = if wear.walls.is_empty() { "every wall".to_string() } else { wear.walls.join(", ") };
    let mut lines = vec![format!(
        "wear         {:?} on {walls}: deposited volume = law × {} ([particles] modifier {} × acceleration {}); walls {}",
        wear.law,
        case.particle_modifier() * wear.acceleration,
        case.particle_modifier(),
        wear.acceleration,
        if wear.receding { "recede" } else { "stay (static-boundary mode)" }
    )];
    match &wear.smoothing {
        Some(s) => lines.push(format!(
            "smoothing    spreading length √(κ/λ) = {:.3e} m, time 1/λ = {:.3e} s (§7.2)",
            (s.diffusivity / s.damping).sqrt(),
            1.0 / s.damping
        )),
        None => lines.push("smoothing    none: each impact recedes at once from the three corners of its triangle".into()),
    }
    if let Some(f) = &wear.fluid_mesh {
        let depth = f.depth.map_or("across the whole mesh".to_string(), |d| format!("over {d} m"));
        lines.push(format!("fluid mesh   follows wall {} on patch {} (bending {depth}; wear-model.md §7.4): the water flows into the crater", f.wall, f.patch));
    }
    if wear.sliding {
        lines
            .push("sliding      on: a contact's normal impulse beyond its collision's wears as grazing re-collisions would (wear-model.md §14 item 12)".into());
    }
    let (Ok(law), Some(particles)) = (ErosionLaw::from_section(wear), &case.particles) else { return lines };
    for feed in &particles.feed {
        let speed = feed.velocity.iter().map(|v| v * v).sum::<f64>().sqrt();
        let Some(material) = particles.materials.iter().find(|m| m.name == feed.material) else { continue };
        if speed == 0.0 {
            continue;
        }
        let d = feed.diameter.largest();
        let volume = std::f64::consts::PI * d.powi(3) / 6.0;
        let removed =
            law.removed_volume(&ImpactInput { speed, angle: 30f64.to_radians(), mass: material.density * volume, diameter: d, density: material.density });
        lines.push(format!(
            "one impact   d = {d} m at the feed speed {speed:.3} m/s and 30°: {:.3e} m³ = {:.3e} particle volumes (erosion ratio {:.3e}){}",
            removed.total(),
            removed.total() / volume,
            removed.total() * law.wall_density() / (material.density * volume),
            if removed.total() > volume { "; more than the particle itself: check the hardness units (wear-model.md §6.7)" } else { "" }
        ));
    }
    lines
}

/// What `spillage check` warns of in a valid case: allowed but unusual values, and a wear
/// profile whose line misses the eroding walls. `spillage run` prints them too.
pub fn warnings(case: &Case) -> Vec<String> {
    let mut warnings = spillage_model::case::unusual::warnings(case);
    warnings.extend(profile_coverage(case).and_then(|(_, warning)| warning));
    warnings.extend(representative_packing(case));
    warnings
}

/// The solids fraction past which nothing but their own contacts keeps representative particles
/// apart without `[particles.solids_pressure]`: α_max of the thesis' solids pressure
/// (wear-model.md §4.3).
pub const MAX_PACKING: f64 = 0.6;

/// Representative particles in the water (`[particles] modifier` m with `[coupling]`): one
/// hexagonal layer of spheres of diameter d resting on a wall fills π/(3√3) d/h of cells h
/// tall, and stands for m times that. Past α_max only the simulated particles' own contacts,
/// m times too few, hold them apart, and α_c reaches its floor (the thesis' fine sand: 0.60 ×
/// 100 × 0.1 mm / 1 mm = 6.0, where its run held α_c at the floor with α_p up to 5.4), unless
/// the case has the solids pressure.
fn representative_packing(case: &Case) -> Option<String> {
    let p = case.particles.as_ref().filter(|p| p.modifier > 1.0 && case.coupling.is_some() && p.solids_pressure.is_none())?;
    let (_, d) = diameter_range(p)?;
    let h = derive(case).min_cell_size?;
    let layer = p.modifier * std::f64::consts::PI / (3.0 * 3f64.sqrt()) * d / h;
    (layer > MAX_PACKING).then(|| {
        format!(
            "particles.modifier = {}: a single layer of the {d:e} m particles on a wall stands for α_p ≈ {layer:.2} in the {h:.3e} m cells (0.60 × modifier × d/h), past α_max = {MAX_PACKING}, which real particles cannot reach: only the simulated particles' own contacts keep them apart{}; the thesis' solids pressure ([particles.solids_pressure], wear-model.md §4.3), a smaller modifier or larger cells keep it below",
            p.modifier,
            match case.coupling.as_ref().map(|c| c.min_fluid_fraction) {
                Some(floor) if layer > 1.0 - floor => format!(", and past 1 − min_fluid_fraction = {} α_c is held at its floor", 1.0 - floor),
                _ => String::new(),
            }
        )
    })
}

/// `[wear.profile]`: how many of its bins lie over the eroding walls as built, and a warning
/// when none does (the line misses the walls: `wear_profile.csv` would hold only empty bins).
/// `None` without a profile, or when the walls cannot be built (the run says why).
fn profile_coverage(case: &Case) -> Option<(String, Option<String>)> {
    use spillage_model::wear::profile::{covered_bins, UnwornWalls};
    let wear = case.wear.as_ref()?;
    let line = wear.profile.as_ref()?;
    let unworn = UnwornWalls::of_case(case).ok()?;
    let eroding = spillage_model::wear::setup::eroding_walls(wear, unworn.walls()).ok()?;
    let covered = covered_bins(line, &unworn, &eroding);
    let text = format!("profile      {} bins from {:?} to {:?}, {} m wide: {covered} over the eroding walls", line.bins, line.from, line.to, line.width);
    let warning = (covered == 0).then(|| {
        format!(
            "wear.profile: the line from {:?} to {:?} ({} m wide) passes over no triangle of the eroding walls, so wear_profile.csv would hold only empty bins; a bin takes the triangles whose centre lies within width/2 of the line",
            line.from, line.to, line.width
        )
    });
    Some((text, warning))
}

/// The turbulence model and, with an imposed velocity, where the first cells sit in wall units:
/// y⁺ ≈ (h/2) u_τ/ν with u_τ ≈ 0.04 U (C_f ≈ 0.003, a turbulent wall far from separation).
fn turbulence_lines(case: &Case, d: &Derived) -> Vec<String> {
    if !case.turbulence.is_k_epsilon() {
        return Vec::new();
    }
    let mut lines = vec!["turbulence   realizable k–ε with standard wall functions (first cell centres at 30 < y⁺ < 500)".to_string()];
    if let (Some(u), Some(h), Some(fluid)) = (d.velocity_scale, d.min_cell_size, case.fluid.as_ref()) {
        let y_plus = 0.5 * h * 0.04 * u / fluid.kinematic_viscosity;
        let note = if y_plus < 30.0 { "  (below 30: the wall cells are in the buffer layer, where the log law does not hold)" } else { "" };
        lines.push(format!("             y⁺ of the smallest cells ≈ {y_plus:.0} (estimate, u_τ ≈ 0.04 U){note}"));
    }
    lines
}

/// The smallest and largest diameter placed or fed (`None` without particles).
fn diameter_range(p: &spillage_model::particles::settings::ParticlesSection) -> Option<(f64, f64)> {
    use spillage_model::particles::settings::GroupSection;
    let mut diameters: Vec<(f64, f64)> = p.feed.iter().map(|f| (f.diameter.smallest(), f.diameter.largest())).collect();
    diameters.extend(p.groups.iter().map(|g| match g {
        GroupSection::List { diameter, .. }
        | GroupSection::Lattice { diameter, .. }
        | GroupSection::HeadLattice { diameter, .. }
        | GroupSection::Random { diameter, .. } => (diameter.smallest(), diameter.largest()),
    }));
    Some((diameters.iter().map(|d| d.0).reduce(f64::min)?, diameters.iter().map(|d| d.1).reduce(f64::max)?))
}

fn particle_lines(case: &Case) -> Vec<String> {
    use spillage_model::closure::{collision_time, restitution};
    use spillage_model::particles::settings::FluidForces;
    let Some(p) = &case.particles else { return Vec::new() };
    let Some((d_min, d_max)) = diameter_range(p) else {
        return vec!["particles    none placed or fed".into()];
    };
    let mut lines = vec![format!("particles    diameters {d_min:.4e} … {d_max:.4e} m")];
    let speed = p.collision_speed;
    // Stiffest material against itself, sphere–sphere: E* = E_c / (2(1 − ν²)) (spec §7.2).
    let stiffest = p
        .materials
        .iter()
        .map(|m| (m.density, m.contact_youngs_modulus() / (2.0 * (1.0 - m.poisson_ratio * m.poisson_ratio))))
        .fold((0.0, 0.0), |a: (f64, f64), b| (a.0.max(b.0), a.1.max(b.1)));
    if stiffest.1 > 0.0 {
        let t_col = collision_time::collision_time(stiffest.0, stiffest.1, 0.25 * d_min, speed);
        let dt_sub = p.substep.unwrap_or(t_col / p.steps_per_collision);
        lines.push(format!("collision    t_col ≈ {t_col:.3e} s at {speed} m/s (smallest pair, spec §7.6)"));
        if let Some(dt) = case.time.dt {
            lines.push(format!("DEM step     {dt_sub:.3e} s: {} sub-steps per step of {dt:e} s", collision_time::substeps(dt, dt_sub, 1.0)));
        }
    }
    let case_fluid = case.fluid.as_ref().map(|f| (f.density, f.kinematic_viscosity));
    let fluid = case_fluid.or(p.ambient.as_ref().map(|a| (a.density, a.kinematic_viscosity)));
    let wet = p.wet_fluid(case_fluid).is_some();
    if fluid.is_some() {
        lines.push(match p.fluid_forces {
            FluidForces::Full => "forces       drag, added mass (C_AM 0.5), pressure gradient, gravity with buoyancy (fluid-dem-model.md §5; fluid_forces = \"full\")".to_string(),
            FluidForces::DragAndBuoyancy => {
                "forces       drag and buoyancy only: the wear model's particle, no added mass or pressure-gradient force (wear-model.md Eqs. 2.11/5.3; fluid_forces = \"drag_and_buoyancy\")".to_string()
            }
        });
    }
    if case.fluid.is_some() {
        use spillage_model::coupling::{Feedback, InterfaceTreatment, MappingMethod};
        let represents = |r#where: &str| match p.modifier {
            1.0 => String::new(),
            m => format!("; each particle counts as {m} real ones {where} ([particles] modifier)"),
        };
        lines.push(match &case.coupling {
            Some(c) => format!(
                "coupling     two-way: method \"{}\", γ = {} (σ = γ d_p), feedback \"{}\"{}{}",
                match c.method {
                    MappingMethod::Centroid => "centroid",
                    MappingMethod::Kernel => "kernel",
                    MappingMethod::Diffusion => "diffusion",
                },
                c.distance_factor,
                match c.feedback {
                    Feedback::DragAndFluidAcceleration => "drag_and_fluid_acceleration",
                    Feedback::Literal => "literal",
                },
                match (c.interface, c.masks_interface()) {
                    (InterfaceTreatment::Span, false) => "; kernels reach across a sliding interface (interface = \"span\")",
                    (InterfaceTreatment::Span, true) => "; kernels reach across a sliding interface (interface = \"span\"), ∂α_c/∂t masked next to it",
                    (InterfaceTreatment::Truncate, true) => "",
                    (InterfaceTreatment::Truncate, false) => "; ∂α_c/∂t not masked next to a sliding interface (interface_mask = false)",
                },
                represents(if case.wear.is_some() { "in the water and on the walls" } else { "in the water" })
            ),
            None => format!(
                "coupling     one-way: the fluid does not feel the particles (no [coupling]){}",
                if case.wear.is_some() { represents("on the walls") } else { String::new() }
            ),
        });
        if let Some(sp) = &p.solids_pressure {
            use spillage_model::particles::solids_pressure::{KtgfForce, Treatment};
            lines.push(format!(
                "solids       KTGF solids pressure between the particles (wear-model.md §4), {}: α_max {}, e {}, from each fluid cell's α_p and Θ; acceleration {}",
                match sp.treatment {
                    Treatment::Implicit => "implicit in α_p",
                    Treatment::Explicit => "explicit (the thesis)",
                },
                sp.packing_limit,
                sp.restitution,
                match sp.force {
                    KtgfForce::PerParticleVolume => "−∇p_p/(α_p ρ_p) (§4.4)",
                    KtgfForce::ThesisLiteral => "−∇p_p/ρ_p (force = \"thesis_literal\": the printed Eq. 2.12 without 1/α_p)",
                }
            ));
        }
    }
    if let Some((rho_f, nu)) = fluid {
        for m in &p.materials {
            let lo = restitution::stokes_number(m.density, rho_f, speed, d_min, nu);
            let hi = restitution::stokes_number(m.density, rho_f, speed, d_max, nu);
            let effect = if wet {
                format!("wet e/e_dry {:.3} … {:.3}, spec §7.5", restitution::wet_restitution(1.0, lo), restitution::wet_restitution(1.0, hi))
            } else {
                "dry restitution: every contact keeps e_dry".to_string()
            };
            lines.push(format!("Stokes       {}: St_AM {lo:.3e} … {hi:.3e} at {speed} m/s ({effect})", m.name));
        }
    }
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn graded_cells_sum_to_the_length() {
        let (len, n, g) = (2.0_f64, 10, 4.0_f64);
        let r = g.powf(1.0 / (n as f64 - 1.0));
        let first = smallest_graded_cell(len, n, g);
        let total: f64 = (0..n).map(|i| first * r.powi(i as i32)).sum();
        assert!((total - len).abs() < 1e-12);
        assert!((smallest_graded_cell(len, n, 1.0 / g) - first).abs() < 1e-12);
    }

    /// The velocity scale is the fastest wall at its own radius (issue 15 item 2): the sliding
    /// Couette case (rotor ω = 1 out to the interface at r = 1.5) with its outer wall (r = 2)
    /// turning at 0.5 rad/s moves fastest at the outer wall, 1.0 m/s; evaluated at the
    /// interface radius it read 0.75.
    #[test]
    fn velocity_scale_is_the_fastest_wall_at_its_radius() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/verification/fluid/couette_sliding.toml");
        let text = std::fs::read_to_string(&path).unwrap();
        let text = text
            .replace("omega = 1.0", "omega = 0.5")
            .replace("[boundary.outer]\ntype = \"wall\"", "[boundary.outer]\ntype = \"wall\"\nangular_velocity = 0.5");
        assert!(text.contains("angular_velocity = 0.5"), "the edit found the outer wall");
        let case = Case::from_toml(&text, &path).unwrap();
        let u = derive(&case).velocity_scale.unwrap();
        assert!((u - 1.0).abs() < 1e-12, "velocity scale {u}");
    }
}
