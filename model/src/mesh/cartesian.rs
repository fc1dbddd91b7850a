//! Cartesian box generator, optionally graded and periodic (DESIGN.md "mesh"; issue #2 item 3).

use super::assemble::{assemble, HexCells, ZoneInput};
use super::{Locator, Mesh, MeshError, PatchKind, Vec3};

/// An axis-aligned box of `cells[0] × cells[1] × cells[2]` hexahedra.
///
/// Cell `(i, j, k)` has index `i + n_x (j + n_y k)`. Patches `x_min, x_max, y_min, y_max,
/// z_min, z_max` (kind [`PatchKind::Patch`]; change with [`Mesh::set_patch_kind`], e.g. z_min
/// and z_max `Empty` for a one-cell-thick 2-D mesh), except in periodic directions, whose
/// faces become internal faces of a [`super::PeriodicPair`] named "x", "y" or "z". All cells
/// form one non-rotating zone "fluid". With `solids`, the cells inside them are left out and the
/// faces next to them form a patch `solid`; cells are then numbered in the same order with the
/// solid ones skipped.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BoxSpec {
    pub min: Vec3,
    pub max: Vec3,
    pub cells: [usize; 3],
    /// Ratio of the last to the first cell size in each direction (1 = uniform); sizes form a
    /// geometric progression.
    pub grading: [f64; 3],
    /// Periodic directions need at least 3 cells (so no two cells share two faces).
    pub periodic: [bool; 3],
    /// Solid boxes (min, max): cells whose centre lies inside one are removed; the faces they
    /// leave exposed form the patch `solid` (a backward-facing step, a block in a channel).
    #[serde(default)]
    pub solids: Vec<(Vec3, Vec3)>,
}

impl BoxSpec {
    /// Uniform, non-periodic box.
    pub fn uniform(min: Vec3, max: Vec3, cells: [usize; 3]) -> Self {
        BoxSpec { min, max, cells, grading: [1.0; 3], periodic: [false; 3], solids: Vec::new() }
    }
}

const AXES: [&str; 3] = ["x", "y", "z"];

/// `n + 1` edges from `start` to `end` whose interval sizes grow geometrically so that
/// last / first = `ratio`: size_k = size_0 q^k with q = ratio^(1/(n−1)).
pub(crate) fn graded_edges(name: &str, start: f64, end: f64, n: usize, ratio: f64) -> Result<Vec<f64>, MeshError> {
    if !(ratio.is_finite() && ratio > 0.0) {
        return Err(MeshError::input(name, ratio, "grading must be a finite ratio > 0"));
    }
    let length = end - start;
    let mut edges = Vec::with_capacity(n + 1);
    if n == 1 || ratio == 1.0 {
        edges.extend((0..=n).map(|k| start + length * k as f64 / n as f64));
    } else {
        let q = ratio.powf(1.0 / (n - 1) as f64);
        let total = (q.powi(n as i32) - 1.0) / (q - 1.0);
        let mut partial = 0.0;
        let mut size = 1.0;
        for _ in 0..n {
            edges.push(start + length * partial / total);
            partial += size;
            size *= q;
        }
        edges.push(end);
    }
    edges[n] = end;
    Ok(edges)
}

