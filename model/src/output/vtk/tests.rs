//! Write-then-read tests of the VTK files: the strict reader checks ParaView's required attributes,
//! counts against array lengths, cell layouts, and that every value comes back bit for bit.

use super::*;
use crate::output::{test_dir, OutputError};
use std::path::Path;

const BOTH: [Encoding; 2] = [Encoding::Ascii, Encoding::AppendedRaw];

/// Values whose decimal text is long or extreme, to catch any lossy formatting.
fn awkward(i: usize) -> f64 {
    let base = [1.0 / 3.0, -2.0 / 7.0, 1e-300, -6.02214076e23, 0.1, 5e-324, 0.0, 1e15 + 0.5];
    base[i % base.len()] * (1.0 + i as f64)
}

/// Two unit hexahedra side by side along x: 12 points, VTK point order per cell.
fn two_hexahedra() -> (Vec<[f64; 3]>, UnstructuredCells) {
    let mut points = Vec::new();
    for k in 0..2 {
        for j in 0..2 {
            for i in 0..3 {
                points.push([i as f64, j as f64, k as f64 + awkward(i + 3 * j) * 1e-3]);
            }
        }
    }
    let id = |i: usize, j: usize, k: usize| i + 3 * j + 6 * k;
    let hex = |i: usize| [id(i, 0, 0), id(i + 1, 0, 0), id(i + 1, 1, 0), id(i, 1, 0), id(i, 0, 1), id(i + 1, 0, 1), id(i + 1, 1, 1), id(i, 1, 1)];
    (points, UnstructuredCells::hexahedra(&[hex(0), hex(1)]))
}

fn assert_bits_equal(read: &[f64], written: &[f64], what: &str) {
    assert_eq!(read.len(), written.len(), "{what}: length");
    for (i, (r, w)) in read.iter().zip(written).enumerate() {
        assert_eq!(r.to_bits(), w.to_bits(), "{what}[{i}]: read {r:e}, wrote {w:e}");
    }
}

fn text_of(path: &Path) -> String {
    String::from_utf8_lossy(&std::fs::read(path).unwrap()).into_owned()
}

#[test]
fn hexahedral_grid_round_trips_in_both_encodings() {
    let dir = test_dir::fresh("vtu_round_trip");
    let (points, cells) = two_hexahedra();
    let pressure = [awkward(1), awkward(2)];
    let velocity = [[awkward(3), awkward(4), awkward(5)], [0.0, -1.5, 2.25]];
    let owner = [7_i64, -3];
    let node_scalar: Vec<f64> = (0..points.len()).map(awkward).collect();
    for encoding in BOTH {
        let path = dir.join(format!("grid_{encoding:?}.vtu"));
        let grid = UnstructuredGrid {
            points: &points,
            cells: &cells,
            point_data: vec![Field::scalar("phi", &node_scalar)],
            cell_data: vec![Field::scalar("p", &pressure), Field::vector("U", &velocity), Field::int("owner", &owner)],
        };
        write_vtu(&path, &grid, encoding).unwrap();
        let read = read_vtk(&path).unwrap();
        assert_eq!(read.dataset_type, "UnstructuredGrid");
        assert_eq!(read.encoding, encoding);
        assert_eq!(read.points, points);
        let block = &read.cell_blocks["Cells"];
        assert_eq!(block.types, Some(vec![12, 12]));
        assert_eq!(block.offsets, vec![8, 16]);
        let written_ids: Vec<i64> = (0..2).flat_map(|c| cells.cell(c).1.iter().map(|&i| i as i64)).collect();
        assert_eq!(block.connectivity, written_ids);
        assert_bits_equal(read.cell_field("p").unwrap().values.as_f64().unwrap(), &pressure, "p");
        let u = read.cell_field("U").unwrap();
        assert_eq!(u.components, 3);
        assert_eq!(u.as_vectors().unwrap(), velocity.to_vec());
        assert_eq!(read.cell_field("owner").unwrap().values.as_i64().unwrap(), &owner);
        assert_bits_equal(read.point_field("phi").unwrap().values.as_f64().unwrap(), &node_scalar, "phi");

        // The attributes ParaView's reader requires, as literal text.
        let text = text_of(&path);
        for required in [
            "type=\"UnstructuredGrid\"",
            "version=\"1.0\"",
            "byte_order=\"LittleEndian\"",
            "header_type=\"UInt64\"",
            "NumberOfPoints=\"12\"",
            "NumberOfCells=\"2\"",
            "Name=\"connectivity\"",
            "Name=\"offsets\"",
            "Name=\"types\" NumberOfComponents=\"1\"",
            "type=\"UInt8\"",
            "NumberOfComponents=\"3\"",
        ] {
            assert!(text.contains(required), "{encoding:?} file lacks {required}");
        }
        if encoding == Encoding::AppendedRaw {
            assert!(text.contains("<AppendedData encoding=\"raw\">"));
        }
    }
}

