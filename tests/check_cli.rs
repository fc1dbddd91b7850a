//! `spillage check` as a user runs it on the shipped cases and edits of them: what it says of
//! the particles' restitution and fluid forces, of a later head batch and of a wear profile,
//! and that every TOML snippet of README.md passes it.

use std::path::Path;

mod common;
use common::{scratch, spillage};

/// `text` with the first `from` replaced by `to`; the edit must find `from`.
fn edited_once(text: &str, from: &str, to: &str) -> String {
    let edited = text.replacen(from, to, 1);
    assert_ne!(edited, text, "the edit found {from:?}");
    edited
}

/// `spillage check` says whether the water lowers the restitution: wet by default in a fluid,
/// not with `[particles] restitution = "dry"` (the Coriolis tester).
#[test]
fn check_says_whether_the_restitution_is_wet() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/verification");
    for (case, needle) in [("coupling/settling_single.toml", "wet e/e_dry"), ("wear/coriolis_garnet.toml", "dry restitution: every contact keeps e_dry")] {
        let out = spillage(&["check", root.join(case).to_str().unwrap()]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let text = String::from_utf8_lossy(&out.stdout);
        let stokes: Vec<&str> = text.lines().filter(|l| l.starts_with("Stokes")).collect();
        assert!(!stokes.is_empty() && stokes.iter().all(|l| l.contains(needle)), "{case}: {needle:?} not on every Stokes line of\n{text}");
    }
}

