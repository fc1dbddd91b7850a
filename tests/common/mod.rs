//! What the tests that run the `spillage` program share.

use std::path::PathBuf;
use std::process::{Command, Output};

/// Runs the program with `args`.
pub fn spillage(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_spillage")).args(args).output().expect("the spillage binary runs")
}

/// An empty scratch folder of this test process.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("spillage-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
