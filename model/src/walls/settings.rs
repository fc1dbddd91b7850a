//! `[[walls]]` entries: a triangle-mesh wall (generated or read from STL), its material and its
//! rigid motion.

use serde::Deserialize;

use crate::case::error::{finite_vector, positive, FieldError};

/// One `[[walls]]` entry.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallSection {
    pub name: String,
    /// Name of a `[[particles.materials]]` entry (E, ν, ε_dry and μ_f of the wall side).
    pub material: String,
    pub shape: ShapeSection,
    #[serde(default)]
    pub motion: MotionSection,
}

/// `[walls.shape]`: what the wall looks like, selected by `type`.
#[derive(Clone, Debug, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeSection {
    /// A rectangle centred at `centre` with the given `normal`, side lengths `size` along the
    /// in-plane axes (`u_axis` and normal × u_axis), split into `divisions` cells of two triangles.
    Plane {
        centre: [f64; 3],
        normal: [f64; 3],
        size: [f64; 2],
        #[serde(default = "one_by_one")]
        divisions: [u32; 2],
        u_axis: Option<[f64; 3]>,
    },
    /// The six faces of an axis-aligned box (minus the faces listed in `open`, e.g. `["+z"]`),
    /// each split into `divisions` × `divisions` cells.
    Box {
        min: [f64; 3],
        max: [f64; 3],
        #[serde(default = "one")]
        divisions: u32,
        #[serde(default)]
        open: Vec<String>,
    },
    /// The side of a cylinder: base centre `origin`, `axis` direction, `radius`, `length`.
    Cylinder {
        origin: [f64; 3],
        axis: [f64; 3],
        radius: f64,
        length: f64,
        #[serde(default = "default_segments")]
        segments: u32,
        #[serde(default = "one")]
        layers: u32,
    },
    /// A flat disc (centre, normal, radius) made of `rings` rings of `segments` segments.
    Disc {
        centre: [f64; 3],
        normal: [f64; 3],
        radius: f64,
        #[serde(default = "default_segments")]
        segments: u32,
        #[serde(default = "one")]
        rings: u32,
    },
    /// A mesh read from an ASCII or binary STL file (path relative to the case file), scaled.
    Stl {
        file: String,
        #[serde(default = "unit_scale")]
        scale: f64,
    },
}

fn one() -> u32 {
    1
}
fn one_by_one() -> [u32; 2] {
    [1, 1]
}
fn default_segments() -> u32 {
    32
}
fn unit_scale() -> f64 {
    1.0
}

/// Face names allowed in `open` of a box.
pub const BOX_FACES: [&str; 6] = ["-x", "+x", "-y", "+y", "-z", "+z"];

/// `[walls.motion]`: rigid motion, selected by `type` (default static).
#[derive(Clone, Debug, Deserialize, Default)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum MotionSection {
    #[default]
    Static,
    /// Turns with the `[rotor]` (its ω, axis and origin).
    Rotor,
    /// Turns at `omega` [rad/s] about `axis` through `origin`.
    Rotate {
        omega: f64,
        #[serde(default = "z_axis")]
        axis: [f64; 3],
        #[serde(default)]
        origin: [f64; 3],
    },
    /// Moves at constant `velocity` [m/s].
    Translate { velocity: [f64; 3] },
}

fn z_axis() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

fn non_zero_direction(key: &str, v: [f64; 3]) -> Result<(), FieldError> {
    finite_vector(key, v)?;
    if v.iter().map(|a| a * a).sum::<f64>().sqrt() < 1e-12 {
        return Err(FieldError::new(key, format!("{v:?}"), "a non-zero direction vector"));
    }
    Ok(())
}

