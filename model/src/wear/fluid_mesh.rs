//! A fluid mesh that follows a receding wall (`[wear.fluid_mesh]`; wear-model.md §7.4: the
//! boundary moves with the wear velocity and the mesh moves with it, the thesis' ALE).
//!
//! [R, our construction] The thesis moves its unstructured mesh with the wear velocity and does
//! not say how the interior follows; the spec suggests a Laplacian smoothing of the interior grid
//! velocity (§7.4 [R]). Our meshes are blocks, and a linear blend along the patch's normal does
//! what that smoothing does for a plane wall, with no solve, keeping every point on its grid
//! line. The boundary part is the spec's: the patch's nodes move along the fluid's outward
//! normal, into the wall material, by the wall's recession (its rim pinned, as the wear's).
//! The fluid patch lies in the plane of an eroding plane wall. Each step the wall's
//! worn surface is read as a height field over that plane: a point of the patch moves along the
//! patch's outward normal n onto the worn surface, h(q) = the surface's height above the plane at
//! the point's position q in the plane (barycentric on the worn triangle over q; zero beyond
//! the wall's outline, where rim nodes are pinned anyway). A point inside the water moves by
//! the same h(q) times a share falling linearly from 1 on the patch to 0 at `depth` from it,
//! so the cells next to the wall stretch into the crater; the points keep their order along the
//! normal (the stretch is 1 + h/depth), so no cell folds.
//! The points move along n only: the mesh keeps its topology, and the solver's swept volumes
//! ([`crate::mesh::deform`]) keep its continuity exact.
//!
//! The displacement is a function of the wall state alone, so a restarted run recomputes it
//! bit for bit; the fluid state stores the mesh's displacement at tⁿ, from which each step moves.

use crate::case::Case;
use crate::mesh::{Mesh, Vec3};
use crate::walls::state::{WallMotion, WallState};

/// Relative tolerance of "in the plane": the wall's vertices and the patch's faces must lie in
/// one plane to this fraction of the patch's size (round-off of the generators' coordinates).
const PLANE_TOLERANCE: f64 = 1e-9;

/// The patch and wall a fluid mesh follows, and each mesh point's place over the wall.
#[derive(Clone, Debug)]
pub struct WallFollower {
    /// The eroding wall's name (looked up in the wall state each step).
    pub wall: String,
    /// Outward unit normal of the fluid at the patch (into the wall).
    pub normal: Vec3,
    /// The patch's plane, x·n = offset.
    pub offset: f64,
    tangents: [Vec3; 2],
    /// Per mesh point (from its reference position): its coordinates in the plane and the share
    /// of the recession it takes.
    plane_position: Vec<[f64; 2]>,
    share: Vec<f64>,
}

