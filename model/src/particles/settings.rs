//! `[particles]` section: materials, sizes, initial placement, feed, DEM numerics and the
//! still ambient fluid of particles-only cases.

use serde::Deserialize;

use crate::case::error::{finite_vector, in_range, non_negative, positive, FieldError};
use crate::closure::contact::SlipTest;
use crate::closure::drag::DragLaw;

/// `[particles]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParticlesSection {
    /// Materials of particles and walls, referred to by name.
    pub materials: Vec<MaterialSection>,
    /// Initial particles, one entry per group.
    #[serde(default)]
    pub groups: Vec<GroupSection>,
    /// Continuous feeds.
    #[serde(default)]
    pub feed: Vec<FeedSection>,
    /// DEM sub-steps per collision time, N_timeSteps of (T3.106); the thesis used 12–20.
    #[serde(default = "ParticlesSection::default_steps_per_collision")]
    pub steps_per_collision: f64,
    /// Lowest speed used in the collision-time estimate (T3.105) [m/s], so a packing at rest
    /// still gets a finite sub-step; the actual worst-case speed is used when larger (§7.6).
    #[serde(default = "ParticlesSection::default_collision_speed")]
    pub collision_speed: f64,
    /// Fixed DEM sub-step [s] instead of the one from the collision time.
    pub substep: Option<f64>,
    /// Coulomb slip test (fluid-dem-model.md §7.8 step 5).
    #[serde(default)]
    pub slip_test: SlipTest,
    /// Still fluid around the particles (particles-only cases); with a `[fluid]` section the
    /// coupled solver supplies the fluid instead.
    pub ambient: Option<AmbientFluid>,
    /// Particles whose centre leaves this box are removed and counted as escaped.
    pub domain: Option<BoxRegion>,
    /// How the DEM moves the particles ([`Motion`]): `"free"` (the default) or `"held"`.
    #[serde(default)]
    pub motion: Motion,
    /// Which normal restitution a contact starts with in a fluid ([`Restitution`]): `"wet"`
    /// (the default) or `"dry"`.
    #[serde(default)]
    pub restitution: Restitution,
    /// Which fluid forces act on a particle ([`FluidForces`]): `"full"` (the default) or
    /// `"drag_and_buoyancy"`.
    #[serde(default)]
    pub fluid_forces: FluidForces,
    /// Real particles each simulated one stands for (wear-model.md §8, Eq. 4.9, the thesis'
    /// "particle scaling"): its volume and its forces on the fluid count this many times in the
    /// coupling (§2.4 [R]), and its impacts this many times in the wear (§7.1). Its own motion
    /// is that of one real particle. Default 1.
    #[serde(default = "one")]
    pub modifier: f64,
    /// The KTGF solids pressure between the particles (`[particles.solids_pressure]`,
    /// wear-model.md §4; [`crate::particles::solids_pressure`]); none by default.
    pub solids_pressure: Option<crate::particles::solids_pressure::SolidsPressureSection>,
}

/// `[particles] fluid_forces`: the particle equation's fluid forces.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FluidForces {
    /// Drag, added mass (C_AM 0.5), the pressure-gradient (fluid-acceleration) force, gravity
    /// with buoyancy (fluid-dem-model.md §5), and in a turning frame the fictitious forces with
    /// the pressure gradient's share of them (wear-model.md §2.6 [R], first form).
    #[default]
    Full,
    /// The wear model's representative particle (wear-model.md Eqs. 2.11 and 5.3, §2.6 [R]
    /// second form): drag and buoyancy-reduced gravity and centrifugal force, the whole
    /// Coriolis force, no added mass and no pressure-gradient force
    /// (`crate::closure::drag_and_buoyancy`).
    DragAndBuoyancy,
}

/// `[particles] restitution`: whether the surrounding fluid lowers the restitution.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Restitution {
    /// With a `[fluid]` (or a `[particles.ambient]` with `wet_restitution`), every contact
    /// starts with ε_wet = ε_dry exp(−35/St_AM) of its approach (fluid-dem-model.md §7.5,
    /// T3.103–104): a slow approach through water barely rebounds.
    #[default]
    Wet,
    /// Every contact keeps the materials' ε_dry, at any approach speed: the rebound of the
    /// wear model's point particles (wear-model.md §5.2: e = 0.99 constant, the tangential
    /// velocity kept), which re-collide wherever the Coriolis tester's force presses them
    /// onto the coupon.
    Dry,
}

