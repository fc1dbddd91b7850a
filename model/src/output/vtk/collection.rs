//! ParaView data collection (`.pvd`): the time index that lets ParaView play a series of frames.
//! The whole index is rewritten atomically each time a frame is added, so a crash leaves the
//! previous complete index, never a truncated one.

use super::writer::xml_escape;
use crate::output::{format_f64, write_atomically, OutputError};
use std::io::Write;
use std::path::{Path, PathBuf};

/// One frame of a collection.
#[derive(Clone, Debug, PartialEq)]
pub struct PvdEntry {
    /// Simulation time of the frame (ParaView's `timestep` attribute).
    pub time: f64,
    /// Frames with different groups or parts at one time are shown as blocks of one dataset.
    pub group: String,
    pub part: u32,
    /// Path of the frame file relative to the `.pvd` file's directory.
    pub file: String,
}

impl PvdEntry {
    /// A frame in group "" and part 0, the usual case of one file per time.
    pub fn new(time: f64, file: impl Into<String>) -> Self {
        PvdEntry { time, group: String::new(), part: 0, file: file.into() }
    }
}

/// A `.pvd` index kept on disk in step with the frames added to it.
#[derive(Debug)]
pub struct PvdCollection {
    path: PathBuf,
    entries: Vec<PvdEntry>,
}

impl PvdCollection {
    /// Starts a new, empty index at `path` (replacing any existing one) and writes it.
    pub fn create(path: &Path) -> Result<Self, OutputError> {
        let collection = PvdCollection { path: path.to_path_buf(), entries: Vec::new() };
        collection.write()?;
        Ok(collection)
    }

    /// Continues the index at `path` after a restart from time `restart_time`: frames later than
    /// `restart_time` are dropped (they will be produced again) and the index is rewritten.
    /// Without an existing file this is [`PvdCollection::create`].
    pub fn resume(path: &Path, restart_time: f64) -> Result<Self, OutputError> {
        if !path.exists() {
            return Self::create(path);
        }
        let mut entries = read_pvd(path)?;
        entries.retain(|e| e.time <= restart_time);
        let collection = PvdCollection { path: path.to_path_buf(), entries };
        collection.write()?;
        Ok(collection)
    }

    /// Adds a frame at `time` (group "", part 0) and rewrites the index.
    pub fn add(&mut self, time: f64, file: &str) -> Result<(), OutputError> {
        self.add_entry(PvdEntry::new(time, file))
    }

    /// Adds `entry` and rewrites the index. Times must be finite and not decrease.
    pub fn add_entry(&mut self, entry: PvdEntry) -> Result<(), OutputError> {
        if !entry.time.is_finite() {
            return Err(OutputError::NonFinite {
                path: self.path.clone(),
                field: format!("timestep of {}", entry.file),
                index: self.entries.len(),
                value: entry.time,
            });
        }
        if let Some(last) = self.entries.last() {
            if entry.time < last.time {
                return Err(OutputError::invalid(
                    &self.path,
                    format!("frame {} at time {} comes before the last frame's time {}; times must not decrease", entry.file, entry.time, last.time),
                ));
            }
        }
        if entry.file.trim().is_empty() || entry.file.chars().any(char::is_control) {
            return Err(OutputError::invalid(&self.path, format!("frame file name {:?} must be non-empty without control characters", entry.file)));
        }
        self.entries.push(entry);
        if let Err(e) = self.write() {
            self.entries.pop();
            return Err(e);
        }
        Ok(())
    }

    pub fn entries(&self) -> &[PvdEntry] {
        &self.entries
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    fn write(&self) -> Result<(), OutputError> {
        let path = &self.path;
        write_atomically(path, |w| {
            (|| -> std::io::Result<()> {
                writeln!(w, "<?xml version=\"1.0\"?>")?;
                writeln!(
                    w,
                    "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\" \
                     header_type=\"UInt64\">"
                )?;
                writeln!(w, "  <Collection>")?;
                for e in &self.entries {
                    writeln!(
                        w,
                        "    <DataSet timestep=\"{}\" group=\"{}\" part=\"{}\" file=\"{}\"/>",
                        format_f64(e.time),
                        xml_escape(&e.group),
                        e.part,
                        xml_escape(&e.file)
                    )?;
                }
                writeln!(w, "  </Collection>")?;
                writeln!(w, "</VTKFile>")
            })()
            .map_err(|e| OutputError::io(path, e))
        })
    }
}

/// Reads the frames of a `.pvd` index, checking the attributes ParaView needs.
pub fn read_pvd(path: &Path) -> Result<Vec<PvdEntry>, OutputError> {
    let text = std::fs::read_to_string(path).map_err(|e| OutputError::io(path, e))?;
    let bad = |message: String| OutputError::malformed(path, message);
    let document = roxmltree::Document::parse(&text).map_err(|e| bad(format!("not well-formed XML: {e}")))?;
    let root = document.root_element();
    if root.tag_name().name() != "VTKFile" || root.attribute("type") != Some("Collection") {
        return Err(bad("root must be <VTKFile type=\"Collection\">".to_string()));
    }
    for attribute in ["version", "byte_order"] {
        if root.attribute(attribute).is_none() {
            return Err(bad(format!("<VTKFile> lacks `{attribute}`")));
        }
    }
    let collections: Vec<_> = root.children().filter(|n| n.is_element()).collect();
    let [collection] = collections.as_slice() else {
        return Err(bad("expected exactly one <Collection>".to_string()));
    };
    if collection.tag_name().name() != "Collection" {
        return Err(bad(format!("unexpected <{}>", collection.tag_name().name())));
    }
    let mut entries = Vec::new();
    for node in collection.children().filter(|n| n.is_element()) {
        if node.tag_name().name() != "DataSet" {
            return Err(bad(format!("unexpected <{}> in <Collection>", node.tag_name().name())));
        }
        let attribute = |name: &str| node.attribute(name).ok_or_else(|| bad(format!("<DataSet> {} lacks `{name}`", entries.len())));
        let time_text = attribute("timestep")?;
        let time: f64 = time_text.parse().ok().filter(|t: &f64| t.is_finite()).ok_or_else(|| bad(format!("timestep {time_text:?} is not a finite number")))?;
        let part_text = attribute("part")?;
        let part = part_text.parse().map_err(|_| bad(format!("part {part_text:?} is not a non-negative integer")))?;
        entries.push(PvdEntry { time, group: attribute("group")?.to_string(), part, file: attribute("file")?.to_string() });
    }
    Ok(entries)
}
