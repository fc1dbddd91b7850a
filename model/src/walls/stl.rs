//! STL reader (ASCII and binary) with errors naming the file.

use std::collections::BTreeMap;
use std::path::Path;

use super::geometry::TriangleMesh;
use super::state::Vec3;

/// Reads an STL file, merging bit-identical vertices; `scale` multiplies all coordinates.
pub fn read_stl(path: &Path, scale: f64) -> Result<TriangleMesh, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read STL file {}: {e}", path.display()))?;
    let triangles = parse_stl(&bytes).map_err(|e| format!("STL file {}: {e}", path.display()))?;
    if triangles.is_empty() {
        return Err(format!("STL file {} contains no triangles", path.display()));
    }
    Ok(merge_vertices(&triangles, scale))
}

/// The triangles (three corners each) of STL data, ASCII or binary.
pub fn parse_stl(bytes: &[u8]) -> Result<Vec<[Vec3; 3]>, String> {
    // Binary files may also begin with "solid"; the size formula decides.
    if bytes.len() >= 84 {
        let count = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        if bytes.len() == 84 + 50 * count {
            return Ok(parse_binary(bytes, count));
        }
    }
    let text = std::str::from_utf8(bytes).map_err(|_| "neither a binary STL (size does not match the triangle count) nor UTF-8 text".to_string())?;
    if !text.trim_start().starts_with("solid") {
        return Err("neither a binary STL (size does not match the triangle count) nor ASCII STL (no leading `solid`)".into());
    }
    parse_ascii(text)
}

fn parse_binary(bytes: &[u8], count: usize) -> Vec<[Vec3; 3]> {
    let f = |at: usize| f32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]) as f64;
    (0..count)
        .map(|t| {
            let base = 84 + 50 * t + 12; // skip the stored normal
            let corner = |k: usize| Vec3::new(f(base + 12 * k), f(base + 12 * k + 4), f(base + 12 * k + 8));
            [corner(0), corner(1), corner(2)]
        })
        .collect()
}

fn parse_ascii(text: &str) -> Result<Vec<[Vec3; 3]>, String> {
    let mut triangles = Vec::new();
    let mut corners: Vec<Vec3> = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("vertex") => {
                let numbers: Result<Vec<f64>, _> = words.map(str::parse::<f64>).collect();
                match numbers {
                    Ok(v) if v.len() == 3 && v.iter().all(|x| x.is_finite()) => corners.push(Vec3::new(v[0], v[1], v[2])),
                    _ => return Err(format!("line {}: `vertex` needs three finite numbers, found `{}`", n + 1, line.trim())),
                }
            }
            Some("endloop") => {
                if corners.len() != 3 {
                    return Err(format!("line {}: a facet needs exactly 3 vertices, found {}", n + 1, corners.len()));
                }
                triangles.push([corners[0], corners[1], corners[2]]);
                corners.clear();
            }
            _ => {}
        }
    }
    Ok(triangles)
}

fn merge_vertices(triangles: &[[Vec3; 3]], scale: f64) -> TriangleMesh {
    let mut index: BTreeMap<[u64; 3], u32> = BTreeMap::new();
    let mut mesh = TriangleMesh::default();
    for t in triangles {
        let mut ids = [0u32; 3];
        for (k, v) in t.iter().enumerate() {
            let key = [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
            ids[k] = *index.entry(key).or_insert_with(|| {
                mesh.vertices.push(v * scale);
                (mesh.vertices.len() - 1) as u32
            });
        }
        mesh.triangles.push(ids);
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    const ASCII: &str = "solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\n facet normal 0 0 1\n  outer loop\n   vertex 1 0 0\n   vertex 1 1 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid t\n";

    #[test]
    fn ascii_and_binary_give_the_same_mesh() {
        let a = parse_stl(ASCII.as_bytes()).unwrap();
        let mut bin = vec![0u8; 80];
        bin.extend_from_slice(&(a.len() as u32).to_le_bytes());
        for t in &a {
            bin.extend_from_slice(&[0u8; 12]);
            for v in t {
                for x in [v.x, v.y, v.z] {
                    bin.extend_from_slice(&(x as f32).to_le_bytes());
                }
            }
            bin.extend_from_slice(&[0u8; 2]);
        }
        assert_eq!(parse_stl(&bin).unwrap(), a);
        let mesh = merge_vertices(&a, 2.0);
        assert_eq!(mesh.vertices.len(), 4);
        assert_eq!(mesh.triangles.len(), 2);
        assert_eq!(mesh.vertices[1], Vec3::new(2.0, 0.0, 0.0));
    }

    #[test]
    fn bad_files_give_errors() {
        assert!(parse_stl(b"hello").unwrap_err().contains("ASCII"));
        let bad = ASCII.replace("vertex 1 1 0", "vertex 1 x 0");
        assert!(parse_stl(bad.as_bytes()).unwrap_err().contains("`vertex 1 x 0`"));
        let e = read_stl(Path::new("/nonexistent/part.stl"), 1.0).unwrap_err();
        assert!(e.contains("/nonexistent/part.stl"));
    }
}
