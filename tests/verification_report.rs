//! The verification report (issue 20): `spillage verify --report` assembles, per case, the rows of
//! each solver, the fast-vs-reference equivalence and the case's description. The whole coarse
//! ladder takes ~15 min on two cores (the cutter head alone several minutes), too slow for
//! `cargo test`, so this test generates the report for a representative subset — a fluid case
//! run by both fluid solvers and compared step by step, DEM cases (one pass, no fast
//! counterpart), a case whose comparison is skipped with its reason — and snapshots its
//! assembled tables (numbers rounded to a tenth of each row's tolerance, no times, no figures)
//! in golden/verification_report.snap. The checks' individual snapshots (golden/*.snap) cover the
//! rest of the ladder's numbers.

use std::path::PathBuf;

use spillage::verify::report::{render, run_case_for_report, Comparison, Numbers};
use spillage_model::case::Case;

/// The subset: cheap cases of every kind the report distinguishes.
const CASES: &[&str] =
    &["fluid/poiseuille_periodic.toml", "dem/dry_restitution.toml", "dem/wet_restitution.toml", "dem/oblique_wall.toml", "rotating_frame/fluid_at_rest.toml"];

#[test]
fn report_of_a_representative_subset() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut results = Vec::new();
    for name in CASES {
        let case = Case::load(&root.join("cases/verification").join(name)).unwrap_or_else(|e| panic!("{e}"));
        let mut result = run_case_for_report(&case, false, None).unwrap_or_else(|e| panic!("{name}: {e:#}"));
        // the report names cases by their path in the repository, wherever it is checked out
        result.path = PathBuf::from("cases/verification").join(name);
        results.push(result);
    }
    // the snapshot first: a moved number shows up in `cargo insta review` with its row
    let text = render(&results, false, Numbers::Rounded);
    insta::with_settings!({ snapshot_path => "../golden", prepend_module_to_snapshot => false }, {
        insta::assert_snapshot!("verification_report", text);
    });
    for c in &results {
        for r in &c.rows {
            assert!(r.pass, "{}: {} = {} fails (reference {}, tolerance {})", c.name, r.quantity, r.value, r.reference, r.tolerance);
        }
    }
    // both fluid solvers ran the fluid case, and it was compared step by step
    let fluid = &results[0];
    assert!(fluid.rows.iter().any(|r| r.solver == "fast") && fluid.rows.iter().any(|r| r.solver == "reference"));
    assert!(matches!(fluid.comparison, Comparison::Compared(_)));
    assert!(matches!(results[1].comparison, Comparison::NotApplicable));
    assert!(matches!(results[4].comparison, Comparison::Skipped(_)));
}
