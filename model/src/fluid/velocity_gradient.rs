//! The Gauss cell gradient of the velocity and the explicit part of the viscous wall flux, as the
//! reference momentum assembly forms them (fluid-dem-model.md §8.2), for the budgets that
//! re-derive wall forces from a solution (the closed box's momentum, the rotor's torque).

use crate::fluid::conditions::{Condition, Conditions};
use crate::mesh::{Mesh, PatchKind, Vec3};
use crate::step::RotorPose;

/// g[c][i] = ∂u/∂x_i by Gauss with linear face values on internal faces and
/// `boundary_value(f, owner)` on boundary faces (`None`: the face adds nothing, as a wall at rest
/// with u_b = 0 does); empty faces carry none.
pub fn gauss_velocity_gradient(mesh: &Mesh, u: &[[f64; 3]], boundary_value: impl Fn(usize, usize) -> Option<Vec3>) -> Vec<[Vec3; 3]> {
    let v = |c: usize| Vec3::from(u[c]);
    let mut grad = vec![[Vec3::zeros(); 3]; u.len()];
    for f in 0..mesh.n_internal_faces {
        let (o, nb, w) = (mesh.face_owner[f], mesh.face_neighbour[f], mesh.face_weight[f]);
        let face = v(o) * w + v(nb) * (1.0 - w);
        let s = mesh.face_areas[f];
        for i in 0..3 {
            grad[o][i] += face * s[i];
            grad[nb][i] -= face * s[i];
        }
    }
    for patch in mesh.patches.iter().filter(|p| p.kind != PatchKind::Empty) {
        for f in patch.faces() {
            let c = mesh.face_owner[f];
            if let Some(face) = boundary_value(f, c) {
                let s = mesh.face_areas[f];
                for i in 0..3 {
                    grad[c][i] += face * s[i];
                }
            }
        }
    }
    for (c, g) in grad.iter_mut().enumerate() {
        for row in g.iter_mut() {
            *row /= mesh.cell_volumes[c];
        }
    }
    grad
}

/// The velocity of every boundary face (index f − n_internal_faces) as the momentum assembly
/// takes it: fixed where the condition fixes it (a rotating wall adds the rotor's rigid velocity
/// at `pose`), the cell's tangential part on a symmetry plane, the cell's own elsewhere (outlets,
/// sliding interfaces, empty faces).
pub fn boundary_velocities(mesh: &Mesh, conditions: &Conditions, u: &[[f64; 3]], pose: Option<&RotorPose>) -> Vec<Vec3> {
    let n_internal = mesh.n_internal_faces;
    let rotor_velocity = pose.map(|p| move |x: &Vec3| p.velocity_at(x));
    let mut boundary_u = vec![Vec3::zeros(); mesh.n_faces() - n_internal];
    for (k, patch) in mesh.patches.iter().enumerate() {
        for f in patch.faces() {
            let own = Vec3::from(u[mesh.face_owner[f]]);
            boundary_u[f - n_internal] = match conditions.patch_condition[k].map(|i| (i, &conditions.conditions[i])) {
                Some((i, Condition::FixedVelocity { .. })) => conditions.fixed_velocity(i, &mesh.face_centres[f], rotor_velocity).unwrap_or(own),
                Some((_, Condition::Symmetry)) => {
                    let n = mesh.face_areas[f].normalize();
                    own - n * own.dot(&n)
                }
                _ => own,
            };
        }
    }
    boundary_u
}

/// [(∇u)ᵀ − ⅔ tr(∇u) I]·S for g[i][j] = ∂u_j/∂x_i (the reference assembly's explicit part).
pub fn explicit_stress(g: &[Vec3; 3], s: &Vec3) -> Vec3 {
    let trace = g[0][0] + g[1][1] + g[2][2];
    Vec3::new(g[0].dot(s), g[1].dot(s), g[2].dot(s)) - s * (2.0 / 3.0 * trace)
}
