//! The thesis' out-flowing flux (spillage-and-flow-verification.md §5.1, Eqs. 8.1–8.4): the
//! cell-centre velocities interpolated onto the surface of revolution r = R(z) that wraps the
//! blade contour, u_rad,i = u_i·n_i (Eq. 8.1), φ_rad,i = u_rad,i A_i (Eq. 8.2), the net flux
//! Σ φ (Eq. 8.3, ≈ −Q_m with outward normals, §5.1 note) and Q_out = Σ pos(φ) (Eq. 8.4).
//!
//! The face hull of [`super::spillage::HullFaces`] sums the solver's own face fluxes, so its net
//! flux is Q_m to solver tolerance, but its surface is the staircase of the cells the contour
//! crosses: it lies up to one cell outside R(z) and moves when the mesh changes, so Q_out
//! measured on it mixes the flow's convergence with the surface's. This surface stays at R(z)
//! on every mesh; its net flux misses Q_m by the interpolation error (the thesis: −3 % to
//! +10 %).
//!
//! - The surface is cut into quadrilaterals of about `SPACING_FACTOR` R_max, independent of the
//!   mesh, each with its midpoint and exact area vector (R cos θ, R sin θ, −R R′) Δθ Δz of the
//!   frustum r = R(z), outward.
//! - A point's velocity is its cell's centre value plus the Gauss gradient times the offset
//!   (linear interpolation; boundary faces take the assembly's boundary values, so the blades'
//!   faces bring the rotor's velocity). A point inside a solid's staircase slot lies in the
//!   rotor's material: its velocity is the rotor's ω × r, tangent to the surface, and it carries
//!   no flux.
//! - The surface lies in the rotor zone (the interface radius exceeds the widest part of the
//!   head, settings.rs), so each point is fixed in the rotor's frame: it is located once, and its
//!   cell, being rigid, carries it round.

use super::geometry::CutterHead;
use super::spillage::EXIT_BIN;
use crate::coupling::mapping::host_cell;
use crate::mesh::{Mesh, Vec3, ZoneRotation};
use std::f64::consts::TAU;

/// Quadrilateral size over the widest contour radius: 360 around the widest circle (6.5 mm on
/// the 1:4 head), several per cell on the meshes run (3–5 cm), so the linear interpolation is
/// integrated, not sampled.
pub const SPACING_FACTOR: f64 = TAU / 360.0;

/// One quadrature point of the surface.
#[derive(Clone, Copy, Debug)]
struct SurfacePoint {
    /// Position and outward area vector in the rotor's reference pose (angle 0).
    position: Vec3,
    area: Vec3,
    /// The open cell holding it; `None` inside a solid (no flux).
    cell: Option<usize>,
}

/// The fluxes through the contour surface of one step [m³/s].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContourFlux {
    /// Q_out = Σ pos(φ) (Eq. 8.4).
    pub outflow: f64,
    /// Σ φ, outward positive (Eq. 8.3): ≈ −Q_m.
    pub net: f64,
    /// Q_out through the top `EXIT_BIN` under the ring.
    pub outflow_top_bin: f64,
}

/// The contour surface as quadrature points.
#[derive(Clone, Debug)]
pub struct HullSurface {
    /// The surface r = R(z), −H ≤ z ≤ 0 (the ring above and the hub below are solid).
    hull: Vec<SurfacePoint>,
    /// Heights of the hull points (for the top exit bin and the laboratory elements).
    heights: Vec<f64>,
    /// The rotor zone (whose rotation carries the points).
    zone: usize,
    /// Points per ring around the axis: point i lies on ring i / n_theta at azimuth
    /// (i mod n_theta + ½) Δθ in the reference pose.
    n_theta: usize,
}

/// One element of the contour fixed in the laboratory ([`HullSurface::laboratory_elements`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaboratoryElement {
    /// Height [m] (the ring at 0) and radius [m] of its midpoint.
    pub z: f64,
    pub radius: f64,
    /// Azimuth of its midpoint about +z from +x [rad], in 0…2π.
    pub azimuth: f64,
    /// Outward area vector [m²].
    pub area: Vec3,
}

