//! Atomic file output: every image and depth map is written to a temporary file in the
//! target's own directory and then renamed over the target. A rename within one
//! directory is atomic on POSIX file systems, so a reader (or a crash) sees either the
//! old file or the complete new one, never a half-written output (STYLE.md, Errors).
use std::fs::{self, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::{Error, Result};

/// Distinguishes temporary files of concurrent writes from one process.
static TEMPORARY_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `bytes` to `path` atomically; on failure the target is untouched and the
/// temporary file is removed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let temporary = temporary_path(path)?;
    let written = write_synced(&temporary, bytes).and_then(|()| fs::rename(&temporary, path));
    written.map_err(|err| {
        // Best effort: the temporary may not exist if creating it was what failed, and
        // the original error is the one worth reporting.
        let _ = fs::remove_file(&temporary);
        Error::io(path, err)
    })
}

/// `.NAME.PID.N.tmp` next to the target: same directory, so the rename cannot cross
/// file systems; hidden, so a half-written file does not look like an output.
fn temporary_path(path: &Path) -> Result<PathBuf> {
    let name = path
        .file_name()
        .ok_or_else(|| Error::io(path, "not a file path"))?;
    let serial = TEMPORARY_COUNTER.fetch_add(1, Ordering::Relaxed);
    let temporary_name = format!(
        ".{}.{}.{serial}.tmp",
        name.to_string_lossy(),
        std::process::id()
    );
    Ok(path.with_file_name(temporary_name))
}

/// Creates `path` (which must not exist yet), writes `bytes` and flushes them to disk
/// so that the rename publishes complete data.
fn write_synced(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut file = OpenOptions::new().write(true).create_new(true).open(path)?;
    file.write_all(bytes)?;
    file.sync_all()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A fresh, empty directory for one test.
    pub(crate) fn scratch_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "glyphcast-{name}-{}-{}",
            std::process::id(),
            TEMPORARY_COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|entry| entry.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn writes_and_leaves_no_temporary_behind() {
        let dir = scratch_dir("atomic-ok");
        let target = dir.join("out.bin");
        write_atomic(&target, b"first").unwrap();
        write_atomic(&target, b"second, longer").unwrap();
        assert_eq!(fs::read(&target).unwrap(), b"second, longer");
        assert_eq!(entries(&dir), vec!["out.bin".to_string()]);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn failed_rename_removes_the_temporary() {
        let dir = scratch_dir("atomic-fail");
        // A non-empty directory cannot be replaced by a file: the rename fails after
        // the temporary was written.
        let target = dir.join("occupied");
        fs::create_dir_all(target.join("inside")).unwrap();
        let err = write_atomic(&target, b"data").unwrap_err();
        assert!(matches!(err, Error::Io { .. }), "{err}");
        assert!(err.to_string().contains("occupied"), "{err}");
        assert_eq!(entries(&dir), vec!["occupied".to_string()]);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn missing_directory_is_an_io_error() {
        let dir = scratch_dir("atomic-missing");
        let target = dir.join("no-such-dir").join("out.bin");
        let err = write_atomic(&target, b"data").unwrap_err();
        assert!(matches!(err, Error::Io { .. }), "{err}");
        assert!(entries(&dir).is_empty());
        fs::remove_dir_all(&dir).unwrap();
    }
}