impl Mesh {
    /// Generate the box described by `spec`.
    pub fn cartesian_box(spec: &BoxSpec) -> Result<Mesh, MeshError> {
        let mut edges: [Vec<f64>; 3] = Default::default();
        for d in 0..3 {
            let axis = AXES[d];
            let (lo, hi) = (spec.min[d], spec.max[d]);
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(MeshError::input(&format!("box.min/max.{axis}"), format!("[{lo}, {hi}]"), "need finite min < max"));
            }
            let n = spec.cells[d];
            let least = if spec.periodic[d] { 3 } else { 1 };
            if n < least {
                return Err(MeshError::input(&format!("box.cells.{axis}"), n, &format!("need at least {least} cells in this direction")));
            }
            edges[d] = graded_edges(&format!("box.grading.{axis}"), lo, hi, n, spec.grading[d])?;
        }
        let [nx, ny, nz] = spec.cells;
        let point_id = |i: usize, j: usize, k: usize| i + (nx + 1) * (j + (ny + 1) * k);
        let wrap = |index: usize, d: usize| {
            if spec.periodic[d] && index == spec.cells[d] {
                0
            } else {
                index
            }
        };
        let mut points = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
        let mut canonical = Vec::with_capacity(points.capacity());
        for k in 0..=nz {
            for j in 0..=ny {
                for i in 0..=nx {
                    points.push(Vec3::new(edges[0][i], edges[1][j], edges[2][k]));
                    canonical.push(point_id(wrap(i, 0), wrap(j, 1), wrap(k, 2)));
                }
            }
        }
        let mut cells: Vec<[usize; 8]> = Vec::with_capacity(nx * ny * nz);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    cells.push([
                        point_id(i, j, k),
                        point_id(i + 1, j, k),
                        point_id(i + 1, j + 1, k),
                        point_id(i, j + 1, k),
                        point_id(i, j, k + 1),
                        point_id(i + 1, j, k + 1),
                        point_id(i + 1, j + 1, k + 1),
                        point_id(i, j + 1, k + 1),
                    ]);
                }
            }
        }
        // Local face 2d + side is the `side` end of direction d (see geometry::HEX_FACES).
        let mut patches = Vec::new();
        let mut patch_of_local = [usize::MAX; 6];
        let mut periodic = Vec::new();
        for d in 0..3 {
            if spec.periodic[d] {
                let mut shift = Vec3::zeros();
                shift[d] = spec.max[d] - spec.min[d];
                periodic.push((AXES[d].to_string(), shift));
            } else {
                for (side, end) in ["min", "max"].iter().enumerate() {
                    patch_of_local[2 * d + side] = patches.len();
                    patches.push((format!("{}_{end}", AXES[d]), PatchKind::Patch));
                }
            }
        }
        // slots (i, j, k) whose centre is inside a solid hold no cell
        let centre = |d: usize, index: usize| 0.5 * (edges[d][index] + edges[d][index + 1]);
        let mut slot_of_cell = Vec::with_capacity(cells.len());
        let mut cell_of_slot = Vec::new();
        if !spec.solids.is_empty() {
            for (d, (lo, hi)) in spec.solids.iter().enumerate() {
                if !(0..3).all(|a| lo[a].is_finite() && hi[a].is_finite() && lo[a] < hi[a]) {
                    return Err(MeshError::input(&format!("box.solids.{d}"), format!("{lo:?} … {hi:?}"), "need finite min < max in every direction"));
                }
            }
            cell_of_slot = vec![None; cells.len()];
            for k in 0..nz {
                for j in 0..ny {
                    for i in 0..nx {
                        let c = Vec3::new(centre(0, i), centre(1, j), centre(2, k));
                        let solid = spec.solids.iter().any(|(lo, hi)| (0..3).all(|a| c[a] > lo[a] && c[a] < hi[a]));
                        if !solid {
                            let slot = i + nx * (j + ny * k);
                            cell_of_slot[slot] = Some(slot_of_cell.len());
                            slot_of_cell.push(slot);
                        }
                    }
                }
            }
            if slot_of_cell.is_empty() {
                return Err(MeshError::input("box.solids", spec.solids.len(), "solids that leave at least one cell open"));
            }
            cells = slot_of_cell.iter().map(|&slot| cells[slot]).collect();
            patches.push(("solid".to_string(), PatchKind::Patch));
        }
        let solid_patch = patches.len().wrapping_sub(1);
        let n_cells = cells.len();
        let input = HexCells {
            points,
            cells,
            canonical,
            patches,
            periodic,
            zones: vec![ZoneInput { name: "fluid".to_string(), cells: (0..n_cells).collect(), rotation: None }],
            locator: Locator::Box { edges, cell_of_slot, deformed: false, moved_bounds: [[0.0; 3]; 2] },
        };
        let n = spec.cells;
        assemble(input, |cell, local| {
            if !slot_of_cell.is_empty() {
                // a face inside the box next to a removed cell is a solid face
                let slot = slot_of_cell[cell];
                let index = [slot % n[0], (slot / n[0]) % n[1], slot / (n[0] * n[1])];
                let (d, side) = (local / 2, local % 2);
                let on_box_side = if side == 0 { index[d] == 0 } else { index[d] == n[d] - 1 };
                if !on_box_side {
                    return Ok(solid_patch);
                }
            }
            match patch_of_local[local] {
                usize::MAX => Err(MeshError::Topology(format!("cell {cell} face {local} lies on a periodic side but found no partner"))),
                patch => Ok(patch),
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::test_support::*;

    fn graded_box() -> BoxSpec {
        BoxSpec {
            min: Vec3::new(-1.0, 0.5, 2.0),
            max: Vec3::new(2.0, 1.7, 2.9),
            cells: [5, 4, 3],
            grading: [3.0, 0.25, 1.0],
            periodic: [false; 3],
            solids: Vec::new(),
        }
    }

    #[test]
    fn a_solid_step_is_cut_out_and_its_exposed_faces_form_the_solid_patch() {
        // a backward-facing step: the block x < 0.4, y < 0.25 of a unit box, 10 × 4 × 2 cells
        let spec = BoxSpec {
            solids: vec![(Vec3::new(-1.0, -1.0, -1.0), Vec3::new(0.4, 0.25, 2.0))],
            ..BoxSpec::uniform(Vec3::zeros(), Vec3::new(1.0, 1.0, 1.0), [10, 4, 2])
        };
        let mesh = Mesh::cartesian_box(&spec).unwrap();
        assert_eq!(mesh.n_cells(), 80 - 4 * 2);
        let total: f64 = mesh.cell_volumes.iter().sum();
        // round-off of ~70 summed products of O(0.1) numbers
        assert!((total - (1.0 - 0.4 * 0.25)).abs() < 1e-14, "{total}");
        let solid = mesh.patches.iter().find(|p| p.name == "solid").expect("a solid patch");
        let area: f64 = solid.faces().map(|f| mesh.face_areas[f].norm()).sum();
        // the step's top (0.4 × 1) and its face (0.25 × 1)
        assert!((area - 0.65).abs() < 1e-14, "{area}");
        assert_eq!(mesh.locate(&Vec3::new(0.1, 0.1, 0.5)), None);
        let c = mesh.locate(&Vec3::new(0.45, 0.1, 0.5)).unwrap();
        assert!(mesh.contains(c, &Vec3::new(0.45, 0.1, 0.5)));
    }

    #[test]
    fn volumes_sum_to_box_volume() {
        let mesh = Mesh::cartesian_box(&graded_box()).unwrap();
        assert_eq!(mesh.n_cells(), 60);
        let total: f64 = mesh.cell_volumes.iter().sum();
        let exact = 3.0 * 1.2 * 0.9;
        // Round-off of ~60 summed products of O(1) numbers.
        assert!((total - exact).abs() < 1e-14 * exact, "total {total} vs {exact}");
        for (c, v) in mesh.cell_volumes.iter().enumerate() {
            let ids = mesh.cell_points[c];
            let diagonal = mesh.points[ids[6]] - mesh.points[ids[0]];
            let product = diagonal.x * diagonal.y * diagonal.z;
            assert!((v - product).abs() < 1e-14 * product, "cell {c}: {v} vs {product}");
        }
    }

    #[test]
    fn grading_gives_requested_size_ratio() {
        let spec = graded_box();
        let edges = graded_edges("t", spec.min.x, spec.max.x, 5, 3.0).unwrap();
        let ratio = (edges[5] - edges[4]) / (edges[1] - edges[0]);
        assert!((ratio - 3.0).abs() < 1e-13, "ratio {ratio}");
        let q = 3.0f64.powf(0.25);
        for k in 1..5 {
            let growth = (edges[k + 1] - edges[k]) / (edges[k] - edges[k - 1]);
            assert!((growth - q).abs() < 1e-13, "interval {k}: growth {growth} vs {q}");
        }
        assert_eq!(edges[0], spec.min.x);
        assert_eq!(edges[5], spec.max.x);
    }

    #[test]
    fn cells_are_closed_and_faces_oriented() {
        let mesh = Mesh::cartesian_box(&graded_box()).unwrap();
        assert_cells_closed(&mesh);
        assert_internal_faces_oriented(&mesh);
        assert_boundary_faces_outward(&mesh);
        // Internal faces: (n_x − 1) n_y n_z + … ; boundary: 2 (n_x n_y + n_y n_z + n_z n_x).
        assert_eq!(mesh.n_internal_faces, 4 * 4 * 3 + 5 * 3 * 3 + 5 * 4 * 2);
        assert_eq!(mesh.n_faces() - mesh.n_internal_faces, 2 * (20 + 12 + 15));
        let names: Vec<&str> = mesh.patches.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["x_min", "x_max", "y_min", "y_max", "z_min", "z_max"]);
        let x_min = mesh.patch("x_min").unwrap();
        assert_eq!(x_min.len, 4 * 3);
        for f in x_min.faces() {
            // Triangle-decomposed centre: round-off of O(1) coordinates.
            assert!((mesh.face_centres[f].x + 1.0).abs() < 1e-15);
            assert_eq!(mesh.boundary_patch_of(f), Some(0));
        }
    }

    #[test]
    fn interpolation_weight_matches_distances() {
        let mesh = Mesh::cartesian_box(&graded_box()).unwrap();
        for f in 0..mesh.n_internal_faces {
            let owner = mesh.cell_centres[mesh.face_owner[f]];
            let neighbour = mesh.cell_centres[mesh.face_neighbour[f]];
            let to_owner = (mesh.face_centres[f] - owner).norm();
            let to_neighbour = (neighbour - mesh.face_centres[f]).norm();
            let expected = to_neighbour / (to_owner + to_neighbour);
            assert!((mesh.face_weight[f] - expected).abs() < 1e-14, "face {f}");
            assert!((mesh.face_delta[f] - (neighbour - owner)).norm() < 1e-15);
        }
    }

    #[test]
    fn fully_periodic_box_has_six_internal_faces_per_cell() {
        let spec = BoxSpec {
            min: Vec3::new(0.0, 0.0, 0.0),
            max: Vec3::new(2.0, 3.0, 0.5),
            cells: [4, 3, 5],
            grading: [1.0, 2.0, 1.0],
            periodic: [true; 3],
            solids: Vec::new(),
        };
        let mesh = Mesh::cartesian_box(&spec).unwrap();
        assert!(mesh.patches.is_empty());
        assert_eq!(mesh.n_faces(), mesh.n_internal_faces);
        assert_eq!(mesh.n_internal_faces, 3 * mesh.n_cells());
        for c in 0..mesh.n_cells() {
            assert_eq!(mesh.faces_of_cell(c).len(), 6, "cell {c}");
        }
        let lengths = [2.0, 3.0, 0.5];
        for (d, pair) in mesh.periodic.iter().enumerate() {
            assert_eq!(pair.name, AXES[d]);
            let mut expected = Vec3::zeros();
            expected[d] = lengths[d];
            assert_eq!(pair.shift, expected);
            let cross_section = spec.cells[0] * spec.cells[1] * spec.cells[2] / spec.cells[d];
            assert_eq!(pair.faces.len(), cross_section);
            for &f in &pair.faces {
                // The face sits on the low side, owned by a low-side cell.
                assert!(mesh.face_centres[f][d].abs() < 1e-15);
                assert!(mesh.face_areas[f][d] < 0.0);
            }
        }
        assert_cells_closed(&mesh);
        assert_internal_faces_oriented(&mesh);
        // Across every face (periodic or not) the neighbour (image) centre lies half a cell
        // width on each side of the face: |delta| = (h_P + h_N)/2 along the face normal.
        let width = |c: usize, d: usize| {
            let ids = mesh.cell_points[c];
            mesh.points[ids[6]][d] - mesh.points[ids[0]][d]
        };
        for f in 0..mesh.n_internal_faces {
            let d = mesh.face_areas[f].iamax();
            let expected = 0.5 * (width(mesh.face_owner[f], d) + width(mesh.face_neighbour[f], d));
            let delta = mesh.face_delta[f];
            assert!((delta.norm() - expected).abs() < 1e-14, "face {f} delta {delta:?}");
            assert!((delta[d].abs() - expected).abs() < 1e-14, "face {f} delta {delta:?}");
        }
    }

    #[test]
    fn two_d_mesh_marks_front_and_back_empty() {
        let mut mesh = Mesh::cartesian_box(&BoxSpec::uniform(Vec3::zeros(), Vec3::new(1.0, 1.0, 0.1), [4, 4, 1])).unwrap();
        mesh.set_patch_kind("z_min", PatchKind::Empty).unwrap();
        mesh.set_patch_kind("z_max", PatchKind::Empty).unwrap();
        assert_eq!(mesh.patch("z_max").unwrap().kind, PatchKind::Empty);
        assert!(matches!(mesh.set_patch_kind("front", PatchKind::Empty), Err(MeshError::UnknownPatch { .. })));
    }

    #[test]
    fn bad_input_is_rejected_with_its_name() {
        let mut spec = graded_box();
        spec.cells[1] = 0;
        let error = Mesh::cartesian_box(&spec).unwrap_err().to_string();
        assert!(error.contains("box.cells.y"), "{error}");
        let mut spec = graded_box();
        spec.max.z = spec.min.z;
        assert!(Mesh::cartesian_box(&spec).unwrap_err().to_string().contains("box.min/max.z"));
        let mut spec = graded_box();
        spec.grading[0] = -1.0;
        assert!(Mesh::cartesian_box(&spec).unwrap_err().to_string().contains("box.grading.x"));
        let mut spec = graded_box();
        spec.periodic[2] = true;
        spec.cells[2] = 2;
        assert!(Mesh::cartesian_box(&spec).unwrap_err().to_string().contains("box.cells.z"));
    }

    #[test]
    fn locate_finds_random_points() {
        let spec = graded_box();
        let mesh = Mesh::cartesian_box(&spec).unwrap();
        let mut random = Lcg::new(7);
        for _ in 0..2000 {
            let p = Vec3::from_fn(|d, _| spec.min[d] + random.next() * (spec.max[d] - spec.min[d]));
            let cell = mesh.locate(&p).expect("point inside the box");
            // Independent check: the cell's own corner box contains the point.
            let ids = mesh.cell_points[cell];
            let (lo, hi) = (mesh.points[ids[0]], mesh.points[ids[6]]);
            assert!((0..3).all(|d| lo[d] <= p[d] && p[d] <= hi[d]), "{p:?} not in {cell}");
            assert!(mesh.contains(cell, &p));
        }
        assert_eq!(mesh.locate(&Vec3::new(2.1, 1.0, 2.5)), None);
        assert_eq!(mesh.locate(&spec.max), Some(mesh.n_cells() - 1));
    }
}