#[test]
fn mixed_cell_types_keep_their_vtk_numbers() {
    let dir = test_dir::fresh("vtu_mixed");
    let points: Vec<[f64; 3]> = (0..14).map(|i| [i as f64, (i * i) as f64, 0.5]).collect();
    let mut cells = UnstructuredCells::new();
    cells.push(CellType::Hexahedron, &[0, 1, 2, 3, 4, 5, 6, 7]);
    cells.push(CellType::Wedge, &[8, 9, 10, 11, 12, 13]);
    cells.push(CellType::Tetra, &[0, 2, 4, 13]);
    let grid = UnstructuredGrid { points: &points, cells: &cells, point_data: vec![], cell_data: vec![] };
    for encoding in BOTH {
        let path = dir.join(format!("mixed_{encoding:?}.vtu"));
        write_vtu(&path, &grid, encoding).unwrap();
        let block = &read_vtk(&path).unwrap().cell_blocks["Cells"];
        assert_eq!(block.types, Some(vec![12, 13, 10]));
        assert_eq!(block.offsets, vec![8, 14, 18]);
    }
}

#[test]
fn particles_round_trip_as_vertices_with_point_fields() {
    let dir = test_dir::fresh("vtp_particles");
    let n = 37;
    let centres: Vec<[f64; 3]> = (0..n).map(|i| [awkward(i), awkward(i + 1), awkward(i + 2)]).collect();
    let ids: Vec<i64> = (0..n as i64).map(|i| 1000 + 3 * i).collect();
    let diameter: Vec<f64> = (0..n).map(|i| 0.01 + 1e-4 * i as f64).collect();
    let velocity: Vec<[f64; 3]> = (0..n).map(|i| [awkward(i + 5), 0.0, -(i as f64)]).collect();
    let spin: Vec<[f64; 3]> = (0..n).map(|i| [0.0, awkward(i + 7), 1.0]).collect();
    let contacts: Vec<i64> = (0..n as i64).map(|i| i % 4).collect();
    for encoding in BOTH {
        let path = dir.join(format!("particles_{encoding:?}.vtp"));
        let poly = PolyData::particles(
            &centres,
            vec![
                Field::int("id", &ids),
                Field::scalar("diameter", &diameter),
                Field::vector("velocity", &velocity),
                Field::vector("angular_velocity", &spin),
                Field::int("contacts", &contacts),
            ],
        );
        write_vtp(&path, &poly, encoding).unwrap();
        let read = read_vtk(&path).unwrap();
        assert_eq!(read.dataset_type, "PolyData");
        assert_eq!(read.points, centres);
        let verts = &read.cell_blocks["Verts"];
        assert_eq!(verts.connectivity, (0..n as i64).collect::<Vec<_>>());
        assert_eq!(verts.offsets, (1..=n as i64).collect::<Vec<_>>());
        assert_eq!(read.point_field("id").unwrap().values.as_i64().unwrap(), &ids);
        assert_eq!(read.point_field("contacts").unwrap().values.as_i64().unwrap(), &contacts);
        assert_bits_equal(read.point_field("diameter").unwrap().values.as_f64().unwrap(), &diameter, "diameter");
        assert_eq!(read.point_field("velocity").unwrap().as_vectors().unwrap(), velocity);
        assert_eq!(read.point_field("angular_velocity").unwrap().as_vectors().unwrap(), spin);
        let text = text_of(&path);
        for required in [
            "type=\"PolyData\"",
            &format!("NumberOfPoints=\"{n}\""),
            &format!("NumberOfVerts=\"{n}\""),
            "NumberOfLines=\"0\"",
            "NumberOfStrips=\"0\"",
            "NumberOfPolys=\"0\"",
            "type=\"Int64\" Name=\"id\"",
        ] {
            assert!(text.contains(required), "{encoding:?} file lacks {required}");
        }
    }
}

