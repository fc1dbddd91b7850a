//! What a checkpoint's state means: a fingerprint of the parts of the case that define it, so a
//! checkpoint is refused by a case that would read its numbers as something else (issue 14:
//! a DEM checkpoint run as a fluid case, another case's walls or materials).
//!
//! Each part is hashed from the parsed case section (its `Debug` form, so the values count, not
//! their spelling in the file) and summarised in words for the refusal message. Parts that a
//! restart may legitimately change (the end time, output, boundary values, numerics, fluid
//! properties) are not in it.

use serde::{Deserialize, Serialize};

use crate::case::{Case, MeshSection};

/// One part of the case that defines the state's meaning.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Part {
    /// What the part is, as the message names it (`"the mesh"`).
    pub what: String,
    /// In words, for the message (`"a rotor_stator mesh of 1200 cells"`).
    pub summary: String,
    /// FNV-1a of the section's parsed values.
    pub hash: u64,
}

/// The parts of a case that define the meaning of its state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fingerprint {
    pub parts: Vec<Part>,
}

fn part(what: &str, summary: String, values: &str) -> Part {
    Part { what: what.into(), summary, hash: super::fnv1a(values.as_bytes()) }
}

fn phase(what: &str, present: bool) -> Part {
    part(what, if present { format!("a {what}") } else { format!("no {what}") }, if present { "1" } else { "0" })
}

/// The mesh part's hashed values: the mesh section and the cutter head. The head's blade lean
/// is left out at its default (`"backward"`), so that checkpoints written before it existed
/// still match the heads they were written by.
pub(super) fn mesh_values(case: &Case) -> String {
    let head = format!("{:?}", case.cutter_head);
    format!("{:?}{}", case.mesh, head.replace("blade_sweep: Backward, ", ""))
}

impl Fingerprint {
    pub fn of_case(case: &Case) -> Fingerprint {
        let mut parts =
            vec![phase("fluid phase", case.fluid.is_some()), phase("particle phase", case.particles.is_some()), phase("wear phase", case.wear.is_some())];
        let mesh_summary = match (&case.mesh, &case.cutter_head) {
            (Some(mesh), _) => {
                let generator = match mesh {
                    MeshSection::Box { .. } => "box",
                    MeshSection::Annulus { .. } => "annulus",
                    MeshSection::RotorStator { .. } => "rotor_stator",
                };
                format!("a {generator} mesh of {} cells", mesh.cell_count())
            }
            (None, Some(head)) => format!("a cutter-head mesh ({} blades)", head.blades),
            (None, None) => "no mesh".into(),
        };
        parts.push(part("mesh", mesh_summary, &mesh_values(case)));
        let following = case.wear.as_ref().and_then(|w| w.fluid_mesh.as_ref());
        let motion = following.map_or("a mesh standing still".to_string(), |f| format!("a mesh following wall {:?} on patch {:?}", f.wall, f.patch));
        parts.push(part("mesh motion", motion, &format!("{following:?}")));
        if let Some(p) = &case.particles {
            let names: Vec<&str> = p.materials.iter().map(|m| m.name.as_str()).collect();
            parts.push(part("particle materials", format!("materials {names:?}"), &format!("{:?}", p.materials)));
            // the modifier weighs the checkpoint's α_c time levels; left out at 1 so that older
            // checkpoints, written before it existed, still match
            let each = if p.modifier == 1.0 { String::new() } else { format!(", each for {} real ones", p.modifier) };
            parts.push(part(
                "particle set",
                format!("{} particle groups and {} feeds{each}", p.groups.len(), p.feed.len()),
                &format!("{:?}{:?}{each}", p.groups, p.feed),
            ));
        }
        let turbulence = if case.turbulence.is_k_epsilon() { "the realizable k–ε model" } else { "laminar flow" };
        parts.push(part("turbulence model", turbulence.to_string(), &format!("{:?}", case.turbulence.model)));
        let walls: Vec<&str> = case.walls.iter().map(|w| w.name.as_str()).collect();
        parts.push(part("walls", format!("walls {walls:?}"), &format!("{:?}", case.walls)));
        let frame = match &case.physics.rotating_frame {
            Some(f) => format!("a frame rotating at {} rad/s", f.omega),
            None => "an inertial frame".into(),
        };
        parts.push(part("physics", format!("gravity {:?} in {frame}", case.physics.gravity), &format!("{:?}", case.physics)));
        Fingerprint { parts }
    }

    /// `Ok` when `self` (from a checkpoint) means what `case` (of the run) means; otherwise what
    /// differs, in words.
    pub fn compare(&self, case: &Fingerprint) -> Result<(), String> {
        let mut differences = Vec::new();
        for now in &case.parts {
            match self.parts.iter().find(|p| p.what == now.what) {
                Some(then) if then.hash == now.hash => {}
                Some(then) if now.what.ends_with(" phase") => differences.push(if then.summary.starts_with("no ") {
                    format!("the checkpoint has no {}, but the case has one", now.what)
                } else {
                    format!("the checkpoint has a {} but the case has none", now.what)
                }),
                Some(then) if then.summary != now.summary => {
                    differences.push(format!("the {}: the checkpoint has {}, the case {}", now.what, then.summary, now.summary))
                }
                Some(then) => differences.push(format!("the {}: {} in both, but with other values", now.what, then.summary)),
                None => differences.push(format!("the {}: not recorded in the checkpoint", now.what)),
            }
        }
        if differences.is_empty() {
            Ok(())
        } else {
            Err(differences.join("; "))
        }
    }
}