/// `spillage check` names the particle equation's fluid forces: the full set by default, the
/// wear model's drag and buoyancy when the case asks for them.
#[test]
fn check_names_the_fluid_forces_on_the_particles() {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/verification/wear/coriolis_garnet.toml");
    let text = std::fs::read_to_string(&source).unwrap();
    let dir = scratch("fluid-forces");
    let thesis = dir.join("coriolis_drag_and_buoyancy.toml");
    let edited = edited_once(&text, "[particles]\n", "[particles]\nfluid_forces = \"drag_and_buoyancy\"\n");
    std::fs::write(&thesis, edited).unwrap();
    for (case, needle) in [(source, "forces       drag, added mass (C_AM 0.5)"), (thesis, "forces       drag and buoyancy only")] {
        let out = spillage(&["check", case.to_str().unwrap()]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let text = String::from_utf8_lossy(&out.stdout);
        assert_eq!(text.lines().filter(|l| l.starts_with("forces ")).count(), 1, "{text}");
        assert!(text.contains(needle), "{}: {needle:?} not in\n{text}", case.display());
    }
}

/// `spillage check` counts the wear profile's bins over the eroding walls, and warns when its
/// line misses them (moved from the coupon's face at y = −5 mm to the channel's top at +5 mm).
#[test]
fn check_warns_of_a_wear_profile_that_misses_the_walls() {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/verification/wear/coriolis_garnet.toml");
    let text = std::fs::read_to_string(&source).unwrap();
    let dir = scratch("profile-line");
    let missing = dir.join("coriolis_profile_off_the_coupon.toml");
    let edited = edited_once(&text, "from = [0.103, -0.005, 0.0]\nto = [0.147, -0.005, 0.0]\n", "from = [0.103, 0.005, 0.0]\nto = [0.147, 0.005, 0.0]\n");
    std::fs::write(&missing, edited).unwrap();
    for (case, covered, warned) in [(&source, "44 over the eroding walls", false), (&missing, "0 over the eroding walls", true)] {
        let out = spillage(&["check", case.to_str().unwrap()]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        assert!(stdout.lines().any(|l| l.starts_with("profile ") && l.ends_with(covered)), "{}: {covered:?} not in\n{stdout}", case.display());
        assert_eq!(stderr.contains("warning: wear.profile: the line from [0.103, 0.005, 0.0]"), warned, "{}:\n{stderr}", case.display());
    }
    // a run started without `spillage check` warns at its start and says so at its end
    let one_step = dir.join("coriolis_profile_off_the_coupon_one_step.toml");
    let text = std::fs::read_to_string(&missing).unwrap();
    let edited = edited_once(&text, "end_time = 0.025\n", "end_time = 2.5e-5\n");
    std::fs::write(&one_step, edited).unwrap();
    let out = spillage(&["run", one_step.to_str().unwrap(), "--out", dir.join("run").to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(stderr.contains("warning: wear.profile: the line from [0.103, 0.005, 0.0]"), "{stderr}");
    // the end report goes to stderr with the progress, away from a piped stdout
    assert!(stderr.contains("every bin empty, the line passes over no triangle of the eroding walls"), "{stdout}\n{stderr}");
}

/// `spillage check` says when a head batch placed after the water has turned comes in, warns
/// when the run ends before it, and names the key of a negative number of revolutions.
#[test]
fn check_says_when_a_later_batch_is_placed() {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/cutter_head.toml")).unwrap();
    let dir = scratch("later-batch");
    let with = |after: &str, revolutions: &str, name: &str| {
        let edited = text.replacen("z = [-0.30, -0.03]\n", &format!("z = [-0.30, -0.03]\nafter_revolutions = {after}\n"), 1).replacen(
            "revolutions = 1\n",
            &format!("revolutions = {revolutions}\n"),
            1,
        );
        assert_ne!(edited, text);
        let case = dir.join(name);
        std::fs::write(&case, edited).unwrap();
        spillage(&["check", case.to_str().unwrap()])
    };
    let out = with("1.0", "2", "later.toml");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("batch        particles.groups.0 placed after 1 revolution of water alone, at t = 1.0000e0 s"), "{stdout}");
    assert!(!stdout.contains("the run ends first"), "{stdout}");
    let out = with("1.0", "1", "too_late.toml");
    assert!(String::from_utf8_lossy(&out.stdout).contains("; the run ends first, at t = 1.0000e0 s"), "{}", String::from_utf8_lossy(&out.stdout));
    let out = with("-0.5", "2", "negative.toml");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("particles.groups.0.after_revolutions") && stderr.contains("-0.5"), "{stderr}");
}

/// Issue 15 item 5: every TOML snippet of README.md is accepted by `spillage check`. A snippet
/// with a `[case]` table is a whole case; any other is a fragment, put into the shipped cutter
/// head (its tables replace the head's tables of the same name).
#[test]
fn every_toml_snippet_of_the_readme_is_accepted_by_check() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let mut snippets = Vec::new();
    let mut current: Option<String> = None;
    for line in readme.lines() {
        match (&mut current, line.trim_start()) {
            (None, l) if l.starts_with("```toml") => current = Some(String::new()),
            (Some(s), l) if l.starts_with("```") => {
                snippets.push(std::mem::take(s));
                current = None;
            }
            (Some(s), _) => {
                s.push_str(line);
                s.push('\n');
            }
            _ => {}
        }
    }
    assert!(!snippets.is_empty(), "README.md has no ```toml snippet: this test checks nothing");
    let base: toml::Table = std::fs::read_to_string(root.join("cases/cutter_head.toml")).unwrap().parse().unwrap();
    let dir = scratch("readme-snippets");
    for (k, snippet) in snippets.iter().enumerate() {
        let table: toml::Table = snippet.parse().unwrap_or_else(|e| panic!("README snippet {k} is not TOML: {e}\n{snippet}"));
        let case = if table.contains_key("case") {
            table
        } else {
            let mut merged = base.clone();
            merged.extend(table);
            merged
        };
        let path = dir.join(format!("snippet_{k}.toml"));
        std::fs::write(&path, toml::to_string(&case).unwrap()).unwrap();
        let out = spillage(&["check", path.to_str().unwrap()]);
        assert!(out.status.success(), "README snippet {k} is refused by `spillage check`:\n{snippet}\n{}", String::from_utf8_lossy(&out.stderr));
    }
}

/// `spillage check` says whether the water feels the particles, and how many real particles each
/// simulated one counts for, where it counts: one-way with the modifier on the walls only (the
/// fine sand), two-way in the water and on the walls.
#[test]
fn check_says_how_the_particles_are_coupled() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let cases = [
        ("cases/verification/coupling/settling_single.toml", "coupling     two-way: method \"kernel\""),
        (
            "cases/wear/coriolis_fine_sand.toml",
            "coupling     one-way: the fluid does not feel the particles (no [coupling]); each particle counts as 100 real ones on the walls",
        ),
    ];
    for (case, needle) in cases {
        let out = spillage(&["check", root.join(case).to_str().unwrap()]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains(needle), "{case}: {needle:?} not in\n{text}");
    }
}

