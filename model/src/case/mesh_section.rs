//! `[mesh]`: which block-structured generator builds the mesh, and its parameters.

use serde::Deserialize;

use super::error::{positive, FieldError};

/// A solid block of a box mesh: `{ min = [..], max = [..] }`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SolidBlock {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

/// `[mesh]`, selected by `generator = "box" | "annulus" | "rotor_stator"`.
#[derive(Clone, Debug, Deserialize)]
#[serde(tag = "generator", rename_all = "snake_case", deny_unknown_fields)]
pub enum MeshSection {
    /// Cartesian box `min`..`max` with `cells` per direction.
    Box {
        min: [f64; 3],
        max: [f64; 3],
        cells: [usize; 3],
        /// Ratio of last to first cell size per direction (1 = uniform).
        #[serde(default = "unit_grading")]
        grading: [f64; 3],
        /// Directions joined periodically: any of "x", "y", "z".
        #[serde(default)]
        periodic: Vec<String>,
        /// One cell thick in z with `empty` front and back: a 2-D mesh.
        #[serde(default)]
        two_d: bool,
        /// Solid blocks removed from the box; their faces form the patch `solid`.
        #[serde(default)]
        solids: Vec<SolidBlock>,
    },
    /// Cylindrical annulus about the z axis.
    Annulus {
        r_inner: f64,
        r_outer: f64,
        z_min: f64,
        z_max: f64,
        n_r: usize,
        n_theta: usize,
        #[serde(default = "one")]
        n_z: usize,
        #[serde(default = "unit")]
        radial_grading: f64,
        #[serde(default)]
        two_d: bool,
    },
    /// A rotor annulus inside a stator annulus meeting at a sliding interface at `r_interface`.
    RotorStator {
        r_inner: f64,
        r_interface: f64,
        r_outer: f64,
        z_min: f64,
        z_max: f64,
        n_r_rotor: usize,
        n_r_stator: usize,
        n_theta_rotor: usize,
        n_theta_stator: usize,
        #[serde(default = "one")]
        n_z: usize,
        #[serde(default = "unit")]
        radial_grading: f64,
        #[serde(default)]
        two_d: bool,
    },
}

fn unit_grading() -> [f64; 3] {
    [1.0; 3]
}
fn one() -> usize {
    1
}
fn unit() -> f64 {
    1.0
}

fn count(key: &str, n: usize, min: usize) -> Result<(), FieldError> {
    if n >= min && n <= 100_000_000 {
        Ok(())
    } else {
        Err(FieldError::new(key, n, format!("a whole number of cells from {min} to 10⁸")))
    }
}

impl MeshSection {
    /// Whether the mesh is one cell thick in z with `empty` front and back (`two_d = true`).
    pub fn is_two_d(&self) -> bool {
        match self {
            MeshSection::Box { two_d, .. } | MeshSection::Annulus { two_d, .. } | MeshSection::RotorStator { two_d, .. } => *two_d,
        }
    }

