//! `[fluid]`, `[numerics]` and `[boundary.<patch>]` sections.

use serde::Deserialize;

use crate::case::error::{finite_vector, in_range, positive, FieldError};

/// `[fluid]`: fluid properties and the initial velocity field.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidSection {
    /// Density ρ [kg/m³].
    pub density: f64,
    /// Kinematic viscosity ν [m²/s].
    pub kinematic_viscosity: f64,
    /// Velocity at t = 0 (default: at rest). Pressure starts at 0.
    #[serde(default)]
    pub initial: InitialVelocity,
}

impl FluidSection {
    pub fn validate(&self) -> Result<(), FieldError> {
        positive("fluid.density", self.density, "kg/m³")?;
        positive("fluid.kinematic_viscosity", self.kinematic_viscosity, "m²/s")?;
        self.initial.validate("fluid.initial")
    }
}

/// `[fluid.initial]`: the initial velocity field, selected by `type`.
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum InitialVelocity {
    /// u = 0 everywhere.
    #[default]
    Rest,
    /// u = `velocity` everywhere [m/s].
    Uniform { velocity: [f64; 3] },
    /// 2-D Taylor–Green vortex in the x–y plane:
    /// u = U sin(x/L) cos(y/L), v = −U cos(x/L) sin(y/L), w = 0 (periodic on a box of side 2πL).
    TaylorGreen {
        /// Velocity scale U [m/s].
        speed: f64,
        /// Length scale L [m] (the box side is 2πL).
        length: f64,
    },
    /// Solid-body rotation with the `[rotor]`, u = ω × (x − origin), inside the cylinder
    /// r < `radius`, `z[0]` < z < `z[1]` about the rotor axis z; at rest outside: a start-up
    /// closer to the turning head's flow than rest (spillage-and-flow-verification.md §4.2).
    SolidBody { radius: f64, z: [f64; 2] },
    /// A frozen-rotor (multiple reference frame, MRF) start-up of `time` seconds before the
    /// sliding-mesh run starts at t = 0 ([`crate::fluid::frozen_rotor`]; spec
    /// spillage-and-flow-verification.md §4.2, §5.4): the run starts at t = −`time` from
    /// `from` (default at rest) with the rotor zone held at its start pose while ω acts.
    FrozenRotor {
        /// Length of the start-up in pseudo-time [s].
        time: f64,
        /// The velocity the start-up begins from (any other `type`; default `rest`).
        #[serde(default)]
        from: Option<Box<InitialVelocity>>,
    },
}

impl InitialVelocity {
    pub fn validate(&self, key: &str) -> Result<(), FieldError> {
        match self {
            InitialVelocity::Rest => Ok(()),
            InitialVelocity::Uniform { velocity } => finite_vector(&format!("{key}.velocity"), *velocity),
            InitialVelocity::TaylorGreen { speed, length } => {
                if !speed.is_finite() {
                    return Err(FieldError::new(format!("{key}.speed"), speed, "a finite velocity in m/s"));
                }
                positive(&format!("{key}.length"), *length, "m")
            }
            InitialVelocity::SolidBody { radius, z } => {
                positive(&format!("{key}.radius"), *radius, "m")?;
                if !(z.iter().all(|v| v.is_finite()) && z[1] > z[0]) {
                    return Err(FieldError::new(format!("{key}.z"), format!("{z:?}"), "[bottom, top] in m with bottom < top"));
                }
                Ok(())
            }
            InitialVelocity::FrozenRotor { time, from } => {
                positive(&format!("{key}.time"), *time, "s (the length of the frozen-rotor start-up)")?;
                match from.as_deref() {
                    Some(InitialVelocity::FrozenRotor { .. }) => Err(FieldError::new(
                        format!("{key}.from.type"),
                        "\"frozen_rotor\"",
                        "\"rest\", \"uniform\", \"taylor_green\" or \"solid_body\" (a start-up begins from a velocity field)",
                    )),
                    Some(inner) => inner.validate(&format!("{key}.from")),
                    None => Ok(()),
                }
            }
        }
    }

    /// The velocity field the run starts from: the `from` of a frozen-rotor start-up, else
    /// `self`.
    pub fn start_field(&self) -> &InitialVelocity {
        match self {
            InitialVelocity::FrozenRotor { from: Some(inner), .. } => inner,
            InitialVelocity::FrozenRotor { from: None, .. } => &InitialVelocity::Rest,
            other => other,
        }
    }