/// A zone's rotation about its axis by its angle (Rodrigues), its sine and cosine taken once.
struct Turning<'a> {
    rotation: &'a ZoneRotation,
    sin: f64,
    cos: f64,
}

impl<'a> Turning<'a> {
    fn new(rotation: &'a ZoneRotation) -> Self {
        let (sin, cos) = rotation.angle.sin_cos();
        Turning { rotation, sin, cos }
    }

    /// A vector turned (no origin shift).
    fn vector(&self, v: &Vec3) -> Vec3 {
        let a = self.rotation.axis;
        v * self.cos + a.cross(v) * self.sin + a * (a.dot(v) * (1.0 - self.cos))
    }

    /// A point turned about the axis through the zone's origin.
    fn point(&self, x: &Vec3) -> Vec3 {
        self.vector(&(x - self.rotation.origin)) + self.rotation.origin
    }
}

/// Rotation of `x` about the zone's axis by its angle, as a vector (no origin shift) when
/// `vector`.
#[cfg(test)]
fn turn(rotation: &ZoneRotation, x: &Vec3, vector: bool) -> Vec3 {
    let turning = Turning::new(rotation);
    if vector {
        turning.vector(x)
    } else {
        turning.point(x)
    }
}

impl HullSurface {
    /// The surface of `head` on `mesh` (at whatever angle its rotor zone is now). Errors when a
    /// point of the surface lies outside the rotor zone.
    pub fn new(head: &CutterHead, mesh: &Mesh) -> Result<HullSurface, String> {
        let r_max = head.contour().iter().map(|p| p.1).fold(0.0, f64::max);
        let h = SPACING_FACTOR * r_max;
        let n_theta = (TAU * r_max / h).round() as usize;
        let dtheta = TAU / n_theta as f64;
        // ∫ (cos θ, sin θ) dθ over a strip = 2 sin(Δθ/2) (cos θ_m, sin θ_m): exact area vectors
        let chord = 2.0 * (0.5 * dtheta).sin();
        let mut hull = Vec::new();
        let mut heights = Vec::new();
        // the contour's segments (s from the ring toward the hub; z = −s)
        for pair in head.contour().windows(2) {
            let ((s0, r0, _), (s1, r1, _)) = (pair[0], pair[1]);
            let length = (s1 - s0).hypot(r1 - r0);
            let n_s = ((length / h).ceil() as usize).max(1);
            // dR/dz along the segment (z = −s)
            let slope = -(r1 - r0) / (s1 - s0);
            for i in 0..n_s {
                let t = (i as f64 + 0.5) / n_s as f64;
                let (z, r) = (-(s0 + t * (s1 - s0)), r0 + t * (r1 - r0));
                let dz = (s1 - s0) / n_s as f64;
                for j in 0..n_theta {
                    let theta = (j as f64 + 0.5) * dtheta;
                    let (sin, cos) = theta.sin_cos();
                    hull.push((Vec3::new(r * cos, r * sin, z), Vec3::new(r * cos * chord, r * sin * chord, -r * slope * dtheta) * dz));
                    heights.push(z);
                }
            }
        }
        if hull.is_empty() {
            return Err(format!("the contour surface of {} contour points has no area", head.contour().len()));
        }
        let zone = mesh.zones.iter().position(|z| z.rotation.is_some()).ok_or("the cutter head's mesh has no rotating zone")?;
        // located in the rotor's reference pose, so a run restarted at another angle finds the
        // same cells (a point on a cell boundary goes the same way)
        let mut reference = mesh.clone();
        reference.set_zone_angle(zone, 0.0).map_err(|e| e.to_string())?;
        let mut in_zone = vec![false; mesh.n_cells()];
        for &c in &mesh.zones[zone].cells {
            in_zone[c] = true;
        }
        let locate = |(position, area): (Vec3, Vec3)| -> Result<SurfacePoint, String> {
            let cell = if reference.in_solid(&position) {
                None
            } else {
                // in the sliver between a cell's chord face and its arc no cell holds the point:
                // the cell with the nearest centre takes it (as a particle's host cell)
                match host_cell(&reference, &position) {
                    c if in_zone[c] => Some(c),
                    _ => return Err(format!("the contour surface point {position:?} lies outside the rotor zone (interface radius too small?)")),
                }
            };
            Ok(SurfacePoint { position, area, cell })
        };
        Ok(HullSurface { hull: hull.into_iter().map(locate).collect::<Result<_, _>>()?, heights, zone, n_theta })
    }