#[test]
fn no_particles_is_a_valid_empty_file() {
    let dir = test_dir::fresh("vtp_empty");
    for encoding in BOTH {
        let path = dir.join(format!("none_{encoding:?}.vtp"));
        let poly = PolyData::particles(&[], vec![Field::scalar("diameter", &[])]);
        write_vtp(&path, &poly, encoding).unwrap();
        let read = read_vtk(&path).unwrap();
        assert!(read.points.is_empty());
        assert_eq!(read.point_field("diameter").unwrap().values.len(), 0);
    }
}

#[test]
fn wall_triangles_round_trip_with_cell_and_point_fields() {
    let dir = test_dir::fresh("vtp_wall");
    // A unit square split into two triangles, plus a tilted third triangle.
    let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.5, 1.0 / 3.0]];
    let triangles = [[0, 1, 2], [0, 2, 3], [1, 2, 4]];
    let wear_depth = [1.5e-7, 0.0, awkward(3)];
    let normals = [[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.6, 0.0, 0.8]];
    let nodal = [0.0, 1.0, 2.0, 3.0, awkward(9)];
    for encoding in BOTH {
        let path = dir.join(format!("wall_{encoding:?}.vtp"));
        let poly = PolyData::triangles(
            &points,
            &triangles,
            vec![Field::scalar("nodal_wear", &nodal)],
            vec![Field::scalar("wear_depth", &wear_depth), Field::vector("normal", &normals)],
        );
        write_vtp(&path, &poly, encoding).unwrap();
        let read = read_vtk(&path).unwrap();
        let polys = &read.cell_blocks["Polys"];
        assert_eq!(polys.connectivity, vec![0, 1, 2, 0, 2, 3, 1, 2, 4]);
        assert_eq!(polys.offsets, vec![3, 6, 9]);
        assert!(!read.cell_blocks.contains_key("Verts"));
        assert_eq!(read.number_of_cells(), 3);
        assert_bits_equal(read.cell_field("wear_depth").unwrap().values.as_f64().unwrap(), &wear_depth, "wear_depth");
        assert_eq!(read.cell_field("normal").unwrap().as_vectors().unwrap(), normals.to_vec());
        assert_bits_equal(read.point_field("nodal_wear").unwrap().values.as_f64().unwrap(), &nodal, "nodal_wear");
        assert!(text_of(&path).contains("NumberOfPolys=\"3\""));
    }
}

#[test]
fn general_polygons_are_written_with_their_offsets() {
    let dir = test_dir::fresh("vtp_polygons");
    let points: Vec<[f64; 3]> = (0..7).map(|i| [i as f64, 0.0, (i % 2) as f64]).collect();
    let poly = PolyData {
        points: &points,
        cells: PolyCells::Polygons { connectivity: &[0, 1, 2, 3, 3, 4, 5, 6, 0], offsets: &[4, 9] },
        point_data: vec![],
        cell_data: vec![Field::int("patch", &[1, 2])],
    };
    let path = dir.join("polygons.vtp");
    write_vtp(&path, &poly, Encoding::AppendedRaw).unwrap();
    let polys = read_vtk(&path).unwrap().cell_blocks["Polys"].clone();
    assert_eq!(polys.offsets, vec![4, 9]);
    assert_eq!(polys.connectivity, vec![0, 1, 2, 3, 3, 4, 5, 6, 0]);
}

