//! Time-series CSV (`series.csv`): named columns fixed at creation, one row per step.
//!
//! Each row goes to the operating system in one `write` as soon as it is given, so a crash of the
//! program loses no finished row (a power cut may lose what the OS had not yet stored; we do not
//! sync per row, which would cost a disk flush per step). Numbers are written in the shortest
//! form that parses back to the same bits. A restarted run reopens the file, checks the header,
//! drops rows later than the restart time and a half-written last line, and appends.

use super::{check_finite, format_f64, write_atomically, OutputError};
use std::collections::BTreeSet;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};

/// An open time-series file that rows are appended to.
#[derive(Debug)]
pub struct SeriesWriter {
    path: PathBuf,
    file: File,
    columns: Vec<String>,
}

impl SeriesWriter {
    /// Creates (or truncates) `path` and writes the header line of `columns`.
    pub fn create(path: &Path, columns: &[&str]) -> Result<Self, OutputError> {
        let columns = checked_columns(path, columns)?;
        let header = header_line(&columns);
        write_atomically(path, |w| w.write_all(header.as_bytes()).map_err(|e| OutputError::io(path, e)))?;
        Self::open_for_append(path, columns)
    }

    /// Reopens `path` after a restart at which the first column had the value `restart_time` (the
    /// run loop's first column is the step): the header must list exactly `columns`; rows whose
    /// first column exceeds it (they will be computed again) and an
    /// unfinished last line are removed. `None` keeps every complete row. Without an existing
    /// file this is [`SeriesWriter::create`].
    pub fn resume(path: &Path, columns: &[&str], restart_time: Option<f64>) -> Result<Self, OutputError> {
        if !path.exists() {
            return Self::create(path, columns);
        }
        let columns = checked_columns(path, columns)?;
        let text = std::fs::read_to_string(path).map_err(|e| OutputError::io(path, e))?;
        let mut lines = text.split_inclusive('\n');
        let expected = header_line(&columns);
        let found = lines.next().unwrap_or("");
        if found != expected {
            return Err(OutputError::invalid(path, format!("cannot resume: header is {:?} but this run writes {:?}", found.trim_end(), expected.trim_end())));
        }
        let mut kept = expected.clone();
        for (index, line) in lines.enumerate() {
            if !line.ends_with('\n') {
                break; // the line a crash interrupted
            }
            let row = parse_row(path, line, columns.len(), index + 2)?;
            if restart_time.is_some_and(|t| row[0] > t) {
                break;
            }
            kept.push_str(line);
        }
        write_atomically(path, |w| w.write_all(kept.as_bytes()).map_err(|e| OutputError::io(path, e)))?;
        Self::open_for_append(path, columns)
    }

    fn open_for_append(path: &Path, columns: Vec<String>) -> Result<Self, OutputError> {
        let file = OpenOptions::new().append(true).open(path).map_err(|e| OutputError::io(path, e))?;
        Ok(SeriesWriter { path: path.to_path_buf(), file, columns })
    }

    /// Appends one row; `values` are in column order. Non-finite values are refused (nothing is
    /// written) with an error naming the column.
    pub fn write_row(&mut self, values: &[f64]) -> Result<(), OutputError> {
        if values.len() != self.columns.len() {
            return Err(OutputError::invalid(
                &self.path,
                format!("a row has {} values but the columns are {} ({})", values.len(), self.columns.len(), self.columns.join(",")),
            ));
        }
        for (column, value) in self.columns.iter().zip(values) {
            check_finite(&self.path, column, std::slice::from_ref(value))?;
        }
        let mut line = values.iter().map(|&v| format_f64(v)).collect::<Vec<_>>().join(",");
        line.push('\n');
        self.file.write_all(line.as_bytes()).map_err(|e| OutputError::io(&self.path, e))
    }

    pub fn columns(&self) -> &[String] {
        &self.columns
    }

    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// A whole series file read back.
#[derive(Clone, Debug, PartialEq)]
pub struct SeriesTable {
    pub columns: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl SeriesTable {
    /// All values of column `name`, in row order.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let index = self.columns.iter().position(|c| c == name)?;
        Some(self.rows.iter().map(|r| r[index]).collect())
    }

