//! The solids-pressure stage against closed forms, conservation and its own limits.

use super::*;
use crate::closure::solids_pressure::{solids_pressure_slope_per_density, VelocityMoments, PACKING_LIMIT, RESTITUTION};
use crate::mesh::BoxSpec;

/// N cells along a periodic x of length 1 (one cell across y and z, whose walls carry no
/// correction).
fn periodic_row(n: usize) -> Mesh {
    let h = 1.0 / n as f64;
    Mesh::cartesian_box(&BoxSpec { periodic: [true, false, false], ..BoxSpec::uniform(Vec3::zeros(), Vec3::new(1.0, h, h), [n, 1, 1]) }).unwrap()
}

fn stage(treatment: Treatment) -> SolidsPressure {
    SolidsPressure::new(SolidsPressureSection { treatment, ..SolidsPressureSection::default() })
}

/// α_p = 0.3 + 0.1 sin 2πx at the cell centres, Θ uniform.
fn wave(mesh: &Mesh, theta: f64, treatment: Treatment, dt: f64) -> SolidsPressure {
    let mut s = stage(treatment);
    s.fraction = mesh.cell_centres.iter().map(|c| 0.3 + 0.1 * (2.0 * std::f64::consts::PI * c.x).sin()).collect();
    s.temperature = vec![theta; mesh.n_cells()];
    s.correction_field(mesh, dt).unwrap();
    s
}

/// −(1/α_p) ∂(p_p/ρ_p)/∂x of the wave at x: the acceleration of §4.4 in closed form.
fn wave_acceleration(x: f64, theta: f64) -> f64 {
    let k = 2.0 * std::f64::consts::PI;
    let alpha = 0.3 + 0.1 * (k * x).sin();
    -solids_pressure_slope_per_density(alpha, theta, RESTITUTION, PACKING_LIMIT) * 0.1 * k * (k * x).cos() / alpha
}

#[test]
fn explicit_acceleration_converges_at_second_order_to_the_closed_form() {
    let theta = 2.0;
    let dt = 1e-6;
    let errors: Vec<f64> = [16, 32, 64]
        .iter()
        .map(|&n| {
            let mesh = periodic_row(n);
            let s = wave(&mesh, theta, Treatment::Explicit, dt);
            (0..n).map(|j| (s.correction[j].x / dt - wave_acceleration(mesh.cell_centres[j].x, theta)).abs()).fold(0.0, f64::max)
        })
        .collect();
    // central differences of p_p and the average of two face velocities: order 2 (1.8
    // leaves room for the nonlinearity of g₀ on the coarsest mesh)
    for w in errors.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!(order > 1.8, "errors {errors:?}: order {order}");
    }
    assert!(errors[2] < 1e-2 * wave_acceleration(0.0, theta).abs(), "errors {errors:?}");
}

#[test]
fn implicit_correction_tends_to_the_explicit_one_at_second_order_in_the_step() {
    // α_p* differs from α_p by the step's own displacement, Δt² a: the implicit velocity
    // change over Δt, divided by Δt, moves by O(Δt²) as Δt shrinks (successive differences
    // fall 4×; 3.5 allows for the next term)
    let mesh = periodic_row(64);
    let theta = 10.0;
    let per_step = |dt: f64| -> Vec<f64> { wave(&mesh, theta, Treatment::Implicit, dt).correction.iter().map(|u| u.x / dt).collect() };
    let results: Vec<Vec<f64>> = [4e-4, 2e-4, 1e-4].iter().map(|&dt| per_step(dt)).collect();
    let difference = |a: &Vec<f64>, b: &Vec<f64>| a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    let (d1, d2) = (difference(&results[0], &results[1]), difference(&results[1], &results[2]));
    assert!(d1 / d2 > 3.5 && d1 / d2 < 4.5, "successive differences {d1:e}, {d2:e}");
    // and the largest step still moves the acceleration by a visible amount (the test
    // would pass trivially if the solve did nothing)
    assert!(d1 > 1e-3 * results[0].iter().fold(0.0_f64, |a, v| a.max(v.abs())), "d1 {d1:e}");
    // its limit is the acceleration of §4.4: at the smallest step within the explicit
    // form's spatial error at 64 cells (1e-2 of the largest, as in the explicit test)
    let scale = wave_acceleration(0.0, theta).abs();
    let worst = (0..64).map(|j| (results[2][j] - wave_acceleration(mesh.cell_centres[j].x, theta)).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-2 * scale, "implicit at Δt 1e-4 against the closed form: {worst:e} of {scale:e}");
}

