//! Bad case files: each must give an error that names the file, the line, the key, the value
//! and what is allowed — never a panic.

use std::path::Path;

use spillage_model::case::Case;

const GOOD: &str = r#"
[case]
name = "lid"

[time]
dt = 0.01
steps = 10

[fluid]
density = 1000.0
kinematic_viscosity = 1e-3

[mesh]
generator = "box"
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 0.1]
cells = [8, 8, 1]
two_d = true

[boundary.x_min]
type = "wall"
[boundary.x_max]
type = "wall"
[boundary.y_min]
type = "wall"
[boundary.y_max]
type = "wall"
velocity = [1.0, 0.0, 0.0]
"#;

fn parse(text: &str) -> Result<Case, String> {
    Case::from_toml(text, Path::new("cases/bad.toml")).map_err(|e| e.to_string())
}

#[test]
fn the_good_case_parses() {
    let case = parse(GOOD).expect("good case");
    assert_eq!(case.case.name, "lid");
    assert_eq!(case.boundary.len(), 4);
}

/// (what is changed, replacement text, substrings the message must contain)
fn bad_inputs() -> Vec<(&'static str, String, Vec<&'static str>)> {
    let r = |from: &str, to: &str| GOOD.replacen(from, to, 1);
    vec![
        ("syntax", r("steps = 10", "steps = = 10"), vec!["cases/bad.toml:7:"]),
        ("unknown top key", format!("{GOOD}\n[fluids]\ndensity = 1.0\n"), vec!["fluids", "unknown field"]),
        ("unknown key in section", r("density = 1000.0", "densty = 1000.0"), vec!["densty", "cases/bad.toml:10:"]),
        ("wrong type", r("density = 1000.0", "density = \"water\""), vec!["cases/bad.toml:10:", "fluid.density", "string"]),
        ("negative density", r("density = 1000.0", "density = -1000.0"), vec!["fluid.density", "-1000", "> 0", "cases/bad.toml:10:11"]),
        ("zero viscosity", r("kinematic_viscosity = 1e-3", "kinematic_viscosity = 0.0"), vec!["fluid.kinematic_viscosity", "= 0 ", "> 0"]),
        ("nan viscosity", r("kinematic_viscosity = 1e-3", "kinematic_viscosity = nan"), vec!["fluid.kinematic_viscosity", "NaN"]),
        ("negative dt", r("dt = 0.01", "dt = -0.01"), vec!["time.dt", "-0.01", "cases/bad.toml:6:"]),
        ("dt and courant", r("dt = 0.01", "dt = 0.01\nmax_courant = 0.5"), vec!["time.max_courant", "not both"]),
        ("no step size", r("dt = 0.01", ""), vec!["`time`", "max_courant"]),
        ("zero steps", r("steps = 10", "steps = 0"), vec!["time.steps", "≥ 1"]),
        ("negative steps", r("steps = 10", "steps = -3"), vec!["cases/bad.toml:7:", "time.steps", "-3"]),
        ("steps and end_time", r("steps = 10", "steps = 10\nend_time = 1.0"), vec!["time.steps", "not both"]),
        ("empty name", r("name = \"lid\"", "name = \"  \""), vec!["case.name", "non-empty"]),
        ("missing name", r("name = \"lid\"", ""), vec!["name", "missing"]),
        ("unknown generator", r("generator = \"box\"", "generator = \"sphere\""), vec!["sphere", "box"]),
        ("max below min", r("max = [1.0, 1.0, 0.1]", "max = [1.0, -1.0, 0.1]"), vec!["mesh.max", "min.y"]),
        ("zero cells", r("cells = [8, 8, 1]", "cells = [8, 0, 1]"), vec!["mesh.cells", "from 1"]),
        ("two_d with 2 layers", r("cells = [8, 8, 1]", "cells = [8, 8, 2]"), vec!["mesh.cells", "two_d"]),
        ("bad periodic axis", r("two_d = true", "two_d = true\nperiodic = [\"w\"]"), vec!["mesh.periodic", "\"w\""]),
        ("negative grading", r("two_d = true", "two_d = true\ngrading = [1.0, -2.0, 1.0]"), vec!["mesh.grading", "-2"]),
        ("unknown patch", format!("{GOOD}\n[boundary.lid]\ntype = \"wall\"\n"), vec!["boundary.lid", "x_min", "y_max"]),
        ("missing patch", r("[boundary.x_min]\ntype = \"wall\"\n", ""), vec!["[boundary.x_min]", "every patch"]),
        ("unknown bc type", r("[boundary.x_min]\ntype = \"wall\"", "[boundary.x_min]\ntype = \"slip\""), vec!["slip", "wall"]),
        ("nan wall velocity", r("velocity = [1.0, 0.0, 0.0]", "velocity = [1.0, nan, 0.0]"), vec!["boundary.y_max.velocity", "finite"]),
        (
            "rotating wall with velocity",
            r("velocity = [1.0, 0.0, 0.0]", "velocity = [1.0, 0.0, 0.0]\nrotating = true"),
            vec!["boundary.y_max.velocity", "rotating"],
        ),
        ("rotor on a box", format!("{GOOD}\n[rotor]\nomega = 1.0\n"), vec!["rotor", "rotor_stator"]),
        ("rotor omega and rpm", format!("{GOOD}\n[rotor]\nomega = 1.0\nrpm = 30.0\n"), vec!["rotor.rpm", "not both"]),
        ("zero rotor axis", format!("{GOOD}\n[rotor]\nomega = 1.0\naxis = [0.0, 0.0, 0.0]\n"), vec!["rotor.axis", "non-zero"]),
        ("fluid without mesh", GOOD.split("[mesh]").next().unwrap().to_string(), vec!["mesh", "needs a mesh"]),
        ("gravity with nan", format!("[physics]\ngravity = [0.0, nan, -9.81]\n{GOOD}"), vec!["physics.gravity", "finite", "cases/bad.toml:2:"]),
        (
            "zero rotating-frame axis",
            format!("[physics.rotating_frame]\nomega = 1.0\naxis = [0.0, 0.0, 0.0]\n{GOOD}"),
            vec!["physics.rotating_frame.axis", "non-zero", "cases/bad.toml:3:"],
        ),
        (
            "nan rotating-frame omega",
            format!("[physics.rotating_frame]\nomega = nan\n{GOOD}"),
            vec!["physics.rotating_frame.omega", "finite", "cases/bad.toml:2:"],
        ),
        ("rotating frame without omega", format!("[physics.rotating_frame]\naxis = [0.0, 0.0, 1.0]\n{GOOD}"), vec!["omega", "missing"]),
        ("rotating frame with rpm", format!("[physics.rotating_frame]\nomega = 1.0\nrpm = 3000.0\n{GOOD}"), vec!["rpm", "unknown field"]),
        (
            "rotating-frame origin with inf",
            format!("[physics.rotating_frame]\nomega = 1.0\norigin = [0.0, inf, 0.0]\n{GOOD}"),
            vec!["physics.rotating_frame.origin", "finite"],
        ),
        (
            "rotating-frame axis in a 2-D plane",
            format!("[physics.rotating_frame]\nomega = 1.0\naxis = [0.0, 1.0, 1.0]\n{GOOD}"),
            vec!["physics.rotating_frame.axis", "2-D mesh", "cases/bad.toml:3:"],
        ),
    ]
}

#[test]
fn every_bad_input_gets_a_clear_located_error() {
    let cases = bad_inputs();
    assert!(cases.len() >= 20);
    for (what, text, needles) in cases {
        let message = match parse(&text) {
            Ok(_) => panic!("{what}: accepted a bad case"),
            Err(m) => m,
        };
        assert!(message.starts_with("cases/bad.toml"), "{what}: message does not name the file: {message}");
        for needle in needles {
            assert!(message.contains(needle), "{what}: message lacks {needle:?}:\n{message}");
        }
    }
}

#[test]
fn a_missing_file_is_an_error_naming_it() {
    let err = Case::load(Path::new("no/such/case.toml")).unwrap_err().to_string();
    assert!(err.contains("no/such/case.toml") && err.contains("cannot read"), "{err}");
}
