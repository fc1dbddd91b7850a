//! Where a particle has gone when it is no longer inside: the case's domain box or a patch of
//! the fluid mesh ([`exit_route`]).

use crate::mesh::{Mesh, Vec3};
use crate::particles::bookkeeping::ExitRoute;

/// Where a particle at `position` has left to, if anywhere: outside `[particles] domain`, or
/// outside the fluid mesh (through the patch of the nearest boundary face). A point outside
/// every cell whose nearest boundary face is on a sliding interface is in the sliver between
/// the rotor's and the stator's polygonal rings (up to r(1 − cos π/n_θ) wide), inside the
/// domain: not an exit.
///
/// Likewise a particle less than `beyond_closed` beyond a closed patch (a wall or a symmetry
/// plane, `closed[patch]`) has not left: it sits in the crater of a receding DEM wall (the fluid
/// mesh does not follow the wear) or in the gap between a DEM wall and the mesh. The caller
/// gives its diameter plus the deepest recession of the eroding walls. It leaves only through
/// open patches (inlets, outlets) or farther out.
pub(super) fn exit_route(
    domain: Option<&crate::particles::settings::BoxRegion>,
    mesh: Option<&Mesh>,
    closed: &[bool],
    position: &Vec3,
    beyond_closed: f64,
) -> Option<ExitRoute> {
    if let Some(d) = domain {
        if !d.contains([position.x, position.y, position.z]) {
            return Some(ExitRoute::Domain);
        }
    }
    let mesh = mesh?;
    if mesh.locate(position).is_some() {
        return None;
    }
    let nearest = (mesh.n_internal_faces..mesh.n_faces())
        .min_by(|&a, &b| (mesh.face_centres[a] - position).norm_squared().total_cmp(&(mesh.face_centres[b] - position).norm_squared()))?;
    let (index, patch) = mesh.patches.iter().enumerate().find(|(_, p)| p.faces().contains(&nearest))?;
    if matches!(patch.kind, crate::mesh::PatchKind::Interface { .. }) {
        return None;
    }
    let normal = mesh.face_areas[nearest].normalize();
    if closed.get(index).copied().unwrap_or(false) && (position - mesh.face_centres[nearest]).dot(&normal).abs() < beyond_closed {
        return None;
    }
    Some(ExitRoute::Patch(patch.name.clone()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::cartesian::BoxSpec;

    /// A 1 mm grain 3 mm below a closed floor (the Coriolis coupon's crater, 3.2 mm deep
    /// two-way coupled) is inside while the crater is counted, and leaves through the floor
    /// only without it (as 420 of 1 933 garnet grains did before the crater was counted);
    /// beyond an open patch it leaves either way.
    #[test]
    fn a_grain_in_a_crater_below_a_closed_patch_has_not_left() {
        let mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(0.01, 0.01, 0.01), [4, 4, 4])).unwrap();
        // patches in the order x_min, x_max, y_min, y_max, z_min, z_max: all closed but x_max
        let closed = [true, false, true, true, true, true];
        let in_crater = Vec3::new(0.005, -0.003, 0.005);
        assert_eq!(exit_route(None, Some(&mesh), &closed, &in_crater, 0.001 + 0.0032), None);
        assert_eq!(exit_route(None, Some(&mesh), &closed, &in_crater, 0.001), Some(ExitRoute::Patch("y_min".into())));
        let past_outlet = Vec3::new(0.012, 0.005, 0.005);
        assert_eq!(exit_route(None, Some(&mesh), &closed, &past_outlet, 0.001 + 0.0032), Some(ExitRoute::Patch("x_max".into())));
        assert_eq!(exit_route(None, Some(&mesh), &closed, &Vec3::new(0.005, 0.005, 0.005), 0.001), None);
    }
}
