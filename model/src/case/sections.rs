//! Case-file sections that belong to no single model: case info, physics, time control, mesh
//! generator, rotor, output and verification.

use serde::Deserialize;

use super::error::{finite_vector, positive, FieldError};

/// `[case]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseInfo {
    pub name: String,
    #[serde(default)]
    pub description: String,
}

/// `[physics]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Physics {
    /// Gravitational acceleration [m/s²].
    #[serde(default = "Physics::default_gravity")]
    pub gravity: [f64; 3],
    /// The whole case is written in a frame rotating rigidly at Ω (wear-model.md §2.6, the
    /// Coriolis tester); absent = an inertial frame.
    pub rotating_frame: Option<RotatingFrameSection>,
}

impl Default for Physics {
    fn default() -> Self {
        Self { gravity: Self::default_gravity(), rotating_frame: None }
    }
}

impl Physics {
    fn default_gravity() -> [f64; 3] {
        [0.0, 0.0, -9.81]
    }
    pub fn validate(&self) -> Result<(), FieldError> {
        finite_vector("physics.gravity", self.gravity)?;
        if let Some(frame) = &self.rotating_frame {
            frame.validate()?;
        }
        Ok(())
    }
}

/// `[physics.rotating_frame]`: the case's coordinates, velocities and walls are those seen from a
/// frame turning at the constant angular velocity Ω = `omega` · `axis`/|`axis`| about the line
/// through `origin` (wear-model.md §2.6 [R]; the fictitious forces are
/// [`crate::closure::rotating_frame`]). Not to be confused with `[rotor]`, which turns one mesh
/// zone inside an inertial frame.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RotatingFrameSection {
    /// Signed angular speed about `axis` [rad/s] (3000 rpm = 314.159265 rad/s, §15 A39).
    pub omega: f64,
    /// Direction of the rotation axis (any non-zero length; normalised), default +z.
    #[serde(default = "RotatingFrameSection::default_axis")]
    pub axis: [f64; 3],
    /// A point on the rotation axis [m], default the coordinate origin.
    #[serde(default)]
    pub origin: [f64; 3],
}

impl RotatingFrameSection {
    fn default_axis() -> [f64; 3] {
        [0.0, 0.0, 1.0]
    }

    /// |axis|, the length the axis is divided by.
    pub fn axis_length(&self) -> f64 {
        self.axis.iter().map(|a| a * a).sum::<f64>().sqrt()
    }

    pub fn validate(&self) -> Result<(), FieldError> {
        if !self.omega.is_finite() {
            return Err(FieldError::new("physics.rotating_frame.omega", self.omega, "a finite angular velocity in rad/s"));
        }
        finite_vector("physics.rotating_frame.axis", self.axis)?;
        finite_vector("physics.rotating_frame.origin", self.origin)?;
        // the same threshold as `rotor.axis`: a direction, not round-off (the axis is finite here)
        if self.axis_length() < 1e-12 {
            return Err(FieldError::new("physics.rotating_frame.axis", format!("{:?}", self.axis), "a non-zero direction vector"));
        }
        Ok(())
    }
}

/// `[time]`: the step size is either fixed (`dt`) or set from a maximum Courant number; the run
/// ends at `end_time` or after `steps` steps.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeControl {
    /// Fixed time step [s].
    pub dt: Option<f64>,
    /// Maximum Courant number (spec fluid-dem-model.md §8.9) used to set the step.
    pub max_courant: Option<f64>,
    /// Largest step with `max_courant` [s] (default unbounded); also the first step when the
    /// start state does not move.
    pub max_dt: Option<f64>,
    /// Simulated end time [s].
    pub end_time: Option<f64>,
    /// Number of steps.
    pub steps: Option<u64>,
    /// Revolutions of the `[rotor]` to run (sets `end_time` = revolutions · 2π/|ω|, so a
    /// sweep over rpm runs the same number of revolutions at every speed).
    pub revolutions: Option<f64>,
    /// Write fields every this many steps (0 = only at the end).
    #[serde(default)]
    pub write_every: u64,
}

