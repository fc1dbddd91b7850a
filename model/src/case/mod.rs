//! Case files: TOML → a validated, typed [`Case`] in SI units.
//!
//! Parsing happens in two passes. Serde turns the text into typed sections (unknown keys and
//! wrong types are errors located by the parser); then each section's `validate()` checks
//! ranges and consistency and returns a [`FieldError`] with the dotted key path, which
//! [`locate`] maps back to a line and column of the file.

pub mod error;
pub mod limits;
pub mod locate;
pub mod mesh_section;
pub mod parse_error;
pub mod sections;
pub mod unusual;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;

pub use error::{CaseError, CaseErrorKind, FieldError};
pub use mesh_section::MeshSection;
pub use sections::{CaseInfo, OutputSection, Physics, RotatingFrameSection, RotorSection, TimeControl, VerifySection};

use crate::fluid::settings::{BoundaryCondition, FluidSection, NumericsSection};
use crate::particles::settings::ParticlesSection;
use crate::walls::settings::WallSection;

/// A whole case file, validated.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Case {
    pub case: CaseInfo,
    #[serde(default)]
    pub physics: Physics,
    pub time: TimeControl,
    pub fluid: Option<FluidSection>,
    /// Fluid discretisation and PIMPLE settings.
    #[serde(default)]
    pub numerics: NumericsSection,
    pub mesh: Option<MeshSection>,
    /// A parametric cutter head: it makes the fluid mesh (instead of `[mesh]`) and the DEM
    /// walls of the head.
    pub cutter_head: Option<crate::cutter_head::CutterHeadSection>,
    pub rotor: Option<RotorSection>,
    /// Boundary condition per mesh patch name.
    #[serde(default)]
    pub boundary: BTreeMap<String, BoundaryCondition>,
    pub particles: Option<ParticlesSection>,
    /// Two-way coupling of particles and fluid; without it a case with both is one-way coupled.
    pub coupling: Option<crate::coupling::CouplingSection>,
    #[serde(default)]
    pub walls: Vec<WallSection>,
    /// Erosive wear of the walls.
    pub wear: Option<crate::wear::settings::WearSection>,
    /// The fluid's turbulence model (laminar without the section).
    #[serde(default)]
    pub turbulence: crate::turbulence::TurbulenceSection,
    #[serde(default)]
    pub output: OutputSection,
    pub verify: Option<VerifySection>,
    /// The file this case was read from (set by [`Case::load`]).
    #[serde(skip)]
    pub path: PathBuf,
    /// Whether the conditions a `[cutter_head]` derives (its floor and suction) are in
    /// `boundary` ([`Case::finish`]).
    #[serde(skip)]
    derived_conditions: bool,
    /// The file's `[boundary.tank]` while a cutter head's current replaces it by the far field
    /// ([`crate::cutter_head::current`]), put back by [`Case::finish`].
    #[serde(skip)]
    still_tank: Option<BoundaryCondition>,
    /// Whether `time.end_time` was derived from `time.revolutions` ([`Case::finish`]).
    #[serde(skip)]
    derived_end_time: bool,
}

impl Case {
    /// Real particles per simulated one, `[particles] modifier` (1 without particles).
    pub fn particle_modifier(&self) -> f64 {
        self.particles.as_ref().map_or(1.0, |p| p.modifier)
    }

    /// Reads and validates a case file.
    pub fn load(path: &Path) -> Result<Case, CaseError> {
        let bytes = std::fs::read(path).map_err(|e| CaseError { file: path.to_path_buf(), line: None, column: None, kind: CaseErrorKind::Io(e) })?;
        Case::from_bytes(&bytes, path)
    }

    /// Parses and validates the bytes of a case file; a file that is not UTF-8 text is refused
    /// at its first bad byte (offset, line, column and the key on that line).
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Case, CaseError> {
        match std::str::from_utf8(bytes) {
            Ok(text) => Case::from_toml(text, path),
            Err(e) => {
                let offset = e.valid_up_to();
                let valid = std::str::from_utf8(&bytes[..offset]).expect("valid up to here");
                let (line, column) = locate::line_column(valid, offset);
                let key = locate::key_of_line(&String::from_utf8_lossy(bytes), line)
                    .map_or("before any key: ".to_string(), |k| format!("key `{}`: ", k.escape_debug()));
                let message = format!("{key}byte {offset} (0x{:02x}) is not UTF-8 text; a case file is UTF-8 text", bytes[offset]);
                Err(CaseError { file: path.to_path_buf(), line: Some(line), column: Some(column), kind: CaseErrorKind::Parse(message) })
            }
        }
    }

