//! Errors of case files: every message names the file, the line and column, the key, the bad
//! value and what is allowed.

use std::fmt;
use std::path::PathBuf;

/// A value that failed validation, before the file location is known.
///
/// Section validators (`validate()` on each section struct) return these with the dotted key
/// path from the case-file root, e.g. `fluid.density` or `boundary.inner.velocity`.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldError {
    /// Dotted key path from the file root (`particles.feed.rate`).
    pub key: String,
    /// The offending value as written (or as understood).
    pub value: String,
    /// What is allowed, in words ("a positive number of kg/m³").
    pub allowed: String,
}

impl FieldError {
    pub fn new(key: impl Into<String>, value: impl fmt::Display, allowed: impl Into<String>) -> Self {
        Self { key: key.into(), value: value.to_string(), allowed: allowed.into() }
    }
}

/// Checks that a value is finite and strictly positive.
pub fn positive(key: &str, value: f64, unit: &str) -> Result<(), FieldError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(FieldError::new(key, value, format!("a finite number > 0 {unit}")))
    }
}

/// Checks that a value is finite and ≥ 0.
pub fn non_negative(key: &str, value: f64, unit: &str) -> Result<(), FieldError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(FieldError::new(key, value, format!("a finite number ≥ 0 {unit}")))
    }
}

/// Checks `lo <= value <= hi` (closed interval), finite.
pub fn in_range(key: &str, value: f64, lo: f64, hi: f64, unit: &str) -> Result<(), FieldError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(FieldError::new(key, value, format!("a number in [{lo}, {hi}] {unit}")))
    }
}

/// Checks every component of a vector is finite.
pub fn finite_vector(key: &str, value: [f64; 3]) -> Result<(), FieldError> {
    if value.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(FieldError::new(key, format!("{value:?}"), "three finite numbers"))
    }
}

/// A case-file error located in its file.
#[derive(Debug)]
pub struct CaseError {
    pub file: PathBuf,
    /// 1-based line and column, when known.
    pub line: Option<usize>,
    pub column: Option<usize>,
    pub kind: CaseErrorKind,
}

#[derive(Debug)]
pub enum CaseErrorKind {
    /// The file could not be read.
    Io(std::io::Error),
    /// TOML syntax, unknown key or wrong type (message from the parser).
    Parse(String),
    /// A value out of range or inconsistent with others.
    Invalid(FieldError),
}

impl fmt::Display for CaseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let (Some(l), Some(c)) = (self.line, self.column) {
            write!(f, ":{l}:{c}")?;
        }
        match &self.kind {
            CaseErrorKind::Io(e) => write!(f, ": cannot read the case file: {e}"),
            CaseErrorKind::Parse(m) => write!(f, ": {m}"),
            CaseErrorKind::Invalid(e) => {
                write!(f, ": key `{}` = {} is not allowed; expected {}", e.key, e.value, e.allowed)
            }
        }
    }
}

impl std::error::Error for CaseError {}
