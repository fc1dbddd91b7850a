//! Builds the mesh a case's `[mesh]` section describes.

use crate::case::MeshSection;

use super::{AnnulusSpec, BoxSpec, Mesh, MeshError, PatchKind, RotorStatorSpec, Vec3};

/// The mesh of a case: its `[mesh]` generator, or the mesh its `[cutter_head]` makes; `None`
/// without either.
pub fn for_case(case: &crate::case::Case) -> Option<Result<Mesh, MeshError>> {
    match (&case.mesh, &case.cutter_head) {
        (Some(section), _) => Some(build(section)),
        (None, Some(head)) => Some(crate::cutter_head::fluid_mesh::build(head)),
        (None, None) => None,
    }
}

/// Runs the generator named in the case and marks the front and back of 2-D meshes `Empty`.
pub fn build(section: &MeshSection) -> Result<Mesh, MeshError> {
    let (mut mesh, two_d) = match section {
        MeshSection::Box { min, max, cells, grading, periodic, two_d, solids } => {
            let spec = BoxSpec {
                min: Vec3::from(*min),
                max: Vec3::from(*max),
                cells: *cells,
                grading: *grading,
                periodic: ["x", "y", "z"].map(|axis| periodic.iter().any(|p| p == axis)),
                solids: solids.iter().map(|b| (Vec3::from(b.min), Vec3::from(b.max))).collect(),
            };
            (Mesh::cartesian_box(&spec)?, *two_d)
        }
        MeshSection::Annulus { r_inner, r_outer, z_min, z_max, n_r, n_theta, n_z, radial_grading, two_d } => {
            let spec = AnnulusSpec {
                r_inner: *r_inner,
                r_outer: *r_outer,
                z_min: *z_min,
                z_max: *z_max,
                n_r: *n_r,
                n_theta: *n_theta,
                n_z: *n_z,
                radial_grading: *radial_grading,
            };
            (Mesh::annulus(&spec)?, *two_d)
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
            let spec = RotorStatorSpec {
                r_inner: *r_inner,
                r_interface: *r_interface,
                r_outer: *r_outer,
                z_min: *z_min,
                z_max: *z_max,
                n_r_rotor: *n_r_rotor,
                n_r_stator: *n_r_stator,
                n_theta_rotor: *n_theta_rotor,
                n_theta_stator: *n_theta_stator,
                n_z: *n_z,
                radial_grading_rotor: *radial_grading,
                radial_grading_stator: *radial_grading,
            };
            (Mesh::rotor_stator(&spec)?, *two_d)
        }
    };
    if two_d {
        mesh.set_patch_kind("z_min", PatchKind::Empty)?;
        mesh.set_patch_kind("z_max", PatchKind::Empty)?;
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_patch_needing_a_condition_exists_and_two_d_faces_are_empty() {
        let sections = [
            r#"generator = "box"
               min = [0.0, 0.0, 0.0]
               max = [1.0, 2.0, 0.1]
               cells = [4, 5, 1]
               periodic = ["x"]
               two_d = true"#,
            r#"generator = "annulus"
               r_inner = 1.0
               r_outer = 2.0
               z_min = 0.0
               z_max = 1.0
               n_r = 3
               n_theta = 12
               n_z = 2"#,
            r#"generator = "rotor_stator"
               r_inner = 1.0
               r_interface = 1.5
               r_outer = 2.0
               z_min = 0.0
               z_max = 0.1
               n_r_rotor = 2
               n_r_stator = 3
               n_theta_rotor = 16
               n_theta_stator = 20
               two_d = true"#,
        ];
        for text in sections {
            let section: MeshSection = toml::from_str(text).unwrap();
            section.validate().unwrap();
            let mesh = build(&section).unwrap();
            assert_eq!(mesh.n_cells(), section.cell_count());
            for name in section.boundary_patches() {
                let patch = mesh.patch(&name).unwrap();
                assert!(!matches!(patch.kind, PatchKind::Empty | PatchKind::Interface { .. }), "{name}");
            }
            for patch in &mesh.patches {
                let needs_condition = !matches!(patch.kind, PatchKind::Empty | PatchKind::Interface { .. });
                assert_eq!(needs_condition, section.boundary_patches().contains(&patch.name), "{}", patch.name);
            }
        }
    }
}
