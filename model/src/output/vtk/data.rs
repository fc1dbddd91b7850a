//! What a VTK file holds, as borrowed slices: points, cells and named fields.

/// How the arrays are stored. Both are read by ParaView ≥ 5 / VTK ≥ 6 (file version 1.0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// Numbers as text inside the XML: human-readable, for small files and tests.
    Ascii,
    /// Little-endian binary bytes after the XML (`<AppendedData encoding="raw">`), each array
    /// preceded by its byte count as UInt64: compact and fast, for production frames.
    AppendedRaw,
}

impl Encoding {
    /// ASCII below `threshold_values` numbers in total, raw binary above: a convenience for
    /// writers that want readable small files and compact large ones.
    pub fn by_size(total_values: usize, threshold_values: usize) -> Encoding {
        if total_values < threshold_values {
            Encoding::Ascii
        } else {
            Encoding::AppendedRaw
        }
    }
}

/// Linear VTK cell types with a fixed or free point count. Polyhedra (VTK type 42) need the extra
/// `faces`/`faceoffsets` arrays and will be added as their own variant with that data.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum CellType {
    Vertex,
    Line,
    Triangle,
    /// Planar polygon with any number ≥ 3 of points.
    Polygon,
    Quad,
    Tetra,
    /// VTK order: bottom face 0-1-2-3 counter-clockwise seen from above, then top face 4-5-6-7
    /// with point 4 above point 0.
    Hexahedron,
    /// VTK order: triangle 0-1-2, then triangle 3-4-5 with point 3 above point 0.
    Wedge,
    Pyramid,
}

impl CellType {
    /// The VTK cell type number written into the `types` array.
    pub fn vtk_id(self) -> u8 {
        match self {
            CellType::Vertex => 1,
            CellType::Line => 3,
            CellType::Triangle => 5,
            CellType::Polygon => 7,
            CellType::Quad => 9,
            CellType::Tetra => 10,
            CellType::Hexahedron => 12,
            CellType::Wedge => 13,
            CellType::Pyramid => 14,
        }
    }

    /// The inverse of [`CellType::vtk_id`].
    pub fn from_vtk_id(id: u8) -> Option<CellType> {
        ALL_CELL_TYPES.into_iter().find(|t| t.vtk_id() == id)
    }

    /// Points per cell, `None` for polygons (any count ≥ 3).
    pub fn point_count(self) -> Option<usize> {
        match self {
            CellType::Vertex => Some(1),
            CellType::Line => Some(2),
            CellType::Triangle => Some(3),
            CellType::Polygon => None,
            CellType::Quad => Some(4),
            CellType::Tetra => Some(4),
            CellType::Hexahedron => Some(8),
            CellType::Wedge => Some(6),
            CellType::Pyramid => Some(5),
        }
    }

    /// Whether `n` points make a valid cell of this type.
    pub fn accepts_point_count(self, n: usize) -> bool {
        match self.point_count() {
            Some(expected) => n == expected,
            None => n >= 3,
        }
    }
}

const ALL_CELL_TYPES: [CellType; 9] = [
    CellType::Vertex,
    CellType::Line,
    CellType::Triangle,
    CellType::Polygon,
    CellType::Quad,
    CellType::Tetra,
    CellType::Hexahedron,
    CellType::Wedge,
    CellType::Pyramid,
];

/// The cells of an unstructured grid in VTK's flat layout. Point counts and ids are checked when
/// the grid is written (where the file name is known for the error), not when cells are pushed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UnstructuredCells {
    pub(crate) connectivity: Vec<usize>,
    /// End of each cell in `connectivity` (VTK's `offsets` convention for file version 1.0).
    pub(crate) offsets: Vec<usize>,
    pub(crate) types: Vec<CellType>,
}

impl UnstructuredCells {
    pub fn new() -> Self {
        Self::default()
    }

    /// Room for `cells` cells of `points_per_cell` points each.
    pub fn with_capacity(cells: usize, points_per_cell: usize) -> Self {
        UnstructuredCells { connectivity: Vec::with_capacity(cells * points_per_cell), offsets: Vec::with_capacity(cells), types: Vec::with_capacity(cells) }
    }

    /// All-hexahedron cells, each given as 8 point ids in VTK order.
    pub fn hexahedra(cells: &[[usize; 8]]) -> Self {
        let mut all = Self::with_capacity(cells.len(), 8);
        for cell in cells {
            all.push(CellType::Hexahedron, cell);
        }
        all
    }

    /// Appends one cell of `cell_type` through the points `point_ids` (in VTK order).
    pub fn push(&mut self, cell_type: CellType, point_ids: &[usize]) {
        self.connectivity.extend_from_slice(point_ids);
        self.offsets.push(self.connectivity.len());
        self.types.push(cell_type);
    }

    pub fn len(&self) -> usize {
        self.types.len()
    }

    pub fn is_empty(&self) -> bool {
        self.types.is_empty()
    }

