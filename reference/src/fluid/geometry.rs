//! The face connections the discretisation loops over, rebuilt at every step (the rotor moves).
//!
//! A *link* joins two cells: every internal mesh face (periodic ones included) and every
//! rotor/stator overlap of a sliding interface. A *boundary face* is a mesh boundary face with a
//! condition from the case; empty faces (2-D) and interface faces carry no flux of their own and
//! are not listed.

use spillage_model::mesh::{Mesh, PatchKind, Vec3};

/// Where a link comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LinkOrigin {
    /// Internal mesh face.
    Face(usize),
    /// Overlap of a rotor-side and a stator-side interface face (owner = rotor cell).
    Interface { rotor_face: usize, stator_face: usize },
}

/// A face between two cells, with the geometry the schemes need.
#[derive(Clone, Debug)]
pub struct Link {
    pub owner: usize,
    pub neighbour: usize,
    /// Area vector S_f, pointing from owner to neighbour.
    pub area: Vec3,
    pub centre: Vec3,
    /// Owner centre → neighbour centre d (periodic shift included).
    pub delta: Vec3,
    /// Linear-interpolation weight of the owner value.
    pub weight: f64,
    /// Volume swept per second by the moving face, ∫(ω×r)·dS (spec §4.1).
    pub mesh_flux: f64,
    pub origin: LinkOrigin,
    /// Skewness vector k = x_f − (w x_P + (1 − w) x_N): linear interpolation gives the value
    /// at x_f − k. Zero on mesh faces (the mesh's own interpolation is used unchanged there);
    /// on overlap links it is O(h) along the interface (`spillage_model::mesh::InterfaceFrame::
    /// overlap_link`), and the predicted flux adds (k·∇)(A⁻¹H) (module `pressure`, issue 12).
    pub skew: Vec3,
}

impl Link {
    /// Implicit Laplacian coefficient |S|²/(d·S) ("over-relaxed" split S = E + T with E ∥ d,
    /// |E| = |S|²/(d·S)·|d|), so that (∇φ)_f·S ≈ coef·(φ_N − φ_P) + (∇φ)_f·T (Jasak 1996).
    pub fn laplacian_coefficient(&self) -> f64 {
        self.area.norm_squared() / self.delta.dot(&self.area)
    }

    /// Non-orthogonal remainder T = S − coef·d.
    pub fn non_orthogonal_part(&self) -> Vec3 {
        self.area - self.delta * self.laplacian_coefficient()
    }

    /// Linear interpolation to the face.
    pub fn interpolate(&self, owner_value: f64, neighbour_value: f64) -> f64 {
        self.weight * owner_value + (1.0 - self.weight) * neighbour_value
    }

    pub fn interpolate_vec(&self, owner_value: Vec3, neighbour_value: Vec3) -> Vec3 {
        owner_value * self.weight + neighbour_value * (1.0 - self.weight)
    }
}

/// A boundary face that carries a condition.
#[derive(Clone, Debug)]
pub struct BoundaryFace {
    pub face: usize,
    /// Index into per-boundary-face arrays: face − n_internal_faces.
    pub index: usize,
    pub cell: usize,
    /// Outward area vector.
    pub area: Vec3,
    pub centre: Vec3,
    /// Normal distance from the cell centre to the face, (x_f − x_P)·n.
    pub normal_distance: f64,
    pub mesh_flux: f64,
    /// Index of the case condition (into `Conditions::patches`).
    pub patch: usize,
    /// The interior neighbour across the cell from this face, for second-order extrapolation
    /// to the face: (neighbour cell, (x_f − x_P)·n / (x_P − x_N)·n). `None` where no neighbour
    /// centre lies within 25° of the inward normal.
    pub across: Option<(usize, f64)>,
}

/// Rigid rotation of the rotor zone, if any: the model's rotor zone and pose.
pub type RotorMotion = spillage_model::step::RotorZone;

/// All links and boundary faces of the current mesh position.
#[derive(Clone, Debug)]
pub struct Geometry {
    pub links: Vec<Link>,
    pub boundary: Vec<BoundaryFace>,
    /// Links touching each cell.
    pub cell_links: Vec<Vec<usize>>,
    /// Boundary faces (indices into `boundary`) of each cell.
    pub cell_boundary: Vec<Vec<usize>>,
    /// Velocity components solved (false along the normal of empty patches: 2-D meshes).
    pub solved_components: [bool; 3],
}

