//! A strict reader for the VTK XML files this crate writes (`.vtu`, `.vtp`; ASCII or raw appended,
//! UInt64 headers). It exists to prove the files are what ParaView expects: it refuses anything
//! missing a required attribute or disagreeing with itself, rather than guessing.

use super::data::{CellType, Encoding};
use crate::output::OutputError;
use std::collections::BTreeMap;
use std::path::Path;

/// The numbers of one array read back.
#[derive(Clone, Debug, PartialEq)]
pub enum ArrayValues {
    Float64(Vec<f64>),
    Int64(Vec<i64>),
    UInt8(Vec<u8>),
}

impl ArrayValues {
    pub fn len(&self) -> usize {
        match self {
            ArrayValues::Float64(v) => v.len(),
            ArrayValues::Int64(v) => v.len(),
            ArrayValues::UInt8(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    pub fn as_f64(&self) -> Option<&[f64]> {
        match self {
            ArrayValues::Float64(v) => Some(v),
            _ => None,
        }
    }

    pub fn as_i64(&self) -> Option<&[i64]> {
        match self {
            ArrayValues::Int64(v) => Some(v),
            _ => None,
        }
    }
}

/// One `DataArray` read back.
#[derive(Clone, Debug, PartialEq)]
pub struct ReadArray {
    pub name: String,
    pub components: usize,
    pub values: ArrayValues,
}

impl ReadArray {
    /// The values grouped into 3-vectors, when the array has three components of Float64.
    pub fn as_vectors(&self) -> Option<Vec<[f64; 3]>> {
        match (&self.values, self.components) {
            (ArrayValues::Float64(v), 3) => Some(v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()),
            _ => None,
        }
    }
}

/// A cell block (`Cells` of a grid, `Verts`/`Polys` of poly data) read back.
#[derive(Clone, Debug, PartialEq)]
pub struct ReadCells {
    pub connectivity: Vec<i64>,
    pub offsets: Vec<i64>,
    /// VTK cell type numbers; only `Cells` of an unstructured grid has them.
    pub types: Option<Vec<u8>>,
}

/// A whole `.vtu` or `.vtp` file read back and checked.
#[derive(Clone, Debug, PartialEq)]
pub struct VtkDataset {
    /// `UnstructuredGrid` or `PolyData`.
    pub dataset_type: String,
    pub version: String,
    pub encoding: Encoding,
    pub points: Vec<[f64; 3]>,
    /// Keyed by element name: `Cells`, `Verts` or `Polys`.
    pub cell_blocks: BTreeMap<String, ReadCells>,
    pub point_data: Vec<ReadArray>,
    pub cell_data: Vec<ReadArray>,
}

impl VtkDataset {
    pub fn point_field(&self, name: &str) -> Option<&ReadArray> {
        self.point_data.iter().find(|a| a.name == name)
    }

    pub fn cell_field(&self, name: &str) -> Option<&ReadArray> {
        self.cell_data.iter().find(|a| a.name == name)
    }

    pub fn number_of_cells(&self) -> usize {
        self.cell_blocks.values().map(|b| b.offsets.len()).sum()
    }
}

/// Reads and checks a `.vtu` or `.vtp` file written by [`super::write_vtu`] / [`super::write_vtp`].
pub fn read_vtk(path: &Path) -> Result<VtkDataset, OutputError> {
    let bytes = std::fs::read(path).map_err(|e| OutputError::io(path, e))?;
    let bad = |message: String| OutputError::malformed(path, message);
    let (xml_text, appended) = split_appended_data(&bytes).map_err(bad)?;
    let document = roxmltree::Document::parse(&xml_text).map_err(|e| bad(format!("not well-formed XML: {e}")))?;
    let mut reader = ArrayReader { appended, blocks: Vec::new() };
    let dataset = read_document(&document, &mut reader).map_err(bad)?;
    reader.check_appended_blocks_tile_the_data().map_err(bad)?;
    Ok(dataset)
}

/// Splits the file into the XML text (with the raw bytes cut out) and the raw appended bytes.
fn split_appended_data(bytes: &[u8]) -> Result<(String, Option<&[u8]>), String> {
    let Some(open) = find(bytes, b"<AppendedData") else {
        let text = std::str::from_utf8(bytes).map_err(|e| format!("not UTF-8 text: {e}"))?;
        return Ok((text.to_string(), None));
    };
    let tag_end = open + find(&bytes[open..], b">").ok_or("unterminated <AppendedData> tag")?;
    let underscore = tag_end + find(&bytes[tag_end..], b"_").ok_or("<AppendedData> without the `_` data marker")?;
    if !bytes[tag_end + 1..underscore].iter().all(u8::is_ascii_whitespace) {
        return Err("text between <AppendedData> and the `_` marker".to_string());
    }
    let close = rfind(bytes, b"</AppendedData>").ok_or("no </AppendedData> closing tag")?;
    if close < underscore {
        return Err("</AppendedData> before the `_` marker".to_string());
    }
    let mut xml = Vec::with_capacity(underscore + bytes.len() - close);
    xml.extend_from_slice(&bytes[..underscore]);
    xml.extend_from_slice(&bytes[close..]);
    let text = String::from_utf8(xml).map_err(|e| format!("XML part is not UTF-8: {e}"))?;
    Ok((text, Some(&bytes[underscore + 1..close])))
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

fn rfind(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).rposition(|w| w == needle)
}

type Node<'a, 'input> = roxmltree::Node<'a, 'input>;

fn required<'a>(node: Node<'a, '_>, attribute: &str) -> Result<&'a str, String> {
    node.attribute(attribute).ok_or_else(|| format!("<{}> lacks the required attribute `{attribute}`", node.tag_name().name()))
}

fn required_count(node: Node, attribute: &str) -> Result<usize, String> {
    let text = required(node, attribute)?;
    text.parse().map_err(|_| format!("`{attribute}` = {text:?} is not a non-negative integer"))
}

fn element_children<'a, 'input>(node: Node<'a, 'input>) -> impl Iterator<Item = Node<'a, 'input>> {
    node.children().filter(|c| c.is_element())
}

fn read_document(document: &roxmltree::Document, reader: &mut ArrayReader) -> Result<VtkDataset, String> {
    let root = document.root_element();
    if root.tag_name().name() != "VTKFile" {
        return Err(format!("root element is <{}>, expected <VTKFile>", root.tag_name().name()));
    }
    let dataset_type = required(root, "type")?.to_string();
    let version = required(root, "version")?.to_string();
    let byte_order = required(root, "byte_order")?;
    if byte_order != "LittleEndian" {
        return Err(format!("byte_order {byte_order:?}; this reader handles LittleEndian"));
    }
    let header_type = required(root, "header_type")?;
    if header_type != "UInt64" {
        return Err(format!("header_type {header_type:?}; this reader handles UInt64"));
    }
    if version != "1.0" {
        return Err(format!("version {version:?}; header_type needs file version 1.0"));
    }
    let mut children = element_children(root);
    let dataset_node = children.next().ok_or("<VTKFile> has no dataset element")?;
    if dataset_node.tag_name().name() != dataset_type {
        return Err(format!("type=\"{dataset_type}\" but the dataset element is <{}>", dataset_node.tag_name().name()));
    }
    match children.next() {
        None => {}
        Some(n) if n.tag_name().name() == "AppendedData" => {
            let encoding = required(n, "encoding")?;
            if encoding != "raw" {
                return Err(format!("AppendedData encoding {encoding:?}; expected \"raw\""));
            }
        }
        Some(n) => return Err(format!("unexpected <{}> in <VTKFile>", n.tag_name().name())),
    }

    let pieces: Vec<_> = element_children(dataset_node).collect();
    let [piece] = pieces.as_slice() else {
        return Err(format!("expected exactly one <Piece>, found {}", pieces.len()));
    };
    let n_points = required_count(*piece, "NumberOfPoints")?;
    let block_counts: Vec<(&str, usize)> = match dataset_type.as_str() {
        "UnstructuredGrid" => vec![("Cells", required_count(*piece, "NumberOfCells")?)],
        "PolyData" => {
            let mut counts = Vec::new();
            for (element, attribute) in [("Verts", "NumberOfVerts"), ("Lines", "NumberOfLines"), ("Strips", "NumberOfStrips"), ("Polys", "NumberOfPolys")] {
                counts.push((element, required_count(*piece, attribute)?));
            }
            counts
        }
        other => return Err(format!("dataset type {other:?} is not read here")),
    };
    let n_cells: usize = block_counts.iter().map(|(_, n)| n).sum();

    let mut points = None;
    let mut point_data = None;
    let mut cell_data = None;
    let mut cell_blocks = BTreeMap::new();
    let mut encodings = Vec::new();
    for section in element_children(*piece) {
        let tag = section.tag_name().name();
        let arrays = element_children(section).map(|a| reader.read(a, &mut encodings)).collect::<Result<Vec<_>, _>>().map_err(|e| format!("<{tag}>: {e}"))?;
        match tag {
            "Points" => {
                let [array] = arrays.as_slice() else {
                    return Err(format!("<Points> holds {} arrays, expected 1", arrays.len()));
                };
                if array.components != 3 {
                    return Err("<Points> array must have NumberOfComponents=\"3\"".to_string());
                }
                let coordinates = array.as_vectors().ok_or("<Points> array must be Float64")?;
                check_tuples("Points", array, n_points)?;
                set_once(&mut points, coordinates, tag)?;
            }
            "PointData" => {
                for array in &arrays {
                    check_tuples("PointData", array, n_points)?;
                }
                set_once(&mut point_data, arrays, tag)?;
            }
            "CellData" => {
                for array in &arrays {
                    check_tuples("CellData", array, n_cells)?;
                }
                set_once(&mut cell_data, arrays, tag)?;
            }
            _ => {
                let Some(&(_, count)) = block_counts.iter().find(|(t, _)| *t == tag) else {
                    return Err(format!("unexpected <{tag}> in a {dataset_type} piece"));
                };
                let block = cell_block(tag, arrays, count, n_points, dataset_type == "UnstructuredGrid")?;
                if cell_blocks.insert(tag.to_string(), block).is_some() {
                    return Err(format!("<{tag}> appears twice"));
                }
            }
        }
    }
    for (tag, count) in &block_counts {
        if *count > 0 && !cell_blocks.contains_key(*tag) {
            return Err(format!("the piece declares {count} {tag} but has no <{tag}> element"));
        }
    }
    if dataset_type == "UnstructuredGrid" && !cell_blocks.contains_key("Cells") {
        return Err("an UnstructuredGrid piece needs a <Cells> element".to_string());
    }
    encodings.dedup();
    let encoding = match encodings.as_slice() {
        [] | [Encoding::Ascii] => Encoding::Ascii,
        [Encoding::AppendedRaw] => Encoding::AppendedRaw,
        _ => return Err("arrays mix ascii and appended formats".to_string()),
    };
    if (encoding == Encoding::AppendedRaw) != reader.appended.is_some() {
        return Err("appended arrays and the <AppendedData> section must come together".to_string());
    }
    Ok(VtkDataset {
        dataset_type,
        version,
        encoding,
        points: points.ok_or("the piece has no <Points>")?,
        cell_blocks,
        point_data: point_data.ok_or("the piece has no <PointData>")?,
        cell_data: cell_data.ok_or("the piece has no <CellData>")?,
    })
}

fn set_once<T>(slot: &mut Option<T>, value: T, tag: &str) -> Result<(), String> {
    if slot.replace(value).is_some() {
        return Err(format!("<{tag}> appears twice"));
    }
    Ok(())
}

fn check_tuples(section: &str, array: &ReadArray, expected: usize) -> Result<(), String> {
    let expected_values = expected * array.components;
    if array.values.len() != expected_values {
        return Err(format!(
            "<{section}> array `{}` holds {} values; {expected} tuples of {} components need {expected_values}",
            array.name,
            array.values.len(),
            array.components
        ));
    }
    Ok(())
}

fn cell_block(tag: &str, arrays: Vec<ReadArray>, count: usize, n_points: usize, with_types: bool) -> Result<ReadCells, String> {
    let mut by_name: BTreeMap<String, ArrayValues> = arrays.into_iter().map(|a| (a.name, a.values)).collect();
    let mut take_int = |name: &str| -> Result<Vec<i64>, String> {
        match by_name.remove(name) {
            Some(ArrayValues::Int64(v)) => Ok(v),
            Some(_) => Err(format!("<{tag}> array `{name}` must be Int64")),
            None => Err(format!("<{tag}> lacks the `{name}` array")),
        }
    };
    let connectivity = take_int("connectivity")?;
    let offsets = take_int("offsets")?;
    if offsets.len() != count {
        return Err(format!("<{tag}> has {} offsets but the piece declares {count} cells", offsets.len()));
    }
    let mut start = 0i64;
    for (i, &end) in offsets.iter().enumerate() {
        if end <= start {
            return Err(format!("<{tag}> offsets must increase: cell {i} ends at {end} after {start}"));
        }
        start = end;
    }
    if start != connectivity.len() as i64 {
        return Err(format!("<{tag}> last offset {start} but {} connectivity entries", connectivity.len()));
    }
    if let Some(&bad) = connectivity.iter().find(|&&id| id < 0 || id as usize >= n_points) {
        return Err(format!("<{tag}> refers to point {bad} of {n_points}"));
    }
    let types = if with_types {
        let types = match by_name.remove("types") {
            Some(ArrayValues::UInt8(v)) => v,
            Some(_) => return Err(format!("<{tag}> array `types` must be UInt8")),
            None => return Err(format!("<{tag}> lacks the `types` array")),
        };
        if types.len() != count {
            return Err(format!("<{tag}> has {} types for {count} cells", types.len()));
        }
        let mut start = 0;
        for (i, (&t, &end)) in types.iter().zip(&offsets).enumerate() {
            let cell_type = CellType::from_vtk_id(t).ok_or_else(|| format!("<{tag}> cell {i} has unknown VTK type {t}"))?;
            let n = (end - start) as usize;
            if !cell_type.accepts_point_count(n) {
                return Err(format!("<{tag}> cell {i} is {cell_type:?} with {n} points"));
            }
            start = end;
        }
        Some(types)
    } else {
        None
    };
    if let Some(extra) = by_name.keys().next() {
        return Err(format!("<{tag}> has an unexpected array `{extra}`"));
    }
    Ok(ReadCells { connectivity, offsets, types })
}

/// Decodes `DataArray`s, remembering where each appended one sat in the raw bytes.
struct ArrayReader<'b> {
    appended: Option<&'b [u8]>,
    /// (offset, header + payload length) of each appended array read.
    blocks: Vec<(usize, usize)>,
}

impl ArrayReader<'_> {
    fn read(&mut self, node: Node, encodings: &mut Vec<Encoding>) -> Result<ReadArray, String> {
        if node.tag_name().name() != "DataArray" {
            return Err(format!("unexpected <{}>", node.tag_name().name()));
        }
        let name = required(node, "Name")?.to_string();
        let vtk_type = required(node, "type")?;
        let format = required(node, "format")?;
        let components = required_count(node, "NumberOfComponents")?;
        if components == 0 {
            return Err(format!("`{name}` has NumberOfComponents=\"0\""));
        }
        let values = match format {
            "ascii" => {
                encodings.push(Encoding::Ascii);
                let tokens = node.text().unwrap_or("").split_whitespace();
                parse_ascii(vtk_type, tokens).map_err(|e| format!("`{name}`: {e}"))?
            }
            "appended" => {
                encodings.push(Encoding::AppendedRaw);
                let offset = required_count(node, "offset")?;
                let payload = self.payload(offset).map_err(|e| format!("`{name}`: {e}"))?;
                decode_raw(vtk_type, payload).map_err(|e| format!("`{name}`: {e}"))?
            }
            other => return Err(format!("`{name}` has format {other:?}; expected ascii or appended")),
        };
        if values.len() % components != 0 {
            return Err(format!("`{name}` holds {} values, not a multiple of its {components} components", values.len()));
        }
        if let ArrayValues::Float64(v) = &values {
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err(format!("`{name}` has the non-finite value {} at {i}", v[i]));
            }
        }
        Ok(ReadArray { name, components, values })
    }