    /// The point ids of cell `index`.
    pub fn cell(&self, index: usize) -> (CellType, &[usize]) {
        let start = if index == 0 { 0 } else { self.offsets[index - 1] };
        (self.types[index], &self.connectivity[start..self.offsets[index]])
    }
}

/// The values of one named field: one entry per point or per cell.
#[derive(Clone, Copy, Debug)]
pub enum FieldValues<'a> {
    /// One `Float64` per entry.
    Scalar(&'a [f64]),
    /// Three `Float64` components per entry (ParaView shows magnitude and components).
    Vector(&'a [[f64; 3]]),
    /// One `Int64` per entry (ids, counts, flags).
    Int(&'a [i64]),
}

impl FieldValues<'_> {
    /// Number of entries (tuples), which must equal the number of points or cells.
    pub fn len(&self) -> usize {
        match self {
            FieldValues::Scalar(v) => v.len(),
            FieldValues::Vector(v) => v.len(),
            FieldValues::Int(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A named point or cell field.
#[derive(Clone, Copy, Debug)]
pub struct Field<'a> {
    pub name: &'a str,
    pub values: FieldValues<'a>,
}

impl<'a> Field<'a> {
    pub fn scalar(name: &'a str, values: &'a [f64]) -> Self {
        Field { name, values: FieldValues::Scalar(values) }
    }

    pub fn vector(name: &'a str, values: &'a [[f64; 3]]) -> Self {
        Field { name, values: FieldValues::Vector(values) }
    }

    pub fn int(name: &'a str, values: &'a [i64]) -> Self {
        Field { name, values: FieldValues::Int(values) }
    }
}

/// A volume mesh with fields: written as `.vtu`.
#[derive(Clone, Debug)]
pub struct UnstructuredGrid<'a> {
    pub points: &'a [[f64; 3]],
    pub cells: &'a UnstructuredCells,
    pub point_data: Vec<Field<'a>>,
    pub cell_data: Vec<Field<'a>>,
}

/// The cells of a poly data file.
#[derive(Clone, Copy, Debug)]
pub enum PolyCells<'a> {
    /// One vertex cell per point, in point order (particles).
    Vertices,
    /// Triangles through three point ids each (wall surface meshes).
    Triangles(&'a [[usize; 3]]),
    /// General polygons in flat layout: `offsets[i]` is the end of polygon `i` in `connectivity`.
    Polygons { connectivity: &'a [usize], offsets: &'a [usize] },
}

/// Points with vertex or polygon cells and fields: written as `.vtp`.
#[derive(Clone, Debug)]
pub struct PolyData<'a> {
    pub points: &'a [[f64; 3]],
    pub cells: PolyCells<'a>,
    pub point_data: Vec<Field<'a>>,
    pub cell_data: Vec<Field<'a>>,
}

impl<'a> PolyData<'a> {
    /// Particles: one vertex per centre; `point_data` holds the per-particle fields.
    pub fn particles(centres: &'a [[f64; 3]], point_data: Vec<Field<'a>>) -> Self {
        PolyData { points: centres, cells: PolyCells::Vertices, point_data, cell_data: Vec::new() }
    }

    /// A triangulated surface with per-vertex and per-triangle fields.
    pub fn triangles(points: &'a [[f64; 3]], triangles: &'a [[usize; 3]], point_data: Vec<Field<'a>>, cell_data: Vec<Field<'a>>) -> Self {
        PolyData { points, cells: PolyCells::Triangles(triangles), point_data, cell_data }
    }

    /// Number of cells the file will hold (the length every cell field must have).
    pub fn cell_count(&self) -> usize {
        match self.cells {
            PolyCells::Vertices => self.points.len(),
            PolyCells::Triangles(t) => t.len(),
            PolyCells::Polygons { offsets, .. } => offsets.len(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_type_ids_round_trip_and_match_vtk_numbers() {
        for t in ALL_CELL_TYPES {
            assert_eq!(CellType::from_vtk_id(t.vtk_id()), Some(t));
        }
        // VTK's vtkCellType.h numbers for the types the solvers use.
        assert_eq!(CellType::Hexahedron.vtk_id(), 12);
        assert_eq!(CellType::Wedge.vtk_id(), 13);
        assert_eq!(CellType::Triangle.vtk_id(), 5);
        assert_eq!(CellType::Vertex.vtk_id(), 1);
        assert_eq!(CellType::from_vtk_id(42), None);
    }

    #[test]
    fn pushed_cells_are_read_back_by_index() {
        let mut cells = UnstructuredCells::new();
        cells.push(CellType::Tetra, &[0, 1, 2, 3]);
        cells.push(CellType::Wedge, &[4, 5, 6, 7, 8, 9]);
        assert_eq!(cells.len(), 2);
        assert_eq!(cells.cell(0), (CellType::Tetra, &[0, 1, 2, 3][..]));
        assert_eq!(cells.cell(1), (CellType::Wedge, &[4, 5, 6, 7, 8, 9][..]));
    }
}