    /// Velocity at a point; `rotor` is the rotor's (ω about z, origin) for `SolidBody`.
    pub fn velocity_at(&self, x: [f64; 3], rotor: Option<(f64, [f64; 3])>) -> [f64; 3] {
        match self {
            InitialVelocity::SolidBody { radius, z } => {
                let (omega, o) = rotor.unwrap_or((0.0, [0.0; 3]));
                let (dx, dy) = (x[0] - o[0], x[1] - o[1]);
                if dx.hypot(dy) < *radius && x[2] > z[0] && x[2] < z[1] {
                    [-omega * dy, omega * dx, 0.0]
                } else {
                    [0.0; 3]
                }
            }
            InitialVelocity::Rest => [0.0; 3],
            InitialVelocity::FrozenRotor { .. } => self.start_field().velocity_at(x, rotor),
            InitialVelocity::Uniform { velocity } => *velocity,
            InitialVelocity::TaylorGreen { speed, length } => {
                let (a, b) = (x[0] / length, x[1] / length);
                [speed * a.sin() * b.cos(), -speed * a.cos() * b.sin(), 0.0]
            }
        }
    }
}

/// `[boundary.<patch>]`: the condition on one mesh patch, selected by `type`.
///
/// Periodic, empty (2-D front/back) and sliding-interface patches need no entry: their
/// treatment follows from the mesh.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum BoundaryCondition {
    /// No-slip wall. Its velocity is `velocity`
    /// + `angular_velocity` × (x − `origin`) about `axis` (a wall turning in place, e.g. the inner
    /// cylinder of the wall-velocity Couette case)
    /// + ω_rotor × (x − rotor origin) if `rotating = true` (a wall attached to the rotor).
    /// Normal flux: the wall's own normal velocity (zero for walls sliding along themselves).
    Wall {
        #[serde(default)]
        velocity: [f64; 3],
        #[serde(default)]
        rotating: bool,
        /// Angular velocity of a wall turning in place [rad/s].
        #[serde(default)]
        angular_velocity: f64,
        #[serde(default = "z_axis")]
        axis: [f64; 3],
        #[serde(default)]
        origin: [f64; 3],
        /// A stationary suction mouth in this wall: where it lies over the mouth the wall lets
        /// the water out (the back plate of a cutter head, derived from `[cutter_head] suction`;
        /// a case file cannot set it).
        #[serde(skip)]
        suction: Option<crate::cutter_head::mouth::SuctionWindow>,
    },
    /// Fixed velocity (the flux u·S may point in or out); pressure by the wall condition of
    /// `[numerics] pressure_wall` (spec §8.8). With a `profile`, `velocity` is the mean over it.
    VelocityInlet {
        velocity: [f64; 3],
        #[serde(default)]
        profile: Option<ParabolicProfile>,
    },
    /// Fixed pressure `pressure` [Pa], zero-gradient velocity.
    PressureOutlet {
        #[serde(default)]
        pressure: f64,
    },
    /// Symmetry plane: no normal flux, zero normal gradient of the tangential velocity.
    Symmetry,
}

/// A parabolic profile across one direction: u(s) = ū · 3/2 (1 − ξ²), ξ = (s − centre)/half
/// width for s between `from` and `to` along `axis` (0 outside), so ū is the mean over the
/// span: a developed channel inlet (the Coriolis tester's, wear-model.md §12.4, scaled to the
/// flow rate as §13 row 18 recommends).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ParabolicProfile {
    /// "x", "y" or "z".
    pub axis: String,
    pub from: f64,
    pub to: f64,
}

impl ParabolicProfile {
    /// The factor u/ū at point `x`.
    pub fn factor(&self, x: [f64; 3]) -> f64 {
        let d = match self.axis.as_str() {
            "x" => 0,
            "y" => 1,
            _ => 2,
        };
        let (centre, half) = (0.5 * (self.from + self.to), 0.5 * (self.to - self.from));
        let xi = (x[d] - centre) / half;
        (1.5 * (1.0 - xi * xi)).max(0.0)
    }

    pub fn validate(&self, key: &str) -> Result<(), FieldError> {
        if !matches!(self.axis.as_str(), "x" | "y" | "z") {
            return Err(FieldError::new(format!("{key}.axis"), format!("{:?}", self.axis), "\"x\", \"y\" or \"z\""));
        }
        if !(self.from.is_finite() && self.to.is_finite() && self.to > self.from) {
            return Err(FieldError::new(format!("{key}.to"), self.to, format!("a coordinate beyond from = {}", self.from)));
        }
        Ok(())
    }
}

