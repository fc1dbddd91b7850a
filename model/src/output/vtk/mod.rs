//! ParaView output in VTK XML form, written by our own code (no system libraries):
//! `.vtu` unstructured grids (fluid mesh fields), `.vtp` poly data (particles as vertices, wall
//! triangle meshes), `.pvd` collections (time index), and a strict reader for our own files.

mod collection;
mod data;
mod reader;
mod writer;

pub use collection::{read_pvd, PvdCollection, PvdEntry};
pub use data::{CellType, Encoding, Field, FieldValues, PolyCells, PolyData, UnstructuredCells, UnstructuredGrid};
pub use reader::{read_vtk, ArrayValues, ReadArray, ReadCells, VtkDataset};
pub use writer::{write_vtp, write_vtu};

#[cfg(test)]
mod tests;