    fn payload(&mut self, offset: usize) -> Result<&[u8], String> {
        let data = self.appended.ok_or("appended array but no <AppendedData>")?;
        let header = data.get(offset..offset + 8).ok_or_else(|| format!("offset {offset} is past the appended data ({} bytes)", data.len()))?;
        let length = u64::from_le_bytes(header.try_into().expect("8 bytes")) as usize;
        let payload = data.get(offset + 8..offset + 8 + length).ok_or_else(|| format!("its {length} bytes at offset {offset} overrun the appended data"))?;
        self.blocks.push((offset, 8 + length));
        Ok(payload)
    }

    /// The appended arrays must follow each other without gap or overlap from offset 0, and only
    /// the whitespace before `</AppendedData>` may follow the last one.
    fn check_appended_blocks_tile_the_data(&self) -> Result<(), String> {
        let Some(data) = self.appended else {
            return Ok(());
        };
        let mut blocks = self.blocks.clone();
        blocks.sort_unstable();
        let mut next = 0;
        for (offset, length) in blocks {
            if offset != next {
                return Err(format!("appended array at offset {offset}, expected {next}"));
            }
            next = offset + length;
        }
        if !data[next..].iter().all(u8::is_ascii_whitespace) {
            return Err(format!("{} unexplained bytes after the last appended array", data.len() - next));
        }
        Ok(())
    }
}