    pub fn validate(&self) -> Result<(), FieldError> {
        match self {
            MeshSection::Box { min, max, cells, grading, periodic, two_d, solids } => {
                for (i, b) in solids.iter().enumerate() {
                    for (d, axis) in ["x", "y", "z"].iter().enumerate() {
                        if !(b.min[d].is_finite() && b.max[d].is_finite() && b.max[d] > b.min[d]) {
                            return Err(FieldError::new(
                                format!("mesh.solids.{i}.max"),
                                format!("{:?} (min = {:?})", b.max, b.min),
                                format!("max.{axis} > min.{axis}, both finite"),
                            ));
                        }
                    }
                }
                for (d, axis) in ["x", "y", "z"].iter().enumerate() {
                    if !(min[d].is_finite() && max[d].is_finite() && max[d] > min[d]) {
                        return Err(FieldError::new("mesh.max", format!("{max:?} (min = {min:?})"), format!("max.{axis} > min.{axis}, both finite")));
                    }
                    count("mesh.cells", cells[d], 1)?;
                    positive("mesh.grading", grading[d], "(ratio of last to first cell size)")?;
                }
                for p in periodic {
                    if !matches!(p.as_str(), "x" | "y" | "z") {
                        return Err(FieldError::new("mesh.periodic", format!("{p:?}"), "a list of directions among \"x\", \"y\", \"z\""));
                    }
                }
                if *two_d && cells[2] != 1 {
                    return Err(FieldError::new("mesh.cells", format!("{cells:?}"), "exactly 1 cell in z when two_d = true"));
                }
                if *two_d && periodic.iter().any(|p| p == "z") {
                    return Err(FieldError::new("mesh.periodic", "[\"z\"]", "no z periodicity when two_d = true (z faces are empty)"));
                }
                Ok(())
            }
            MeshSection::Annulus { r_inner, r_outer, z_min, z_max, n_r, n_theta, n_z, radial_grading, two_d } => {
                positive("mesh.r_inner", *r_inner, "m (the axis itself is not meshed)")?;
                radii_order(&[("mesh.r_inner", *r_inner), ("mesh.r_outer", *r_outer)])?;
                z_range(*z_min, *z_max)?;
                count("mesh.n_r", *n_r, 1)?;
                count("mesh.n_theta", *n_theta, 3)?;
                count("mesh.n_z", *n_z, 1)?;
                positive("mesh.radial_grading", *radial_grading, "")?;
                two_d_layers(*two_d, *n_z)
            }
            MeshSection::RotorStator {
                r_inner,
                r_interface,
                r_outer,
                z_min,
                z_max,
                n_r_rotor,
                n_r_stator,
                n_theta_rotor,
                n_theta_stator,
                n_z,
                radial_grading,
                two_d,
            } => {
                positive("mesh.r_inner", *r_inner, "m (the axis itself is not meshed)")?;
                radii_order(&[("mesh.r_inner", *r_inner), ("mesh.r_interface", *r_interface), ("mesh.r_outer", *r_outer)])?;
                z_range(*z_min, *z_max)?;
                count("mesh.n_r_rotor", *n_r_rotor, 1)?;
                count("mesh.n_r_stator", *n_r_stator, 1)?;
                count("mesh.n_theta_rotor", *n_theta_rotor, 3)?;
                count("mesh.n_theta_stator", *n_theta_stator, 3)?;
                count("mesh.n_z", *n_z, 1)?;
                positive("mesh.radial_grading", *radial_grading, "")?;
                two_d_layers(*two_d, *n_z)
            }
        }
    }

    /// Names of the patches that need a boundary condition (periodic, empty and interface
    /// faces need none).
    pub fn boundary_patches(&self) -> Vec<String> {
        let mut names = Vec::new();
        match self {
            MeshSection::Box { periodic, two_d, solids, .. } => {
                for axis in ["x", "y", "z"] {
                    if periodic.iter().any(|p| p == axis) || (*two_d && axis == "z") {
                        continue;
                    }
                    names.push(format!("{axis}_min"));
                    names.push(format!("{axis}_max"));
                }
                if !solids.is_empty() {
                    names.push("solid".to_string());
                }
            }
            MeshSection::Annulus { two_d, .. } | MeshSection::RotorStator { two_d, .. } => {
                names.extend(["inner".to_string(), "outer".to_string()]);
                if !*two_d {
                    names.extend(["z_min".to_string(), "z_max".to_string()]);
                }
            }
        }
        names
    }

    /// Number of cells the generator will make (for `spillage check` and memory estimates).
    pub fn cell_count(&self) -> usize {
        match self {
            MeshSection::Box { cells, .. } => cells.iter().product(),
            MeshSection::Annulus { n_r, n_theta, n_z, .. } => n_r * n_theta * n_z,
            MeshSection::RotorStator { n_r_rotor, n_r_stator, n_theta_rotor, n_theta_stator, n_z, .. } => {
                (n_r_rotor * n_theta_rotor + n_r_stator * n_theta_stator) * n_z
            }
        }
    }
}

fn radii_order(radii: &[(&str, f64)]) -> Result<(), FieldError> {
    for w in radii.windows(2) {
        let ((_, a), (kb, b)) = (w[0], w[1]);
        if !(b.is_finite() && b > a) {
            return Err(FieldError::new(kb, b, format!("a radius > {} = {a} m", w[0].0)));
        }
    }
    Ok(())
}

fn z_range(z_min: f64, z_max: f64) -> Result<(), FieldError> {
    if z_min.is_finite() && z_max.is_finite() && z_max > z_min {
        Ok(())
    } else {
        Err(FieldError::new("mesh.z_max", z_max, format!("a finite height > mesh.z_min = {z_min} m")))
    }
}

fn two_d_layers(two_d: bool, n_z: usize) -> Result<(), FieldError> {
    if two_d && n_z != 1 {
        Err(FieldError::new("mesh.n_z", n_z, "1 when two_d = true"))
    } else {
        Ok(())
    }
}
