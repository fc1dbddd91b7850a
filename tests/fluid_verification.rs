//! Coarse levels of the reference fluid verification ladder (issue #4); `spillage verify --full`
//! adds the fine levels.

use std::path::PathBuf;

use spillage::verify::{run_case, CheckRow};
use spillage_model::case::Case;

fn case(name: &str) -> Case {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases/verification/fluid").join(name);
    Case::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn print_rows(rows: &[CheckRow]) {
    for r in rows {
        eprintln!("{:<60} value {:>12.5e} ref {:>10.3e} tol {:>10.3e} {}", r.quantity, r.value, r.reference, r.tolerance, if r.pass { "ok" } else { "FAIL" });
    }
}

fn check(name: &str) -> Vec<CheckRow> {
    let rows = run_case(&case(name), false).unwrap_or_else(|e| panic!("{name}: {e:#}"));
    print_rows(&rows);
    for r in &rows {
        assert!(r.pass, "{name}: {} = {} fails (reference {}, tolerance {})", r.quantity, r.value, r.reference, r.tolerance);
    }
    rows
}

#[test]
fn couette_wall_velocity() {
    check("couette_wall_velocity.toml");
}

#[test]
#[ignore]
fn debug_geometry() {
    let c = case("couette_wall_velocity.toml");
    let mesh = spillage::verify::fluid::build_mesh(&c).unwrap();
    eprintln!("cells {} faces {} internal {}", mesh.cell_volumes.len(), mesh.face_areas.len(), mesh.n_internal_faces);
    for p in &mesh.patches { eprintln!("{} {:?} {} {}", p.name, p.kind, p.start, p.len); }
    eprintln!("vol0 {} w0 {} d0 {:?} S0 {:?}", mesh.cell_volumes[0], mesh.face_weight[0], mesh.face_delta[0], mesh.face_areas[0]);
    let s = spillage_reference::fluid::ReferenceFluid::new(&c, mesh, Default::default()).unwrap();
    let g = s.geometry();
    eprintln!("solved {:?} links {} boundary {}", g.solved_components, g.links.len(), g.boundary.len());
    for b in g.boundary.iter().take(3) { eprintln!("{:?}", b); }
    let bad: Vec<_> = g.links.iter().filter(|l| !l.laplacian_coefficient().is_finite() || !l.weight.is_finite()).collect();
    eprintln!("bad links {}", bad.len());
}

#[test]
#[ignore]
fn debug_step() {
    use spillage_model::solver::Solver;
    let c = case("couette_wall_velocity.toml");
    let mesh = spillage::verify::fluid::build_mesh(&c).unwrap();
    let mut s = spillage_reference::fluid::ReferenceFluid::new(&c, mesh, Default::default()).unwrap();
    for _ in 0..3 {
        match s.step() { Ok(r) => eprintln!("{:?}", r.values), Err(e) => { eprintln!("{e}"); break } }
    }
}