fn z_axis() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

impl BoundaryCondition {
    /// `key` is the section path, e.g. `boundary.inner`.
    pub fn validate(&self, key: &str) -> Result<(), FieldError> {
        match self {
            BoundaryCondition::Wall { velocity, rotating, angular_velocity, axis, origin, .. } => {
                finite_vector(&format!("{key}.velocity"), *velocity)?;
                finite_vector(&format!("{key}.axis"), *axis)?;
                finite_vector(&format!("{key}.origin"), *origin)?;
                if !angular_velocity.is_finite() {
                    return Err(FieldError::new(format!("{key}.angular_velocity"), angular_velocity, "a finite angular velocity in rad/s"));
                }
                if *rotating && velocity.iter().any(|v| *v != 0.0) {
                    return Err(FieldError::new(format!("{key}.velocity"), format!("{velocity:?}"), "no velocity on a rotating wall (its velocity is ω×r)"));
                }
                if *rotating && *angular_velocity != 0.0 {
                    return Err(FieldError::new(
                        format!("{key}.angular_velocity"),
                        angular_velocity,
                        "0 on a wall with rotating = true (it turns with the rotor)",
                    ));
                }
                if axis.iter().map(|a| a * a).sum::<f64>().sqrt() < 1e-12 {
                    return Err(FieldError::new(format!("{key}.axis"), format!("{axis:?}"), "a non-zero direction vector"));
                }
                Ok(())
            }
            BoundaryCondition::VelocityInlet { velocity, profile } => {
                if let Some(p) = profile {
                    p.validate(&format!("{key}.profile"))?;
                }
                finite_vector(&format!("{key}.velocity"), *velocity)
            }
            BoundaryCondition::PressureOutlet { pressure } => {
                if pressure.is_finite() {
                    Ok(())
                } else {
                    Err(FieldError::new(format!("{key}.pressure"), pressure, "a finite pressure in Pa"))
                }
            }
            BoundaryCondition::Symmetry => Ok(()),
        }
    }
}

impl BoundaryCondition {
    /// Largest speed this condition imposes, given the largest radius of the mesh (for walls
    /// turning in place). `None` when it imposes no velocity. A wall with `rotating = true`
    /// moves with the rotor, whose speed the caller adds.
    pub fn imposed_speed(&self, r_max: f64) -> Option<f64> {
        let norm = |v: &[f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        match self {
            BoundaryCondition::Wall { velocity, angular_velocity, origin, .. } => Some(norm(velocity) + angular_velocity.abs() * (r_max + norm(origin))),
            BoundaryCondition::VelocityInlet { velocity, profile } => Some(norm(velocity) * if profile.is_some() { 1.5 } else { 1.0 }),
            BoundaryCondition::PressureOutlet { .. } | BoundaryCondition::Symmetry => None,
        }
    }
}

/// Convection scheme for the momentum equation (spec §8.10).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ConvectionScheme {
    /// Central (linear interpolation); second order.
    #[default]
    Linear,
    /// First-order upwind.
    Upwind,
    /// OpenFOAM's `limitedLinearV 1`: linear limited towards upwind by a TVD limiter.
    LimitedLinear,
    /// `linear_fraction`·linear + (1 − `linear_fraction`)·upwind.
    Blended,
}

/// When the `limited_linear` scheme's limiter is evaluated (spec §8.10).
///
/// Per outer iteration (OpenFOAM's way) the limiter, and with it each face's share of the
/// momentum matrix's diagonal, follows the latest iterate, so every outer iteration solves a
/// different system. In the Coriolis arm at 3000 rpm (cases/verification/wear/) that outer loop
/// did not converge: every step ended at the cap of 10 iterations with the pressure residual at
/// 1e-3 … 8e-3 (40 did no better), and the two solvers, which differ by round-off, grew apart
/// about twofold per outer iteration (1e-5 of the fields after three steps). Evaluated once per
/// time step, from the step's first iterate (the last step's solution on the new geometry), the
/// system's weights stay put within the step: the same arm converges in 4–7 outer iterations
/// and the solvers agree to 1.6e-11 over 30 steps (tests/rotating_frame.rs). The face values
/// still take the latest iterate (λ u_P + (1 − λ) u_N); only the weight λ is a step old.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum LimiterUpdate {
    /// From the latest outer iterate, every outer iteration (OpenFOAM's `limitedLinearV`).
    #[default]
    OuterIteration,
    /// From the first outer iterate of the step, kept for the step.
    TimeStep,
}

