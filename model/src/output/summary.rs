//! `summary.json`: what a run was (case, solver, versions) and what it found (key results,
//! timings). Written atomically so a reader never sees half a file.

use super::{write_atomically, OutputError};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The program versions that produced a result.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Versions {
    /// Version of `spillage-model` (the workspace version).
    pub crate_version: String,
    /// Git commit of the build (set by `model/build.rs` from the checkout; absent outside one).
    pub git_hash: Option<String>,
}

impl Versions {
    /// The versions of this build.
    pub fn of_this_build() -> Self {
        Versions { crate_version: env!("CARGO_PKG_VERSION").to_string(), git_hash: option_env!("SPILLAGE_GIT_HASH").map(str::to_string) }
    }
}

/// The contents of `summary.json`. Maps are ordered (BTreeMap) so the file is deterministic.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub case_name: String,
    /// Which solver produced the run (`reference` or `fast`).
    pub solver: String,
    pub versions: Versions,
    /// Wall-clock seconds per phase (e.g. "total", "fluid", "dem").
    pub timings_s: BTreeMap<String, f64>,
    /// Key scalar results (e.g. "spillage_fraction"); must be finite.
    pub results: BTreeMap<String, f64>,
    /// Anything else worth keeping: strings, arrays, nested objects.
    pub details: BTreeMap<String, serde_json::Value>,
}

impl Summary {
    /// An empty summary of `case_name` run by `solver`, stamped with this build's versions.
    pub fn new(case_name: &str, solver: &str) -> Self {
        Summary {
            case_name: case_name.to_string(),
            solver: solver.to_string(),
            versions: Versions::of_this_build(),
            timings_s: BTreeMap::new(),
            results: BTreeMap::new(),
            details: BTreeMap::new(),
        }
    }

    pub fn set_result(&mut self, key: &str, value: f64) {
        self.results.insert(key.to_string(), value);
    }

    pub fn set_timing(&mut self, key: &str, seconds: f64) {
        self.timings_s.insert(key.to_string(), seconds);
    }

    pub fn set_detail(&mut self, key: &str, value: impl Into<serde_json::Value>) {
        self.details.insert(key.to_string(), value.into());
    }

    /// Writes the summary as pretty JSON at `path`, atomically. Non-finite results or timings are
    /// refused naming the key (JSON has no NaN; serde_json would silently write `null`).
    pub fn write(&self, path: &Path) -> Result<(), OutputError> {
        for (map_name, map) in [("results", &self.results), ("timings_s", &self.timings_s)] {
            for (index, (key, &value)) in map.iter().enumerate() {
                if !value.is_finite() {
                    return Err(OutputError::NonFinite { path: path.to_path_buf(), field: format!("{map_name}.{key}"), index, value });
                }
            }
        }
        let mut text = serde_json::to_string_pretty(self).map_err(|e| OutputError::invalid(path, format!("cannot serialise: {e}")))?;
        text.push('\n');
        write_atomically(path, |w| std::io::Write::write_all(w, text.as_bytes()).map_err(|e| OutputError::io(path, e)))
    }

    /// Reads a summary written by [`Summary::write`].
    pub fn read(path: &Path) -> Result<Self, OutputError> {
        let text = std::fs::read_to_string(path).map_err(|e| OutputError::io(path, e))?;
        serde_json::from_str(&text).map_err(|e| OutputError::malformed(path, e.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::test_dir;

    #[test]
    fn summary_round_trips_with_exact_numbers() {
        let dir = test_dir::fresh("summary_round_trip");
        let path = dir.join("summary.json");
        let mut summary = Summary::new("cutter_small", "reference");
        summary.set_result("spillage_fraction", 1.0 / 3.0);
        summary.set_result("production_m3_per_s", 2.5e-7);
        summary.set_timing("total", 12.75);
        summary.set_detail("mesh", serde_json::json!({"cells": 4096, "kind": "hex"}));
        summary.set_detail("note", "converged");
        summary.write(&path).unwrap();
        let read = Summary::read(&path).unwrap();
        assert_eq!(read, summary);
        assert_eq!(read.results["spillage_fraction"].to_bits(), (1.0_f64 / 3.0).to_bits());
        assert_eq!(read.versions.crate_version, env!("CARGO_PKG_VERSION"));

        let value: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        assert_eq!(value["case_name"], "cutter_small");
        assert_eq!(value["solver"], "reference");
        assert_eq!(value["details"]["mesh"]["cells"], 4096);
        assert!(value["versions"]["git_hash"].is_null() || value["versions"]["git_hash"].is_string());
    }

    #[test]
    fn a_build_from_a_git_checkout_records_its_commit() {
        // The build script reruns when the branch moves, so the recorded commit is the checkout's.
        let head = std::process::Command::new("git")
            .args(["rev-parse", "HEAD"])
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .ok()
            .filter(|out| out.status.success())
            .map(|out| String::from_utf8_lossy(&out.stdout).trim().to_string());
        let recorded = Versions::of_this_build().git_hash;
        match (head, std::env::var_os("SPILLAGE_GIT_HASH")) {
            (Some(head), None) => assert_eq!(recorded.as_deref(), Some(head.as_str())),
            _ => assert!(recorded.is_none_or(|hash| !hash.is_empty())),
        }
    }

    #[test]
    fn every_result_reads_back_to_the_same_bits() {
        let dir = test_dir::fresh("summary_bits");
        let path = dir.join("summary.json");
        let mut summary = Summary::new("bits", "reference");
        // A deterministic spread of magnitudes and digit patterns.
        let mut x = 1.234567890123e-200_f64;
        for i in 0..300 {
            summary.set_result(&format!("r{i:03}"), if i % 2 == 0 { x } else { -x / 3.0 });
            x *= 4.7;
        }
        summary.write(&path).unwrap();
        let read = Summary::read(&path).unwrap();
        for (key, value) in &summary.results {
            assert_eq!(read.results[key].to_bits(), value.to_bits(), "{key}: {value:e}");
        }
    }

    #[test]
    fn non_finite_results_are_refused_and_the_old_file_kept() {
        let dir = test_dir::fresh("summary_nan");
        let path = dir.join("summary.json");
        let mut summary = Summary::new("case", "fast");
        summary.set_result("torque", 4.0);
        summary.write(&path).unwrap();
        summary.set_result("torque", f64::NAN);
        let e = summary.write(&path).unwrap_err();
        assert!(e.to_string().contains("results.torque"), "{e}");
        assert_eq!(Summary::read(&path).unwrap().results["torque"], 4.0);

        summary.set_result("torque", 4.0);
        summary.set_timing("fluid", f64::INFINITY);
        let e = summary.write(&path).unwrap_err();
        assert!(e.to_string().contains("timings_s.fluid"), "{e}");
    }
}