/// `[particles] motion`: whether the DEM moves the particles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Motion {
    /// Newton's second law with every force (fluid-dem-model.md §5.7, §7).
    #[default]
    Free,
    /// Every particle keeps its initial position and velocity for the whole run: nothing
    /// moves it, yet the fluid forces are evaluated with that velocity and, two-way coupled,
    /// fed back (spec §12 U-33: a suspension "held at terminal settling"). A particle given its
    /// terminal settling velocity then hands its submerged weight to the fluid through the
    /// drag, while α_c stays constant in time (no ∂α_c/∂t, no return flow). Its added-mass
    /// force has no particle-acceleration part (the particle does not accelerate); contact
    /// and rotating-frame forces are computed but move nothing. Both DEMs take the kicks and
    /// drifts from [`Motion::kick`] and [`Motion::drift`] and the fluid force from
    /// [`crate::particles::non_contact::NonContactForces::update`], so they hold particles
    /// identically.
    Held,
}

impl Motion {
    /// The velocity (or spin) `v` after a kick by `change`: unchanged when held. Free motion
    /// returns `v + change`, the same bits as `v += change`.
    #[inline]
    pub fn kick(self, v: super::state::Vec3, change: super::state::Vec3) -> super::state::Vec3 {
        match self {
            Motion::Free => v + change,
            Motion::Held => v,
        }
    }

    /// The position `x` after a drift over `dt` with velocity `v`: unchanged when held.
    #[inline]
    pub fn drift(self, x: super::state::Vec3, v: super::state::Vec3, dt: f64) -> super::state::Vec3 {
        match self {
            Motion::Free => x + dt * v,
            Motion::Held => x,
        }
    }
}

impl ParticlesSection {
    fn default_steps_per_collision() -> f64 {
        12.0
    }
    fn default_collision_speed() -> f64 {
        1.0
    }

    /// (ρ_f, ν) of the fluid whose wet restitution law (T3.103–104) the contacts follow, if any:
    /// the case's `fluid` (density, viscosity), else a `[particles.ambient]` with
    /// `wet_restitution`; none with `restitution = "dry"`. Both DEMs and `spillage check` ask here.
    pub fn wet_fluid(&self, fluid: Option<(f64, f64)>) -> Option<(f64, f64)> {
        match (self.restitution, fluid, &self.ambient) {
            (Restitution::Dry, _, _) => None,
            (Restitution::Wet, Some(fluid), _) => Some(fluid),
            (Restitution::Wet, None, Some(a)) if a.wet_restitution => Some((a.density, a.kinematic_viscosity)),
            _ => None,
        }
    }

    /// Index of the material called `name`.
    pub fn material_index(&self, name: &str) -> Option<usize> {
        self.materials.iter().position(|m| m.name == name)
    }

    pub fn validate(&self) -> Result<(), FieldError> {
        if self.materials.is_empty() {
            return Err(FieldError::new("particles.materials", "(none)", "at least one [[particles.materials]] entry"));
        }
        for (i, m) in self.materials.iter().enumerate() {
            m.validate(&format!("particles.materials.{i}"))?;
            if self.materials[..i].iter().any(|o| o.name == m.name) {
                return Err(FieldError::new(format!("particles.materials.{i}.name"), format!("{:?}", m.name), "a material name not used before"));
            }
        }
        positive("particles.steps_per_collision", self.steps_per_collision, "sub-steps per collision")?;
        positive("particles.collision_speed", self.collision_speed, "m/s")?;
        positive("particles.modifier", self.modifier, "(real particles per simulated one)")?;
        if let Some(dt) = self.substep {
            positive("particles.substep", dt, "s")?;
        }
        if let Some(a) = &self.ambient {
            a.validate()?;
        }
        if let Some(s) = &self.solids_pressure {
            s.validate()?;
        }
        if let Some(d) = &self.domain {
            d.validate("particles.domain")?;
        }
        let names: Vec<&str> = self.materials.iter().map(|m| m.name.as_str()).collect();
        for (i, g) in self.groups.iter().enumerate() {
            g.validate(&format!("particles.groups.{i}"), &names)?;
        }
        for (i, f) in self.feed.iter().enumerate() {
            f.validate(&format!("particles.feed.{i}"), &names)?;
        }
        Ok(())
    }
}

fn check_material(key: &str, name: &str, names: &[&str]) -> Result<(), FieldError> {
    if names.contains(&name) {
        Ok(())
    } else {
        Err(FieldError::new(key, format!("{name:?}"), format!("one of the [[particles.materials]] names: {}", names.join(", "))))
    }
}