    /// Parses and validates case text; `path` is used in messages only.
    pub fn from_toml(text: &str, path: &Path) -> Result<Case, CaseError> {
        let mut case: Case = toml::from_str(text).map_err(|e| {
            let (line, column, message) = parse_error::locate(text, e.span(), e.message());
            CaseError { file: path.to_path_buf(), line: Some(line), column: Some(column), kind: CaseErrorKind::Parse(message) }
        })?;
        case.path = path.to_path_buf();
        case.finish().map_err(|field| Case::located(text, path, field))?;
        Ok(case)
    }

    /// A validation error of the case read from `text` at `path`, located at its key.
    pub fn located(text: &str, path: &Path, field: FieldError) -> CaseError {
        // a key of a missing section has no place in the file: the file's start
        let (line, column) = locate::key_position(text, &field.key).unwrap_or((1, 1));
        CaseError { file: path.to_path_buf(), line: Some(line), column: Some(column), kind: CaseErrorKind::Invalid(field) }
    }

    /// Validates the case and derives what follows from it (a cutter head's floor and suction
    /// conditions from its discharge and mesh). Call it again after editing a loaded case.
    pub fn finish(&mut self) -> Result<(), FieldError> {
        if self.derived_end_time {
            // derived from the revolutions below again (the rotor may have been edited)
            self.time.end_time = None;
            self.derived_end_time = false;
        }
        if self.derived_conditions {
            for p in crate::cutter_head::fluid_mesh::FLOW_PATCHES {
                self.boundary.remove(p);
            }
            if let Some(tank) = self.still_tank.take() {
                self.boundary.insert("tank".into(), tank);
            }
            self.derived_conditions = false;
        }
        self.validate()?;
        if let Some(n) = self.time.revolutions {
            let omega = self.rotor.as_ref().map_or(0.0, |r| r.angular_velocity().abs());
            if omega == 0.0 {
                return Err(FieldError::new("time.revolutions", n, "revolutions only with a turning [rotor]"));
            }
            self.time.end_time = Some(n * std::f64::consts::TAU / omega);
            self.derived_end_time = true;
        }
        self.add_suction_condition()
    }

    /// A cutter head's tank floor gets the uniform upward velocity that carries
    /// `cutter_head.suction_discharge` in through the exact area of its faces, and the pipe's
    /// end a fixed-pressure outlet ([`crate::cutter_head::fluid_mesh::FLOW_PATCHES`]); an
    /// eccentric mouth's back plate a wall at rest that lets Q_m out over the mouth. With a
    /// `haul_velocity` the floor and the tank's side also carry the current, the far field of
    /// [`crate::cutter_head::current`] (the file's `[boundary.tank]` is kept for still water).
    fn add_suction_condition(&mut self) -> Result<(), FieldError> {
        use crate::cutter_head::current;
        let Some(head) = &self.cutter_head else { return Ok(()) };
        // an input of the head the generator refuses is named as the generator names it
        let refused = |e: crate::mesh::MeshError| match e {
            crate::mesh::MeshError::InvalidInput { input, value, allowed } if input.starts_with("cutter_head.") => FieldError::new(input, value, allowed),
            e => FieldError::new("cutter_head.mesh", format!("({e})"), "a resolution the mesh generator accepts"),
        };
        let spec = crate::cutter_head::fluid_mesh::blocked_rotor_stator(head).map_err(refused)?;
        let area = crate::cutter_head::fluid_mesh::floor_area(head, &spec).map_err(refused)?;
        let velocity = head.suction_discharge / area;
        let tank = current::tank_condition(head);
        self.boundary.insert("floor".into(), current::floor_condition(head, velocity));
        let suction = match crate::cutter_head::fluid_mesh::suction_window(head, &spec) {
            // the back plate at rest with its mouth; the pressure level is then set by a reference
            // cell, as every other boundary fixes the flux
            Some(window) => BoundaryCondition::Wall {
                velocity: [0.0; 3],
                rotating: false,
                angular_velocity: 0.0,
                axis: [0.0, 0.0, 1.0],
                origin: [0.0; 3],
                suction: Some(window),
            },
            None => BoundaryCondition::PressureOutlet { pressure: 0.0 },
        };
        self.boundary.insert("suction".into(), suction);
        if let Some(tank) = tank {
            self.still_tank = self.boundary.insert("tank".into(), tank);
        }
        self.derived_conditions = true;
        Ok(())
    }

