//! Boundary conditions of the case resolved per mesh patch (spec fluid-dem-model.md §8.8): the
//! one definition both fluid solvers use.

use crate::case::Case;
use crate::cutter_head::mouth::SuctionWindow;
use crate::mesh::motion::rigid_rotation_velocity;
use crate::mesh::{Mesh, PatchKind, Vec3};
use crate::solver::SolverError;

use super::settings::{BoundaryCondition, ParabolicProfile};

/// What a boundary patch imposes.
#[derive(Clone, Debug)]
pub enum Condition {
    /// Fixed velocity u_b(x) = `velocity` + ω â × (x − `origin`) (ω = `angular_velocity` about the
    /// unit `axis`), plus the rotor's rigid motion if `rotating`, plus the outflow through a
    /// stationary `suction` mouth where the face lies over it; prescribed flux u_b·S.
    FixedVelocity {
        velocity: Vec3,
        angular_velocity: f64,
        axis: Vec3,
        origin: Vec3,
        rotating: bool,
        profile: Option<ParabolicProfile>,
        suction: Option<SuctionWindow>,
    },
    /// Fixed kinematic pressure, zero-gradient velocity.
    FixedPressure { pressure: f64 },
    /// No normal flux relative to the mesh, zero-gradient tangential velocity.
    Symmetry,
}

/// Per-patch conditions: `patch_condition[k]` is the index into `conditions` of mesh patch k,
/// `None` for patches that carry no condition (empty, sliding interface).
#[derive(Clone, Debug)]
pub struct Conditions {
    pub conditions: Vec<Condition>,
    pub patch_condition: Vec<Option<usize>>,
    /// True when some boundary fixes the pressure level (otherwise a reference cell does).
    pub has_fixed_pressure: bool,
    /// Per condition: whether it is a `wall` (wall functions of the turbulence model apply; a
    /// velocity inlet fixes the velocity too but brings its own k and ε).
    pub wall: Vec<bool>,
}

impl Conditions {
    /// The condition of every mesh patch from the case's `[boundary.<patch>]` tables; pressures
    /// are made kinematic with the fluid `density`.
    pub fn from_case(case: &Case, mesh: &Mesh, density: f64) -> Result<Conditions, SolverError> {
        let mut conditions = Vec::new();
        let mut patch_condition = Vec::new();
        let mut has_fixed_pressure = false;
        let mut wall = Vec::new();
        for patch in &mesh.patches {
            match patch.kind {
                PatchKind::Empty | PatchKind::Interface { .. } => {
                    patch_condition.push(None);
                    continue;
                }
                PatchKind::Patch | PatchKind::Wall => {}
            }
            let Some(bc) = case.boundary.get(&patch.name) else {
                return Err(SolverError::Unsupported(format!("mesh patch `{}` has no [boundary.{}] condition in the case", patch.name, patch.name)));
            };
            let condition = match bc {
                BoundaryCondition::Wall { velocity, rotating, angular_velocity, axis, origin, suction } => Condition::FixedVelocity {
                    velocity: Vec3::from(*velocity),
                    angular_velocity: *angular_velocity,
                    axis: Vec3::from(*axis).normalize(),
                    origin: Vec3::from(*origin),
                    rotating: *rotating,
                    profile: None,
                    suction: suction.clone(),
                },
                BoundaryCondition::VelocityInlet { velocity, profile } => Condition::FixedVelocity {
                    velocity: Vec3::from(*velocity),
                    angular_velocity: 0.0,
                    axis: Vec3::zeros(),
                    origin: Vec3::zeros(),
                    rotating: false,
                    profile: profile.clone(),
                    suction: None,
                },
                BoundaryCondition::PressureOutlet { pressure } => {
                    has_fixed_pressure = true;
                    Condition::FixedPressure { pressure: pressure / density }
                }
                BoundaryCondition::Symmetry => Condition::Symmetry,
            };
            patch_condition.push(Some(conditions.len()));
            conditions.push(condition);
            wall.push(matches!(bc, BoundaryCondition::Wall { .. }));
        }
        Ok(Conditions { conditions, patch_condition, has_fixed_pressure, wall })
    }

    /// The condition that carries a suction mouth, if any ([`SuctionWindow`]).
    pub fn suction_condition(&self) -> Option<usize> {
        self.conditions.iter().position(|c| matches!(c, Condition::FixedVelocity { suction: Some(_), .. }))
    }

