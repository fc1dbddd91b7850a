//! The head's batch placed once the water has turned (model::particles::batch, the thesis'
//! initialisation of spillage-and-flow-verification.md §5.4), on the coarse head of the tests
//! around it.

use super::*;

/// `case` with its batch placed once the head has turned `revolutions` (the thesis'
/// initialisation, spillage-and-flow-verification.md §5.4, model::particles::batch).
fn batch_after(mut case: Case, revolutions: f64) -> Case {
    for group in &mut case.particles.as_mut().unwrap().groups {
        if let spillage_model::particles::settings::GroupSection::HeadLattice { after_revolutions, .. } = group {
            *after_revolutions = revolutions;
        }
    }
    case.finish().unwrap_or_else(|e| panic!("{e:?}"));
    case
}

/// The batch placed after the water turned alone: no particle before its step (t_b = 0.011 s,
/// in the sixth step of 2 ms), then all of it at once, accounted for at every step, the same in
/// both fluids to 1e-8. The water is not driven out of the batch's cells: its volume counts at
/// the fluid's earlier time levels too, so the hull's net inflow and the mouth's flux differ
/// only by what the moving particles' α does (measured: ≤ 6 % of Q_m here, and up to 14 % in
/// the first steps of the batch placed at t = 0; bound 20 %). Counted as appearing within the
/// step, the batch's volume drove 1.2 m³/s = 10 Q_m out of the mouth in that step (measured
/// with the earlier levels left alone: the sum is then 8.9 Q_m).
#[test]
fn a_batch_placed_after_the_water_has_turned() {
    let case = batch_after(coarse_head(true, 9), 0.011);
    let q_m = case.cutter_head.as_ref().unwrap().suction_discharge;
    let mut reference = coupled(&case, None, |c, s| ReferenceFluid::new(c, mesh(c), s).unwrap());
    let mut fast = coupled(&case, None, |c, s| FastFluid::new(c, mesh(c), s).unwrap());
    assert!(fast.state().particles.as_ref().unwrap().particles.is_empty());
    let mut batch = 0.0;
    for step in 1..=9 {
        let (a, report) = (reference.step().unwrap(), fast.step().unwrap());
        let created = fast.state().particles.as_ref().unwrap().counts.created as f64;
        if step < 6 {
            assert_eq!(created, 0.0, "step {step}: particles before the batch's time");
        } else if step == 6 {
            batch = created;
            assert!(batch > 50.0, "the batch placed {batch} particles");
        }
        assert_eq!(created, batch, "step {step}: created");
        let (inside, sucked, spilled) = (value(&report, "particles"), value(&report, "sucked"), value(&report, "spilled"));
        assert_eq!(inside + sucked + spilled, batch, "step {step}");
        let (net, suction) = (value(&report, "hull_net_flux"), value(&report, "suction_flux"));
        assert!((net + suction).abs() <= 0.2 * q_m, "step {step}: net hull flux {net} vs mouth {suction}");
        let diff = spillage_model::state_diff::diff(reference.state(), fast.state());
        let error = spillage::verify::equivalence_error(reference.state(), &diff);
        assert!(error <= 1e-8, "step {step}: {}", diff.report());
        assert_eq!(value(&a, "particles"), inside, "step {step}");
    }
}

/// Where the batch is placed into a turning head, every sphere is clear of the blades as the
/// DEM's walls stand then (the head's second consumer of the same geometry), and of the
/// particles already there; the sites skipped for those are the only ones missing.
#[test]
fn a_later_batch_is_clear_of_the_turned_blades_and_the_particles_there() {
    use spillage_model::particles::batch;
    let case = batch_after(coarse_head(true, 1), 0.3);
    let section = case.particles.as_ref().unwrap();
    let head = spillage_model::cutter_head::CutterHead::new(case.cutter_head.as_ref().unwrap());
    let later = batch::later_batches(&case).unwrap();
    let omega = case.rotor.as_ref().unwrap().angular_velocity();
    assert_eq!(later.len(), 1);
    assert!((later[0].time - 0.3).abs() < 1e-15, "t_b = {} s at 60 rpm", later[0].time);
    let angle = 1.9;
    let mut state = spillage_model::particles::ParticleState::default();
    let alone = batch::place(section, omega, &head, &later[0], angle, &mut state).unwrap();
    let mut walls = spillage_model::walls::build(&case, Path::new(".")).unwrap();
    walls.place(later[0].time, spillage_model::step::RotorPose::from_case(&case, angle).as_ref());
    for wall in &walls.walls {
        let mesh = spillage_model::walls::geometry::WallMesh::new(&wall.vertices, &wall.triangles).unwrap();
        for p in &state.particles {
            let r = p.radius();
            let touching =
                mesh.sphere_contacts(wall.to_body(p.position), r).into_iter().find(|c| r - c.distance > spillage_model::particles::placement::TOUCHING * r);
            assert!(touching.is_none(), "particle {} at {:?} touches wall {} at {:?}", p.id, p.position, wall.name, touching);
        }
    }
    // placed again where every other sphere of the first is still there: only the others' sites are free
    let mut occupied = spillage_model::particles::ParticleState::default();
    occupied.particles.extend(state.particles.iter().step_by(2).cloned());
    let before = occupied.particles.len();
    let again = batch::place(section, omega, &head, &later[0], angle, &mut occupied).unwrap();
    assert_eq!((again, occupied.counts.created), (alone - before, again as u64), "{again} of {alone} sites free, {before} taken");
    for p in &occupied.particles[before..] {
        assert!(occupied.particles[..before].iter().all(|q| (q.position - p.position).norm() >= q.radius() + p.radius()), "particle {} overlaps", p.id);
    }
}

/// A run restarted before its batch is placed places it in the same step and continues
/// bit-for-bit (the batch keeps no state of its own).
#[test]
fn a_head_run_restarted_before_its_batch_continues_bit_for_bit() {
    let end = restarts_bit_for_bit(&batch_after(coarse_head(true, 12), 0.017));
    assert!(end.particles.as_ref().unwrap().counts.created > 50, "the batch was placed after the restart");
}