impl WallFollower {
    /// The follower of `case`'s `[wear.fluid_mesh]`, `None` without one, over `walls` (the
    /// case's as built when `None`). Errors name the key, the patch or wall and what is allowed.
    pub fn from_case(case: &Case, mesh: &Mesh, walls: Option<&WallState>) -> Result<Option<Self>, String> {
        let Some(section) = case.wear.as_ref().and_then(|w| w.fluid_mesh.as_ref()) else { return Ok(None) };
        let patch = mesh.patch(&section.patch).map_err(|e| format!("[wear.fluid_mesh] patch = {:?}: {e}", section.patch))?;
        if patch.len == 0 {
            return Err(format!("[wear.fluid_mesh] patch = {:?}: the patch has no faces", section.patch));
        }
        let faces = patch.faces();
        let total: Vec3 = faces.clone().map(|f| mesh.face_areas[f]).sum();
        let normal = total.normalize();
        let size = total.norm().sqrt();
        let offset = mesh.face_centres[faces.start].dot(&normal);
        for f in faces.clone() {
            let off_plane = (mesh.face_centres[f].dot(&normal) - offset).abs();
            let tilt = (mesh.face_areas[f].normalize() - normal).norm();
            if off_plane > PLANE_TOLERANCE * size || tilt > PLANE_TOLERANCE {
                return Err(format!(
                    "[wear.fluid_mesh] patch = {:?}: the patch is not planar (face {f}); only a plane patch can follow a plane wall",
                    section.patch
                ));
            }
        }
        // the state's walls (worn, on a restart), or the case's as built (the particle phase
        // may not have put them in the state yet)
        let built;
        let walls = match walls {
            Some(w) => w,
            None => {
                let dir = case.path.parent().unwrap_or(std::path::Path::new("."));
                built = crate::walls::build(case, dir).map_err(|e| format!("[wear.fluid_mesh]: the walls: {e}"))?;
                &built
            }
        };
        let wall = walls.walls.iter().find(|w| w.name == section.wall).ok_or_else(|| format!("[wear.fluid_mesh] wall = {:?}: no such wall", section.wall))?;
        if !matches!(wall.motion, WallMotion::Static) {
            return Err(format!("[wear.fluid_mesh] wall = {:?}: the wall moves; only a wall standing still can carry the fluid mesh", section.wall));
        }
        // as built the wall lies in the patch's plane; worn (a restart) it has receded behind
        // it, its pinned rim still in the plane: never in front of it
        let height = |v: &Vec3| v.dot(&normal) - offset;
        let in_front = wall.vertices.iter().find(|v| height(v) < -PLANE_TOLERANCE * size);
        if let Some(v) = in_front.or_else(|| wall.vertices.iter().all(|v| height(v) > PLANE_TOLERANCE * size).then(|| &wall.vertices[0])) {
            return Err(format!(
                "[wear.fluid_mesh] wall = {:?}: the wall does not lie in the plane of patch {:?} (vertex ({:.6}, {:.6}, {:.6}) m is {:e} m off it); it must be a plane wall on the patch, as built",
                section.wall,
                section.patch,
                v.x,
                v.y,
                v.z,
                height(v)
            ));
        }
        let helper = if normal.x.abs() < 0.9 { Vec3::x() } else { Vec3::y() };
        let first = normal.cross(&helper).normalize();
        let tangents = [first, normal.cross(&first)];
        // a 2-D mesh (one layer between `empty` patches) stays 2-D: its points are read at the
        // layer's middle, so that both sides of a cell take one height
        let empty = mesh.patches.iter().find(|p| p.kind == crate::mesh::PatchKind::Empty && p.len > 0).map(|p| mesh.face_areas[p.start].normalize());
        let middle = empty.map(|e| {
            let (lo, hi) = mesh.reference_points.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| (lo.min(p.dot(&e)), hi.max(p.dot(&e))));
            (e, 0.5 * (lo + hi))
        });
        let in_plane = |p: &Vec3| {
            let p = middle.map_or(*p, |(e, m)| p + e * (m - p.dot(&e)));
            [p.dot(&tangents[0]), p.dot(&tangents[1])]
        };
        let distance: Vec<f64> = mesh.reference_points.iter().map(|p| offset - p.dot(&normal)).collect();
        let depth = section.depth.unwrap_or_else(|| distance.iter().fold(0.0, |a: f64, d| a.max(*d)));
        let follower = WallFollower {
            wall: section.wall.clone(),
            normal,
            offset,
            tangents,
            plane_position: mesh.reference_points.iter().map(in_plane).collect(),
            share: distance.iter().map(|d| (1.0 - d / depth).clamp(0.0, 1.0)).collect(),
        };
        // no other boundary face may move across itself: its flux is fixed (an inlet, a wall at
        // rest) or zero (a slip wall), so it may only slide in its own plane (spec §7.4 [R]:
        // other walls have no normal grid velocity)
        let patch_index = mesh.patch_index(&section.patch).map_err(|e| e.to_string())?;
        for (k, other) in mesh.patches.iter().enumerate() {
            if k == patch_index || other.kind == crate::mesh::PatchKind::Empty {
                continue;
            }
            for f in other.faces() {
                let across = mesh.face_areas[f].normalize().dot(&normal).abs() > PLANE_TOLERANCE;
                // (1e-12: a depth equal to the distance to a face leaves round-off there)
                if across && mesh.face_points[f].iter().any(|&p| follower.share[p] > 1e-12) {
                    let c = mesh.face_centres[f];
                    return Err(format!(
                        "[wear.fluid_mesh]: face {f} of patch {:?} at ({:.6}, {:.6}, {:.6}) m would move across itself as the mesh bends toward patch {:?}; a shorter depth (at most the distance to the faces facing the wall) keeps it still",
                        other.name, c.x, c.y, c.z, section.patch
                    ));
                }
            }
        }
        // every point of the patch must lie over the wall, or its recession would be unknown
        for f in faces {
            for &p in &mesh.face_points[f] {
                if follower.height_over(&wall.vertices, &wall.triangles, follower.plane_position[p]).is_none() {
                    let x = mesh.reference_points[p];
                    return Err(format!(
                        "[wear.fluid_mesh]: point ({:.6}, {:.6}, {:.6}) m of patch {:?} lies outside wall {:?}; the wall must cover the patch",
                        x.x, x.y, x.z, section.patch, section.wall
                    ));
                }
            }
        }
        Ok(Some(follower))
    }

    /// Height of the worn surface above the plane (along the normal, into the wall) over the
    /// plane point `q`: the first triangle (in order) whose projection contains q, barycentric;
    /// `None` outside the outline. 1e-12: points on shared edges and the outline, to round-off.
    fn height_over(&self, vertices: &[Vec3], triangles: &[[u32; 3]], q: [f64; 2]) -> Option<f64> {
        let plane = |v: &Vec3| [v.dot(&self.tangents[0]), v.dot(&self.tangents[1])];
        for t in triangles {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            let [pa, pb, pc] = [plane(&a), plane(&b), plane(&c)];
            let det = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pc[0] - pa[0]) * (pb[1] - pa[1]);
            if det == 0.0 {
                continue;
            }
            let l1 = ((q[0] - pa[0]) * (pc[1] - pa[1]) - (pc[0] - pa[0]) * (q[1] - pa[1])) / det;
            let l2 = ((pb[0] - pa[0]) * (q[1] - pa[1]) - (q[0] - pa[0]) * (pb[1] - pa[1])) / det;
            let l0 = 1.0 - l1 - l2;
            if l0 >= -1e-12 && l1 >= -1e-12 && l2 >= -1e-12 {
                let height = |v: &Vec3| v.dot(&self.normal) - self.offset;
                return Some(l0 * height(&a) + l1 * height(&b) + l2 * height(&c));
            }
        }
        None
    }

    /// Each mesh point's displacement along the normal for the wall as it is in `walls`, into
    /// `out` (its storage reused).
    pub fn displacement(&self, walls: &WallState, out: &mut Vec<f64>) -> Result<(), String> {
        let wall =
            walls.walls.iter().find(|w| w.name == self.wall).ok_or_else(|| format!("[wear.fluid_mesh] wall = {:?}: no such wall in the state", self.wall))?;
        out.clear();
        out.extend(self.plane_position.iter().zip(&self.share).map(|(q, share)| {
            if *share > 0.0 {
                share * self.height_over(&wall.vertices, &wall.triangles, *q).unwrap_or(0.0)
            } else {
                0.0
            }
        }));
        Ok(())
    }

    /// Moves `mesh` to its points displaced by `displacement` along the normal from their
    /// reference (`points` and `swept` are work storage; `swept` gets the faces' swept volumes).
    fn move_mesh(&self, mesh: &mut Mesh, displacement: &[f64], points: &mut Vec<Vec3>, swept: &mut Vec<f64>) -> Result<(), String> {
        points.clear();
        points.extend(mesh.reference_points.iter().zip(displacement).map(|(p, d)| p + self.normal * *d));
        mesh.move_points(points, swept).map_err(|e| e.to_string())
    }
}