/// Time scheme (spec §8.2; the thesis' "backward" is BDF2).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum TimeScheme {
    /// BDF2, started with one implicit-Euler step.
    #[default]
    Backward,
    Euler,
}

/// Pressure condition at boundaries with a prescribed flux (walls, velocity inlets, symmetry).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum PressureWallCondition {
    /// Spec §8.8 (T4.42): the normal gradient that makes the corrected flux equal the
    /// prescribed one, with A⁻¹H extrapolated from the cell (OpenFOAM
    /// `fixedFluxExtrapolatedPressure`). Kept for side-by-side runs with OpenFOAM.
    FixedFluxExtrapolated,
    /// T4.42 with the normal gradient extrapolated linearly to the face from the cell and the
    /// interior neighbour across the cell from it (second order; the cell value alone gives
    /// the wall cell a one-sided, first-order pressure gradient). Falls back to the
    /// `fixed_flux_extrapolated` value where no neighbour lies across. The default: it makes the
    /// Couette dp/dr converge at second order (cases/verification/fluid/couette_wall_velocity.toml).
    #[default]
    FixedFluxLinear,
    /// dp/dn = 0 (the wrong condition at rotating walls, kept for the comparison of spec
    /// spillage-and-flow-verification.md §3.4).
    ZeroGradient,
}

/// `[numerics]`: discretisation and PIMPLE settings of the fluid solver (spec §8.5, §8.10).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct NumericsSection {
    #[serde(default)]
    pub convection: ConvectionScheme,
    /// Linear share of the `blended` scheme.
    #[serde(default = "NumericsSection::default_linear_fraction")]
    pub linear_fraction: f64,
    /// When the `limited_linear` limiter is evaluated ([`LimiterUpdate`]).
    #[serde(default)]
    pub limiter_update: LimiterUpdate,
    #[serde(default)]
    pub time_scheme: TimeScheme,
    /// Maximum PIMPLE outer (SIMPLE) iterations per step.
    #[serde(default = "NumericsSection::default_outer")]
    pub max_outer_iterations: usize,
    /// Outer loops stop once the initial pressure residual of an outer iteration is below this
    /// (spec §8.5, App. C "p_ini").
    #[serde(default = "NumericsSection::default_p_initial")]
    pub p_initial_residual: f64,
    /// PISO correctors per outer iteration.
    #[serde(default = "one")]
    pub piso_correctors: usize,
    /// Extra pressure solves per corrector for the explicit non-orthogonal correction.
    #[serde(default = "one")]
    pub non_orthogonal_correctors: usize,
    /// Momentum under-relaxation (Patankar, implicit).
    #[serde(default = "unit")]
    pub relax_velocity: f64,
    /// Pressure under-relaxation.
    #[serde(default = "unit")]
    pub relax_pressure: f64,
    #[serde(default)]
    pub pressure_wall: PressureWallCondition,
    /// Extra kinematic body force [m/s²] (drives periodic channels; equivalent to a mean
    /// pressure gradient −∇P).
    #[serde(default)]
    pub body_force: [f64; 3],
    /// Include gravity in the fluid momentum (a hydrostatic pressure in single-phase flow).
    #[serde(default = "yes")]
    pub fluid_gravity: bool,
    /// Normalised residual (OpenFOAM's definition) to which the fast solver's iterative linear
    /// solves converge; the reference solver factorises exactly and ignores it. The default is
    /// tight enough for the step-by-step equivalence with the reference.
    #[serde(default = "NumericsSection::default_linear_tolerance")]
    pub linear_tolerance: f64,
    /// Iteration cap of the fast solver's linear solves.
    #[serde(default = "NumericsSection::default_max_linear_iterations")]
    pub max_linear_iterations: usize,
    /// Time-derivative flux correction of the face-flux interpolation (OpenFOAM's
    /// `fvc::ddtCorr`, coupling coefficient 1): the old-time part of the predicted face flux
    /// is the old flux, not the interpolated old velocity (reference fluid module doc, step
    /// 4d). Off by default: with coupling coefficient 1 the flux/velocity mismatch is carried
    /// over from step to step and, on the Taylor–Green case (Δt ∝ h, diffusion number ≈ 0.07
    /// on 16²), made the errors 13× (KE) and 7× (velocity) larger on 16² and 2.2× / 3.7× on
    /// 32² (measured; see the module doc of the reference fluid solver).
    #[serde(default)]
    pub ddt_flux_correction: bool,
}