    /// φ_rad of one point (Eqs. 8.1–8.2) with the rotor turned by `turning`; 0 inside a solid.
    fn point_flux(&self, turning: &Turning, mesh: &Mesh, u: &[[f64; 3]], grad: &[[Vec3; 3]], p: &SurfacePoint) -> f64 {
        let Some(c) = p.cell else { return 0.0 };
        let d = turning.point(&p.position) - mesh.cell_centres[c];
        let g = &grad[c];
        let velocity = Vec3::from(u[c]) + g[0] * d.x + g[1] * d.y + g[2] * d.z;
        velocity.dot(&turning.vector(&p.area))
    }

    /// The rotor zone's rotation on `mesh`, ready to turn points.
    fn turning<'a>(&self, mesh: &'a Mesh) -> Turning<'a> {
        Turning::new(mesh.zones[self.zone].rotation.as_ref().expect("checked in new"))
    }

    /// Eqs. 8.1–8.4 on the velocity `u` with its cell gradients `grad` (g[c][i] = ∂u/∂x_i), the
    /// mesh at the velocity's time.
    pub fn flux(&self, mesh: &Mesh, u: &[[f64; 3]], grad: &[[Vec3; 3]]) -> ContourFlux {
        let turning = self.turning(mesh);
        let (mut outflow, mut net, mut top) = (0.0, 0.0, 0.0);
        for (p, &z) in self.hull.iter().zip(&self.heights) {
            let q = self.point_flux(&turning, mesh, u, grad, p);
            net += q;
            if q > 0.0 {
                outflow += q;
                if z >= -EXIT_BIN {
                    top += q;
                }
            }
        }
        ContourFlux { outflow, net, outflow_top_bin: top }
    }

    /// φ_rad per element of the surface as it stands in the laboratory: element ring·n_θ + j
    /// lies at azimuth (j + ½) Δθ about the axis from +x, whatever the rotor's angle. The
    /// rotor's points are rotated into these places to the nearest Δθ (1° apart), so a time
    /// mean of these values is the mean flow through fixed places of the contour, with the
    /// blades' passing averaged out: the kind of map the thesis' statements about where its
    /// heads let water in and out read best against (spillage-and-flow-verification.md §5.2;
    /// its Fig. 8.2 itself is not in the spec). The rounding moves a point by at most ½° (3 mm
    /// on the ring).
    pub fn laboratory_fluxes(&self, mesh: &Mesh, u: &[[f64; 3]], grad: &[[Vec3; 3]]) -> Vec<f64> {
        let turning = self.turning(mesh);
        let n = self.n_theta;
        let shift = self.laboratory_shift(&turning);
        let mut out = vec![0.0; self.hull.len()];
        for (i, p) in self.hull.iter().enumerate() {
            let (ring, j) = (i / n, i % n);
            out[ring * n + (j + shift) % n] = self.point_flux(&turning, mesh, u, grad, p);
        }
        out
    }

    /// How many Δθ the rotor has carried its points round the axis, in 0..n_θ (from where the
    /// first point stands now, so the axis' direction and the angle's sign take care of
    /// themselves).
    fn laboratory_shift(&self, turning: &Turning) -> usize {
        let p = &self.hull[0].position;
        let now = turning.point(p);
        let dtheta = TAU / self.n_theta as f64;
        let turned = now.y.atan2(now.x) - p.y.atan2(p.x);
        ((turned / dtheta).round() as i64).rem_euclid(self.n_theta as i64) as usize
    }

    /// The laboratory elements in the order of [`HullSurface::laboratory_fluxes`].
    pub fn laboratory_elements(&self) -> impl Iterator<Item = LaboratoryElement> + '_ {
        let dtheta = TAU / self.n_theta as f64;
        // the surface is round, so element i has the geometry of point i at rest
        self.hull.iter().zip(&self.heights).enumerate().map(move |(i, (p, &z))| LaboratoryElement {
            z,
            radius: p.position.xy().norm(),
            azimuth: ((i % self.n_theta) as f64 + 0.5) * dtheta,
            area: p.area,
        })
    }

    /// Points per ring around the axis.
    pub fn points_around(&self) -> usize {
        self.n_theta
    }

    /// Σ |A| of the surface [m²].
    pub fn area(&self) -> f64 {
        self.hull.iter().map(|p| p.area.norm()).sum()
    }

    /// The fraction of the lateral surface's area inside solids.
    pub fn solid_fraction(&self) -> f64 {
        self.hull.iter().filter(|p| p.cell.is_none()).map(|p| p.area.norm()).sum::<f64>() / self.area()
    }
}