impl WallSection {
    pub fn validate(&self, index: usize) -> Result<(), FieldError> {
        let key = format!("walls.{index}");
        if self.name.trim().is_empty() {
            return Err(FieldError::new(format!("{key}.name"), "\"\"", "a non-empty name"));
        }
        let shape = format!("{key}.shape");
        match &self.shape {
            ShapeSection::Plane { centre, normal, size, divisions, u_axis } => {
                finite_vector(&format!("{shape}.centre"), *centre)?;
                non_zero_direction(&format!("{shape}.normal"), *normal)?;
                positive(&format!("{shape}.size"), size[0].min(size[1]), "m")?;
                if divisions.contains(&0) {
                    return Err(FieldError::new(format!("{shape}.divisions"), format!("{divisions:?}"), "two whole numbers ≥ 1"));
                }
                if let Some(u) = u_axis {
                    non_zero_direction(&format!("{shape}.u_axis"), *u)?;
                    let n = nalgebra::Vector3::from(*normal).normalize();
                    let u = nalgebra::Vector3::from(*u).normalize();
                    if n.cross(&u).norm() < 1e-6 {
                        return Err(FieldError::new(format!("{shape}.u_axis"), format!("{:?}", u_axis.unwrap()), "a direction not parallel to the normal"));
                    }
                }
            }
            ShapeSection::Box { min, max, divisions, open } => {
                finite_vector(&format!("{shape}.min"), *min)?;
                finite_vector(&format!("{shape}.max"), *max)?;
                if (0..3).any(|k| max[k] <= min[k]) {
                    return Err(FieldError::new(format!("{shape}.max"), format!("{max:?}"), format!("a corner above min = {min:?} in every direction")));
                }
                if *divisions == 0 {
                    return Err(FieldError::new(format!("{shape}.divisions"), divisions, "a whole number ≥ 1"));
                }
                for face in open {
                    if !BOX_FACES.contains(&face.as_str()) {
                        return Err(FieldError::new(format!("{shape}.open"), format!("{face:?}"), format!("face names from {}", BOX_FACES.join(", "))));
                    }
                }
            }
            ShapeSection::Cylinder { origin, axis, radius, length, segments, layers } => {
                finite_vector(&format!("{shape}.origin"), *origin)?;
                non_zero_direction(&format!("{shape}.axis"), *axis)?;
                positive(&format!("{shape}.radius"), *radius, "m")?;
                positive(&format!("{shape}.length"), *length, "m")?;
                if *segments < 3 {
                    return Err(FieldError::new(format!("{shape}.segments"), segments, "a whole number ≥ 3"));
                }
                if *layers == 0 {
                    return Err(FieldError::new(format!("{shape}.layers"), layers, "a whole number ≥ 1"));
                }
            }
            ShapeSection::Disc { centre, normal, radius, segments, rings } => {
                finite_vector(&format!("{shape}.centre"), *centre)?;
                non_zero_direction(&format!("{shape}.normal"), *normal)?;
                positive(&format!("{shape}.radius"), *radius, "m")?;
                if *segments < 3 {
                    return Err(FieldError::new(format!("{shape}.segments"), segments, "a whole number ≥ 3"));
                }
                if *rings == 0 {
                    return Err(FieldError::new(format!("{shape}.rings"), rings, "a whole number ≥ 1"));
                }
            }
            ShapeSection::Stl { file, scale } => {
                if file.trim().is_empty() {
                    return Err(FieldError::new(format!("{shape}.file"), "\"\"", "the path of an STL file"));
                }
                positive(&format!("{shape}.scale"), *scale, "")?;
            }
        }
        let motion = format!("{key}.motion");
        match &self.motion {
            MotionSection::Static | MotionSection::Rotor => Ok(()),
            MotionSection::Rotate { omega, axis, origin } => {
                if !omega.is_finite() {
                    return Err(FieldError::new(format!("{motion}.omega"), omega, "a finite angular velocity in rad/s"));
                }
                non_zero_direction(&format!("{motion}.axis"), *axis)?;
                finite_vector(&format!("{motion}.origin"), *origin)
            }
            MotionSection::Translate { velocity } => finite_vector(&format!("{motion}.velocity"), *velocity),
        }
    }
}