fn parse_ascii<'t>(vtk_type: &str, tokens: impl Iterator<Item = &'t str>) -> Result<ArrayValues, String> {
    fn all<T: std::str::FromStr>(tokens: impl Iterator<Item = impl AsRef<str>>) -> Result<Vec<T>, String> {
        tokens.map(|t| t.as_ref().parse().map_err(|_| format!("cannot parse {:?}", t.as_ref()))).collect()
    }
    Ok(match vtk_type {
        "Float64" => ArrayValues::Float64(all(tokens)?),
        "Int64" => ArrayValues::Int64(all(tokens)?),
        "UInt8" => ArrayValues::UInt8(all(tokens)?),
        other => return Err(format!("type {other:?} is not one this crate writes")),
    })
}

fn decode_raw(vtk_type: &str, bytes: &[u8]) -> Result<ArrayValues, String> {
    let eight = |what: &str| -> Result<std::slice::ChunksExact<'_, u8>, String> {
        #[allow(clippy::manual_is_multiple_of)] // is_multiple_of needs Rust 1.87; MSRV is 1.85
        if bytes.len() % 8 != 0 {
            return Err(format!("{} bytes is not a whole number of {what}", bytes.len()));
        }
        Ok(bytes.chunks_exact(8))
    };
    Ok(match vtk_type {
        "Float64" => ArrayValues::Float64(eight("Float64")?.map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes"))).collect()),
        "Int64" => ArrayValues::Int64(eight("Int64")?.map(|c| i64::from_le_bytes(c.try_into().expect("8 bytes"))).collect()),
        "UInt8" => ArrayValues::UInt8(bytes.to_vec()),
        other => return Err(format!("type {other:?} is not one this crate writes")),
    })
}