    /// Sets the speed of the suction mouth's outflow ([`crate::cutter_head::mouth::balancing_speed`]).
    pub fn set_suction_speed(&mut self, speed: f64) {
        for c in &mut self.conditions {
            if let Condition::FixedVelocity { suction: Some(window), .. } = c {
                window.set_speed(speed);
            }
        }
    }

    /// These conditions with the suction mouth's speed of the step that produced the face fluxes
    /// `flux` on `mesh` (at that step's rotor angle), recovered from the mouth's faces as
    /// U = Σ φ / Σ share·A: the speed the solver balanced, for diagnostics that rebuild its
    /// boundary values. Borrowed unchanged without a mouth.
    pub fn with_solved_suction(&self, mesh: &Mesh, flux: &[f64]) -> std::borrow::Cow<'_, Conditions> {
        let Some(suction) = self.suction_condition() else { return std::borrow::Cow::Borrowed(self) };
        let mut unit = self.clone();
        unit.set_suction_speed(1.0);
        let (mut carried, mut per_speed) = (0.0, 0.0);
        for (patch, condition) in mesh.patches.iter().zip(&self.patch_condition) {
            if *condition == Some(suction) {
                for f in patch.faces() {
                    carried += flux[f];
                    per_speed += unit.fixed_velocity(suction, &mesh.face_centres[f], None::<fn(&Vec3) -> Vec3>).map_or(0.0, |u| u.dot(&mesh.face_areas[f]));
                }
            }
        }
        unit.set_suction_speed(carried / per_speed);
        std::borrow::Cow::Owned(unit)
    }

    /// Per condition: the mesh patch name of a wall condition (the y⁺ diagnostics of the
    /// turbulence model), `None` for other conditions.
    pub fn wall_patch_names(&self, mesh: &Mesh) -> Vec<Option<String>> {
        let mut names = vec![None; self.conditions.len()];
        for (patch, condition) in mesh.patches.iter().zip(&self.patch_condition) {
            if let Some(c) = condition {
                if self.wall[*c] {
                    names[*c] = Some(patch.name.clone());
                }
            }
        }
        names
    }

    /// Fixed velocity at a boundary face centre, if `condition` fixes one. `rotor_velocity` is
    /// the rigid velocity of the rotor at a point (added on `rotating` walls; `None` without a
    /// rotor).
    pub fn fixed_velocity(&self, condition: usize, centre: &Vec3, rotor_velocity: Option<impl Fn(&Vec3) -> Vec3>) -> Option<Vec3> {
        match &self.conditions[condition] {
            Condition::FixedVelocity { velocity, angular_velocity, axis, origin, rotating, profile, suction } => {
                let shape = profile.as_ref().map_or(1.0, |p| p.factor([centre.x, centre.y, centre.z]));
                let mut u = shape * velocity + rigid_rotation_velocity(*angular_velocity, axis, origin, centre);
                if let Some(window) = suction {
                    u += window.velocity(centre);
                }
                if *rotating {
                    if let Some(rotor_velocity) = rotor_velocity {
                        u += rotor_velocity(centre);
                    }
                }
                Some(u)
            }
            _ => None,
        }
    }

    /// Prescribed absolute flux of a boundary face with area vector `area` and mesh flux
    /// `mesh_flux` (`None` where the pressure is fixed instead).
    pub fn prescribed_flux(&self, condition: usize, centre: &Vec3, area: &Vec3, mesh_flux: f64, rotor_velocity: Option<impl Fn(&Vec3) -> Vec3>) -> Option<f64> {
        match &self.conditions[condition] {
            Condition::FixedVelocity { .. } => self.fixed_velocity(condition, centre, rotor_velocity).map(|u| u.dot(area)),
            Condition::Symmetry => Some(mesh_flux),
            Condition::FixedPressure { .. } => None,
        }
    }
}

/// Σ_c V_c ∂α_c/∂t with the step's time coefficients [m³/s]: what the particles give up to the
/// water per second (the pressure equation's cell source, summed; the interface mask moves it
/// between cells and keeps its sum).
pub fn fluid_volume_rate(alpha: [&[f64]; 3], volumes: &[f64], coefficients: [f64; 3], dt: f64) -> f64 {
    let [c0, c1, c2] = coefficients;
    (0..volumes.len()).map(|c| (c0 * alpha[0][c] + c1 * alpha[1][c] + c2 * alpha[2][c]) * volumes[c] / dt).sum()
}