#[cfg(test)]
mod tests_support {
    use super::*;
    use crate::cutter_head::fluid_mesh::{self, tests::section};

    pub fn surface(cell_size: f64, angle: f64) -> (CutterHead, Mesh, HullSurface) {
        let section = section(cell_size);
        let head = CutterHead::new(&section);
        let mut mesh = fluid_mesh::build(&section).unwrap();
        let zone = mesh.zones.iter().position(|z| z.rotation.is_some()).unwrap();
        mesh.set_zone_angle(zone, angle).unwrap();
        let surface = HullSurface::new(&head, &mesh).unwrap();
        (head, mesh, surface)
    }
}

#[cfg(test)]
mod tests {
    use super::tests_support::surface;
    use super::*;

    /// The area is the frustums' π (R₀ + R₁) × slant whatever the mesh: the surface is the contour's, not the cells'. (1e-12: sums of ~3e4
    /// areas with coordinates from sin/cos.)
    #[test]
    fn the_surface_is_the_contour_on_every_mesh() {
        for (cell_size, angle) in [(0.05, 0.0), (0.04, 1.3)] {
            let (head, _, s) = surface(cell_size, angle);
            let lateral: f64 = head.contour().windows(2).map(|w| std::f64::consts::PI * (w[0].1 + w[1].1) * (w[1].0 - w[0].0).hypot(w[1].1 - w[0].1)).sum();
            let a = s.area();
            // a strip's area vector is exact (its flux of a uniform field is), so |A| of its
            // radial part is the chord's, 2 sin(Δθ/2)/Δθ = 1 − 1.3e-5 of the arc's at 360 strips
            let chord = (2.0 * (0.5 * TAU / 360.0).sin()) / (TAU / 360.0);
            assert!(a / lateral > chord - 1e-12 && a / lateral < 1.0 + 1e-12, "lateral {a} vs {lateral}");
            // the blades' staircase covers part of the surface (each blade one or two cells wide)
            let solid = s.solid_fraction();
            assert!(solid > 0.05 && solid < 0.6, "solid fraction {solid}");
        }
    }

