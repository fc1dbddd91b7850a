//! Struct-of-arrays face geometry of the fast solver, built once and updated in place when the
//! rotor turns: links (internal faces, then sliding-interface overlaps), boundary faces with a
//! condition, and the cell → link / cell → boundary-face adjacency the gather loops walk.
//!
//! Same definitions as the reference solver's `geometry` module (module doc of
//! `spillage_reference::fluid`, step 2).

use rayon::prelude::*;
use spillage_model::fluid::conditions::Conditions;
use spillage_model::mesh::{Mesh, PatchKind, Vec3};

use crate::linear::reduce::CHUNK;

/// Rigid rotation of the rotor zone: the model's rotor zone and pose.
pub type Rotor = spillage_model::step::RotorZone;

/// The rotor's velocity field x ↦ ω â × (x − x₀), as the boundary conditions take it (`None`
/// without a rotor).
pub fn rotor_velocity(rotor: Option<&Rotor>) -> Option<impl Fn(&Vec3) -> Vec3 + '_> {
    rotor.map(|r| move |x: &Vec3| r.velocity_at(x))
}

/// Links between two cells, one entry per array per link; links `0..n_internal` are the
/// internal mesh faces (link l = face l), the rest are interface overlaps.
#[derive(Clone, Debug, Default)]
pub struct Links {
    pub n_internal: usize,
    pub owner: Vec<u32>,
    pub neighbour: Vec<u32>,
    /// Area vector S (owner → neighbour).
    pub area: Vec<Vec3>,
    /// Owner → neighbour centre distance d.
    pub delta: Vec<Vec3>,
    /// Non-orthogonal remainder T = S − (|S|²/(d·S)) d.
    pub non_orthogonal: Vec<Vec3>,
    /// Owner weight of linear interpolation.
    pub weight: Vec<f64>,
    /// |S|²/(d·S).
    pub laplacian: Vec<f64>,
    /// ∫(ω×r)·dS of the moving face.
    pub mesh_flux: Vec<f64>,
    /// Rotor and stator faces of overlap link `n_internal + k`.
    pub rotor_face: Vec<u32>,
    pub stator_face: Vec<u32>,
    /// Skewness vector k = x_f − (w x_P + (1 − w) x_N) of overlap link `n_internal + k`
    /// (`spillage_model::mesh::OverlapLinkGeometry::skew`); zero, hence not stored, on mesh faces.
    pub skew: Vec<Vec3>,
}

impl Links {
    pub fn len(&self) -> usize {
        self.owner.len()
    }

    pub fn is_empty(&self) -> bool {
        self.owner.is_empty()
    }

    /// True when every link's non-orthogonal area part (T4.26 over-relaxed split) is below
    /// 1e-12 of its area: rounding of area − δ·|A|²/(δ·A) on an orthogonal face, not geometry.
    /// The explicit non-orthogonal flux term is then below 1e-12 of the gradient flux, so a
    /// further non-orthogonal corrector assembles the same pressure equation to that relative
    /// level, starts converged and leaves the pressure as it is (measured on the lid-driven
    /// cavity: 0 iterations in every such solve); the PISO corrector skips those passes.
    pub fn all_orthogonal(&self) -> bool {
        (0..self.len()).all(|l| self.non_orthogonal[l].norm_squared() <= 1e-24 * self.area[l].norm_squared())
    }

    #[inline]
    pub fn interpolate(&self, l: usize, owner_value: f64, neighbour_value: f64) -> f64 {
        let w = self.weight[l];
        w * owner_value + (1.0 - w) * neighbour_value
    }

    fn set_geometry(&mut self, l: usize, area: Vec3, delta: Vec3, weight: f64, mesh_flux: f64) {
        let lap = area.norm_squared() / delta.dot(&area);
        self.area[l] = area;
        self.delta[l] = delta;
        self.non_orthogonal[l] = area - delta * lap;
        self.weight[l] = weight;
        self.laplacian[l] = lap;
        self.mesh_flux[l] = mesh_flux;
    }

    /// Links of the internal faces of `mesh` (all of them).
    pub fn from_internal_faces(mesh: &Mesh, rotor: Option<&Rotor>, in_rotor: &[bool]) -> Links {
        let n = mesh.n_internal_faces;
        let mut links = Links {
            n_internal: n,
            owner: mesh.face_owner[..n].iter().map(|&c| c as u32).collect(),
            neighbour: mesh.face_neighbour[..n].iter().map(|&c| c as u32).collect(),
            area: vec![Vec3::zeros(); n],
            delta: vec![Vec3::zeros(); n],
            non_orthogonal: vec![Vec3::zeros(); n],
            weight: vec![0.0; n],
            laplacian: vec![0.0; n],
            mesh_flux: vec![0.0; n],
            rotor_face: Vec::new(),
            stator_face: Vec::new(),
            skew: Vec::new(),
        };
        for f in 0..n {
            links.update_face(mesh, f, rotor, in_rotor);
        }
        links
    }

