//! Whole-file writes that are all-or-nothing: write a temporary file beside the target, flush it to
//! disk, then rename it over the target. A crash at any moment leaves either the old file or the
//! new one, never a truncated mix (rename within one directory is atomic on POSIX and NTFS).

use super::OutputError;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// The temporary sibling of `path`; it keeps the extension last because some encoders (the PNG
/// backend) choose the format from it.
pub(crate) fn temporary_sibling(path: &Path) -> PathBuf {
    let file_name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let extension = path.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default();
    path.with_file_name(format!(".{file_name}.tmp{}{extension}", std::process::id()))
}

/// Moves a finished temporary file over `path` (removing the temporary on failure).
pub(crate) fn replace_with(temporary: &Path, path: &Path) -> Result<(), OutputError> {
    std::fs::rename(temporary, path).map_err(|e| {
        let _ = std::fs::remove_file(temporary);
        OutputError::io(path, e)
    })
}

/// Writes `path` atomically: `write` fills a buffered writer for a temporary sibling, which is
/// synced and renamed over `path` only if `write` succeeded.
pub fn write_atomically<F>(path: &Path, write: F) -> Result<(), OutputError>
where
    F: FnOnce(&mut BufWriter<File>) -> Result<(), OutputError>,
{
    let temporary = temporary_sibling(path);
    let result = (|| {
        let file = File::create(&temporary).map_err(|e| OutputError::io(path, e))?;
        let mut writer = BufWriter::with_capacity(1 << 16, file);
        write(&mut writer)?;
        writer.flush().map_err(|e| OutputError::io(path, e))?;
        let file = writer.into_inner().map_err(|e| OutputError::io(path, e.into_error()))?;
        file.sync_all().map_err(|e| OutputError::io(path, e))
    })();
    match result {
        Ok(()) => replace_with(&temporary, path),
        Err(e) => {
            let _ = std::fs::remove_file(&temporary);
            Err(e)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::test_dir;

    #[test]
    fn failed_write_keeps_the_old_file_and_leaves_no_temporary() {
        let dir = test_dir::fresh("atomic_failure");
        let path = dir.join("index.pvd");
        write_atomically(&path, |w| w.write_all(b"old").map_err(|e| OutputError::io(&path, e))).unwrap();
        let failed = write_atomically(&path, |w| {
            w.write_all(b"half of the new").unwrap();
            Err(OutputError::invalid(&path, "simulated failure mid-write"))
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        let leftovers: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert_eq!(leftovers.len(), 1, "only the target file remains");
    }

    #[test]
    fn temporary_sibling_keeps_directory_and_extension() {
        let t = temporary_sibling(Path::new("/a/b/plot.png"));
        assert_eq!(t.parent(), Some(Path::new("/a/b")));
        assert_eq!(t.extension().unwrap(), "png");
        assert_ne!(t.file_name().unwrap(), "plot.png");
    }
}
