//! Turns a list of hexahedral cells into a face-addressed [`Mesh`]: faces shared by two cells
//! become internal faces, the rest boundary faces sorted into patches by the generator.
//!
//! Faces are matched by the sorted *canonical* ids of their points. A generator identifies
//! points that are the same topologically but not geometrically (the two sides of a periodic
//! box) by giving them one canonical id; matched faces whose two copies lie apart become
//! periodic faces.

use super::geometry::{hex_face, HEX_FACES};
use super::{CellZone, Locator, Mesh, MeshError, Patch, PatchKind, PeriodicPair, Vec3, ZoneRotation};

/// A zone as the generator describes it.
pub struct ZoneInput {
    pub name: String,
    pub cells: Vec<usize>,
    pub rotation: Option<ZoneRotation>,
}

/// Everything a block generator produces before faces are known.
pub struct HexCells {
    pub points: Vec<Vec3>,
    /// Cells as 8 point ids in VTK_HEXAHEDRON order.
    pub cells: Vec<[usize; 8]>,
    /// Canonical id of each point, for face matching (identity when nothing is identified).
    pub canonical: Vec<usize>,
    pub patches: Vec<(String, PatchKind)>,
    /// Periodic pairs: name and shift (owner copy → neighbour copy).
    pub periodic: Vec<(String, Vec3)>,
    pub zones: Vec<ZoneInput>,
    pub locator: Locator,
}

/// Build the mesh. `patch_of(cell, local_face)` names the patch (index into
/// `input.patches`) of each unmatched cell face, see [`HEX_FACES`] for local face numbers.
pub fn assemble(input: HexCells, patch_of: impl Fn(usize, usize) -> Result<usize, MeshError>) -> Result<Mesh, MeshError> {
    assemble_with_baffles(input, patch_of, |_, _| None)
}

/// [`assemble`], where a face two cells share becomes a baffle, a boundary face of each cell in
/// patch `baffle_of(cell, local_face)` (asked of the lower-numbered cell), when that is `Some`.
pub fn assemble_with_baffles(
    input: HexCells,
    patch_of: impl Fn(usize, usize) -> Result<usize, MeshError>,
    baffle_of: impl Fn(usize, usize) -> Option<usize>,
) -> Result<Mesh, MeshError> {
    let n_cells = input.cells.len();
    let mut records: Vec<([usize; 4], usize, usize)> = Vec::with_capacity(6 * n_cells);
    for (cell, ids) in input.cells.iter().enumerate() {
        for (local, face) in HEX_FACES.iter().enumerate() {
            let mut key = face.map(|k| input.canonical[ids[k]]);
            key.sort_unstable();
            records.push((key, cell, local));
        }
    }
    records.sort_unstable();

    // (owner, neighbour, owner's local face, neighbour's local face)
    let mut internal: Vec<(usize, usize, usize, usize)> = Vec::new();
    // (patch, cell, local face)
    let mut boundary: Vec<(usize, usize, usize)> = Vec::new();
    let mut i = 0;
    while i < records.len() {
        let mut j = i + 1;
        while j < records.len() && records[j].0 == records[i].0 {
            j += 1;
        }
        match j - i {
            1 => {
                let (_, cell, local) = records[i];
                let patch = patch_of(cell, local)?;
                if patch >= input.patches.len() {
                    return Err(MeshError::Topology(format!("cell {cell} face {local} assigned to patch {patch}, only {} exist", input.patches.len())));
                }
                boundary.push((patch, cell, local));
            }
            2 => {
                let (_, a, local_a) = records[i];
                let (_, b, local_b) = records[i + 1];
                if a == b {
                    return Err(MeshError::Topology(format!("cell {a} is its own neighbour")));
                }
                // records are sorted, so a < b: the lower cell owns the face.
                match baffle_of(a, local_a) {
                    Some(patch) if patch < input.patches.len() => boundary.extend([(patch, a, local_a), (patch, b, local_b)]),
                    Some(patch) => {
                        return Err(MeshError::Topology(format!("baffle of cells {a} and {b} assigned to patch {patch}, only {} exist", input.patches.len())))
                    }
                    None => internal.push((a, b, local_a, local_b)),
                }
            }
            n => return Err(MeshError::Topology(format!("{n} cells share the face with points {:?}", records[i].0))),
        }
        i = j;
    }
    internal.sort_unstable();
    for pair in internal.windows(2) {
        if pair[0].0 == pair[1].0 && pair[0].1 == pair[1].1 {
            return Err(MeshError::Topology(format!("cells {} and {} share more than one face", pair[0].0, pair[0].1)));
        }
    }
    boundary.sort_unstable();

    let n_internal_faces = internal.len();
    let n_faces = n_internal_faces + boundary.len();
    let mut face_points = Vec::with_capacity(n_faces);
    let mut face_owner = Vec::with_capacity(n_faces);
    let mut face_neighbour = Vec::with_capacity(n_internal_faces);
    for &(owner, neighbour, local, _) in &internal {
        face_points.push(HEX_FACES[local].map(|k| input.cells[owner][k]));
        face_owner.push(owner);
        face_neighbour.push(neighbour);
    }
    let mut patches: Vec<Patch> = input.patches.iter().map(|(name, kind)| Patch { name: name.clone(), kind: kind.clone(), start: 0, len: 0 }).collect();
    for (k, &(patch, cell, local)) in boundary.iter().enumerate() {
        if patches[patch].len == 0 {
            patches[patch].start = n_internal_faces + k;
        }
        patches[patch].len += 1;
        face_points.push(HEX_FACES[local].map(|i| input.cells[cell][i]));
        face_owner.push(cell);
    }
    // Empty patches start where the previous one ended, so `faces()` stays in range.
    let mut next_start = n_internal_faces;
    for patch in &mut patches {
        if patch.len == 0 {
            patch.start = next_start;
        }
        next_start = patch.start + patch.len;
    }

    let periodic = periodic_pairs(&input, &internal)?;
    let (cell_face_offsets, cell_faces) = cell_face_lists(n_cells, &face_owner, &face_neighbour);
    let (zones, cell_zone) = build_zones(&input, &cell_face_offsets, &cell_faces)?;

    let mut mesh = Mesh {
        reference_points: input.points.clone(),
        points: input.points,
        cell_points: input.cells,
        cell_centres: vec![Vec3::zeros(); n_cells],
        cell_volumes: vec![0.0; n_cells],
        cell_zone,
        cell_face_offsets,
        cell_faces,
        face_points,
        face_centres: vec![Vec3::zeros(); n_faces],
        face_areas: vec![Vec3::zeros(); n_faces],
        face_owner,
        face_neighbour,
        face_delta: vec![Vec3::zeros(); n_internal_faces],
        face_weight: vec![0.0; n_internal_faces],
        n_internal_faces,
        patches,
        zones,
        periodic,
        interfaces: Vec::new(),
        locator: input.locator,
    };
    mesh.update_all_geometry();
    mesh.capture_zone_geometry();
    Ok(mesh)
}