    /// Recomputes the geometry of internal face `f` from the mesh (after the rotor turned).
    pub fn update_face(&mut self, mesh: &Mesh, f: usize, rotor: Option<&Rotor>, in_rotor: &[bool]) {
        let area = mesh.face_areas[f];
        let mesh_flux = match rotor {
            Some(r) if in_rotor[mesh.face_owner[f]] => r.velocity_at(&mesh.face_centres[f]).dot(&area),
            _ => 0.0,
        };
        self.set_geometry(f, area, mesh.face_delta[f], mesh.face_weight[f], mesh_flux);
    }

    /// Drops the overlap links (their storage is kept).
    pub fn clear_overlaps(&mut self) {
        let n = self.n_internal;
        for v in [&mut self.owner, &mut self.neighbour] {
            v.truncate(n);
        }
        for v in [&mut self.area, &mut self.delta, &mut self.non_orthogonal] {
            v.truncate(n);
        }
        for v in [&mut self.weight, &mut self.laplacian, &mut self.mesh_flux] {
            v.truncate(n);
        }
        self.rotor_face.clear();
        self.stator_face.clear();
        self.skew.clear();
    }

    /// Appends an overlap link.
    #[allow(clippy::too_many_arguments)]
    pub fn push_overlap(
        &mut self,
        owner: usize,
        neighbour: usize,
        area: Vec3,
        delta: Vec3,
        weight: f64,
        skew: Vec3,
        mesh_flux: f64,
        rotor_face: usize,
        stator_face: usize,
    ) {
        let l = self.len();
        self.owner.push(owner as u32);
        self.neighbour.push(neighbour as u32);
        self.area.push(Vec3::zeros());
        self.delta.push(Vec3::zeros());
        self.non_orthogonal.push(Vec3::zeros());
        self.weight.push(0.0);
        self.laplacian.push(0.0);
        self.mesh_flux.push(0.0);
        self.rotor_face.push(rotor_face as u32);
        self.stator_face.push(stator_face as u32);
        self.skew.push(skew);
        self.set_geometry(l, area, delta, weight, mesh_flux);
    }
}

/// Boundary faces that carry a condition, in patch order (as the reference lists them).
#[derive(Clone, Debug, Default)]
pub struct Boundary {
    pub face: Vec<u32>,
    pub cell: Vec<u32>,
    pub area: Vec<Vec3>,
    pub centre: Vec<Vec3>,
    /// (x_f − x_P)·n.
    pub normal_distance: Vec<f64>,
    pub mesh_flux: Vec<f64>,
    /// Index into `Conditions::conditions`.
    pub condition: Vec<u32>,
    /// Boundary faces of cell c: `faces_of_cell[cell_start[c]..cell_start[c + 1]]`.
    pub cell_start: Vec<u32>,
    pub faces_of_cell: Vec<u32>,
    /// The neighbour across the cell from each face (`NO_CELL` if none within 25° of the inward
    /// normal) and the extrapolation ratio (x_f − x_P)·n / (x_P − x_N)·n (reference
    /// `geometry::neighbour_across`).
    pub across: Vec<u32>,
    pub across_ratio: Vec<f64>,
}

pub const NO_CELL: u32 = u32::MAX;

impl Boundary {
    pub fn len(&self) -> usize {
        self.face.len()
    }

    pub fn is_empty(&self) -> bool {
        self.face.is_empty()
    }

    pub fn build(mesh: &Mesh, conditions: &Conditions, rotor: Option<&Rotor>, in_rotor: &[bool]) -> Boundary {
        let mut b = Boundary::default();
        for (k, patch) in mesh.patches.iter().enumerate() {
            let Some(condition) = conditions.patch_condition[k] else { continue };
            for f in patch.faces() {
                b.face.push(f as u32);
                b.cell.push(mesh.face_owner[f] as u32);
                b.condition.push(condition as u32);
            }
        }
        let n = b.face.len();
        b.area = vec![Vec3::zeros(); n];
        b.centre = vec![Vec3::zeros(); n];
        b.normal_distance = vec![0.0; n];
        b.mesh_flux = vec![0.0; n];
        b.update(mesh, rotor, in_rotor);
        let n_cells = mesh.n_cells();
        b.cell_start = vec![0; n_cells + 1];
        for &c in &b.cell {
            b.cell_start[c as usize + 1] += 1;
        }
        for c in 0..n_cells {
            b.cell_start[c + 1] += b.cell_start[c];
        }
        b.faces_of_cell = vec![0; n];
        let mut fill = b.cell_start.clone();
        for (i, &c) in b.cell.iter().enumerate() {
            b.faces_of_cell[fill[c as usize] as usize] = i as u32;
            fill[c as usize] += 1;
        }
        b
    }

