//! The mapping's unit tests: conservation, smooth crossings, the interface, representative
//! particles; and the particles, mapping and loads the other coupling tests build on.

use super::*;
use crate::coupling::settings::{Feedback, InterfaceTreatment};
use crate::mesh::cartesian::BoxSpec;
use crate::mesh::cylindrical::RotorStatorSpec;
use crate::particles::Particle;

pub(in crate::coupling) fn particle(x: Vec3, diameter: f64) -> Particle {
    Particle {
        id: 0,
        material: 0,
        diameter,
        density: 2650.0,
        position: x,
        velocity: Vec3::zeros(),
        spin: Vec3::zeros(),
        contact_force: Vec3::zeros(),
        contact_torque: Vec3::zeros(),
        contacts: 0,
    }
}

pub(in crate::coupling) fn map(method: MappingMethod, mask: bool) -> ParticleMeshMap {
    let section = CouplingSection {
        method,
        distance_factor: 1.0,
        feedback: Feedback::default(),
        interface: Default::default(),
        interface_mask: Some(mask),
        drag: Default::default(),
        min_fluid_fraction: 0.05,
    };
    ParticleMeshMap::new(&section)
}

pub(in crate::coupling) fn load(particles: &[Particle]) -> ParticleLoad {
    let n = particles.len();
    let mut load = ParticleLoad::zeros(n);
    for (i, p) in particles.iter().enumerate() {
        load.volume[i] = p.volume();
        load.implicit_drag[i] = 0.01 * (i + 1) as f64;
        load.explicit_force[i] = [0.3, -((i + 1) as f64), 0.2];
    }
    load
}

/// U-19 and U-24 (§12) for all three methods: Σ_j α_p,j V_j = Σ V_p, Σ_j C_j = Σ K_n and
/// Σ_j F_j = Σ F_n to round-off, in the interior and at walls (the diffusion method to its
/// folded-back residual, also round-off).
#[test]
fn every_method_conserves_volume_drag_and_force() {
    let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(0.2, 0.3, 0.02), [20, 30, 1])).unwrap();
    let particles = [particle(Vec3::new(0.1, 0.15, 0.01), 0.01), particle(Vec3::new(0.004, 0.29, 0.01), 0.01)];
    let load = load(&particles);
    for method in [MappingMethod::Centroid, MappingMethod::Kernel, MappingMethod::Diffusion] {
        let mut cells = CellLoad::default();
        map(method, true).deposit(&mesh, &particles, &load, &mut cells);
        let volume: f64 = cells.particle_fraction.iter().zip(&mesh.cell_volumes).map(|(a, v)| a * v).sum();
        let drag: f64 = cells.implicit_drag.iter().sum();
        let force: Vec3 = cells.explicit_force.iter().sum();
        let exact_volume: f64 = load.volume.iter().sum();
        assert!((volume / exact_volume - 1.0).abs() < 1e-13, "{method:?}: volume {volume} vs {exact_volume}");
        assert!((drag / 0.03 - 1.0).abs() < 1e-13, "{method:?}: drag {drag}");
        assert!((force - Vec3::new(0.6, -3.0, 0.4)).norm() < 1e-13, "{method:?}: force {force}");
        assert!(cells.masked.iter().all(|m| !m), "{method:?}: no interface, no mask");
    }
}

/// Representative particles (wear-model.md §2.4 [R]): with `modifier` m every cell receives
/// m times the volume, drag coefficient and force of one particle each, for all three methods.
/// m = 8 is a power of two, so the scaling is exact and the fields must agree bit for bit.
#[test]
fn a_modifier_counts_each_particle_that_many_times() {
    let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(0.2, 0.3, 0.02), [20, 30, 1])).unwrap();
    let particles = [particle(Vec3::new(0.1, 0.15, 0.01), 0.01), particle(Vec3::new(0.004, 0.29, 0.01), 0.01)];
    let load = load(&particles);
    for method in [MappingMethod::Centroid, MappingMethod::Kernel, MappingMethod::Diffusion] {
        let (mut one, mut eight) = (CellLoad::default(), CellLoad::default());
        map(method, false).deposit(&mesh, &particles, &load, &mut one);
        ParticleMeshMap { modifier: 8.0, ..map(method, false) }.deposit(&mesh, &particles, &load, &mut eight);
        assert!(one.particle_fraction.iter().any(|a| *a > 0.0), "{method:?}: nothing deposited");
        for c in 0..mesh.n_cells() {
            assert_eq!(eight.particle_fraction[c], 8.0 * one.particle_fraction[c], "{method:?}: α_p of cell {c}");
            assert_eq!(eight.implicit_drag[c], 8.0 * one.implicit_drag[c], "{method:?}: drag of cell {c}");
            assert_eq!(eight.explicit_force[c], one.explicit_force[c] * 8.0, "{method:?}: force of cell {c}");
        }
    }
}

