//! Checkpoints: a [`State`] written to disk and read back bit-for-bit.
//!
//! Layout: a text header line (`spillage-checkpoint 7 <case name>\n`, 7 the format version), the
//! payload's length, the payload in postcard (the case's [`Fingerprint`] and the state; f64
//! stored as their 8 bytes, so nothing is rounded), and an FNV-1a 64-bit checksum of the
//! payload, so a truncated or damaged file is refused instead of silently resuming from garbage.
//! Writes go to a temporary file in the same folder that is renamed over the target, so a crash
//! while writing never leaves a half-written checkpoint under the real name.
//!
//! Reading for a case checks, in order: the header, the case name, the checksum, the
//! fingerprint (the checkpoint's state means what the case's would, [`fingerprint`]) and the
//! state's numbers and sizes ([`validate`]), so a foreign or forged checkpoint is refused
//! before any step with a message naming what differs.

pub mod fingerprint;
pub mod validate;

use std::io::Write;
use std::path::{Path, PathBuf};

pub use fingerprint::Fingerprint;

use crate::case::Case;
use crate::state::State;

const MAGIC: &str = "spillage-checkpoint";
/// 2: the one-step pipeline (rotor pose stored once, walls without their own angle, particle
/// exits, the last Courant number); 3: wear (the wear state, wall revisions, impact points);
/// 4: turbulence (k, ε, ν_t in the fluid state); 5: the case's fingerprint before the state;
/// 7: the fluid mesh's displacement in the fluid state (a mesh that follows a receding wall).
const VERSION: u32 = 7;
/// A header longer than this is not one (a case name is a line of text; a damaged file
/// otherwise shows its binary payload as the name).
const MAX_HEADER: usize = 512;
/// Characters of a damaged header shown in a message.
const SHOWN: usize = 60;

#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("{path}: not a spillage checkpoint (it starts with {found})")]
    NotACheckpoint { path: PathBuf, found: String },
    #[error(
        "{path}: checkpoint format version {found}, written by an older spillage; this program reads version {VERSION} only: rerun the case from the start"
    )]
    OlderVersion { path: PathBuf, found: u32 },
    #[error("{path}: checkpoint format version {found}, written by a newer spillage; this program reads version {VERSION} only")]
    NewerVersion { path: PathBuf, found: u32 },
    #[error("{path}: checkpoint of case {found}, but the case being run is {expected:?}")]
    WrongCase { path: PathBuf, found: String, expected: String },
    #[error("{path}: checkpoint is damaged or truncated ({what})")]
    Damaged { path: PathBuf, what: String },
    #[error("{path}: the checkpoint belongs to another case than {case:?}: {what}")]
    Foreign { path: PathBuf, case: String, what: String },
    #[error("{path}: the checkpoint's state cannot be continued: {what}")]
    Invalid { path: PathBuf, what: String },
}

/// `text` for a message: control characters escaped, at most [`SHOWN`] characters, quoted.
fn shown(text: &str) -> String {
    let mut out: String = text.chars().take(SHOWN).flat_map(char::escape_debug).collect();
    if text.chars().count() > SHOWN {
        out.push('…');
    }
    format!("\"{out}\"")
}

/// Writes `state` of `case` to `path` atomically.
pub fn write(path: &Path, case: &Case, state: &State) -> Result<(), CheckpointError> {
    let io = |source| CheckpointError::Io { path: path.to_path_buf(), source };
    let payload = postcard::to_stdvec(&(Fingerprint::of_case(case), state))
        .map_err(|e| CheckpointError::Damaged { path: path.to_path_buf(), what: format!("cannot encode the state: {e}") })?;
    let name = case.case.name.replace(['\n', '\r'], " ");
    let tmp = path.with_extension("tmp");
    {
        let mut file = std::fs::File::create(&tmp).map_err(io)?;
        file.write_all(format!("{MAGIC} {VERSION} {name}\n").as_bytes()).map_err(io)?;
        file.write_all(&(payload.len() as u64).to_le_bytes()).map_err(io)?;
        file.write_all(&payload).map_err(io)?;
        file.write_all(&fnv1a(&payload).to_le_bytes()).map_err(io)?;
        file.sync_all().map_err(io)?;
    }
    std::fs::rename(&tmp, path).map_err(io)
}