    /// Recomputes the geometry from the mesh in its current position.
    pub fn update(&mut self, mesh: &Mesh, rotor: Option<&Rotor>, in_rotor: &[bool]) {
        let Boundary { face, cell, area, centre, normal_distance, mesh_flux, .. } = self;
        area.par_iter_mut()
            .with_min_len(CHUNK)
            .zip(centre.par_iter_mut())
            .zip(normal_distance.par_iter_mut().zip(mesh_flux.par_iter_mut()))
            .enumerate()
            .for_each(|(i, ((a, x), (dn, mf)))| {
                let f = face[i] as usize;
                let c = cell[i] as usize;
                *a = mesh.face_areas[f];
                *x = mesh.face_centres[f];
                let normal = *a / a.norm();
                *dn = (*x - mesh.cell_centres[c]).dot(&normal);
                *mf = match rotor {
                    Some(r) if in_rotor[c] => r.velocity_at(x).dot(a),
                    _ => 0.0,
                };
            });
    }

    /// The neighbour across each face's cell: the one whose centre lies furthest along the
    /// inward normal within 25° of it (cos 25° ≈ 0.906), first in link order on ties.
    pub fn update_across(&mut self, links: &Links, adj: &Adjacency) {
        let n = self.len();
        self.across.resize(n, NO_CELL);
        self.across_ratio.resize(n, 0.0);
        for b in 0..n {
            let c = self.cell[b] as usize;
            let normal = self.area[b] / self.area[b].norm();
            let mut best: Option<(u32, f64, f64)> = None;
            for k in adj.row_start[c] as usize..adj.row_start[c + 1] as usize {
                let (l, owned) = ((adj.entry[k] / 2) as usize, adj.entry[k] % 2 == 1);
                let to_other = if owned { links.delta[l] } else { -links.delta[l] };
                let depth = -to_other.dot(&normal);
                let alignment = depth / to_other.norm();
                if alignment > 0.906 && best.is_none_or(|(_, a, _)| alignment > a) {
                    best = Some((adj.col[k], alignment, depth));
                }
            }
            (self.across[b], self.across_ratio[b]) = match best {
                Some((other, _, depth)) => (other, self.normal_distance[b] / depth),
                None => (NO_CELL, 0.0),
            };
        }
    }
}

/// Cell → link adjacency in compressed rows, links of a cell in ascending link order (the
/// order the reference accumulates in). Entry = 2·link + (1 if the cell owns the link).
#[derive(Clone, Debug, Default)]
pub struct Adjacency {
    pub row_start: Vec<u32>,
    pub entry: Vec<u32>,
    /// The other cell of each entry (the column of the matrix entry).
    pub col: Vec<u32>,
    fill: Vec<u32>,
}

impl Adjacency {
    /// Rebuilds the adjacency of `links` (counting sort: O(cells + links), no allocation once
    /// the buffers are large enough).
    pub fn rebuild(&mut self, n_cells: usize, links: &Links) {
        self.row_start.clear();
        self.row_start.resize(n_cells + 1, 0);
        for l in 0..links.len() {
            self.row_start[links.owner[l] as usize + 1] += 1;
            self.row_start[links.neighbour[l] as usize + 1] += 1;
        }
        for c in 0..n_cells {
            self.row_start[c + 1] += self.row_start[c];
        }
        let nnz = self.row_start[n_cells] as usize;
        self.entry.resize(nnz, 0);
        self.col.resize(nnz, 0);
        self.fill.clear();
        self.fill.extend_from_slice(&self.row_start[..n_cells]);
        for l in 0..links.len() {
            let (o, n) = (links.owner[l] as usize, links.neighbour[l] as usize);
            let k = self.fill[o] as usize;
            self.entry[k] = 2 * l as u32 + 1;
            self.col[k] = n as u32;
            self.fill[o] += 1;
            let k = self.fill[n] as usize;
            self.entry[k] = 2 * l as u32;
            self.col[k] = o as u32;
            self.fill[n] += 1;
        }
    }
}

/// Velocity components solved (false along the normal of empty patches: 2-D meshes).
pub fn solved_components(mesh: &Mesh) -> [bool; 3] {
    let mut solved = [true; 3];
    for patch in &mesh.patches {
        if patch.kind == PatchKind::Empty {
            for f in patch.faces() {
                let n = mesh.face_areas[f].normalize();
                for (d, s) in solved.iter_mut().enumerate() {
                    if n[d].abs() > 0.5 {
                        *s = false;
                    }
                }
            }
        }
    }
    solved
}