/// P1's coarsest mesh (10 cm cells, a 10 mm sphere): as the particle crosses a face in steps
/// of 0.2 mm, the kernel (γ = 1) and diffusion (γ = 3) deposits move their volume across
/// smoothly — the host-cell deposit moved all of it in one step. The bound: a share moves at
/// most at the Gaussian's steepest slope, step/(σ√2π) = 0.8 % of V_p per step for the
/// kernel's σ = 1 cm and 3.6 % for the diffusion's starting width σ₀ = 2.24 mm; 5 % allows
/// for the sum's curvature error (cell_quadrature's test) and is 20× below a jump.
#[test]
fn deposits_move_smoothly_across_a_face_of_cells_wider_than_the_kernel() {
    let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(0.3, 0.8, 0.02), [3, 8, 1])).unwrap();
    for (method, gamma) in [(MappingMethod::Kernel, 1.0), (MappingMethod::Diffusion, 3.0)] {
        let mut m = map(method, false);
        m.distance_factor = gamma;
        let mut previous: Option<Vec<f64>> = None;
        let mut largest = 0.0f64;
        for k in 0..100 {
            let particles = [particle(Vec3::new(0.15005, 0.41 - 2e-4 * k as f64, 0.01), 0.01)];
            let mut cells = CellLoad::default();
            m.deposit(&mesh, &particles, &load(&particles), &mut cells);
            let volumes: Vec<f64> = cells.particle_fraction.iter().zip(&mesh.cell_volumes).map(|(a, v)| a * v / particles[0].volume()).collect();
            if let Some(p) = &previous {
                largest = largest.max(volumes.iter().zip(p).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max));
            }
            previous = Some(volumes);
        }
        assert!(largest < 0.05, "{method:?}: a cell's share moved by {largest} of V_p in one 0.2 mm step");
        assert!(largest > 1e-4, "{method:?}: the particle crossed the face at y = 0.4, so shares must move");
    }
}

/// The diffusion's starting width is the sphere's own (σ₀² = a²/5, a = d/2), and a distance
/// factor below it is refused, naming the key.
#[test]
fn diffusion_starts_from_the_sphere_width_and_refuses_a_narrower_kernel() {
    assert!((SPHERE_WIDTH_FACTOR - 0.5 / 5f64.sqrt()).abs() < 1e-16);
    let mut section = CouplingSection {
        method: MappingMethod::Diffusion,
        distance_factor: 0.2,
        feedback: Feedback::default(),
        interface: Default::default(),
        interface_mask: Some(true),
        drag: Default::default(),
        min_fluid_fraction: 0.05,
    };
    let error = section.validate().unwrap_err();
    assert!(error.key == "coupling.distance_factor" && error.value == "0.2" && error.allowed.contains("0.2236"), "{error:?}");
    section.method = MappingMethod::Kernel;
    assert!(section.validate().is_ok());
}

/// P2's pseudo-2-D annulus (cases/coupling/interface_crossing.toml): interface at r = 0.2 m,
/// 126 rotor and 137 stator cells around.
fn p2_annulus() -> Mesh {
    Mesh::rotor_stator(&RotorStatorSpec {
        r_inner: 0.05,
        r_interface: 0.2,
        r_outer: 0.4,
        z_min: 0.0,
        z_max: 0.02,
        n_r_rotor: 15,
        n_r_stator: 20,
        n_theta_rotor: 126,
        n_theta_stator: 137,
        n_z: 1,
        radial_grading_rotor: 1.0,
        radial_grading_stator: 1.0,
    })
    .unwrap()
}

