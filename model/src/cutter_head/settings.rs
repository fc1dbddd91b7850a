//! `[cutter_head]`: the parametric cutter head, its tank and its mesh resolution
//! (spillage-and-flow-verification.md §2.11, §4, §5.4).
//!
//! Coordinates: the head turns about the z axis through the origin (the `[rotor]`); z = 0 is
//! the underside of the ring (the thesis' "0 at the ring", §0), the hub is at z = −H.

use serde::Deserialize;

use crate::case::error::{finite_vector, in_range, positive, FieldError};

/// `[cutter_head]`
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CutterHeadSection {
    /// Contour points `[s, R, φ]`: axial distance s from the ring toward the hub [m] (first 0,
    /// increasing, the last is the height H), contour radius R(s) of the blade outer edges [m],
    /// blade angle φ(s) to the contour tangent [deg] (spec §2.3, §2.8); linear in between.
    pub contour: Vec<[f64; 3]>,
    /// Number of blades.
    pub blades: usize,
    /// Blade thickness [m].
    pub blade_thickness: f64,
    /// Radial extent of a blade inward from the contour [m].
    pub blade_depth: f64,
    /// Turn of a blade's outer edge from the ring to the hub [deg] (helical blades; positive
    /// turns with the rotation direction of a positive ω).
    #[serde(default)]
    pub blade_twist: f64,
    /// Which way a blade's cross-section leans from its outer edge inward (default
    /// `"backward"`, a pump impeller's: the outer edge trails).
    #[serde(default)]
    pub blade_sweep: BladeSweep,
    /// Inner radius of the ring [m].
    pub ring_inner_radius: f64,
    /// Axial thickness of the ring (and of the back plate) [m].
    pub ring_thickness: f64,
    /// Axial thickness of the hub plate under z = −H [m].
    pub hub_thickness: f64,
    /// Outer radius of the hub plate [m] (default: the contour's radius at the hub, R(H), a
    /// closed bottom). A smaller hub leaves the bottom open between the hub and the blades' outer
    /// edges, as on a real cutter head whose blades converge on a small hub: water is drawn in
    /// there (the axial pump of spec §2.4) and rock that falls through has left the contour
    /// hull, so it counts as spilled.
    #[serde(default)]
    pub hub_radius: Option<f64>,
    /// Radius of the rotating shaft on the axis [m] (the mesh cannot contain the axis).
    pub shaft_radius: f64,
    /// How the mixture leaves: through the whole inner ring area, or through a central mouth
    /// in a back plate.
    pub suction: Suction,
    /// Suction (mixture) discharge Q_m [m³/s], spread uniformly over the pipe section.
    pub suction_discharge: f64,
    /// Length of the suction pipe above the ring (the domain ends there) [m]. With an eccentric
    /// mouth the pipe is not meshed: the back plate's housing rises this far.
    pub pipe_length: f64,
    /// Wall thickness of the suction pipe [m] (not used with an eccentric mouth).
    pub pipe_wall: f64,
    /// A particle whose centre rises this far into the pipe is counted as sucked [m] (with an
    /// eccentric mouth, once its centre passes the plate).
    #[serde(default = "CutterHeadSection::default_capture_height")]
    pub capture_height: f64,
    /// `[[particles.materials]]` entry of the head's steel (DEM walls).
    pub material: Option<String>,
    /// Haul (swing) velocity [m/s]: a uniform current past the head in its frame, across the
    /// axis (z component 0; the swing is horizontal and normal to the ladder, so along ±y
    /// with gravity tilted in the x–z plane). Imposed on the tank's side and floor as a far
    /// field ([`super::current`], spillage-and-flow-verification.md §6.1 item 3, §5.4
    /// difference 3). Default: still water.
    #[serde(default)]
    pub haul_velocity: [f64; 3],
    pub tank: TankSection,
    pub mesh: HeadMeshSection,
}