fn one() -> usize {
    1
}
fn unit() -> f64 {
    1.0
}
fn yes() -> bool {
    true
}

impl Default for NumericsSection {
    fn default() -> Self {
        Self {
            convection: ConvectionScheme::default(),
            linear_fraction: Self::default_linear_fraction(),
            limiter_update: LimiterUpdate::default(),
            time_scheme: TimeScheme::default(),
            max_outer_iterations: Self::default_outer(),
            p_initial_residual: Self::default_p_initial(),
            piso_correctors: 1,
            non_orthogonal_correctors: 1,
            relax_velocity: 1.0,
            relax_pressure: 1.0,
            pressure_wall: PressureWallCondition::default(),
            body_force: [0.0; 3],
            fluid_gravity: true,
            linear_tolerance: Self::default_linear_tolerance(),
            max_linear_iterations: Self::default_max_linear_iterations(),
            ddt_flux_correction: false,
        }
    }
}

impl NumericsSection {
    /// The kinematic body force on the fluid [m/s²]: `body_force`, plus `gravity` when
    /// `fluid_gravity` is on.
    pub fn kinematic_body_force(&self, gravity: [f64; 3]) -> crate::mesh::Vec3 {
        let mut force = crate::mesh::Vec3::from(self.body_force);
        if self.fluid_gravity {
            force += crate::mesh::Vec3::from(gravity);
        }
        force
    }

    fn default_linear_fraction() -> f64 {
        0.9
    }
    fn default_outer() -> usize {
        20
    }
    fn default_p_initial() -> f64 {
        1e-3
    }
    fn default_linear_tolerance() -> f64 {
        1e-12
    }
    fn default_max_linear_iterations() -> usize {
        2000
    }

    pub fn validate(&self) -> Result<(), FieldError> {
        in_range("numerics.linear_fraction", self.linear_fraction, 0.0, 1.0, "")?;
        if !(1..=1000).contains(&self.max_outer_iterations) {
            return Err(FieldError::new("numerics.max_outer_iterations", self.max_outer_iterations, "a whole number from 1 to 1000"));
        }
        positive("numerics.p_initial_residual", self.p_initial_residual, "(relative residual)")?;
        if !(1..=100).contains(&self.piso_correctors) {
            return Err(FieldError::new("numerics.piso_correctors", self.piso_correctors, "a whole number from 1 to 100"));
        }
        if self.non_orthogonal_correctors > 100 {
            return Err(FieldError::new("numerics.non_orthogonal_correctors", self.non_orthogonal_correctors, "a whole number from 0 to 100"));
        }
        for (key, value) in [("numerics.relax_velocity", self.relax_velocity), ("numerics.relax_pressure", self.relax_pressure)] {
            if !(value.is_finite() && value > 0.0 && value <= 1.0) {
                return Err(FieldError::new(key, value, "a relaxation factor in (0, 1]"));
            }
        }
        in_range("numerics.linear_tolerance", self.linear_tolerance, 1e-16, 1e-2, "(normalised residual)")?;
        if !(1..=1_000_000).contains(&self.max_linear_iterations) {
            return Err(FieldError::new("numerics.max_linear_iterations", self.max_linear_iterations, "a whole number from 1 to 10⁶"));
        }
        finite_vector("numerics.body_force", self.body_force)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_parabolic_profile_has_the_given_mean_and_one_and_a_half_times_it_at_its_centre() {
        let p = ParabolicProfile { axis: "y".into(), from: -0.003, to: 0.003 };
        let n = 100_000;
        let mean: f64 = (0..n).map(|k| p.factor([0.0, -0.003 + 0.006 * (k as f64 + 0.5) / n as f64, 0.0])).sum::<f64>() / n as f64;
        // midpoint rule of a parabola: error h²/12 · |u''| / 2 ≈ 1e-10
        assert!((mean - 1.0).abs() < 1e-9, "{mean}");
        assert_eq!(p.factor([0.0, 0.0, 0.0]), 1.5);
        assert_eq!(p.factor([0.0, 0.004, 0.0]), 0.0);
        assert!(ParabolicProfile { axis: "w".into(), from: 0.0, to: 1.0 }.validate("boundary.x_min.profile").is_err());
        assert_eq!(ParabolicProfile { axis: "x".into(), from: 1.0, to: 1.0 }.validate("k").unwrap_err().key, "k.to");
    }
}
