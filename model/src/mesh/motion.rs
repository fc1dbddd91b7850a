//! Rigid rotation of cell zones and the mesh flux it induces.