/// A checkpoint as stored: the case name of its header, the fingerprint of its case and the state.
#[derive(Debug)]
pub struct Stored {
    pub case_name: String,
    pub fingerprint: Fingerprint,
    pub state: State,
}

/// Reads a checkpoint for `case`: refused when it was written for another case (name or
/// fingerprint) or its state is not a valid state of `case`.
pub fn read(path: &Path, case: &Case) -> Result<State, CheckpointError> {
    let stored = read_stored(path, Some(&case.case.name))?;
    stored.fingerprint.compare(&Fingerprint::of_case(case)).map_err(|what| CheckpointError::Foreign {
        path: path.to_path_buf(),
        case: case.case.name.clone(),
        what,
    })?;
    validate::state_for_case(case, &stored.state).map_err(|what| CheckpointError::Invalid { path: path.to_path_buf(), what })?;
    Ok(stored.state)
}

/// Reads a checkpoint without a case to compare it with; `expected_case`, when given, must
/// match the case name stored in it.
pub fn read_stored(path: &Path, expected_case: Option<&str>) -> Result<Stored, CheckpointError> {
    let bytes = std::fs::read(path).map_err(|source| CheckpointError::Io { path: path.to_path_buf(), source })?;
    let damaged = |what: &str| CheckpointError::Damaged { path: path.to_path_buf(), what: what.to_string() };
    let not_a_checkpoint =
        || CheckpointError::NotACheckpoint { path: path.to_path_buf(), found: shown(&String::from_utf8_lossy(&bytes[..bytes.len().min(SHOWN)])) };
    if !bytes.starts_with(MAGIC.as_bytes()) {
        return Err(not_a_checkpoint());
    }
    let newline = bytes[..bytes.len().min(MAX_HEADER)].iter().position(|&b| b == b'\n').ok_or_else(|| damaged("no end to its header line"))?;
    let header = std::str::from_utf8(&bytes[..newline]).map_err(|_| damaged("its header line is not text"))?;
    let mut parts = header.splitn(3, ' ');
    if parts.next() != Some(MAGIC) {
        return Err(not_a_checkpoint());
    }
    let version = parts.next().unwrap_or("");
    match version.parse::<u32>() {
        Ok(VERSION) => {}
        Ok(found) if found < VERSION => return Err(CheckpointError::OlderVersion { path: path.to_path_buf(), found }),
        Ok(found) => return Err(CheckpointError::NewerVersion { path: path.to_path_buf(), found }),
        Err(_) => return Err(damaged(&format!("format version {} is not a number", shown(version)))),
    }
    let name = parts.next().unwrap_or("").to_string();
    if name.chars().any(char::is_control) {
        return Err(damaged(&format!("the case name in its header, {}, is not a line of text", shown(&name))));
    }
    if let Some(expected) = expected_case {
        if name != expected {
            return Err(CheckpointError::WrongCase { path: path.to_path_buf(), found: shown(&name), expected: expected.to_string() });
        }
    }
    let rest = &bytes[newline + 1..];
    if rest.len() < 16 {
        return Err(damaged("shorter than its length and checksum fields"));
    }
    let len = u64::from_le_bytes(rest[..8].try_into().expect("8 bytes"));
    if rest.len() as u64 - 16 != len {
        return Err(damaged(&format!("payload of {} bytes, header says {len}", rest.len() - 16)));
    }
    let len = len as usize;
    let payload = &rest[8..8 + len];
    let checksum = u64::from_le_bytes(rest[8 + len..].try_into().expect("8 bytes"));
    if fnv1a(payload) != checksum {
        return Err(damaged("checksum mismatch"));
    }
    let (fingerprint, state): (Fingerprint, State) = postcard::from_bytes(payload).map_err(|e| damaged(&format!("cannot decode the state: {e}")))?;
    Ok(Stored { case_name: name, fingerprint, state })
}

/// FNV-1a, 64 bit: enough to catch truncation and bit rot, not an adversary.
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    for &b in bytes {
        hash ^= u64::from(b);
        hash = hash.wrapping_mul(0x0000_0100_0000_01b3);
    }
    hash
}

#[cfg(test)]
mod tests;