/// `blade_sweep`: the lean of a blade's cross-section, a logarithmic spiral at the angle φ(z) to
/// every circle it crosses (spec §2.3: φ is read at the outer edge, where the analytical model
/// takes it; the thesis gives the lean only in its drawings, §2.11).
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum BladeSweep {
    /// The outer edge trails the inner part in the direction of rotation, as a centrifugal
    /// pump's backward-swept blades: water the blades drag slower than themselves slides
    /// outward along them.
    #[default]
    Backward,
    /// The outer edge leads, with the teeth, as on a cutter head whose blades turn the cut
    /// material inward (spec §1.5, Den Burger: "a positive C_slip … gives inflow with
    /// outward-pointing blades"): water the blades drag slower than themselves slides inward
    /// along them.
    Forward,
}

/// `suction = { type = "axial" }`, `{ type = "mouth", radius = 0.1 }` or
/// `{ type = "eccentric", angle = 0.0, width = 100.0, radii = [0.07, 0.2] }`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Suction {
    /// Suction spread uniformly over the inner ring area (the thesis' axial head, §4.1 a).
    Axial,
    /// A back plate at the ring, turning with the head, closing it except a central mouth of
    /// this radius [m] that leads into a pipe turning with it.
    Mouth { radius: f64 },
    /// The thesis' back-plate head (§4.1 b, §4.5): a back plate at rest over the whole inner
    /// ring area (z = 0, under the ring's top), with a kidney-shaped mouth that stands still
    /// while the head turns under it ([`super::mouth`]): an annular sector centred on azimuth
    /// `angle` [deg, world frame], `width` [deg] wide, between `radii` [m].
    Eccentric { angle: f64, width: f64, radii: [f64; 2] },
}

/// `[cutter_head.tank]`: the water around the head.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TankSection {
    /// Radius of the tank (the outer boundary) [m].
    pub radius: f64,
    /// Water depth below the hub plate [m].
    pub below_hub: f64,
}

/// `[cutter_head.mesh]`: resolution of the fluid mesh.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct HeadMeshSection {
    /// Cell size in the head and the pipe [m].
    pub cell_size: f64,
    /// Cell size at the tank wall and below the hub [m] (graded from `cell_size`).
    pub outer_cell_size: f64,
    /// Radius of the sliding interface between the rotor and the stator zones [m]; the
    /// head (contour and ring) must fit inside it with one cell to spare.
    pub interface_radius: f64,
    /// How the fluid mesh holds the blades ([`BladeCells`]); the plates are blocked cells either way.
    #[serde(default)]
    pub blades: BladeCells,
}

/// `[cutter_head.mesh] blades`: the blades in the fluid mesh.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum BladeCells {
    /// Every cell a blade touches is removed: a staircase a cell or two thick, whatever the
    /// blade's thickness (0.054 m³ of cells between ring and hub at 5 cm cells on the default
    /// head, for about 0.005 m³ of blade).
    #[default]
    Blocked,
    /// Each blade is a zero-thickness wall on the cell faces its mid-surface crosses between
    /// two cell centres (a baffle): the passages keep their volume at any cell size and only
    /// the blade's orientation is a staircase. A radial cell edge lies on the widest contour
    /// radius, so the tips and the ring end there. The DEM walls keep the blade's thickness.
    Baffles,
}

impl CutterHeadSection {
    fn default_capture_height() -> f64 {
        0.05
    }

    /// Radius of the opening the mixture leaves through (the pipe's inner radius); with an
    /// eccentric mouth, the radius of the back plate (the ring's inner radius).
    pub fn opening_radius(&self) -> f64 {
        match self.suction {
            Suction::Axial | Suction::Eccentric { .. } => self.ring_inner_radius,
            Suction::Mouth { radius } => radius,
        }
    }