/// A fluid solver's mesh that follows a receding wall: the follower, where the mesh is, and the
/// step's face mesh fluxes and old volumes. Both fluid solvers step it the same way
/// ([`MeshFollowing::move_for_step`] at the step's start, [`MeshFollowing::finish_step`],
/// [`MeshFollowing::rewind`]); they differ only in how their discretisations read the fluxes
/// and volumes. Allocation-free once built.
#[derive(Clone, Debug)]
pub struct MeshFollowing {
    follower: WallFollower,
    /// The displacement the mesh has now, and the one it had at the start of the step being
    /// taken (a rejected step goes back to it).
    placed: Vec<f64>,
    step_start: Vec<f64>,
    /// Per face, the mesh flux of the step being taken, swept volume · c₀/Δt [m³/s], and of the
    /// last step taken (the particles' Du/Dt at tⁿ reads the motion that brought the mesh there).
    face_mesh_flux: Vec<f64>,
    finished_flux: Vec<f64>,
    /// `finished_flux` as it was when the step being taken began (a rejected step restores it).
    finished_flux_at_start: Vec<f64>,
    /// The cell volumes at tⁿ of the step being taken.
    volumes_old: Vec<f64>,
    /// Whether the mesh was moved for the step being taken (and not yet finished or rewound).
    moved: bool,
    /// Work storage of a move, sized once: the target displacement, the points, the swept
    /// volumes.
    target: Vec<f64>,
    points: Vec<Vec3>,
    swept: Vec<f64>,
}