/// `[[particles.materials]]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSection {
    pub name: String,
    /// Density ρ [kg/m³].
    pub density: f64,
    /// Young's modulus E [Pa] before softening.
    pub youngs_modulus: f64,
    /// Poisson ratio ν.
    pub poisson_ratio: f64,
    /// E is divided by this (the thesis lowered E about 6000 times, §7.6); 1 = the real material.
    #[serde(default = "one")]
    pub softening: f64,
    /// Dry normal restitution ε_dry.
    pub restitution: f64,
    /// Coulomb friction coefficient μ_f.
    pub friction: f64,
}

fn one() -> f64 {
    1.0
}

impl MaterialSection {
    /// Young's modulus used in the contact law, E / softening [Pa].
    pub fn contact_youngs_modulus(&self) -> f64 {
        self.youngs_modulus / self.softening
    }

    fn validate(&self, key: &str) -> Result<(), FieldError> {
        if self.name.trim().is_empty() {
            return Err(FieldError::new(format!("{key}.name"), "\"\"", "a non-empty name"));
        }
        positive(&format!("{key}.density"), self.density, "kg/m³")?;
        positive(&format!("{key}.youngs_modulus"), self.youngs_modulus, "Pa")?;
        if !(self.poisson_ratio.is_finite() && self.poisson_ratio > -1.0 && self.poisson_ratio < 0.5) {
            return Err(FieldError::new(format!("{key}.poisson_ratio"), self.poisson_ratio, "a Poisson ratio in (−1, 0.5)"));
        }
        if !(self.softening.is_finite() && self.softening >= 1.0) {
            return Err(FieldError::new(format!("{key}.softening"), self.softening, "a factor ≥ 1 dividing E"));
        }
        in_range(&format!("{key}.restitution"), self.restitution, 0.0, 1.0, "")?;
        non_negative(&format!("{key}.friction"), self.friction, "")
    }
}

/// Particle diameter: a single value or a uniform distribution `{ min, max }`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum Diameter {
    Fixed(f64),
    Uniform { min: f64, max: f64 },
}

impl Diameter {
    pub fn smallest(&self) -> f64 {
        match self {
            Diameter::Fixed(d) => *d,
            Diameter::Uniform { min, .. } => *min,
        }
    }
    pub fn largest(&self) -> f64 {
        match self {
            Diameter::Fixed(d) => *d,
            Diameter::Uniform { max, .. } => *max,
        }
    }
    fn validate(&self, key: &str) -> Result<(), FieldError> {
        match self {
            Diameter::Fixed(d) => positive(key, *d, "m"),
            Diameter::Uniform { min, max } => {
                positive(&format!("{key}.min"), *min, "m")?;
                positive(&format!("{key}.max"), *max, "m")?;
                if max < min {
                    return Err(FieldError::new(format!("{key}.max"), max, format!("a diameter ≥ min = {min} m")));
                }
                Ok(())
            }
        }
    }
}

/// An axis-aligned box `{ min = [..], max = [..] }`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BoxRegion {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl BoxRegion {
    pub fn contains(&self, p: [f64; 3]) -> bool {
        (0..3).all(|k| p[k] >= self.min[k] && p[k] <= self.max[k])
    }
    fn validate(&self, key: &str) -> Result<(), FieldError> {
        finite_vector(&format!("{key}.min"), self.min)?;
        finite_vector(&format!("{key}.max"), self.max)?;
        if (0..3).any(|k| self.max[k] <= self.min[k]) {
            return Err(FieldError::new(format!("{key}.max"), format!("{:?}", self.max), format!("a corner above min = {:?} in every direction", self.min)));
        }
        Ok(())
    }
}