    /// The eccentric mouth's shape, if the suction has one.
    pub fn eccentric_mouth(&self) -> Option<super::mouth::EccentricMouth> {
        match self.suction {
            Suction::Eccentric { angle, width, radii } => {
                Some(super::mouth::EccentricMouth { angle: angle.to_radians(), half_width: 0.5 * width.to_radians(), radii })
            }
            _ => None,
        }
    }

    /// Whether a haul velocity (a current past the head) is set.
    pub fn has_current(&self) -> bool {
        self.haul_velocity.iter().any(|v| *v != 0.0)
    }

    /// H, the axial distance from the ring to the hub.
    pub fn height(&self) -> f64 {
        self.contour.last().map_or(0.0, |p| p[0])
    }

    pub fn validate(&self) -> Result<(), FieldError> {
        let key = |k: &str| format!("cutter_head.{k}");
        if self.contour.len() < 2 {
            return Err(FieldError::new(key("contour"), format!("({} points)", self.contour.len()), "at least 2 points [s, R, φ]"));
        }
        if self.contour[0][0] != 0.0 {
            return Err(FieldError::new(key("contour.0"), format!("{:?}", self.contour[0]), "a first point at s = 0 (the ring)"));
        }
        for (i, p) in self.contour.iter().enumerate() {
            if i > 0 && !(p[0] > self.contour[i - 1][0] && p[0].is_finite()) {
                return Err(FieldError::new(
                    key(&format!("contour.{i}")),
                    format!("{p:?}"),
                    format!("s > {} m (s increases from the ring to the hub)", self.contour[i - 1][0]),
                ));
            }
            positive(&key(&format!("contour.{i}")), p[1], "m (the contour radius R)")?;
            if !(p[2] > 0.0 && p[2] < 90.0) {
                return Err(FieldError::new(key(&format!("contour.{i}")), format!("{p:?}"), "a blade angle φ in (0, 90) degrees"));
            }
        }
        if !(1..=64).contains(&self.blades) {
            return Err(FieldError::new(key("blades"), self.blades, "a number of blades from 1 to 64"));
        }
        positive(&key("blade_thickness"), self.blade_thickness, "m")?;
        positive(&key("blade_depth"), self.blade_depth, "m")?;
        in_range(&key("blade_twist"), self.blade_twist, -360.0, 360.0, "degrees")?;
        positive(&key("ring_thickness"), self.ring_thickness, "m")?;
        positive(&key("hub_thickness"), self.hub_thickness, "m")?;
        positive(&key("shaft_radius"), self.shaft_radius, "m")?;
        positive(&key("suction_discharge"), self.suction_discharge, "m³/s")?;
        positive(&key("pipe_length"), self.pipe_length, "m")?;
        positive(&key("pipe_wall"), self.pipe_wall, "m")?;
        positive(&key("capture_height"), self.capture_height, "m")?;
        finite_vector(&key("haul_velocity"), self.haul_velocity)?;
        if self.haul_velocity[2] != 0.0 {
            return Err(FieldError::new(
                key("haul_velocity"),
                format!("{:?}", self.haul_velocity),
                "a current across the head's axis, [v_x, v_y, 0] m/s (the tank's top is a lid, so no current can pass along z; a swing is along ±y)",
            ));
        }
        let ring_radius = self.contour[0][1];
        if !(self.ring_inner_radius > self.shaft_radius && self.ring_inner_radius < ring_radius) {
            return Err(FieldError::new(
                key("ring_inner_radius"),
                self.ring_inner_radius,
                format!("a radius between shaft_radius = {} m and the ring's outer radius R(0) = {ring_radius} m", self.shaft_radius),
            ));
        }
        if let Suction::Mouth { radius } = self.suction {
            if !(radius > self.shaft_radius && radius < self.ring_inner_radius) {
                return Err(FieldError::new(
                    key("suction.radius"),
                    radius,
                    format!("a mouth radius between shaft_radius = {} m and ring_inner_radius = {} m", self.shaft_radius, self.ring_inner_radius),
                ));
            }
        }
        if let Suction::Eccentric { angle, width, radii } = self.suction {
            in_range(&key("suction.angle"), angle, -360.0, 360.0, "degrees")?;
            if !(width > 0.0 && width <= 180.0) {
                return Err(FieldError::new(key("suction.width"), width, "an opening angle in (0, 180] degrees"));
            }
            if !(radii[0] > self.shaft_radius && radii[1] > radii[0] && radii[1] < self.ring_inner_radius) {
                return Err(FieldError::new(
                    key("suction.radii"),
                    format!("{radii:?}"),
                    format!("[inner, outer] with shaft_radius = {} m < inner < outer < ring_inner_radius = {} m", self.shaft_radius, self.ring_inner_radius),
                ));
            }
        }
        if self.capture_height >= self.pipe_length {
            return Err(FieldError::new(key("capture_height"), self.capture_height, format!("less than pipe_length = {} m", self.pipe_length)));
        }
        let hub_radius = self.contour.last().expect("≥ 2 points")[1];
        if hub_radius <= self.shaft_radius {
            return Err(FieldError::new(
                key("contour"),
                format!("(hub radius {hub_radius} m)"),
                format!("a hub radius above shaft_radius = {} m", self.shaft_radius),
            ));
        }
        if let Some(r) = self.hub_radius {
            if !(r > self.shaft_radius && r <= hub_radius) {
                return Err(FieldError::new(
                    key("hub_radius"),
                    r,
                    format!("a radius above shaft_radius = {} m and at most the contour's radius at the hub, R(H) = {hub_radius} m", self.shaft_radius),
                ));
            }
        }
        positive(&key("tank.radius"), self.tank.radius, "m")?;
        positive(&key("tank.below_hub"), self.tank.below_hub, "m")?;
        positive(&key("mesh.cell_size"), self.mesh.cell_size, "m")?;
        positive(&key("mesh.outer_cell_size"), self.mesh.outer_cell_size, "m")?;
        let pipe = if self.eccentric_mouth().is_some() { 0.0 } else { self.pipe_wall };
        let widest = self.contour.iter().map(|p| p[1]).fold(self.opening_radius() + pipe, f64::max);
        if !(self.mesh.interface_radius >= widest + self.mesh.cell_size) {
            return Err(FieldError::new(
                key("mesh.interface_radius"),
                self.mesh.interface_radius,
                format!("at least the widest part of the head ({widest} m) plus one cell_size ({} m)", self.mesh.cell_size),
            ));
        }
        if !(self.tank.radius > self.mesh.interface_radius + self.mesh.cell_size) {
            return Err(FieldError::new(
                key("tank.radius"),
                self.tank.radius,
                format!("more than mesh.interface_radius + cell_size = {} m", self.mesh.interface_radius + self.mesh.cell_size),
            ));
        }
        let cells = self.estimated_cells();
        if cells > 2.0e7 {
            return Err(FieldError::new(
                key("mesh.cell_size"),
                self.mesh.cell_size,
                format!("a cell size giving at most 2·10⁷ cells (this one gives about {cells:.1e})"),
            ));
        }
        Ok(())
    }

    /// A rough cell count (before solids are removed), for validation and `spillage check`.
    pub fn estimated_cells(&self) -> f64 {
        let (h, ho) = (self.mesh.cell_size, self.mesh.outer_cell_size);
        let rotor = (self.mesh.interface_radius - self.shaft_radius) / h * (std::f64::consts::TAU * self.contour[0][1] / h);
        let stator = (self.tank.radius - self.mesh.interface_radius) / (0.5 * (h + ho)) * (std::f64::consts::TAU * self.mesh.interface_radius / h);
        let layers = (self.height() + self.hub_thickness + self.ring_thickness + self.pipe_length) / h + self.tank.below_hub / ho;
        (rotor + stator) * layers
    }
}