    /// Range and consistency checks across sections, of a case before [`Case::finish`] derives
    /// its end time and conditions (after editing a loaded case, call `finish`).
    pub fn validate(&self) -> Result<(), FieldError> {
        if self.case.name.trim().is_empty() {
            return Err(FieldError::new("case.name", "\"\"", "a non-empty name"));
        }
        self.physics.validate()?;
        self.time.validate()?;
        if let Some(fluid) = &self.fluid {
            fluid.validate()?;
        }
        self.numerics.validate()?;
        self.turbulence.validate()?;
        if self.turbulence.is_k_epsilon() && self.fluid.is_none() {
            return Err(FieldError::new("turbulence.model", "\"realizable-k-epsilon\"", "\"laminar\" in a case without a [fluid] section"));
        }
        if let Some(mesh) = &self.mesh {
            mesh.validate()?;
        }
        if let Some(head) = &self.cutter_head {
            head.validate()?;
            if self.mesh.is_some() {
                return Err(FieldError::new("mesh", "(a [mesh] with a [cutter_head])", "no [mesh]: the [cutter_head] makes its own mesh"));
            }
            if self.fluid.is_none() {
                return Err(FieldError::new("fluid", "(missing)", "a [fluid] section with a [cutter_head]"));
            }
            match &self.rotor {
                None => return Err(FieldError::new("rotor", "(missing)", "a [rotor] section (rpm or omega) with a [cutter_head]")),
                Some(r) if r.axis != [0.0, 0.0, 1.0] => {
                    return Err(FieldError::new(
                        "rotor.axis",
                        format!("{:?}", r.axis),
                        "[0, 0, 1] for a cutter head (turn it the other way with a negative rpm)",
                    ))
                }
                _ => {}
            }
        }
        let rotor_mesh = matches!(self.mesh, Some(MeshSection::RotorStator { .. })) || self.cutter_head.is_some();
        if let Some(rotor) = &self.rotor {
            rotor.validate()?;
            match &self.mesh {
                _ if rotor_mesh && rotor.zone == "rotor" => {
                    // The generator builds the rotor about the z axis through the origin.
                    let [ax, ay, az] = rotor.axis;
                    if ax != 0.0 || ay != 0.0 || az == 0.0 {
                        return Err(FieldError::new("rotor.axis", format!("{:?}", rotor.axis), "[0, 0, ±1]: the rotor_stator mesh turns about z"));
                    }
                    if rotor.origin[0] != 0.0 || rotor.origin[1] != 0.0 {
                        return Err(FieldError::new(
                            "rotor.origin",
                            format!("{:?}", rotor.origin),
                            "a point on the z axis ([0, 0, z]): the rotor_stator mesh turns about z",
                        ));
                    }
                }
                _ if rotor_mesh => {
                    return Err(FieldError::new(
                        "rotor.zone",
                        format!("{:?}", rotor.zone),
                        "\"rotor\" (the zone made by the rotor_stator and cutter_head meshes)",
                    ))
                }
                _ if self.fluid.is_some() => {
                    return Err(FieldError::new("rotor", "(a rotor on a mesh without a rotor zone)", "a [rotor] only with mesh.generator = \"rotor_stator\""))
                }
                _ => {}
            }
        }
        if let Some(fluid) = &self.fluid {
            if matches!(fluid.initial.start_field(), crate::fluid::settings::InitialVelocity::SolidBody { .. })
                && self.rotor.as_ref().is_none_or(|r| r.axis[0] != 0.0 || r.axis[1] != 0.0)
            {
                return Err(FieldError::new("fluid.initial.type", "\"solid_body\"", "a solid-body start only with a [rotor] turning about z"));
            }
        }
        crate::fluid::frozen_rotor::check_case(self)?;
        if let (Some(frame), Some(mesh)) = (&self.physics.rotating_frame, &self.mesh) {
            // A 2-D mesh solves no velocity along z: with the axis along z every fictitious force
            // (Ω×u, Ω×(Ω×r), both ⊥ Ω) lies in the plane; with any other axis a 2-D run would drop
            // part of them without saying so.
            let [ax, ay, _] = frame.axis;
            if mesh.is_two_d() && (ax != 0.0 || ay != 0.0) {
                return Err(FieldError::new(
                    "physics.rotating_frame.axis",
                    format!("{:?}", frame.axis),
                    "[0, 0, ±1] with a 2-D mesh (mesh.two_d = true solves no velocity along z)",
                ));
            }
        }
        let has_mesh = self.mesh.is_some() || self.cutter_head.is_some();
        if self.fluid.is_some() != has_mesh {
            let missing = if self.fluid.is_some() { "mesh" } else { "fluid" };
            return Err(FieldError::new(missing, "(missing)", "[fluid] and [mesh] (or [cutter_head]) together: a fluid needs a mesh and a mesh needs a fluid"));
        }
        if self.fluid.is_none() && self.particles.is_none() {
            return Err(FieldError::new("fluid", "(missing)", "a [fluid] with a [mesh], or [particles], or both"));
        }
        let patches = match (&self.mesh, &self.cutter_head) {
            (Some(mesh), _) => Some(mesh.boundary_patches()),
            (None, Some(_)) => {
                use crate::cutter_head::fluid_mesh::{FLOW_PATCHES, PATCHES};
                if let Some(p) = FLOW_PATCHES.iter().find(|p| self.boundary.contains_key(**p) && !self.derived_conditions) {
                    return Err(FieldError::new(
                        format!("boundary.{p}"),
                        format!("(a [boundary.{p}] section)"),
                        "none: the floor's inflow and the pipe's outflow follow from cutter_head.suction_discharge",
                    ));
                }
                if let (Some(head), Some(tank)) = (&self.cutter_head, self.boundary.get("tank")) {
                    if head.has_current() && !self.derived_conditions && !crate::cutter_head::current::still_tank(tank) {
                        return Err(FieldError::new(
                            "boundary.tank",
                            format!("{tank:?}"),
                            "a still tank's wall (type = \"wall\" at rest, or \"symmetry\") with cutter_head.haul_velocity: the current's far field replaces it",
                        ));
                    }
                }
                Some(PATCHES.iter().filter(|p| !FLOW_PATCHES.contains(p)).map(|p| p.to_string()).collect::<Vec<_>>())
            }
            (None, None) => None,
        };
        if let Some(patches) = patches {
            for name in self.boundary.keys() {
                if !patches.iter().any(|p| p == name) {
                    return Err(FieldError::new(format!("boundary.{name}"), format!("{name:?}"), format!("a patch of this mesh: {}", patches.join(", "))));
                }
            }
            for p in &patches {
                if !self.boundary.contains_key(p) {
                    return Err(FieldError::new("boundary", format!("(no [boundary.{p}])"), format!("a condition for every patch: {}", patches.join(", "))));
                }
            }
        }
        for (name, bc) in &self.boundary {
            bc.validate(&format!("boundary.{name}"))?;
        }
        if let Some(particles) = &self.particles {
            particles.validate()?;
        }
        if let Some(coupling) = &self.coupling {
            coupling.validate()?;
            if self.fluid.is_none() || self.particles.is_none() {
                return Err(FieldError::new("coupling", "(a [coupling] section)", "[coupling] only in a case with both [fluid] and [particles]"));
            }
        }
        for (i, wall) in self.walls.iter().enumerate() {
            wall.validate(i)?;
        }
        if let Some(wear) = &self.wear {
            if self.particles.is_none() {
                return Err(FieldError::new("wear", "(a [wear] section)", "a case with [particles]: wear comes from particle–wall impacts"));
            }
            let head_walls = match &self.cutter_head {
                Some(head) if head.material.is_some() => crate::cutter_head::walls::head_wall_names(head),
                _ => Vec::new(),
            };
            let names: Vec<&str> = self.walls.iter().map(|w| w.name.as_str()).chain(head_walls.iter().map(|n| n.as_str())).collect();
            wear.validate(&names)?;
            if let Some(f) = &wear.fluid_mesh {
                self.validate_fluid_mesh(f)?;
            }
        }
        limits::check(self)
    }
}