/// Sort matched faces whose two copies lie apart into the generator's periodic pairs.
fn periodic_pairs(input: &HexCells, internal: &[(usize, usize, usize, usize)]) -> Result<Vec<PeriodicPair>, MeshError> {
    let mut pairs: Vec<PeriodicPair> =
        input.periodic.iter().map(|(name, shift)| PeriodicPair { name: name.clone(), faces: Vec::new(), shift: *shift }).collect();
    let (low, high) = input.points.iter().fold((Vec3::repeat(f64::MAX), Vec3::repeat(f64::MIN)), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
    // Two copies of one face differ by a periodic shift (order of the domain size) or coincide
    // up to round-off of the point coordinates (order 1e-16 of the domain size).
    let tolerance = 1e-9 * (high - low).norm();
    for (face, &(owner, neighbour, owner_local, neighbour_local)) in internal.iter().enumerate() {
        let (owner_copy, _) = hex_face(&input.points, &input.cells[owner], owner_local);
        let (neighbour_copy, _) = hex_face(&input.points, &input.cells[neighbour], neighbour_local);
        let shift = neighbour_copy - owner_copy;
        if shift.norm() <= tolerance {
            continue;
        }
        let pair = pairs.iter_mut().find(|p| (p.shift - shift).norm() <= tolerance).ok_or_else(|| {
            MeshError::Topology(format!(
                "face {face} between cells {owner} and {neighbour} is shifted by {shift:?}, \
                     which matches no periodic pair"
            ))
        })?;
        pair.faces.push(face);
    }
    Ok(pairs)
}

fn cell_face_lists(n_cells: usize, face_owner: &[usize], face_neighbour: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let mut counts = vec![0usize; n_cells + 1];
    for &c in face_owner.iter().chain(face_neighbour) {
        counts[c + 1] += 1;
    }
    for c in 0..n_cells {
        counts[c + 1] += counts[c];
    }
    let offsets = counts;
    let mut fill = offsets.clone();
    let mut faces = vec![0usize; offsets[n_cells]];
    // Owner and neighbour lists are visited in face order, so each cell's faces end up
    // ascending only after a per-cell sort (a cell is neighbour of lower faces than it owns,
    // but boundary faces come last).
    for (f, &c) in face_owner.iter().enumerate() {
        faces[fill[c]] = f;
        fill[c] += 1;
    }
    for (f, &c) in face_neighbour.iter().enumerate() {
        faces[fill[c]] = f;
        fill[c] += 1;
    }
    for c in 0..n_cells {
        faces[offsets[c]..offsets[c + 1]].sort_unstable();
    }
    (offsets, faces)
}

fn build_zones(input: &HexCells, cell_face_offsets: &[usize], cell_faces: &[usize]) -> Result<(Vec<CellZone>, Vec<usize>), MeshError> {
    let n_cells = input.cells.len();
    let mut cell_zone = vec![usize::MAX; n_cells];
    let mut zones = Vec::with_capacity(input.zones.len());
    for (z, zone) in input.zones.iter().enumerate() {
        let mut cells = zone.cells.clone();
        cells.sort_unstable();
        let mut points = Vec::with_capacity(8 * cells.len());
        let mut faces = Vec::with_capacity(6 * cells.len());
        for &c in &cells {
            if cell_zone[c] != usize::MAX {
                return Err(MeshError::Topology(format!("cell {c} is in two zones")));
            }
            cell_zone[c] = z;
            points.extend_from_slice(&input.cells[c]);
            faces.extend_from_slice(&cell_faces[cell_face_offsets[c]..cell_face_offsets[c + 1]]);
        }
        points.sort_unstable();
        points.dedup();
        faces.sort_unstable();
        faces.dedup();
        zones.push(CellZone { name: zone.name.clone(), cells, rotation: zone.rotation.clone(), points, faces, reference_geometry: None });
    }
    if let Some(c) = cell_zone.iter().position(|&z| z == usize::MAX) {
        return Err(MeshError::Topology(format!("cell {c} is in no zone")));
    }
    for (z, zone) in zones.iter().enumerate() {
        if zone.rotation.is_none() {
            continue;
        }
        let foreign = input.cells.iter().enumerate().find(|(c, ids)| cell_zone[*c] != z && ids.iter().any(|p| zone.points.binary_search(p).is_ok()));
        if let Some((c, _)) = foreign {
            return Err(MeshError::Topology(format!("rotating zone `{}` shares points with cell {c} outside it", zone.name)));
        }
    }
    Ok((zones, cell_zone))
}
