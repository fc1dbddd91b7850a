//! VTK XML serial files (`.vtu`, `.vtp`), written by hand after the Kitware format description
//! ("VTK File Formats", XML section): file version 1.0, little-endian, UInt64 binary headers.

use super::data::{CellType, Encoding, Field, FieldValues, PolyCells, PolyData, UnstructuredGrid};
use crate::output::{check_finite, format_f64, write_atomically, OutputError};
use std::borrow::Cow;
use std::collections::BTreeSet;
use std::io::Write;
use std::path::Path;

/// Writes `grid` as a VTK UnstructuredGrid file (`.vtu`) at `path`, atomically.
pub fn write_vtu(path: &Path, grid: &UnstructuredGrid, encoding: Encoding) -> Result<(), OutputError> {
    let n_points = grid.points.len();
    let cells = grid.cells;
    for index in 0..cells.len() {
        let (cell_type, ids) = cells.cell(index);
        check_cell(path, index, cell_type, ids, n_points)?;
    }
    let connectivity = to_i64(path, "connectivity", &cells.connectivity)?;
    let offsets = to_i64(path, "offsets", &cells.offsets)?;
    let types: Vec<u8> = cells.types.iter().map(|t| t.vtk_id()).collect();

    let document = Document {
        dataset: "UnstructuredGrid",
        piece_attributes: vec![("NumberOfPoints", n_points), ("NumberOfCells", cells.len())],
        sections: vec![
            field_section(path, "PointData", &grid.point_data, n_points)?,
            field_section(path, "CellData", &grid.cell_data, cells.len())?,
            points_section(path, grid.points)?,
            Section {
                tag: "Cells",
                arrays: vec![
                    DataArray::int("connectivity", 1, Cow::Owned(connectivity)),
                    DataArray::int("offsets", 1, Cow::Owned(offsets)),
                    DataArray { name: "types", components: 1, numbers: Numbers::U8(types) },
                ],
            },
        ],
    };
    write_document(path, &document, encoding)
}

/// Writes `poly` as a VTK PolyData file (`.vtp`) at `path`, atomically.
pub fn write_vtp(path: &Path, poly: &PolyData, encoding: Encoding) -> Result<(), OutputError> {
    let n_points = poly.points.len();
    let n_cells = poly.cell_count();
    let (cell_tag, connectivity, offsets): (&'static str, Vec<usize>, Vec<usize>) = match poly.cells {
        PolyCells::Vertices => ("Verts", (0..n_points).collect(), (1..=n_points).collect()),
        PolyCells::Triangles(triangles) => ("Polys", triangles.as_flattened().to_vec(), (1..=triangles.len()).map(|i| 3 * i).collect()),
        PolyCells::Polygons { connectivity, offsets } => ("Polys", connectivity.to_vec(), offsets.to_vec()),
    };
    let mut start = 0;
    for (index, &end) in offsets.iter().enumerate() {
        let ids = connectivity.get(start..end).ok_or_else(|| {
            OutputError::invalid(
                path,
                format!(
                    "polygon {index}: offsets must increase and end within the {} connectivity \
                     entries, got {start}..{end}",
                    connectivity.len()
                ),
            )
        })?;
        let cell_type = if cell_tag == "Verts" { CellType::Vertex } else { CellType::Polygon };
        check_cell(path, index, cell_type, ids, n_points)?;
        start = end;
    }
    if start != connectivity.len() {
        return Err(OutputError::invalid(path, format!("the last polygon offset is {start} but there are {} connectivity entries", connectivity.len())));
    }

    let count = |tag: &str| if tag == cell_tag { n_cells } else { 0 };
    let document = Document {
        dataset: "PolyData",
        piece_attributes: vec![
            ("NumberOfPoints", n_points),
            ("NumberOfVerts", count("Verts")),
            ("NumberOfLines", 0),
            ("NumberOfStrips", 0),
            ("NumberOfPolys", count("Polys")),
        ],
        sections: vec![
            field_section(path, "PointData", &poly.point_data, n_points)?,
            field_section(path, "CellData", &poly.cell_data, n_cells)?,
            points_section(path, poly.points)?,
            Section {
                tag: cell_tag,
                arrays: vec![
                    DataArray::int("connectivity", 1, Cow::Owned(to_i64(path, "connectivity", &connectivity)?)),
                    DataArray::int("offsets", 1, Cow::Owned(to_i64(path, "offsets", &offsets)?)),
                ],
            },
        ],
    };
    write_document(path, &document, encoding)
}