impl MeshFollowing {
    /// The following mesh of `case`'s `[wear.fluid_mesh]` (`None` without one), placed where
    /// `fluid` says the mesh is (a restart) or as built (a fresh run, whose displacement it
    /// fills in with zeros). The case has been validated for it (`Case::validate`: a box mesh
    /// without periodic directions, a `symmetry` patch, implicit Euler, laminar flow).
    /// `dt_old` is the state's last step, whose mesh motion (from `mesh_displacement_old`) the
    /// particles sample until the next step.
    pub fn from_case(
        case: &Case,
        mesh: &mut Mesh,
        walls: Option<&WallState>,
        fluid: &mut crate::fluid::state::FluidState,
        dt_old: f64,
    ) -> Result<Option<Self>, String> {
        let Some(follower) = WallFollower::from_case(case, mesh, walls)? else { return Ok(None) };
        for (name, values) in [("mesh displacement", &mut fluid.mesh_displacement), ("mesh displacement at tⁿ⁻¹", &mut fluid.mesh_displacement_old)] {
            if values.is_empty() {
                *values = vec![0.0; mesh.n_points()];
            } else if values.len() != mesh.n_points() {
                return Err(format!("the state's {name} has {} points, the mesh {}", values.len(), mesh.n_points()));
            }
        }
        mesh.use_fan_volumes();
        // the last step's motion, as the run had it, then the mesh where it is now
        let (mut points, mut swept) = (Vec::new(), Vec::new());
        follower.move_mesh(mesh, &fluid.mesh_displacement_old, &mut points, &mut swept)?;
        follower.move_mesh(mesh, &fluid.mesh_displacement, &mut points, &mut swept)?;
        // (Euler's c₀ = 1: the flux the step had, swept · c₀/Δt, to the bit)
        let finished_flux = if dt_old > 0.0 { swept.iter().map(|s| s / dt_old).collect() } else { vec![0.0; mesh.n_faces()] };
        let placed = fluid.mesh_displacement.clone();
        let volumes_old = mesh.cell_volumes.clone();
        Ok(Some(MeshFollowing {
            follower,
            step_start: placed.clone(),
            target: placed.clone(),
            placed,
            face_mesh_flux: vec![0.0; mesh.n_faces()],
            finished_flux_at_start: finished_flux.clone(),
            finished_flux,
            volumes_old,
            moved: false,
            points,
            swept,
        }))
    }

    /// Moves the mesh for the step from tⁿ to tⁿ⁺¹ (the driver's first stage, before the
    /// particles sample it): back to `displacement`, the state's at tⁿ, if it is elsewhere (a restart), then
    /// onto the shape `walls` have at tⁿ, setting each face's mesh flux to its swept volume
    /// · c₀/Δt (implicit Euler: Σ_f φ_mesh = (Vⁿ⁺¹ − Vⁿ)/Δt exactly, crate::mesh::deform) and
    /// keeping the volumes at tⁿ. The mesh lags the wall by the step: the wall recedes after the
    /// fluid's step, from the step's impacts.
    pub fn move_for_step(&mut self, mesh: &mut Mesh, walls: &WallState, displacement: &[f64], time_coefficients: [f64; 3], dt: f64) -> Result<(), String> {
        let [c0, _, c2] = time_coefficients;
        if c2 != 0.0 {
            return Err("[wear.fluid_mesh]: a following mesh steps with implicit Euler only (time coefficient c₂ ≠ 0)".into());
        }
        if self.placed != displacement {
            self.follower.move_mesh(mesh, displacement, &mut self.points, &mut self.swept)?;
            self.placed.copy_from_slice(displacement);
        }
        self.step_start.clone_from(&self.placed);
        self.finished_flux_at_start.clone_from(&self.finished_flux);
        self.volumes_old.clone_from(&mesh.cell_volumes);
        self.follower.displacement(walls, &mut self.target)?;
        self.follower.move_mesh(mesh, &self.target, &mut self.points, &mut self.swept)?;
        for (flux, s) in self.face_mesh_flux.iter_mut().zip(&self.swept) {
            *flux = s * c0 / dt;
        }
        std::mem::swap(&mut self.placed, &mut self.target);
        self.moved = true;
        Ok(())
    }

