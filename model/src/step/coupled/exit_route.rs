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
/// Likewise a particle less than a diameter beyond a closed patch (a wall or a symmetry plane,
/// `closed[patch]`) has not left: it sits in the crater of a receding DEM wall (the fluid mesh
/// does not follow the wear) or in the gap between a DEM wall and the mesh; it leaves only
/// through open patches (inlets, outlets) or farther out.
pub(super) fn exit_route(
    domain: Option<&crate::particles::settings::BoxRegion>,
    mesh: Option<&Mesh>,
    closed: &[bool],
    position: &Vec3,
    diameter: f64,
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
    if closed.get(index).copied().unwrap_or(false) && (position - mesh.face_centres[nearest]).dot(&normal).abs() < diameter {
        return None;
    }
    Some(ExitRoute::Patch(patch.name.clone()))
}