/// `[[particles.groups]]`: initial particles, placed one of three ways.
#[derive(Clone, Debug, Deserialize)]
#[serde(tag = "placement", rename_all = "snake_case", deny_unknown_fields)]
pub enum GroupSection {
    /// Explicit positions (and optionally velocities and spins, one per position).
    List {
        material: String,
        diameter: Diameter,
        positions: Vec<[f64; 3]>,
        #[serde(default)]
        velocities: Vec<[f64; 3]>,
        #[serde(default)]
        spins: Vec<[f64; 3]>,
        #[serde(default)]
        seed: u64,
    },
    /// A cubic lattice of the given spacing filling a box (first site at `region.min + spacing/2`).
    Lattice {
        material: String,
        diameter: Diameter,
        region: BoxRegion,
        spacing: f64,
        #[serde(default)]
        velocity: [f64; 3],
        #[serde(default)]
        seed: u64,
    },
    /// A cubic lattice of the given spacing (sites at multiples of `spacing` from the axis and
    /// the ring) inside a cutter head's contour hull, between `z[0]` and `z[1]` and within the
    /// azimuths `sector` (degrees, lab frame at t = 0), keeping every sphere clear of the
    /// head's solids: the thesis' initial batch between the blades on the cutting side
    /// (spillage-and-flow-verification.md §5.4, Eq. 8.5). `co_rotating` starts the particles
    /// with the rotor's solid-body velocity ω × r.
    ///
    /// `after_revolutions` (default 0: at the start) places the batch later, once the rotor has
    /// turned that many revolutions with water alone, as the thesis did (§5.4, initialisation:
    /// the flow first turned one rotation without particles): see [`super::batch`].
    HeadLattice {
        material: String,
        diameter: Diameter,
        spacing: f64,
        sector: [f64; 2],
        z: [f64; 2],
        #[serde(default = "yes")]
        co_rotating: bool,
        #[serde(default)]
        seed: u64,
        #[serde(default)]
        after_revolutions: f64,
    },
    /// `count` particles at random non-overlapping positions inside a box.
    Random {
        material: String,
        diameter: Diameter,
        region: BoxRegion,
        count: usize,
        #[serde(default)]
        velocity: [f64; 3],
        #[serde(default)]
        seed: u64,
    },
}

impl GroupSection {
    pub fn material(&self) -> &str {
        match self {
            GroupSection::List { material, .. }
            | GroupSection::Lattice { material, .. }
            | GroupSection::HeadLattice { material, .. }
            | GroupSection::Random { material, .. } => material,
        }
    }
    fn validate(&self, key: &str, names: &[&str]) -> Result<(), FieldError> {
        check_material(&format!("{key}.material"), self.material(), names)?;
        match self {
            GroupSection::List { diameter, positions, velocities, spins, .. } => {
                diameter.validate(&format!("{key}.diameter"))?;
                for (i, p) in positions.iter().enumerate() {
                    finite_vector(&format!("{key}.positions.{i}"), *p)?;
                }
                for (name, list) in [("velocities", velocities), ("spins", spins)] {
                    if !list.is_empty() && list.len() != positions.len() {
                        return Err(FieldError::new(
                            format!("{key}.{name}"),
                            format!("({} entries)", list.len()),
                            format!("none or one per position ({})", positions.len()),
                        ));
                    }
                    for (i, v) in list.iter().enumerate() {
                        finite_vector(&format!("{key}.{name}.{i}"), *v)?;
                    }
                }
                Ok(())
            }
            GroupSection::Lattice { diameter, region, spacing, velocity, .. } => {
                diameter.validate(&format!("{key}.diameter"))?;
                region.validate(&format!("{key}.region"))?;
                lattice_spacing(key, *spacing, diameter)?;
                finite_vector(&format!("{key}.velocity"), *velocity)
            }
            GroupSection::HeadLattice { diameter, spacing, sector, z, after_revolutions, .. } => {
                diameter.validate(&format!("{key}.diameter"))?;
                lattice_spacing(key, *spacing, diameter)?;
                if !(sector.iter().all(|a| a.is_finite()) && sector[1] > sector[0] && sector[1] - sector[0] <= 360.0) {
                    return Err(FieldError::new(format!("{key}.sector"), format!("{sector:?}"), "[from, to] in degrees with from < to ≤ from + 360"));
                }
                if !(z.iter().all(|a| a.is_finite()) && z[1] > z[0]) {
                    return Err(FieldError::new(format!("{key}.z"), format!("{z:?}"), "[bottom, top] in m with bottom < top"));
                }
                if !(after_revolutions.is_finite() && *after_revolutions >= 0.0) {
                    return Err(FieldError::new(format!("{key}.after_revolutions"), after_revolutions, "a number of revolutions ≥ 0 (0: placed at the start)"));
                }
                Ok(())
            }
            GroupSection::Random { diameter, region, count, velocity, .. } => {
                diameter.validate(&format!("{key}.diameter"))?;
                region.validate(&format!("{key}.region"))?;
                if *count == 0 {
                    return Err(FieldError::new(format!("{key}.count"), count, "a whole number ≥ 1"));
                }
                finite_vector(&format!("{key}.velocity"), *velocity)
            }
        }
    }
}

