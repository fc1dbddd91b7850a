//! Output writers: ParaView (VTK XML), time series CSV, run summary JSON, PNG plots.
//!
//! Every writer takes plain slices (no mesh or state types), so the run loop decides what goes
//! where. Every error names the file it concerns. Non-finite numbers are refused, never written:
//! a NaN in a result file is a bug that must surface where it is produced.

mod atomic_file;
pub mod bar_chart;
pub mod heat_map;
mod number_format;
pub mod plot;
pub mod series;
pub mod summary;
pub mod vtk;

pub use atomic_file::write_atomically;
pub use number_format::format_f64;

use std::path::{Path, PathBuf};

/// An output file could not be written or read back.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The operating system refused an operation on the file.
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A value that would be written is NaN or infinite.
    #[error("{path}: `{field}` has the non-finite value {value} at index {index}; only finite numbers are written")]
    NonFinite { path: PathBuf, field: String, index: usize, value: f64 },
    /// The data handed to a writer is inconsistent (lengths, names, ids, axis ranges).
    #[error("{path}: {message}")]
    InvalidData { path: PathBuf, message: String },
    /// A file read back is malformed or disagrees with itself.
    #[error("{path}: malformed file: {message}")]
    Malformed { path: PathBuf, message: String },
}

impl OutputError {
    pub(crate) fn io(path: &Path, source: std::io::Error) -> Self {
        OutputError::Io { path: path.to_path_buf(), source }
    }

    pub(crate) fn invalid(path: &Path, message: impl Into<String>) -> Self {
        OutputError::InvalidData { path: path.to_path_buf(), message: message.into() }
    }

    pub(crate) fn malformed(path: &Path, message: impl Into<String>) -> Self {
        OutputError::Malformed { path: path.to_path_buf(), message: message.into() }
    }
}

/// Lets callers that speak `std::io::Error` (e.g. `?` in an io-returning function) use the writers.
impl From<OutputError> for std::io::Error {
    fn from(error: OutputError) -> Self {
        match error {
            OutputError::Io { source, path } => std::io::Error::new(source.kind(), format!("{}: {source}", path.display())),
            OutputError::NonFinite { .. } | OutputError::InvalidData { .. } => std::io::Error::new(std::io::ErrorKind::InvalidInput, error.to_string()),
            OutputError::Malformed { .. } => std::io::Error::new(std::io::ErrorKind::InvalidData, error.to_string()),
        }
    }
}

/// Returns the first non-finite value of `values` as an error naming `field`.
pub(crate) fn check_finite(path: &Path, field: &str, values: &[f64]) -> Result<(), OutputError> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(index) => Err(OutputError::NonFinite { path: path.to_path_buf(), field: field.to_string(), index, value: values[index] }),
    }
}

#[cfg(test)]
pub(crate) mod test_dir {
    use std::path::{Path, PathBuf};

    /// A fresh, empty directory for one test under the system temp dir, removed when the test
    /// passes and kept for inspection when it fails.
    pub struct TestDir(PathBuf);

    pub fn fresh(test_name: &str) -> TestDir {
        let dir = std::env::temp_dir().join(format!("spillage-output-tests-{}-{test_name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("creating a test directory under the temp dir");
        TestDir(dir)
    }

    impl std::ops::Deref for TestDir {
        type Target = Path;
        fn deref(&self) -> &Path {
            &self.0
        }
    }

    impl AsRef<Path> for TestDir {
        fn as_ref(&self) -> &Path {
            &self.0
        }
    }

    impl Drop for TestDir {
        fn drop(&mut self) {
            if !std::thread::panicking() {
                let _ = std::fs::remove_dir_all(&self.0);
            }
        }
    }
}