/// Representative particles that would pack past α_max on a wall are warned of before the run:
/// the fine sand as the thesis represents it (modifier 100, two-way; the run held α_c at its
/// floor with α_p up to 5.4) gets the warning; one-way, with a modifier of 1, or with the
/// solids pressure that keeps them apart, it does not.
#[test]
fn check_warns_of_representative_particles_that_would_pack() {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/wear/coriolis_fine_sand.toml");
    let text = std::fs::read_to_string(&source).unwrap();
    let dir = scratch("representative-packing");
    let coupled = text.replacen("[particles]\n", "[coupling]\nmethod = \"kernel\"\n\n[particles]\n", 1);
    assert_ne!(coupled, text, "the edit found [particles]");
    let cases = [
        ("two_way.toml", coupled.clone(), true),
        ("one_way.toml", text.clone(), false),
        ("one_each.toml", coupled.replacen("modifier = 100.0", "modifier = 1.0", 1), false),
        ("with_the_solids_pressure.toml", format!("{coupled}\n[particles.solids_pressure]\n"), false),
    ];
    for (name, body, warned) in cases {
        let path = dir.join(name);
        std::fs::write(&path, body).unwrap();
        let out = spillage(&["check", path.to_str().unwrap()]);
        let all = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
        assert!(out.status.success(), "{name}: {all}");
        assert_eq!(all.contains("particles.modifier = 100: a single layer of the 1e-4 m particles on a wall stands for α_p ≈ 6.05"), warned, "{name}:\n{all}");
        assert_eq!(
            all.contains("solids       KTGF solids pressure between the particles (wear-model.md §4), implicit in α_p: α_max 0.6, e 0.99"),
            name.starts_with("with_the"),
            "{name}:\n{all}"
        );
    }
}

/// `spillage check` says when kernels reach across a sliding interface (`[coupling] interface =
/// "span"`), and says nothing more for the thesis' truncated, masked kernels; a span with the
/// diffusion method is refused, naming the key.
#[test]
fn check_says_when_kernels_reach_across_the_interface() {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/coupling/interface_crossing.toml");
    let text = std::fs::read_to_string(&source).unwrap();
    let dir = scratch("interface-span");
    let span = dir.join("interface_crossing_span.toml");
    let edited = edited_once(&text, "distance_factor = 1.0\n", "distance_factor = 1.0\ninterface = \"span\"\n");
    std::fs::write(&span, &edited).unwrap();
    for (case, spans) in [(source.clone(), false), (span.clone(), true)] {
        let out = spillage(&["check", case.to_str().unwrap()]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let stdout = String::from_utf8_lossy(&out.stdout);
        let line = stdout.lines().find(|l| l.starts_with("coupling")).unwrap_or_else(|| panic!("no coupling line in\n{stdout}"));
        assert_eq!(line.contains("reach across a sliding interface (interface = \"span\")"), spans, "{line}");
    }
    let diffusion = dir.join("interface_crossing_span_diffusion.toml");
    std::fs::write(&diffusion, edited.replacen("method = \"kernel\"\ndistance_factor = 1.0\n", "method = \"diffusion\"\ndistance_factor = 3.0\n", 1)).unwrap();
    let out = spillage(&["check", diffusion.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("coupling.interface") && stderr.contains("kernel"), "{stderr}");
}