/// At a sliding interface (Table 4.2): a kernel stays on the particle's side and is
/// normalised there, so the load is still conserved; the mask covers exactly the cells
/// within 3γd_max of an interface face, and none with `interface_mask = false`.
#[test]
fn kernels_stop_at_the_interface_and_the_mask_covers_its_band() {
    let mesh = p2_annulus();
    let particles = [particle(Vec3::new(0.195, 0.0, 0.01), 0.01)];
    let load = load(&particles);
    let m = map(MappingMethod::Kernel, true);
    let mut cells = CellLoad::default();
    m.deposit(&mesh, &particles, &load, &mut cells);
    let host_zone = mesh.cell_zone[mesh.locate(&particles[0].position).unwrap()];
    for (c, a) in cells.particle_fraction.iter().enumerate() {
        assert!(*a == 0.0 || mesh.cell_zone[c] == host_zone, "cell {c} across the interface got α_p {a}");
    }
    let volume: f64 = cells.particle_fraction.iter().zip(&mesh.cell_volumes).map(|(a, v)| a * v).sum();
    assert!((volume / particles[0].volume() - 1.0).abs() < 1e-13, "volume {volume}");
    let spread = cells.particle_fraction.iter().filter(|a| **a > 0.0).count();
    assert!(spread > 4, "the kernel spans {spread} cells");
    // the band: |r − 0.2| ≲ 3 cm (face centres of the polygonal interface lie just inside 0.2)
    for (c, masked) in cells.masked.iter().enumerate() {
        let x = mesh.cell_centres[c];
        let r = (x.x * x.x + x.y * x.y).sqrt();
        if (r - 0.2).abs() < 0.029 {
            assert!(masked, "cell {c} at r = {r} should be masked");
        }
        if (r - 0.2).abs() > 0.031 {
            assert!(!masked, "cell {c} at r = {r} should not be masked");
        }
    }
    map(MappingMethod::Kernel, false).deposit(&mesh, &particles, &load, &mut cells);
    assert!(cells.masked.iter().all(|m| !m));
}

/// `interface = "span"`: the same particle's kernel reaches into the rotor's cells across the
/// interface, conserves its volume to round-off, and is not masked unless the case asks; the
/// key takes only the kernel method and names itself when refused.
#[test]
fn a_spanning_kernel_reaches_across_the_interface_unmasked() {
    let mesh = p2_annulus();
    let particles = [particle(Vec3::new(0.205, 0.0, 0.01), 0.01)];
    let load = load(&particles);
    let mut section = CouplingSection {
        method: MappingMethod::Kernel,
        distance_factor: 1.0,
        feedback: Feedback::default(),
        interface: InterfaceTreatment::Span,
        interface_mask: None,
        drag: Default::default(),
        min_fluid_fraction: 0.05,
    };
    assert!(section.validate().is_ok() && !section.masks_interface());
    let mut cells = CellLoad::default();
    ParticleMeshMap::new(&section).deposit(&mesh, &particles, &load, &mut cells);
    let host_zone = mesh.cell_zone[mesh.locate(&particles[0].position).unwrap()];
    let across: f64 = (0..mesh.n_cells()).filter(|&c| mesh.cell_zone[c] != host_zone).map(|c| cells.particle_fraction[c] * mesh.cell_volumes[c]).sum();
    let volume: f64 = cells.particle_fraction.iter().zip(&mesh.cell_volumes).map(|(a, v)| a * v).sum();
    // half a cell's width from the interface, a good part of the Gaussian lies beyond it
    assert!(across > 0.2 * particles[0].volume(), "only {across:e} m³ across the interface");
    assert!((volume / particles[0].volume() - 1.0).abs() < 1e-13, "volume {volume}");
    assert!(cells.masked.iter().all(|m| !m), "a spanning kernel is not masked by default");
    section.interface_mask = Some(true);
    assert!(section.masks_interface());
    section.interface_mask = None;
    section.interface = InterfaceTreatment::Truncate;
    assert!(section.masks_interface(), "the truncated kernel is masked by default, as in the thesis");
    section.interface = InterfaceTreatment::Span;
    section.method = MappingMethod::Diffusion;
    section.distance_factor = 3.0;
    let error = section.validate().unwrap_err();
    assert!(error.key == "coupling.interface" && error.value == "\"span\"" && error.allowed.contains("kernel"), "{error:?}");
}
