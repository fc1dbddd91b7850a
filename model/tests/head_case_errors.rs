//! The cutter head's haul velocity (`cutter_head.haul_velocity`, cutter_head::current) in the
//! shipped case: the conditions it derives, and bad values refused with an error naming the
//! file, the line, the key, the value and what is allowed.

use std::path::Path;

use spillage_model::case::Case;
use spillage_model::fluid::settings::BoundaryCondition;

const STILL: &str = "haul_velocity = [0.0, 0.0, 0.0]";

fn shipped() -> String {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/cutter_head.toml")).unwrap();
    assert!(text.contains(STILL), "the shipped head states its (still) haul velocity");
    text
}

fn parse(text: &str) -> Result<Case, String> {
    Case::from_toml(text, Path::new("cases/bad.toml")).map_err(|e| e.to_string())
}

/// Every (what, text, needles) is refused with a message holding every needle.
fn assert_refused(bad: Vec<(&str, String, Vec<&str>)>) {
    for (what, text, needles) in bad {
        let message = match parse(&text) {
            Ok(_) => panic!("{what}: accepted a bad case"),
            Err(m) => m,
        };
        for needle in needles {
            assert!(message.contains(needle), "{what}: message lacks {needle:?}:\n{message}");
        }
    }
}

fn inlet(case: &Case, patch: &str) -> [f64; 3] {
    match &case.boundary[patch] {
        BoundaryCondition::VelocityInlet { velocity, profile: None } => *velocity,
        other => panic!("{patch}: {other:?}"),
    }
}

#[test]
fn a_current_turns_the_tank_into_its_far_field_and_back() {
    let still = parse(&shipped()).unwrap();
    assert!(matches!(still.boundary["tank"], BoundaryCondition::Wall { .. }));
    let floor = inlet(&still, "floor");
    assert_eq!(floor[..2], [0.0, 0.0]);
    let mut moving = parse(&shipped().replace(STILL, "haul_velocity = [0.0, -0.3, 0.0]")).unwrap();
    assert_eq!(inlet(&moving, "tank"), [0.0, -0.3, 0.0]);
    // the floor carries the current and the same inflow Q_m / A
    assert_eq!(inlet(&moving, "floor"), [0.0, -0.3, floor[2]]);
    // back to still water: the file's wall again, and the conditions equal the still case's
    moving.cutter_head.as_mut().unwrap().haul_velocity = [0.0; 3];
    moving.finish().unwrap();
    assert_eq!(moving.boundary, still.boundary);
    // a slip tank wall gives way to the current too
    let slip = shipped().replace("[boundary.tank]\ntype = \"wall\"", "[boundary.tank]\ntype = \"symmetry\"");
    assert_eq!(inlet(&parse(&slip.replace(STILL, "haul_velocity = [0.1, 0.0, 0.0]")).unwrap(), "tank"), [0.1, 0.0, 0.0]);
}

#[test]
fn bad_haul_velocities_get_a_located_error() {
    let text = shipped();
    let line = text.lines().position(|l| l.starts_with("haul_velocity")).unwrap() + 1;
    let at = format!("cases/bad.toml:{line}:");
    let tank_line = text.lines().position(|l| l == "[boundary.tank]").unwrap() + 1;
    let tank_at = format!("cases/bad.toml:{tank_line}:");
    let with = |v: &str| text.replace(STILL, &format!("haul_velocity = {v}"));
    let bad: Vec<(&str, String, Vec<&str>)> = vec![
        ("along the axis", with("[0.0, 0.3, 0.1]"), vec![&at, "cutter_head.haul_velocity", "0.1", "[v_x, v_y, 0]", "lid"]),
        ("not finite", with("[nan, 0.3, 0.0]"), vec![&at, "cutter_head.haul_velocity", "NaN", "finite"]),
        ("too fast", with("[0.0, 3.0, 0.0]"), vec![&at, "cutter_head.haul_velocity", "3e0", "at most 2 m/s"]),
        ("two components", with("[0.0, 0.3]"), vec![&at, "haul_velocity", "3"]),
        ("a number", with("0.3"), vec![&at, "haul_velocity"]),
        (
            "a moving tank wall with a current",
            with("[0.0, 0.3, 0.0]").replace("[boundary.tank]\ntype = \"wall\"", "[boundary.tank]\ntype = \"wall\"\nvelocity = [0.1, 0.0, 0.0]"),
            vec![&tank_at, "boundary.tank", "still tank", "haul_velocity"],
        ),
        (
            "an inlet on the tank with a current",
            with("[0.0, 0.3, 0.0]").replace("[boundary.tank]\ntype = \"wall\"", "[boundary.tank]\ntype = \"velocity_inlet\"\nvelocity = [0.0, 0.3, 0.0]"),
            vec![&tank_at, "boundary.tank", "still tank"],
        ),
    ];
    assert_refused(bad);
}