impl TimeControl {
    pub fn validate(&self) -> Result<(), FieldError> {
        if let (Some(dt), Some(_)) = (self.dt, self.max_dt) {
            return Err(FieldError::new("time.max_dt", format!("(with time.dt = {dt})"), "max_dt only with time.max_courant"));
        }
        match (self.dt, self.max_courant) {
            (Some(dt), None) => positive("time.dt", dt, "s")?,
            (None, Some(co)) => {
                positive("time.max_courant", co, "")?;
                if let Some(max_dt) = self.max_dt {
                    positive("time.max_dt", max_dt, "s")?;
                }
            }
            (Some(dt), Some(_)) => {
                return Err(FieldError::new("time.max_courant", format!("(with time.dt = {dt})"), "either time.dt or time.max_courant, not both"))
            }
            (None, None) => return Err(FieldError::new("time", "(neither dt nor max_courant)", "`dt = <seconds>` or `max_courant = <number>`")),
        }
        if let Some(n) = self.revolutions {
            positive("time.revolutions", n, "")?;
            return match (self.end_time, self.steps) {
                (None, None) => Ok(()),
                _ => Err(FieldError::new("time.revolutions", n, "either time.revolutions, time.end_time or time.steps, not two of them")),
            };
        }
        match (self.end_time, self.steps) {
            (Some(t), None) => positive("time.end_time", t, "s"),
            (None, Some(n)) if n > 0 => Ok(()),
            (None, Some(n)) => Err(FieldError::new("time.steps", n, "a whole number ≥ 1")),
            (Some(_), Some(_)) => Err(FieldError::new("time.steps", "(with time.end_time)", "either time.end_time or time.steps, not both")),
            (None, None) => Err(FieldError::new("time", "(neither end_time nor steps)", "`end_time = <seconds>` or `steps = <count>`")),
        }
    }
}

/// `[rotor]`: rigid rotation of the cell zone named `zone` (default `rotor`) and of the walls
/// attached to it.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotorSection {
    #[serde(default = "RotorSection::default_zone")]
    pub zone: String,
    /// Angular velocity [rad/s] (give this or `rpm`).
    pub omega: Option<f64>,
    /// Revolutions per minute (give this or `omega`).
    pub rpm: Option<f64>,
    #[serde(default = "RotorSection::default_axis")]
    pub axis: [f64; 3],
    #[serde(default)]
    pub origin: [f64; 3],
}

impl RotorSection {
    fn default_zone() -> String {
        "rotor".into()
    }
    fn default_axis() -> [f64; 3] {
        [0.0, 0.0, 1.0]
    }
    /// Signed angular velocity about `axis` [rad/s].
    pub fn angular_velocity(&self) -> f64 {
        match (self.omega, self.rpm) {
            (Some(w), _) => w,
            (None, Some(rpm)) => rpm * 2.0 * std::f64::consts::PI / 60.0,
            (None, None) => 0.0,
        }
    }
    pub fn validate(&self) -> Result<(), FieldError> {
        match (self.omega, self.rpm) {
            (Some(_), Some(_)) => return Err(FieldError::new("rotor.rpm", "(with rotor.omega)", "either rotor.omega [rad/s] or rotor.rpm, not both")),
            (None, None) => return Err(FieldError::new("rotor", "(no speed)", "`omega = <rad/s>` or `rpm = <rev/min>`")),
            (Some(w), None) if !w.is_finite() => return Err(FieldError::new("rotor.omega", w, "a finite angular velocity in rad/s")),
            (None, Some(r)) if !r.is_finite() => return Err(FieldError::new("rotor.rpm", r, "a finite speed in rev/min")),
            _ => {}
        }
        finite_vector("rotor.axis", self.axis)?;
        finite_vector("rotor.origin", self.origin)?;
        let norm = self.axis.iter().map(|a| a * a).sum::<f64>().sqrt();
        if norm < 1e-12 {
            return Err(FieldError::new("rotor.axis", format!("{:?}", self.axis), "a non-zero direction vector"));
        }
        Ok(())
    }
}

/// `[output]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSection {
    /// Write ParaView files (`.vtu`, `.vtp`, `.pvd`).
    #[serde(default = "yes")]
    pub paraview: bool,
    /// Write PNG plots of the key series at the end.
    #[serde(default = "yes")]
    pub plots: bool,
    /// Write a checkpoint every this many steps (0 = only at the end).
    #[serde(default)]
    pub checkpoint_every: u64,
}

fn yes() -> bool {
    true
}

impl Default for OutputSection {
    fn default() -> Self {
        Self { paraview: true, plots: true, checkpoint_every: 0 }
    }
}

/// `[verify]`: marks a case as part of the verification ladder. `check` names the procedure in
/// `spillage verify` that compares the run with its exact answer; `params` are its settings.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VerifySection {
    pub check: String,
    #[serde(default)]
    pub params: toml::Table,
}
