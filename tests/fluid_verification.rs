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

#[test]
#[ignore]
fn couette_wall_velocity_full() {
    let rows = run_case(&case("couette_wall_velocity.toml"), true).unwrap();
    print_rows(&rows);
}

#[test]
fn couette_sliding() {
    check("couette_sliding.toml");
}

#[test]
fn free_stream_interface() {
    check("free_stream_interface.toml");
}

#[test]
fn free_stream_rotating() {
    check("free_stream_rotating.toml");
}

#[test]
fn poiseuille_periodic() {
    check("poiseuille_periodic.toml");
}

#[test]
fn poiseuille_periodic_graded() {
    check("poiseuille_periodic_graded.toml");
}

#[test]
fn poiseuille_inlet_outlet() {
    check("poiseuille_inlet_outlet.toml");
}

#[test]
fn taylor_green() {
    check("taylor_green.toml");
}

#[test]
#[ignore]
fn debug_rotating() {
    use spillage_model::solver::Solver;
    let c = case("free_stream_rotating.toml");
    let mesh = spillage::verify::fluid::build_mesh(&c).unwrap();
    let mut s = spillage_reference::fluid::ReferenceFluid::new(&c, mesh, Default::default()).unwrap();
    s.step().unwrap();
    let geo = s.geometry();
    // closure of every cell, and mesh-flux sums
    let n = geo.n_cells();
    let mut close = vec![spillage_model::mesh::Vec3::zeros(); n];
    let mut mf = vec![0.0; n];
    for l in &geo.links { close[l.owner] += l.area; close[l.neighbour] -= l.area; mf[l.owner] += l.mesh_flux; mf[l.neighbour] -= l.mesh_flux; }
    for b in &geo.boundary { close[b.cell] += b.area; mf[b.cell] += b.mesh_flux; }
    let worst = close.iter().map(|v| v.norm()).fold(0.0, f64::max);
    eprintln!("closure (no empty faces, xy only) max {:e}; mesh flux sum max {:e}", worst, mf.iter().map(|v| v.abs()).fold(0.0, f64::max));
    for (c, v) in close.iter().enumerate() { if v.norm() > 1e-12 { eprintln!("open cell {c} {:?}", v); } }
    for l in &geo.links { if l.owner == 40 || l.neighbour == 40 { eprintln!("{:?}", l); } }
    for step in 0..3 {
        let r = s.step().unwrap();
        let f = s.state().fluid.as_ref().unwrap();
        let mut worst = (0.0, 0);
        for (c, u) in f.velocity.iter().enumerate() { let d = ((u[0]-1.0).powi(2) + (u[1]-0.3).powi(2)).sqrt(); if d > worst.0 { worst = (d, c); } }
        if step == 0 { for (c, u) in f.velocity.iter().enumerate() { let d = ((u[0]-1.0).powi(2) + (u[1]-0.3).powi(2)).sqrt(); if d > 1e-7 { eprintln!("cell {c} dev {d:e} p {:e}", f.pressure[c]); } } }
        eprintln!("step {step} worst {:e} at cell {} (rotor cells < {}) {:?}", worst.0, worst.1, s.mesh().zones[0].cells.len(), r.values[6]);
    }
}

/// `cargo test --test fluid_verification full_ladder -- --ignored --nocapture` prints the
/// `--full` rows of every case named in SPILLAGE_FULL (comma-separated file names).
#[test]
#[ignore]
fn full_ladder() {
    let names = std::env::var("SPILLAGE_FULL").unwrap_or_default();
    for name in names.split(',').filter(|s| !s.is_empty()) {
        eprintln!("== {name}");
        match run_case(&case(name), true) {
            Ok(rows) => print_rows(&rows),
            Err(e) => eprintln!("{name}: {e:#}"),
        }
    }
}

#[test]
#[ignore]
fn debug_channel() {
    use spillage_model::solver::Solver;
    let c = case("poiseuille_inlet_outlet.toml");
    let mesh = spillage::verify::fluid::build_mesh(&c).unwrap();
    let mut s = spillage_reference::fluid::ReferenceFluid::new(&c, mesh, Default::default()).unwrap();
    for _ in 0..60 { s.step().unwrap(); }
    let f = s.state().fluid.as_ref().unwrap();
    for i in (0..64).step_by(4) { let row: Vec<String> = (0..8).map(|j| format!("{:.5}", f.velocity[i + 64 * j][0])).collect(); eprintln!("x {:.3} {} v {:.2e} p {:.4}", s.mesh().cell_centres[i].x, row.join(" "), f.velocity[i + 64*3][1], f.pressure[i+64*3]); }
}