#[test]
fn non_finite_values_are_refused_naming_the_field_and_no_file_appears() {
    let dir = test_dir::fresh("vtk_nan");
    let (points, cells) = two_hexahedra();
    let path = dir.join("bad.vtu");
    let grid = UnstructuredGrid {
        points: &points,
        cells: &cells,
        point_data: vec![],
        cell_data: vec![Field::scalar("p", &[1.0, 2.0]), Field::scalar("alpha", &[0.5, f64::NAN])],
    };
    let error = write_vtu(&path, &grid, Encoding::Ascii).unwrap_err();
    match &error {
        OutputError::NonFinite { field, index, .. } => {
            assert_eq!(field, "alpha");
            assert_eq!(*index, 1);
        }
        other => panic!("expected NonFinite, got {other}"),
    }
    assert!(error.to_string().contains("bad.vtu"), "{error}");
    assert!(!path.exists());
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "no temporary left behind");

    let velocity = [[0.0, 0.0, 0.0], [1.0, f64::INFINITY, 0.0]];
    let particles = PolyData::particles(&points[..2], vec![Field::vector("velocity", &velocity)]);
    let error = write_vtp(&dir.join("p.vtp"), &particles, Encoding::AppendedRaw).unwrap_err();
    assert!(error.to_string().contains("velocity"), "{error}");

    let mut bad_points = points.clone();
    bad_points[3][2] = f64::NEG_INFINITY;
    let grid = UnstructuredGrid { points: &bad_points, cells: &cells, point_data: vec![], cell_data: vec![] };
    let error = write_vtu(&path, &grid, Encoding::AppendedRaw).unwrap_err();
    assert!(error.to_string().contains("point coordinates"), "{error}");
}

#[test]
fn inconsistent_input_is_refused_with_a_reason() {
    let dir = test_dir::fresh("vtk_invalid");
    let path = dir.join("bad.vtu");
    let (points, cells) = two_hexahedra();
    let expect_error = |grid: &UnstructuredGrid, fragment: &str| {
        let e = write_vtu(&path, grid, Encoding::Ascii).unwrap_err();
        assert!(e.to_string().contains(fragment), "`{e}` should mention `{fragment}`");
    };
    let base = UnstructuredGrid { points: &points, cells: &cells, point_data: vec![], cell_data: vec![] };
    expect_error(&UnstructuredGrid { cell_data: vec![Field::scalar("p", &[1.0])], ..base.clone() }, "has 1 entries but there are 2 cells");
    expect_error(&UnstructuredGrid { cell_data: vec![Field::scalar("p", &[1.0, 2.0]), Field::int("p", &[1, 2])], ..base.clone() }, "two fields named `p`");
    expect_error(&UnstructuredGrid { point_data: vec![Field::scalar("", &[0.0; 12])], ..base.clone() }, "must be non-empty");
    let mut short = UnstructuredCells::new();
    short.push(CellType::Hexahedron, &[0, 1, 2, 3, 4, 5, 6]);
    expect_error(&UnstructuredGrid { cells: &short, ..base.clone() }, "exactly 8");
    let mut out_of_range = UnstructuredCells::new();
    out_of_range.push(CellType::Tetra, &[0, 1, 2, 12]);
    expect_error(&UnstructuredGrid { cells: &out_of_range, ..base.clone() }, "point 12");
    assert!(!path.exists());

    let triangles = [[0, 1, 99]];
    let wall = PolyData::triangles(&points, &triangles, vec![], vec![]);
    let e = write_vtp(&dir.join("wall.vtp"), &wall, Encoding::Ascii).unwrap_err();
    assert!(e.to_string().contains("point 99"), "{e}");
}

#[test]
fn field_names_with_xml_characters_are_escaped() {
    let dir = test_dir::fresh("vtk_escape");
    let path = dir.join("escape.vtp");
    let poly = PolyData::particles(&[[0.0; 3]], vec![Field::scalar("a<b & \"c\"", &[1.0])]);
    write_vtp(&path, &poly, Encoding::Ascii).unwrap();
    assert!(read_vtk(&path).unwrap().point_field("a<b & \"c\"").is_some());
}