fn check_cell(path: &Path, index: usize, cell_type: CellType, ids: &[usize], n_points: usize) -> Result<(), OutputError> {
    if !cell_type.accepts_point_count(ids.len()) {
        return Err(OutputError::invalid(
            path,
            format!(
                "cell {index} ({cell_type:?}) has {} point ids; allowed: {}",
                ids.len(),
                match cell_type.point_count() {
                    Some(n) => format!("exactly {n}"),
                    None => "3 or more".to_string(),
                }
            ),
        ));
    }
    if let Some(&bad) = ids.iter().find(|&&id| id >= n_points) {
        return Err(OutputError::invalid(path, format!("cell {index} refers to point {bad}, but there are only {n_points} points")));
    }
    Ok(())
}

fn to_i64(path: &Path, what: &str, values: &[usize]) -> Result<Vec<i64>, OutputError> {
    values.iter().map(|&v| i64::try_from(v).map_err(|_| OutputError::invalid(path, format!("{what} value {v} does not fit in Int64")))).collect()
}

/// The numbers of one `DataArray`.
enum Numbers<'a> {
    F64(&'a [f64]),
    I64(Cow<'a, [i64]>),
    U8(Vec<u8>),
}

struct DataArray<'a> {
    name: &'a str,
    components: usize,
    numbers: Numbers<'a>,
}

impl<'a> DataArray<'a> {
    fn int(name: &'a str, components: usize, values: Cow<'a, [i64]>) -> Self {
        DataArray { name, components, numbers: Numbers::I64(values) }
    }

    fn vtk_type(&self) -> &'static str {
        match self.numbers {
            Numbers::F64(_) => "Float64",
            Numbers::I64(_) => "Int64",
            Numbers::U8(_) => "UInt8",
        }
    }

    fn byte_count(&self) -> usize {
        match &self.numbers {
            Numbers::F64(v) => 8 * v.len(),
            Numbers::I64(v) => 8 * v.len(),
            Numbers::U8(v) => v.len(),
        }
    }

    fn write_ascii(&self, w: &mut impl Write) -> std::io::Result<()> {
        // One tuple per line for vectors, a few numbers per line for scalars: readable, and
        // lines stay short for text tools.
        let per_line = if self.components > 1 { self.components } else { 8 };
        let line = |w: &mut dyn Write, i: usize, text: String| -> std::io::Result<()> {
            #[allow(clippy::manual_is_multiple_of)] // is_multiple_of needs Rust 1.87; MSRV 1.85
            if i % per_line == 0 {
                write!(w, "\n          {text}")
            } else {
                write!(w, " {text}")
            }
        };
        match &self.numbers {
            Numbers::F64(v) => {
                for (i, x) in v.iter().enumerate() {
                    line(w, i, format_f64(*x))?;
                }
            }
            Numbers::I64(v) => {
                for (i, x) in v.iter().enumerate() {
                    line(w, i, x.to_string())?;
                }
            }
            Numbers::U8(v) => {
                for (i, x) in v.iter().enumerate() {
                    line(w, i, x.to_string())?;
                }
            }
        }
        writeln!(w)
    }

    fn write_raw(&self, w: &mut impl Write) -> std::io::Result<()> {
        w.write_all(&(self.byte_count() as u64).to_le_bytes())?;
        match &self.numbers {
            Numbers::F64(v) => {
                for x in v.iter() {
                    w.write_all(&x.to_le_bytes())?;
                }
            }
            Numbers::I64(v) => {
                for x in v.iter() {
                    w.write_all(&x.to_le_bytes())?;
                }
            }
            Numbers::U8(v) => w.write_all(v)?,
        }
        Ok(())
    }
}

struct Section<'a> {
    tag: &'static str,
    arrays: Vec<DataArray<'a>>,
}

struct Document<'a> {
    dataset: &'static str,
    piece_attributes: Vec<(&'static str, usize)>,
    sections: Vec<Section<'a>>,
}

fn points_section<'a>(path: &Path, points: &'a [[f64; 3]]) -> Result<Section<'a>, OutputError> {
    let flat = points.as_flattened();
    check_finite(path, "point coordinates (flattened x,y,z)", flat)?;
    Ok(Section { tag: "Points", arrays: vec![DataArray { name: "Points", components: 3, numbers: Numbers::F64(flat) }] })
}