/// A lattice spacing: positive and at least the largest diameter (no initial overlap).
fn lattice_spacing(key: &str, spacing: f64, diameter: &Diameter) -> Result<(), FieldError> {
    positive(&format!("{key}.spacing"), spacing, "m")?;
    if spacing < diameter.largest() {
        return Err(FieldError::new(
            format!("{key}.spacing"),
            spacing,
            format!("a spacing ≥ the largest diameter {} m (no initial overlap)", diameter.largest()),
        ));
    }
    Ok(())
}

/// `[[particles.feed]]`: particles created at `rate` per second at random non-overlapping
/// positions in `region`, between `start` and `end`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeedSection {
    pub material: String,
    pub diameter: Diameter,
    pub region: BoxRegion,
    /// Simulated particles per second (each standing for `[particles] modifier` real ones).
    pub rate: f64,
    #[serde(default)]
    pub velocity: [f64; 3],
    /// The velocity varies across the region like a parabolic inlet's (`velocity` is then the
    /// mean of that profile, as for `[boundary.*] profile`): particles enter at the local fluid
    /// velocity of a developed inlet.
    #[serde(default)]
    pub velocity_profile: Option<crate::fluid::settings::ParabolicProfile>,
    #[serde(default)]
    pub start: f64,
    pub end: Option<f64>,
    #[serde(default)]
    pub seed: u64,
}

impl FeedSection {
    fn validate(&self, key: &str, names: &[&str]) -> Result<(), FieldError> {
        check_material(&format!("{key}.material"), &self.material, names)?;
        self.diameter.validate(&format!("{key}.diameter"))?;
        self.region.validate(&format!("{key}.region"))?;
        positive(&format!("{key}.rate"), self.rate, "particles/s")?;
        finite_vector(&format!("{key}.velocity"), self.velocity)?;
        if let Some(p) = &self.velocity_profile {
            p.validate(&format!("{key}.velocity_profile"))?;
        }
        non_negative(&format!("{key}.start"), self.start, "s")?;
        if let Some(end) = self.end {
            if !(end.is_finite() && end > self.start) {
                return Err(FieldError::new(format!("{key}.end"), end, format!("a time after start = {} s", self.start)));
            }
        }
        Ok(())
    }
}

/// `[particles.ambient]`: a still fluid around the particles.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AmbientFluid {
    /// ρ_c [kg/m³].
    pub density: f64,
    /// ν [m²/s].
    pub kinematic_viscosity: f64,
    /// Use the wet restitution law (T3.103) with this fluid.
    #[serde(default = "yes")]
    pub wet_restitution: bool,
    /// Apply drag, added mass and buoyancy of the still fluid to the particles (§5.7).
    #[serde(default = "yes")]
    pub forces: bool,
    #[serde(default)]
    pub drag: DragLaw,
}

fn yes() -> bool {
    true
}

impl AmbientFluid {
    fn validate(&self) -> Result<(), FieldError> {
        positive("particles.ambient.density", self.density, "kg/m³")?;
        positive("particles.ambient.kinematic_viscosity", self.kinematic_viscosity, "m²/s")
    }
}

#[cfg(test)]
mod tests {
    use super::Motion;
    use crate::case::Case;

    const HELD: &str = include_str!("../../../cases/verification/coupling/hydrostatic_held.toml");

    /// `[particles] motion` is `"free"` (the default) or `"held"`; another value is refused at
    /// its line, naming the key and what is allowed.
    #[test]
    fn motion_is_free_or_held_and_a_bad_value_is_located() {
        let path = std::path::Path::new("held.toml");
        assert_eq!(Case::from_toml(HELD, path).unwrap().particles.unwrap().motion, Motion::Held);
        let free = HELD.replace("\nmotion = \"held\"\n", "\n");
        assert_eq!(Case::from_toml(&free, path).unwrap().particles.unwrap().motion, Motion::Free);
        let bad = HELD.replace("\nmotion = \"held\"", "\nmotion = \"hovering\"");
        let e = Case::from_toml(&bad, path).unwrap_err();
        let line = bad.lines().position(|l| l.starts_with("motion")).unwrap() + 1;
        assert_eq!(e.line, Some(line), "{e}");
        let text = e.to_string();
        assert!(text.contains("motion") && text.contains("hovering") && text.contains("free") && text.contains("held"), "{text}");
    }
}