/// The reader is the test oracle, so it must itself fail on broken files.
#[test]
fn reader_rejects_files_that_paraview_would_not_read() {
    let dir = test_dir::fresh("vtk_reader_rejects");
    let (points, cells) = two_hexahedra();
    let grid = UnstructuredGrid { points: &points, cells: &cells, point_data: vec![], cell_data: vec![Field::scalar("p", &[1.0, 2.0])] };
    let ascii = dir.join("ascii.vtu");
    let raw = dir.join("raw.vtu");
    write_vtu(&ascii, &grid, Encoding::Ascii).unwrap();
    write_vtu(&raw, &grid, Encoding::AppendedRaw).unwrap();
    let ascii_text = std::fs::read_to_string(&ascii).unwrap();
    let raw_bytes = std::fs::read(&raw).unwrap();

    let tampered = dir.join("tampered.vtu");
    let rejects = |bytes: &[u8], fragment: &str| {
        std::fs::write(&tampered, bytes).unwrap();
        let e = read_vtk(&tampered).unwrap_err();
        assert!(e.to_string().contains(fragment), "`{e}` should mention `{fragment}`");
    };
    let edit = |from: &str, to: &str| ascii_text.replacen(from, to, 1).into_bytes();
    rejects(&edit(" header_type=\"UInt64\"", ""), "header_type");
    rejects(&edit(" byte_order=\"LittleEndian\"", ""), "byte_order");
    rejects(&edit("NumberOfPoints=\"12\"", "NumberOfPoints=\"11\""), "Points");
    rejects(&edit("NumberOfCells=\"2\"", "NumberOfCells=\"3\""), "3 tuples");
    rejects(&edit(" NumberOfComponents=\"3\"", ""), "NumberOfComponents");
    rejects(&edit("Name=\"types\"", "Name=\"kinds\""), "types");
    rejects(&edit("</Piece>", ""), "well-formed");
    rejects(&edit("\n          12 12\n", "\n          12 13\n"), "Wedge with 8 points");

    // Raw data cut short, or with bytes after the last array.
    let cut = raw_bytes.len() - "\n  </AppendedData>\n</VTKFile>\n".len();
    let mut short = raw_bytes[..cut - 1].to_vec();
    short.extend_from_slice(b"</AppendedData>\n</VTKFile>\n");
    rejects(&short, "overrun");
    let mut long = raw_bytes[..cut].to_vec();
    long.extend_from_slice(b"xyz");
    long.extend_from_slice(&raw_bytes[cut..]);
    rejects(&long, "unexplained bytes");
}

#[test]
fn pvd_index_is_rewritten_whole_on_each_frame() {
    let dir = test_dir::fresh("pvd");
    let path = dir.join("particles.pvd");
    let mut pvd = PvdCollection::create(&path).unwrap();
    assert!(read_pvd(&path).unwrap().is_empty(), "an empty index exists from the start");
    let times = [0.0, 1.0 / 3.0, 2.5e-7 * 4e6];
    for (i, &t) in times.iter().enumerate() {
        pvd.add(t, &format!("particles/p_{i:06}.vtp")).unwrap();
        assert_eq!(read_pvd(&path).unwrap(), pvd.entries(), "index on disk after frame {i}");
    }
    pvd.add_entry(PvdEntry { time: 1.0, group: "walls & rotor".into(), part: 1, file: "walls/w_2.vtp".into() }).unwrap();
    let read = read_pvd(&path).unwrap();
    assert_eq!(read.len(), 4);
    assert_eq!(read[1].time.to_bits(), (1.0_f64 / 3.0).to_bits());
    assert_eq!(read[3].group, "walls & rotor");
    assert_eq!(read[3].part, 1);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\""));
    assert!(text.contains("<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"particles/p_000000.vtp\"/>"));

    let e = pvd.add(0.5, "late.vtp").unwrap_err();
    assert!(e.to_string().contains("must not decrease"), "{e}");
    let e = pvd.add(f64::NAN, "nan.vtp").unwrap_err();
    assert!(matches!(e, OutputError::NonFinite { .. }), "{e}");
    assert_eq!(read_pvd(&path).unwrap().len(), 4, "refused frames leave the index unchanged");

    // Restart from t = 0.5: frames after it are dropped, later ones appended.
    let mut resumed = PvdCollection::resume(&path, 0.5).unwrap();
    assert_eq!(resumed.entries().len(), 2);
    resumed.add(0.75, "particles/p_again.vtp").unwrap();
    let files: Vec<String> = read_pvd(&path).unwrap().into_iter().map(|e| e.file).collect();
    assert_eq!(files, ["particles/p_000000.vtp", "particles/p_000001.vtp", "particles/p_again.vtp"]);

    let fresh = PvdCollection::resume(&dir.join("new.pvd"), 0.0).unwrap();
    assert!(fresh.entries().is_empty());
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 2, "no temporaries left behind");
}