impl Geometry {
    /// Builds the links of the mesh in its current position. `patch_condition[k]` is the index
    /// of the case condition of mesh patch k (`None` for empty and interface patches).
    /// `deforming` is each face's mesh flux of a deforming mesh (swept volume per second,
    /// spillage_model::mesh::deform), or empty.
    pub fn build(mesh: &Mesh, patch_condition: &[Option<usize>], rotor: Option<&RotorMotion>, deforming: &[f64], interface_links: Vec<Link>) -> Geometry {
        // (added only on a deforming mesh, so that a still one keeps its fluxes' bits, −0 included)
        let with_deforming = |f: usize, flux: f64| if deforming.is_empty() { flux } else { flux + deforming[f] };
        let n_cells = mesh.cell_volumes.len();
        let in_rotor = cell_in_rotor(mesh, rotor);
        let moving_velocity = |cell: usize, x: &Vec3| -> Vec3 {
            match rotor {
                Some(r) if in_rotor[cell] => r.velocity_at(x),
                _ => Vec3::zeros(),
            }
        };
        let mut links = Vec::with_capacity(mesh.n_internal_faces + interface_links.len());
        for f in 0..mesh.n_internal_faces {
            let owner = mesh.face_owner[f];
            let centre = mesh.face_centres[f];
            let area = mesh.face_areas[f];
            links.push(Link {
                owner,
                neighbour: mesh.face_neighbour[f],
                area,
                centre,
                delta: mesh.face_delta[f],
                weight: mesh.face_weight[f],
                mesh_flux: with_deforming(f, moving_velocity(owner, &centre).dot(&area)),
                origin: LinkOrigin::Face(f),
                skew: Vec3::zeros(),
            });
        }
        links.extend(interface_links);

        let mut boundary = Vec::new();
        let mut solved_components = [true; 3];
        for (k, patch) in mesh.patches.iter().enumerate() {
            if patch.kind == PatchKind::Empty {
                for f in patch.faces() {
                    let n = mesh.face_areas[f].normalize();
                    for (d, solved) in solved_components.iter_mut().enumerate() {
                        if n[d].abs() > 0.5 {
                            *solved = false;
                        }
                    }
                }
            }
            let Some(condition) = patch_condition[k] else { continue };
            for f in patch.faces() {
                let cell = mesh.face_owner[f];
                let area = mesh.face_areas[f];
                let centre = mesh.face_centres[f];
                let normal = area / area.norm();
                boundary.push(BoundaryFace {
                    face: f,
                    index: f - mesh.n_internal_faces,
                    cell,
                    area,
                    centre,
                    normal_distance: (centre - mesh.cell_centres[cell]).dot(&normal),
                    mesh_flux: with_deforming(f, moving_velocity(cell, &centre).dot(&area)),
                    patch: condition,
                    across: None,
                });
            }
        }

        let mut cell_links = vec![Vec::new(); n_cells];
        for (l, link) in links.iter().enumerate() {
            cell_links[link.owner].push(l);
            cell_links[link.neighbour].push(l);
        }
        let mut cell_boundary = vec![Vec::new(); n_cells];
        for (b, face) in boundary.iter().enumerate() {
            cell_boundary[face.cell].push(b);
        }
        for face in &mut boundary {
            face.across = neighbour_across(face, &links, &cell_links[face.cell]);
        }
        Geometry { links, boundary, cell_links, cell_boundary, solved_components }
    }

    pub fn n_cells(&self) -> usize {
        self.cell_links.len()
    }
}

/// The neighbour of `face.cell` whose centre lies furthest along the inward normal, if within
/// 25° of it (cos 25° ≈ 0.906), and the extrapolation ratio (x_f − x_P)·n / (x_P − x_N)·n.
fn neighbour_across(face: &BoundaryFace, links: &[Link], cell_links: &[usize]) -> Option<(usize, f64)> {
    let normal = face.area / face.area.norm();
    let mut best: Option<(usize, f64, f64)> = None;
    for &l in cell_links {
        let link = &links[l];
        let (other, to_other) = if link.owner == face.cell { (link.neighbour, link.delta) } else { (link.owner, -link.delta) };
        let depth = -to_other.dot(&normal);
        let alignment = depth / to_other.norm();
        if alignment > 0.906 && best.is_none_or(|(_, a, _)| alignment > a) {
            best = Some((other, alignment, depth));
        }
    }
    best.map(|(other, _, depth)| (other, face.normal_distance / depth))
}

/// Marks the cells of the rotating zone.
pub fn cell_in_rotor(mesh: &Mesh, rotor: Option<&RotorMotion>) -> Vec<bool> {
    let mut in_rotor = vec![false; mesh.cell_volumes.len()];
    if let Some(r) = rotor {
        for &c in &mesh.zones[r.zone].cells {
            in_rotor[c] = true;
        }
    }
    in_rotor
}

#[cfg(test)]
mod tests {
    use super::*;
    use spillage_model::mesh::BoxSpec;

    /// On a graded box every boundary face finds the cell behind its own cell along the normal,
    /// and the ratio is (half the wall cell) / (distance between the two centres).
    #[test]
    fn the_neighbour_across_a_wall_face_is_the_next_cell_inwards() {
        let spec = BoxSpec { grading: [2.0, 1.0, 1.0], ..BoxSpec::uniform(Vec3::zeros(), Vec3::new(1.0, 1.0, 1.0), [4, 3, 2]) };
        let mesh = Mesh::cartesian_box(&spec).unwrap();
        let conditions: Vec<Option<usize>> = mesh.patches.iter().map(|_| Some(0)).collect();
        let geo = Geometry::build(&mesh, &conditions, None, &[], Vec::new());
        assert!(!geo.boundary.is_empty());
        for face in &geo.boundary {
            let (across, ratio) = face.across.expect("every cell of a box with ≥ 2 cells per direction has one");
            let normal = face.area / face.area.norm();
            let step = mesh.cell_centres[face.cell] - mesh.cell_centres[across];
            // the neighbour lies straight along the inward normal (no sideways offset); 1e-12:
            // round-off of centroids of order 1
            assert!((step - normal * step.dot(&normal)).norm() < 1e-12, "face {}: cell {across} not straight behind", face.face);
            let expected = face.normal_distance / step.dot(&normal);
            // the same quotient computed the same way up to summation order: round-off
            assert!((ratio - expected).abs() < 1e-14 && ratio > 0.0 && ratio < 1.0, "face {}: ratio {ratio}", face.face);
        }
    }
}
