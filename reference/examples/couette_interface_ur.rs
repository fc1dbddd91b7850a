//! Measurement driver for issue 12: spurious radial velocity at the sliding interface of the
//! circular Couette case (spillage-and-flow-verification.md §3).
//!
//! Runs a Couette case file at several radial resolutions n_r (n_θ = 4 n_r, stator
//! n_θ·`stator_theta_ratio`, Δt ∝ 1/n_r from the case's own (n_r, Δt) pairing as in its
//! `[verify.params] levels`/`dt`), and prints at the end time the max |u_r| over the cells next
//! to the interface circle (the two rings of cells touching r = r_interface, or for an annulus the
//! two rings whose centres lie within 0.6 h of `--ring` radius), the max |u_r| overall and the
//! u_θ rms error, with observed orders.
//!
//! usage: cargo run --release -p spillage-reference --example couette_interface_ur -- \
//!            CASE.toml [n_r ...]   (env RING=1.5 for an annulus; END=t to override end_time)

use std::path::PathBuf;

use spillage_model::case::{Case, MeshSection};
use spillage_model::mesh::{PatchKind, Vec3};
use spillage_model::solver::Solver;
use spillage_model::state::State;
use spillage_model::step::Coupled;
use spillage_reference::fluid::ReferenceFluid;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = PathBuf::from(args.get(1).expect("case file"));
    let levels: Vec<usize> = if args.len() > 2 { args[2..].iter().map(|s| s.parse().expect("n_r")).collect() } else { vec![8, 16, 32] };
    let base = Case::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let ring: f64 = std::env::var("RING").ok().and_then(|s| s.parse().ok()).unwrap_or(1.5);
    let mut previous: Option<(usize, f64, f64)> = None;
    for &n_r in &levels {
        let mut case = base.clone();
        let n_theta = 4 * n_r;
        let (r1, r2);
        match case.mesh.as_mut().expect("mesh") {
            MeshSection::Annulus { n_r: nr, n_theta: nt, r_inner, r_outer, .. } => {
                *nr = n_r;
                *nt = n_theta;
                (r1, r2) = (*r_inner, *r_outer);
            }
            MeshSection::RotorStator { r_inner, r_interface, r_outer, n_r_rotor, n_r_stator, n_theta_rotor, n_theta_stator, .. } => {
                let rotor = ((n_r as f64) * (*r_interface - *r_inner) / (*r_outer - *r_inner)).round().max(1.0) as usize;
                *n_r_rotor = rotor;
                *n_r_stator = n_r - rotor;
                *n_theta_rotor = n_theta;
                *n_theta_stator = (n_theta as f64 * 1.25).round() as usize;
                (r1, r2) = (*r_inner, *r_outer);
            }
            _ => panic!("annulus or rotor_stator mesh"),
        }
        let sliding = matches!(case.mesh, Some(MeshSection::RotorStator { .. }));
        if sliding {
            // the case's Δt pairing: Δt = 0.2 s at n_r = 8, halving with h
            case.time.dt = Some(0.2 * 8.0 / n_r as f64);
        }
        if let Some(t) = std::env::var("END").ok().and_then(|s| s.parse::<f64>().ok()) {
            case.time.end_time = Some(t);
        }
        let mesh = spillage_model::mesh::build(case.mesh.as_ref().unwrap()).expect("mesh");
        let mut state = State::default();
        let fluid = ReferenceFluid::new(&case, mesh, &mut state).expect("solver");
        let mut solver = Coupled::fluid_only(&case, state, fluid).expect("run");
        let dt = case.time.dt.unwrap();
        let steps = (case.time.end_time.unwrap() / dt - 1e-9).ceil() as u64;
        let t0 = std::time::Instant::now();
        let mut max_outer = 0.0f64;
        for _ in 0..steps {
            let report = solver.step().expect("step");
            for (k, v) in report.values {
                if k == "outer_iterations" {
                    max_outer = max_outer.max(v);
                }
            }
        }
        let mesh = solver.mesh().expect("a fluid run");
        let fluid = solver.state().fluid.as_ref().unwrap();
        let h = (r2 - r1) / n_r as f64;
        let mut adjacent = vec![false; mesh.cell_volumes.len()];
        if sliding {
            for patch in &mesh.patches {
                if let PatchKind::Interface { .. } = patch.kind {
                    for f in patch.faces() {
                        adjacent[mesh.face_owner[f]] = true;
                    }
                }
            }
        } else {
            for (c, x) in mesh.cell_centres.iter().enumerate() {
                adjacent[c] = ((x.x * x.x + x.y * x.y).sqrt() - ring).abs() < 0.6 * h;
            }
        }
        let (mut ur_iface, mut ur_all, mut su, mut n) = (0.0f64, 0.0f64, 0.0, 0.0);
        let a = -r1 * r1 / (r2 * r2 - r1 * r1);
        let b = r1 * r1 * r2 * r2 / (r2 * r2 - r1 * r1);
        for (c, x) in mesh.cell_centres.iter().enumerate() {
            let r = (x.x * x.x + x.y * x.y).sqrt();
            let e_r = Vec3::new(x.x / r, x.y / r, 0.0);
            let e_t = Vec3::new(-x.y / r, x.x / r, 0.0);
            let u = Vec3::from(fluid.velocity[c]);
            let ur = u.dot(&e_r).abs();
            ur_all = ur_all.max(ur);
            if adjacent[c] {
                ur_iface = ur_iface.max(ur);
            }
            su += (u.dot(&e_t) - (a * r + b / r)).powi(2);
            n += 1.0;
        }
        let u_rms = (su / n).sqrt();
        let orders = previous.map(|(nr0, ui0, urms0)| {
            let h = (n_r as f64 / nr0 as f64).ln();
            ((ui0 / ur_iface).ln() / h, (urms0 / u_rms).ln() / h)
        });
        println!(
            "n_r {n_r:3} n_θ {n_theta:4} dt {dt:.4} steps {steps:4} ({:.1} s, max outer {max_outer}): max|u_r| interface {ur_iface:.3e}  all {ur_all:.3e}  u_θ rms {u_rms:.3e}  orders {orders:?}",
            t0.elapsed().as_secs_f64()
        );
        previous = Some((n_r, ur_iface, u_rms));
    }
}
