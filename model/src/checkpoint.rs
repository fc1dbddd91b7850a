//! Checkpoints: a [`State`] written to disk and read back bit-for-bit.
//!
//! Layout: a text header line (`spillage-checkpoint 4 <case name>\n`, 2 the format version), the state in postcard
//! (f64 stored as their 8 bytes, so nothing is rounded), and an FNV-1a 64-bit checksum of the
//! payload, so a truncated or damaged file is refused instead of silently resuming from garbage.
//! Writes go to a temporary file in the same folder that is renamed over the target, so a crash
//! while writing never leaves a half-written checkpoint under the real name.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::state::State;

const MAGIC: &str = "spillage-checkpoint";
/// 2: the one-step pipeline (rotor pose stored once, walls without their own angle, particle
/// exits, the last Courant number); 3: wear (the wear state, wall revisions, impact points).
const VERSION: u32 = 4;

#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    #[error("{path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("{path}: not a spillage checkpoint (header {found:?})")]
    NotACheckpoint { path: PathBuf, found: String },
    #[error("{path}: checkpoint format version {found}, this program reads version {VERSION} only (checkpoints of older versions cannot be continued; rerun from the start)")]
    Version { path: PathBuf, found: String },
    #[error("{path}: checkpoint of case {found:?}, but the case being run is {expected:?}")]
    WrongCase { path: PathBuf, found: String, expected: String },
    #[error("{path}: checkpoint is damaged or truncated ({what})")]
    Damaged { path: PathBuf, what: String },
}

/// Writes `state` of case `case_name` to `path` atomically.
pub fn write(path: &Path, case_name: &str, state: &State) -> Result<(), CheckpointError> {
    let io = |source| CheckpointError::Io { path: path.to_path_buf(), source };
    let payload =
        postcard::to_stdvec(state).map_err(|e| CheckpointError::Damaged { path: path.to_path_buf(), what: format!("cannot encode the state: {e}") })?;
    let name = case_name.replace(['\n', '\r'], " ");
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

/// Reads a checkpoint; `expected_case`, when given, must match the case name stored in it.
pub fn read(path: &Path, expected_case: Option<&str>) -> Result<State, CheckpointError> {
    let bytes = std::fs::read(path).map_err(|source| CheckpointError::Io { path: path.to_path_buf(), source })?;
    let damaged = |what: &str| CheckpointError::Damaged { path: path.to_path_buf(), what: what.to_string() };
    let newline = bytes.iter().position(|&b| b == b'\n').ok_or_else(|| CheckpointError::NotACheckpoint {
        path: path.to_path_buf(),
        found: String::from_utf8_lossy(&bytes[..bytes.len().min(40)]).into_owned(),
    })?;
    let header = String::from_utf8_lossy(&bytes[..newline]).into_owned();
    let mut parts = header.splitn(3, ' ');
    if parts.next() != Some(MAGIC) {
        return Err(CheckpointError::NotACheckpoint { path: path.to_path_buf(), found: header });
    }
    let version = parts.next().unwrap_or("");
    if version != VERSION.to_string() {
        return Err(CheckpointError::Version { path: path.to_path_buf(), found: version.to_string() });
    }
    let name = parts.next().unwrap_or("").to_string();
    if let Some(expected) = expected_case {
        if name != expected {
            return Err(CheckpointError::WrongCase { path: path.to_path_buf(), found: name, expected: expected.to_string() });
        }
    }
    let rest = &bytes[newline + 1..];
    if rest.len() < 16 {
        return Err(damaged("shorter than its length and checksum fields"));
    }
    let len = u64::from_le_bytes(rest[..8].try_into().expect("8 bytes")) as usize;
    if rest.len() != 8 + len + 8 {
        return Err(damaged(&format!("payload of {} bytes, header says {len}", rest.len().saturating_sub(16))));
    }
    let payload = &rest[8..8 + len];
    let checksum = u64::from_le_bytes(rest[8 + len..].try_into().expect("8 bytes"));
    if fnv1a(payload) != checksum {
        return Err(damaged("checksum mismatch"));
    }
    postcard::from_bytes(payload).map_err(|e| damaged(&format!("cannot decode the state: {e}")))
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
mod tests {
    use super::*;

    fn sample() -> State {
        State { time: 0.1 + 0.2, step: 7, dt: 1.0 / 3.0, rotor_angle: -std::f64::consts::PI * 1e-17, ..State::default() }
    }

    fn tmp(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("spillage-ckpt-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join("state.ckpt")
    }

    #[test]
    fn round_trips_bit_for_bit() {
        let path = tmp("rt");
        let state = sample();
        write(&path, "demo", &state).unwrap();
        let back = read(&path, Some("demo")).unwrap();
        assert_eq!(back.time.to_bits(), state.time.to_bits());
        assert_eq!(back.dt.to_bits(), state.dt.to_bits());
        assert_eq!(back.rotor_angle.to_bits(), state.rotor_angle.to_bits());
        assert_eq!(back, state);
        assert!(!path.with_extension("tmp").exists(), "temporary file left behind");
    }

    #[test]
    fn refuses_damaged_truncated_foreign_and_wrong_case() {
        let path = tmp("bad");
        write(&path, "demo", &sample()).unwrap();
        let good = std::fs::read(&path).unwrap();

        let mut flipped = good.clone();
        let last = flipped.len() - 9;
        flipped[last] ^= 0x40;
        std::fs::write(&path, &flipped).unwrap();
        assert!(matches!(read(&path, None), Err(CheckpointError::Damaged { .. })));

        std::fs::write(&path, &good[..good.len() - 3]).unwrap();
        assert!(matches!(read(&path, None), Err(CheckpointError::Damaged { .. })));

        std::fs::write(&path, b"hello world\n").unwrap();
        assert!(matches!(read(&path, None), Err(CheckpointError::NotACheckpoint { .. })));

        std::fs::write(&path, &good).unwrap();
        let err = read(&path, Some("other")).unwrap_err();
        assert!(err.to_string().contains("\"other\""), "{err}");
    }
}