    /// Whether the mesh was moved for the step about to be taken; a fluid step without it would
    /// take the last step's mesh fluxes.
    pub fn check_moved(&self) -> Result<(), String> {
        if self.moved {
            Ok(())
        } else {
            Err("[wear.fluid_mesh]: the fluid step was taken without moving the mesh for it first (FluidPhase::follow_walls)".into())
        }
    }

    /// The step is taken: the state's displacement at tⁿ⁺¹ is the mesh's, at tⁿ the step's start,
    /// and the step's mesh flux is the last step's motion from now on.
    pub fn finish_step(&mut self, fluid: &mut crate::fluid::state::FluidState) {
        fluid.mesh_displacement_old.clone_from_slice(&self.step_start);
        fluid.mesh_displacement.clone_from_slice(&self.placed);
        self.finished_flux.clone_from(&self.face_mesh_flux);
        self.moved = false;
    }

    /// The driver rejected the step (its fluid part may have finished): the mesh goes back to
    /// where it started (the particles sample it next), with no mesh fluxes of its own and the
    /// last step's motion as it was.
    pub fn rewind(&mut self, mesh: &mut Mesh) {
        if self.placed != self.step_start {
            // the points the mesh had at that step's start, which were valid then
            self.follower.move_mesh(mesh, &self.step_start, &mut self.points, &mut self.swept).expect("the mesh of the step's start");
            self.placed.clone_from(&self.step_start);
        }
        self.face_mesh_flux.fill(0.0);
        self.finished_flux.clone_from(&self.finished_flux_at_start);
        self.volumes_old.clone_from(&mesh.cell_volumes);
        self.moved = false;
    }

    /// Per face, the mesh flux of the step being taken [m³/s].
    pub fn face_mesh_flux(&self) -> &[f64] {
        &self.face_mesh_flux
    }

    /// Per face, the mesh flux of the last step taken [m³/s] (what the particles sample with
    /// the fluid at tⁿ).
    pub fn finished_mesh_flux(&self) -> &[f64] {
        &self.finished_flux
    }

    /// The cell volumes at tⁿ of the step being taken.
    pub fn volumes_old(&self) -> &[f64] {
        &self.volumes_old
    }
}

/// ∂α/∂t V of a cell of a deforming mesh (implicit Euler), [c₀(α − 1)Vⁿ⁺¹ + c₁(αᵒ − 1)Vⁿ]/Δt:
/// d(αV)/dt less the mesh's own dV/dt = Σ_f φ_mesh,f, which the continuity of the absolute
/// fluxes already carries (crate::mesh::deform). Both fluid solvers' continuity uses it.
#[inline]
pub fn deforming_alpha_rate_volume(time_coefficients: [f64; 3], dt: f64, alpha: f64, alpha_old: f64, volume: f64, volume_old: f64) -> f64 {
    let [c0, c1, _] = time_coefficients;
    (c0 * (alpha - 1.0) * volume + c1 * (alpha_old - 1.0) * volume_old) / dt
}

/// The water's velocity on a slip (`symmetry`) face of a deforming mesh: the cell's tangential
/// velocity plus the face's normal speed φ_mesh/|S|, for a receding slip wall carries the water
/// on it along its normal.
#[inline]
pub fn receding_slip_velocity(cell_velocity: Vec3, area: Vec3, mesh_flux: f64) -> Vec3 {
    let normal = area.normalize();
    cell_velocity - normal * cell_velocity.dot(&normal) + normal * (mesh_flux / area.norm())
}