    /// A linear field u = A x + b is interpolated exactly, so the flux is Σ over the open
    /// points of (A x + b)·S at their turned places: checks the turning of points and area
    /// vectors with the rotor zone. Solid-body rotation (A = ω [ẑ]×, tangent to the surface)
    /// carries nothing through it. (1e-12 of the flux scale: round-off of ~3e4 terms.)
    #[test]
    fn a_linear_field_is_interpolated_exactly_in_a_turned_rotor() {
        let (_, mesh, s) = surface(0.05, 0.9);
        let a = nalgebra::Matrix3::new(0.3, -1.1, 0.2, 0.7, 0.1, -0.4, 0.05, 0.6, -0.2);
        let b = Vec3::new(0.2, -0.1, 0.5);
        let field = |x: &Vec3| a * x + b;
        let u: Vec<[f64; 3]> = mesh.cell_centres.iter().map(|c| field(c).into()).collect();
        // g[c][i] = ∂u/∂x_i = column i of A
        let grad = vec![[a.column(0).into_owned(), a.column(1).into_owned(), a.column(2).into_owned()]; mesh.n_cells()];
        let q = s.flux(&mesh, &u, &grad);
        let rotation = mesh.zones[s.zone].rotation.as_ref().unwrap();
        let expected = |points: &[SurfacePoint]| -> f64 {
            points.iter().filter(|p| p.cell.is_some()).map(|p| field(&turn(rotation, &p.position, false)).dot(&turn(rotation, &p.area, true))).sum()
        };
        let scale = s.area();
        assert!((q.net - expected(&s.hull)).abs() < 1e-12 * scale, "{} vs {}", q.net, expected(&s.hull));
        assert!(q.outflow > 0.0 && q.outflow >= q.net.max(0.0));

        let omega = 6.0;
        let spin = nalgebra::Matrix3::new(0.0, -omega, 0.0, omega, 0.0, 0.0, 0.0, 0.0, 0.0);
        let u: Vec<[f64; 3]> = mesh.cell_centres.iter().map(|c| (spin * c).into()).collect();
        let grad = vec![[spin.column(0).into_owned(), spin.column(1).into_owned(), spin.column(2).into_owned()]; mesh.n_cells()];
        let q = s.flux(&mesh, &u, &grad);
        assert!(q.net.abs() < 1e-12 * omega * 0.375 * scale && q.outflow < 1e-12 * omega * 0.375 * scale, "{q:?}");
    }

    /// The laboratory elements stay where they are while the rotor turns: with the rotor at a
    /// whole number of elements' angle, a field fixed in the laboratory gives each open
    /// element exactly that field's flux through the element's own place, whatever the angle;
    /// the elements the blades cover carry none, and as many are covered as at rest. (1e-12 of
    /// the element's flux scale: round-off of the interpolation.)
    #[test]
    fn laboratory_elements_stay_in_place_as_the_rotor_turns() {
        let a = nalgebra::Matrix3::new(0.3, -1.1, 0.2, 0.7, 0.1, -0.4, 0.05, 0.6, -0.2);
        let b = Vec3::new(0.2, -0.1, 0.5);
        let field = |x: &Vec3| a * x + b;
        let grad = |mesh: &Mesh| vec![[a.column(0).into_owned(), a.column(1).into_owned(), a.column(2).into_owned()]; mesh.n_cells()];
        let (_, mesh, s) = surface(0.05, 0.0);
        let covered_at_rest = s
            .laboratory_fluxes(&mesh, &mesh.cell_centres.iter().map(|c| field(c).into()).collect::<Vec<_>>(), &grad(&mesh))
            .iter()
            .filter(|q| **q == 0.0)
            .count();
        for steps in [37, 200] {
            let angle = steps as f64 * TAU / s.points_around() as f64;
            let (_, mesh, s) = surface(0.05, angle);
            let u: Vec<[f64; 3]> = mesh.cell_centres.iter().map(|c| field(c).into()).collect();
            let q = s.laboratory_fluxes(&mesh, &u, &grad(&mesh));
            let mut covered = 0;
            for (e, q) in s.laboratory_elements().zip(&q) {
                let place = Vec3::new(e.radius * e.azimuth.cos(), e.radius * e.azimuth.sin(), e.z);
                if *q == 0.0 {
                    covered += 1;
                } else {
                    let expected = field(&place).dot(&e.area);
                    assert!((q - expected).abs() < 1e-12 * field(&place).norm() * e.area.norm(), "{steps} steps: {q} vs {expected}");
                }
            }
            assert_eq!(covered, covered_at_rest, "{steps} steps");
        }
    }

    /// A run restarted with its rotor at another angle finds the same cells for every point
    /// (they are located in the reference pose), so it continues bit for bit.
    #[test]
    fn the_points_find_the_same_cells_at_any_rotor_angle() {
        let (_, _, a) = surface(0.05, 0.0);
        let (_, _, b) = surface(0.05, 2.0 + std::f64::consts::PI / 48.0);
        assert!(a.hull.iter().zip(&b.hull).all(|(p, q)| p.cell == q.cell));
    }
}