#[test]
fn a_fast_swing_is_allowed_with_a_warning() {
    let case = parse(&shipped().replace(STILL, "haul_velocity = [0.0, 0.8, 0.0]")).unwrap();
    let warnings = spillage_model::case::unusual::warnings(&case);
    assert!(warnings.iter().any(|w| w.contains("cutter_head.haul_velocity") && w.contains("fast swing")), "{warnings:?}");
    assert!(spillage_model::case::unusual::warnings(&parse(&shipped()).unwrap()).iter().all(|w| !w.contains("haul")));
}

/// The eccentric mouth (cutter_head::mouth) of `cases/cutter_head_eccentric.toml`: bad shapes,
/// and a mouth over cells the blades' staircase blocks, are refused naming the line, the key,
/// the value and what fits.
#[test]
fn bad_eccentric_mouths_get_a_located_error() {
    const MOUTH: &str = "suction = { type = \"eccentric\", angle = 180.0, width = 103.0, radii = [0.07, 0.2] }";
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/cutter_head_eccentric.toml")).unwrap();
    assert!(text.contains(MOUTH));
    parse(&text).unwrap();
    let line = text.lines().position(|l| l.starts_with("suction =")).unwrap() + 1;
    let at = format!("cases/bad.toml:{line}:");
    let with = |m: &str| text.replace(MOUTH, &format!("suction = {{ type = \"eccentric\", {m} }}"));
    let bad: Vec<(&str, String, Vec<&str>)> = vec![
        ("too wide", with("angle = 0.0, width = 200.0, radii = [0.07, 0.2]"), vec![&at, "cutter_head.suction.width", "200", "(0, 180]"]),
        (
            "inside the shaft",
            with("angle = 0.0, width = 90.0, radii = [0.05, 0.2]"),
            vec![&at, "cutter_head.suction.radii", "[0.05, 0.2]", "shaft_radius = 0.06"],
        ),
        ("reversed radii", with("angle = 0.0, width = 90.0, radii = [0.2, 0.1]"), vec![&at, "cutter_head.suction.radii", "inner < outer"]),
        (
            "over the blades",
            with("angle = 0.0, width = 90.0, radii = [0.07, 0.27]"),
            vec![&at, "cutter_head.suction.radii", "[0.07, 0.27]", "radii within [0.06, "],
        ),
        ("no angle", with("width = 90.0, radii = [0.07, 0.2]"), vec![&at, "angle"]),
    ];
    assert_refused(bad);
}

/// The blade's lean (`cutter_head.blade_sweep`): the two names are read, anything else is
/// refused naming the line, the key, the value and the allowed names.
#[test]
fn the_blade_sweep_is_read_and_a_bad_one_refused() {
    const TWIST: &str = "blade_twist = 40.0\n";
    let text = shipped();
    assert!(text.contains(TWIST));
    let with = |v: &str| text.replace(TWIST, &format!("{TWIST}blade_sweep = {v}\n"));
    let sweep = |t: &str| parse(t).unwrap().cutter_head.unwrap().blade_sweep;
    use spillage_model::cutter_head::BladeSweep;
    assert_eq!(sweep(&text), BladeSweep::Backward, "the default");
    assert_eq!(sweep(&with("\"forward\"")), BladeSweep::Forward);
    assert_eq!(sweep(&with("\"backward\"")), BladeSweep::Backward);
    let line = text.lines().position(|l| l.starts_with("blade_twist")).unwrap() + 2;
    let at = format!("cases/bad.toml:{line}:");
    assert_refused(vec![
        ("unknown", with("\"sideways\""), vec![&at, "blade_sweep", "sideways", "backward", "forward"]),
        ("a number", with("1.0"), vec![&at, "blade_sweep"]),
    ]);
}
