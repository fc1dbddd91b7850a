//! The `spillage` program's library side: the verification ladder, shared by the command line
//! (`spillage verify`) and the tests in `tests/`.

pub mod check;
pub mod verify;
