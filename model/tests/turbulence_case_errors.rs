//! Bad `[turbulence]` sections: an error naming the file, line, key, value and what is allowed.

use std::path::Path;

use spillage_model::case::Case;

const GOOD: &str = r#"
[case]
name = "channel"

[time]
dt = 0.5
steps = 10

[fluid]
density = 1000.0
kinematic_viscosity = 1e-3

[turbulence]
model = "realizable-k-epsilon"
initial_k = 1.0
initial_epsilon = 1.0

[mesh]
generator = "box"
min = [0.0, 0.0, 0.0]
max = [1.0, 1.0, 0.1]
cells = [3, 6, 1]
periodic = ["x"]
two_d = true

[boundary.y_min]
type = "wall"
[boundary.y_max]
type = "symmetry"
"#;

fn parse(text: &str) -> Result<Case, String> {
    Case::from_toml(text, Path::new("cases/bad.toml")).map_err(|e| e.to_string())
}

#[test]
fn the_good_case_parses_and_its_snake_case_spelling_too() {
    assert!(parse(GOOD).unwrap().turbulence.is_k_epsilon());
    assert!(parse(&GOOD.replace("realizable-k-epsilon", "realizable_k_epsilon")).unwrap().turbulence.is_k_epsilon());
    assert!(!parse(&GOOD.replace("model = \"realizable-k-epsilon\"\n", "")).unwrap().turbulence.is_k_epsilon(), "laminar is the default");
}

#[test]
fn every_bad_turbulence_input_gets_a_clear_located_error() {
    let r = |from: &str, to: &str| GOOD.replacen(from, to, 1);
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        (
            "unknown model",
            r("model = \"realizable-k-epsilon\"", "model = \"k-omega\""),
            vec!["turbulence.model", "k-omega", "realizable-k-epsilon", "cases/bad.toml:14:"],
        ),
        ("negative k", r("initial_k = 1.0", "initial_k = -1.0"), vec!["turbulence.initial_k", "-1", "> 0", "cases/bad.toml:15:"]),
        ("nan epsilon", r("initial_epsilon = 1.0", "initial_epsilon = nan"), vec!["turbulence.initial_epsilon", "NaN"]),
        ("intensity above 1", r("initial_k = 1.0", "initial_k = 1.0\ninlet_intensity = 5.0"), vec!["turbulence.inlet_intensity", "5"]),
        ("misplaced constant", r("initial_k = 1.0", "initial_k = 1.0\nkappa = 0.4"), vec!["kappa", "unknown field"]),
        ("wall E below 1", format!("{GOOD}\n[turbulence.constants]\nwall_e = 0.5\n"), vec!["turbulence.constants.wall_e", "0.5"]),
        ("k–ε without fluid", GOOD.replace("[fluid]\ndensity = 1000.0\nkinematic_viscosity = 1e-3\n", ""), vec!["turbulence.model", "[fluid]"]),
    ];
    for (what, text, expected) in cases {
        let message = parse(&text).expect_err(what);
        for part in expected {
            assert!(message.contains(part), "{what}: `{part}` missing from: {message}");
        }
    }
}