impl Case {
    /// What a fluid mesh that follows a receding wall needs of the case
    /// (crate::wear::fluid_mesh): a box mesh without periodic directions, the patch a
    /// `symmetry` boundary (the water does not cross the wall it follows), implicit Euler (the
    /// swept volumes balance its volume change) and laminar flow (the k–ε equations do not take
    /// the cells' volume change). The geometry (the wall on the patch) is checked on the mesh.
    fn validate_fluid_mesh(&self, f: &crate::wear::settings::FluidMeshSection) -> Result<(), FieldError> {
        let key = "wear.fluid_mesh";
        match (&self.fluid, &self.mesh) {
            (Some(_), Some(MeshSection::Box { periodic, .. })) if periodic.is_empty() => {}
            (Some(_), Some(MeshSection::Box { .. })) => {
                return Err(FieldError::new(key, "(a [wear.fluid_mesh] section)", "a mesh without periodic directions: its points move with the wall"))
            }
            _ => return Err(FieldError::new(key, "(a [wear.fluid_mesh] section)", "a case with [fluid] on a `box` [mesh]: the fluid mesh follows the wall")),
        }
        match self.boundary.get(&f.patch) {
            Some(crate::fluid::settings::BoundaryCondition::Symmetry) => {}
            Some(_) => {
                return Err(FieldError::new(
                    "wear.fluid_mesh.patch",
                    format!("{:?}", f.patch),
                    format!("a `symmetry` patch: [boundary.{}] lets no water through the wall the mesh follows", f.patch),
                ))
            }
            None => {
                let patches: Vec<&str> = self.boundary.keys().map(String::as_str).collect();
                return Err(FieldError::new(
                    "wear.fluid_mesh.patch",
                    format!("{:?}", f.patch),
                    format!("a patch with a [boundary.*] section: {}", patches.join(", ")),
                ));
            }
        }
        if self.numerics.time_scheme != crate::fluid::settings::TimeScheme::Euler {
            return Err(FieldError::new(
                "numerics.time_scheme",
                format!("\"{}\"", format!("{:?}", self.numerics.time_scheme).to_lowercase()),
                "\"euler\" with [wear.fluid_mesh]: the swept volumes of a mesh that follows a wall balance the implicit Euler volume change",
            ));
        }
        if self.turbulence.is_k_epsilon() {
            return Err(FieldError::new(
                "turbulence.model",
                "\"realizable-k-epsilon\"",
                "\"laminar\" with [wear.fluid_mesh]: the k–ε equations do not take the cells' volume change",
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn head_case(edit: impl Fn(String) -> String) -> Result<Case, CaseError> {
        let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../cases/cutter_head.toml")).unwrap();
        Case::from_toml(&edit(text), Path::new("cutter_head.toml"))
    }

    #[test]
    fn revolutions_set_the_end_time_from_the_rotor_and_follow_an_edited_speed() {
        let mut case = head_case(|t| t.replace("revolutions = 1", "revolutions = 3")).unwrap();
        assert_eq!(case.time.end_time, Some(3.0 * std::f64::consts::TAU / (60.0 * std::f64::consts::TAU / 60.0)));
        case.rotor.as_mut().unwrap().rpm = Some(30.0);
        case.finish().unwrap();
        assert!((case.time.end_time.unwrap() - 6.0).abs() < 1e-12, "{:?}", case.time.end_time);
        let both = head_case(|t| t.replace("revolutions = 1", "revolutions = 1\nend_time = 2.0")).unwrap_err();
        assert!(both.to_string().contains("time.revolutions"), "{both}");
    }

    #[test]
    fn a_head_sets_its_floor_and_suction_and_refuses_them_in_the_file() {
        let case = head_case(|t| t).unwrap();
        assert!(matches!(case.boundary["floor"], BoundaryCondition::VelocityInlet { velocity, .. } if velocity[2] > 0.0));
        assert!(matches!(case.boundary["suction"], BoundaryCondition::PressureOutlet { .. }));
        let mut again = case.clone();
        again.cutter_head.as_mut().unwrap().suction_discharge = 0.24;
        again.finish().unwrap();
        let speed = |c: &Case| match c.boundary["floor"] {
            BoundaryCondition::VelocityInlet { velocity, .. } => velocity[2],
            _ => unreachable!(),
        };
        // the floor's inflow follows the discharge (same area)
        assert!((speed(&again) - 2.0 * speed(&case)).abs() < 1e-15);
        let error = head_case(|t| t + "\n[boundary.floor]\ntype = \"wall\"\n").unwrap_err();
        assert!(error.to_string().contains("boundary.floor"), "{error}");
        let error = head_case(|t| {
            t.replace("[cutter_head]", "[mesh]\ngenerator = \"box\"\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\ncells = [2, 2, 2]\n\n[cutter_head]")
        })
        .unwrap_err();
        assert!(error.to_string().contains("mesh"), "{error}");
    }
}