/// Checks names, lengths and finiteness of `fields` and turns them into arrays of `tag`.
fn field_section<'a>(path: &Path, tag: &'static str, fields: &[Field<'a>], expected_len: usize) -> Result<Section<'a>, OutputError> {
    let owner = if tag == "PointData" { "points" } else { "cells" };
    let mut names = BTreeSet::new();
    let mut arrays = Vec::with_capacity(fields.len());
    for field in fields {
        check_name(path, tag, field.name)?;
        if !names.insert(field.name) {
            return Err(OutputError::invalid(path, format!("{tag} has two fields named `{}`; names must be unique", field.name)));
        }
        if field.values.len() != expected_len {
            return Err(OutputError::invalid(
                path,
                format!("{tag} field `{}` has {} entries but there are {expected_len} {owner}", field.name, field.values.len()),
            ));
        }
        let (components, numbers) = match field.values {
            FieldValues::Scalar(v) => {
                check_finite(path, field.name, v)?;
                (1, Numbers::F64(v))
            }
            FieldValues::Vector(v) => {
                let flat = v.as_flattened();
                check_finite(path, &format!("{} (flattened components)", field.name), flat)?;
                (3, Numbers::F64(flat))
            }
            FieldValues::Int(v) => (1, Numbers::I64(Cow::Borrowed(v))),
        };
        arrays.push(DataArray { name: field.name, components, numbers });
    }
    Ok(Section { tag, arrays })
}

fn check_name(path: &Path, tag: &str, name: &str) -> Result<(), OutputError> {
    if name.trim().is_empty() || name.chars().any(char::is_control) {
        return Err(OutputError::invalid(path, format!("{tag} field name {name:?} must be non-empty and free of control characters")));
    }
    Ok(())
}

/// Escapes the five XML special characters for use inside an attribute value.
pub(crate) fn xml_escape(text: &str) -> Cow<'_, str> {
    if !text.contains(['&', '<', '>', '"', '\'']) {
        return Cow::Borrowed(text);
    }
    let mut escaped = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match c {
            '&' => escaped.push_str("&amp;"),
            '<' => escaped.push_str("&lt;"),
            '>' => escaped.push_str("&gt;"),
            '"' => escaped.push_str("&quot;"),
            '\'' => escaped.push_str("&apos;"),
            _ => escaped.push(c),
        }
    }
    Cow::Owned(escaped)
}

fn write_document(path: &Path, document: &Document, encoding: Encoding) -> Result<(), OutputError> {
    write_atomically(path, |w| write_document_to(w, document, encoding).map_err(|e| OutputError::io(path, e)))
}

fn write_document_to(w: &mut impl Write, document: &Document, encoding: Encoding) -> std::io::Result<()> {
    let dataset = document.dataset;
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"{dataset}\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">"
    )?;
    writeln!(w, "  <{dataset}>")?;
    write!(w, "    <Piece")?;
    for (name, value) in &document.piece_attributes {
        write!(w, " {name}=\"{value}\"")?;
    }
    writeln!(w, ">")?;
    let mut appended_offset: usize = 0;
    for section in &document.sections {
        writeln!(w, "      <{}>", section.tag)?;
        for array in &section.arrays {
            write!(w, "        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\"", array.vtk_type(), xml_escape(array.name), array.components)?;
            match encoding {
                Encoding::Ascii => {
                    write!(w, " format=\"ascii\">")?;
                    array.write_ascii(w)?;
                    writeln!(w, "        </DataArray>")?;
                }
                Encoding::AppendedRaw => {
                    writeln!(w, " format=\"appended\" offset=\"{appended_offset}\"/>")?;
                    appended_offset += 8 + array.byte_count();
                }
            }
        }
        writeln!(w, "      </{}>", section.tag)?;
    }
    writeln!(w, "    </Piece>")?;
    writeln!(w, "  </{dataset}>")?;
    if encoding == Encoding::AppendedRaw {
        write!(w, "  <AppendedData encoding=\"raw\">\n   _")?;
        for section in &document.sections {
            for array in &section.arrays {
                array.write_raw(w)?;
            }
        }
        writeln!(w, "\n  </AppendedData>")?;
    }
    writeln!(w, "</VTKFile>")
}