#[test]
fn an_over_packed_cell_unpacks_in_one_implicit_step_and_keeps_the_particle_volume() {
    let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(5e-3, 5e-3, 5e-3), [5, 5, 5])).unwrap();
    let centre = mesh.locate(&Vec3::new(2.5e-3, 2.5e-3, 2.5e-3)).unwrap();
    for treatment in [Treatment::Implicit, Treatment::Explicit] {
        let mut s = stage(treatment);
        s.fraction = vec![0.1; mesh.n_cells()];
        s.fraction[centre] = 2.0;
        s.temperature = vec![1.0; mesh.n_cells()];
        let report = s.correction_field(&mesh, 2.5e-5).unwrap();
        assert_eq!(report.largest_fraction, 2.0);
        if treatment == Treatment::Implicit {
            let before: f64 = s.fraction.iter().zip(&mesh.cell_volumes).map(|(a, v)| a * v).sum();
            let after: f64 = s.fraction_after.iter().zip(&mesh.cell_volumes).map(|(a, v)| a * v).sum();
            // the solve's transfers cancel face by face: round-off of 125 terms
            assert!((after - before).abs() <= 1e-14 * before, "Σ α V {before:e} → {after:e}");
        }
        // the packed cell's particles are spread outward: a positive divergence there
        let nb = centre + 1;
        assert!(
            s.correction_gradient[centre].trace() > 0.0,
            "{treatment:?}: trace {:e}, α* {} {} flux {:?} δ {} {}",
            s.correction_gradient[centre].trace(),
            s.fraction_after[centre],
            s.fraction_after[nb],
            mesh.faces_of_cell(centre).iter().filter(|&&f| f < mesh.n_internal_faces).map(|&f| s.face_flux[f]).collect::<Vec<_>>(),
            s.change[centre],
            s.change[nb]
        );
        if treatment == Treatment::Implicit {
            assert!(report.largest_fraction_after < PACKING_LIMIT, "{report:?}");
            assert!(report.iterations > 0);
        } else {
            assert_eq!(report.largest_fraction_after, 2.0);
        }
    }
}

#[test]
fn particles_are_binned_with_their_modifier_and_take_their_cells_correction() {
    let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(3e-3, 1e-3, 1e-3), [3, 1, 1])).unwrap();
    let particle = |id: u64, x: f64, u: f64| Particle {
        id,
        material: 0,
        diameter: 1e-4,
        density: 2500.0,
        position: Vec3::new(x, 5e-4, 5e-4),
        velocity: Vec3::new(u, 0.0, 0.0),
        spin: Vec3::zeros(),
        contact_force: Vec3::zeros(),
        contact_torque: Vec3::zeros(),
        contacts: 0,
    };
    // A34 in the first cell (±1 m/s: Θ = 1/3), one particle in the second, none in the third
    let mut particles = vec![particle(0, 4e-4, 1.0), particle(1, 6e-4, -1.0), particle(2, 1.5e-3, 0.0), particle(3, 9.0, 0.0)];
    let before = particles.clone();
    let mut s = stage(Treatment::Implicit);
    let modifier = 100.0;
    s.correct(&mesh, &mut particles, modifier, 1e-5).unwrap();
    assert!((s.temperature[0] - 1.0 / 3.0).abs() <= 1e-14);
    assert_eq!(s.temperature[1], 0.0);
    let binned: f64 = s.fraction.iter().zip(&mesh.cell_volumes).map(|(a, v)| a * v).sum();
    let real = modifier * 3.0 * before[0].volume();
    assert!((binned - real).abs() <= 1e-15 * real, "{binned:e} vs {real:e}");
    for (p, q) in particles.iter().zip(&before).take(3) {
        let cell = mesh.locate(&q.position).unwrap();
        let expected = s.correction_at(&mesh, cell, &q.position);
        // (u + Δu) − u: round-off of u
        assert!((p.velocity - q.velocity - expected).norm() <= 1e-15 * q.velocity.norm().max(1.0), "{:?} vs {expected:?}", p.velocity - q.velocity);
    }
    // the first cell pushes its particles toward the emptier second cell
    assert!(s.correction[0].x > 0.0);
    // outside the mesh: untouched
    assert_eq!(particles[3].velocity, before[3].velocity);
}