    /// (x, y) pairs of two columns, ready for [`super::plot::Series`].
    pub fn pairs(&self, x: &str, y: &str) -> Option<Vec<(f64, f64)>> {
        let xs = self.column(x)?;
        let ys = self.column(y)?;
        Some(xs.into_iter().zip(ys).collect())
    }
}

/// How much of the step (`step_start`, `step_end`] lies in the window [start, end] [s]: the
/// weight of the step's row in a time-weighted mean over the window (a Courant-controlled step
/// is not uniform; the step straddling an edge counts with its part inside).
pub fn time_in_window(step_start: f64, step_end: f64, (start, end): (f64, f64)) -> f64 {
    (step_end.min(end) - step_start.max(start)).max(0.0)
}

/// Reads a series file, refusing ragged rows and unparsable numbers (with their line number).
pub fn read_series(path: &Path) -> Result<SeriesTable, OutputError> {
    let text = std::fs::read_to_string(path).map_err(|e| OutputError::io(path, e))?;
    let mut lines = text.lines();
    let header = lines.next().ok_or_else(|| OutputError::malformed(path, "empty file, no header line"))?;
    let columns: Vec<String> = header.split(',').map(str::to_string).collect();
    let rows = lines.enumerate().map(|(index, line)| parse_row(path, line, columns.len(), index + 2)).collect::<Result<_, _>>()?;
    Ok(SeriesTable { columns, rows })
}

fn parse_row(path: &Path, line: &str, width: usize, line_number: usize) -> Result<Vec<f64>, OutputError> {
    let values = line
        .trim_end_matches(['\n', '\r'])
        .split(',')
        .map(|field| {
            field
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| OutputError::malformed(path, format!("line {line_number}: {field:?} is not a finite number")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    if values.len() != width {
        return Err(OutputError::malformed(path, format!("line {line_number} has {} values, the header {width}", values.len())));
    }
    Ok(values)
}

fn checked_columns(path: &Path, columns: &[&str]) -> Result<Vec<String>, OutputError> {
    if columns.is_empty() {
        return Err(OutputError::invalid(path, "a series needs at least one column"));
    }
    let mut seen = BTreeSet::new();
    for &name in columns {
        if name.is_empty() || name.trim() != name || name.contains([',', '"', '\n', '\r']) || name.chars().any(char::is_control) {
            return Err(OutputError::invalid(
                path,
                format!(
                    "column name {name:?} must be non-empty, without commas, quotes, control \
                     characters or surrounding spaces"
                ),
            ));
        }
        if !seen.insert(name) {
            return Err(OutputError::invalid(path, format!("column {name:?} appears twice")));
        }
    }
    Ok(columns.iter().map(|c| c.to_string()).collect())
}

fn header_line(columns: &[String]) -> String {
    format!("{}\n", columns.join(","))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::test_dir;

    const COLUMNS: [&str; 3] = ["time", "spillage_fraction", "torque"];

    fn row(step: usize) -> [f64; 3] {
        let t = step as f64 * 0.1;
        [t, (t / 3.0).sin().abs() * 1e-9, -(1.0 / 7.0) * 1e20 * t]
    }

    #[test]
    fn rows_round_trip_bit_exactly_and_are_on_disk_after_each_write() {
        let dir = test_dir::fresh("series_round_trip");
        let path = dir.join("series.csv");
        let mut writer = SeriesWriter::create(&path, &COLUMNS).unwrap();
        for step in 0..50 {
            writer.write_row(&row(step)).unwrap();
            // Read while the writer is still open: the row must already be in the file.
            assert_eq!(read_series(&path).unwrap().rows.len(), step + 1);
        }
        let table = read_series(&path).unwrap();
        assert_eq!(table.columns, COLUMNS);
        for (step, read) in table.rows.iter().enumerate() {
            for (r, w) in read.iter().zip(row(step)) {
                assert_eq!(r.to_bits(), w.to_bits(), "step {step}: {r:e} vs {w:e}");
            }
        }
        let pairs = table.pairs("time", "torque").unwrap();
        assert_eq!(pairs[3], (row(3)[0], row(3)[2]));
        assert!(table.column("missing").is_none());
    }

    #[test]
    fn resume_checks_header_drops_later_rows_and_a_torn_line() {
        let dir = test_dir::fresh("series_resume");
        let path = dir.join("series.csv");
        let mut writer = SeriesWriter::create(&path, &COLUMNS).unwrap();
        for step in 0..10 {
            writer.write_row(&row(step)).unwrap();
        }
        drop(writer);
        // A crash in the middle of writing a row.
        let mut file = OpenOptions::new().append(true).open(&path).unwrap();
        file.write_all(b"1.0,2.5e-").unwrap();
        drop(file);

        let e = SeriesWriter::resume(&path, &["time", "torque"], None).unwrap_err();
        assert!(e.to_string().contains("cannot resume"), "{e}");

        // Restart from the checkpoint at t = 0.45: rows at t = 0.5 .. 0.9 go.
        let mut writer = SeriesWriter::resume(&path, &COLUMNS, Some(0.45)).unwrap();
        writer.write_row(&[0.5, 1.0, 2.0]).unwrap();
        let table = read_series(&path).unwrap();
        assert_eq!(table.rows.len(), 6);
        assert_eq!(table.rows[4], row(4).to_vec());
        assert_eq!(table.rows[5], vec![0.5, 1.0, 2.0]);

        let mut writer = SeriesWriter::resume(&path, &COLUMNS, None).unwrap();
        writer.write_row(&row(7)).unwrap();
        assert_eq!(read_series(&path).unwrap().rows.len(), 7);

        let fresh = dir.join("fresh.csv");
        SeriesWriter::resume(&fresh, &COLUMNS, Some(1.0)).unwrap();
        assert_eq!(std::fs::read_to_string(&fresh).unwrap(), "time,spillage_fraction,torque\n");
    }

    #[test]
    fn bad_rows_and_columns_are_refused_naming_the_culprit() {
        let dir = test_dir::fresh("series_refuse");
        let path = dir.join("series.csv");
        let mut writer = SeriesWriter::create(&path, &COLUMNS).unwrap();
        let e = writer.write_row(&[0.0, f64::NAN, 1.0]).unwrap_err();
        assert!(matches!(&e, OutputError::NonFinite { field, .. } if field == "spillage_fraction"), "{e}");
        let e = writer.write_row(&[0.0, 1.0]).unwrap_err();
        assert!(e.to_string().contains("has 2 values"), "{e}");
        assert!(read_series(&path).unwrap().rows.is_empty(), "refused rows are not written");

        for bad in [&["t", "t"][..], &["a,b"], &[""], &[" x"], &[]] {
            assert!(SeriesWriter::create(&dir.join("x.csv"), bad).is_err(), "{bad:?}");
        }
        std::fs::write(&path, "a,b\n1,2\n3\n").unwrap();
        let e = read_series(&path).unwrap_err();
        assert!(e.to_string().contains("line 3"), "{e}");
    }
}