#[test]
fn particles_already_moving_apart_get_only_what_they_lack() {
    // the packed-cell set-up of a 3-cell row, its particles' mean velocities given: moving
    // outward faster than the correction, they get none on those faces; at rest, all of it
    let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(3e-3, 1e-3, 1e-3), [3, 1, 1])).unwrap();
    let run = |outward: f64| {
        let mut s = stage(Treatment::Implicit);
        s.fraction = vec![0.1, 1.0, 0.1];
        s.temperature = vec![1.0; 3];
        s.moments = [-outward, 0.0, outward]
            .iter()
            .map(|&u| {
                let mut m = VelocityMoments::default();
                m.add([u, 0.0, 0.0], 1.0);
                m
            })
            .collect();
        s.correction_field(&mesh, 2.5e-5).unwrap();
        s.face_flux.clone()
    };
    let at_rest = run(0.0);
    assert!(at_rest[0] < 0.0 && at_rest[1] > 0.0, "{at_rest:?}");
    // face velocity of the mean motion: ±u/2 (the middle cell is at rest), times the area
    let area = 1e-6;
    let fast = 4.0 * at_rest[1].abs() / area;
    assert_eq!(run(fast), vec![0.0, 0.0]);
    let slow = 0.5 * at_rest[1].abs() / area;
    let partly = run(slow);
    for (p, r) in partly.iter().zip(&at_rest) {
        assert!((p - (r - r.signum() * 0.5 * slow * area)).abs() <= 1e-12 * r.abs(), "{partly:?} against {at_rest:?}");
    }
}

#[test]
fn the_thesis_literal_force_lacks_the_fraction() {
    // explicit: face by face the per-particle-volume correction times α_p,f (exactly, up to
    // the one division); implicit: a weaker correction of the same sign on the wave, at most
    // α_p ≤ 0.4 of it (0.45: at Δt 1e-5 the two solves' α_p* differ by far less than that
    // margin)
    let mesh = periodic_row(32);
    let dt = 1e-5;
    let field = |treatment, force| {
        let mut s = SolidsPressure::new(SolidsPressureSection { treatment, force, ..SolidsPressureSection::default() });
        s.fraction = mesh.cell_centres.iter().map(|c| 0.3 + 0.1 * (2.0 * std::f64::consts::PI * c.x).sin()).collect();
        s.temperature = vec![2.0; mesh.n_cells()];
        s.correction_field(&mesh, dt).unwrap();
        s
    };
    let volume = field(Treatment::Explicit, KtgfForce::PerParticleVolume);
    let literal = field(Treatment::Explicit, KtgfForce::ThesisLiteral);
    for f in 0..mesh.n_internal_faces {
        let (o, nb, w) = (mesh.face_owner[f], mesh.face_neighbour[f], mesh.face_weight[f]);
        let alpha = w * volume.fraction[o] + (1.0 - w) * volume.fraction[nb];
        assert!((literal.face_flux[f] - alpha * volume.face_flux[f]).abs() <= 1e-15 * literal.face_flux[f].abs().max(1e-300), "face {f}");
    }
    let volume = field(Treatment::Implicit, KtgfForce::PerParticleVolume);
    let literal = field(Treatment::Implicit, KtgfForce::ThesisLiteral);
    for (l, v) in literal.correction.iter().zip(&volume.correction) {
        assert!(l.x * v.x >= 0.0 && l.x.abs() < 0.45 * v.x.abs().max(1e-300) + 1e-300, "{l:?} vs {v:?}");
    }
}

#[test]
fn bad_settings_name_their_key() {
    let bad = SolidsPressureSection { packing_limit: 1.2, ..SolidsPressureSection::default() };
    assert_eq!(bad.validate().unwrap_err().key, "particles.solids_pressure.packing_limit");
    let bad = SolidsPressureSection { restitution: -0.1, ..SolidsPressureSection::default() };
    assert_eq!(bad.validate().unwrap_err().key, "particles.solids_pressure.restitution");
    assert_eq!(stage(Treatment::Implicit).correction_field(&periodic_row(4), 0.0).unwrap_err(), SolidsPressureError::BadStep(0.0));
}
