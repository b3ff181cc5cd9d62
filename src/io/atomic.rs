//! Atomic file output: every image and depth map is written to a temporary file in the
//! target's own directory and then renamed over the target. A rename within one
//! directory is atomic on POSIX file systems, so a reader (or a crash) sees either the
//! old file or the complete new one, never a half-written output (STYLE.md, Errors).
//!
//! What the user's path names is kept: a symbolic link is followed and the file it names
//! is replaced (the link stays), and a special file (`/dev/null`, `/dev/stdout`, a named
//! pipe) is written through, never replaced by a regular file.
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
    let path = &follow_links(path)?;
    match fs::metadata(path) {
        Ok(meta) if meta.is_dir() => return Err(Error::io(path, "is a directory")),
        Ok(meta) if !meta.is_file() => {
            // A device or a pipe: written through, in place.
            let written = OpenOptions::new()
                .write(true)
                .open(path)
                .and_then(|mut file| file.write_all(bytes).and_then(|()| file.flush()));
            return written.map_err(|err| Error::io(path, err));
        }
        _ => {}
    }
    let temporary = temporary_path(path)?;
    let written = write_synced(&temporary, bytes).and_then(|()| fs::rename(&temporary, path));
    written.map_err(|err| {
        // Best effort: the temporary may not exist if creating it was what failed, and
        // the original error is the one worth reporting.
        let _ = fs::remove_file(&temporary);
        Error::io(path, err)
    })
}

/// Links followed at most (the limit of Linux's own resolution).
const MAX_LINKS: usize = 40;

/// The path with its last component's symbolic links followed (to a file that may not
/// exist yet); the path itself when it is no link.
fn follow_links(path: &Path) -> Result<PathBuf> {
    let mut current = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        match fs::symlink_metadata(&current) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let link = fs::read_link(&current).map_err(|err| Error::io(&current, err))?;
                current = match current.parent() {
                    Some(parent) if link.is_relative() => parent.join(link),
                    _ => link,
                };
            }
            _ => return Ok(current),
        }
    }
    Err(Error::io(path, "too many levels of symbolic links"))
}

/// File names longer than this (bytes) are refused by most file systems.
const NAME_MAX: usize = 255;

/// `.NAME.PID.N.tmp` next to the target: same directory, so the rename cannot cross
/// file systems; hidden, so a half-written file does not look like an output. NAME is
/// shortened where the whole would pass NAME_MAX.
fn temporary_path(path: &Path) -> Result<PathBuf> {
    let name = path
        .file_name()
        .ok_or_else(|| Error::io(path, "not a file path"))?;
    let serial = TEMPORARY_COUNTER.fetch_add(1, Ordering::Relaxed);
    let suffix = format!(".{}.{serial}.tmp", std::process::id());
    let name = name.to_string_lossy();
    let mut keep = name.len().min(NAME_MAX - 1 - suffix.len());
    while !name.is_char_boundary(keep) {
        keep -= 1;
    }
    Ok(path.with_file_name(format!(".{}{suffix}", &name[..keep])))
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
        // A directory is never replaced by a file: refused, and nothing is left behind.
        let target = dir.join("occupied");
        fs::create_dir_all(target.join("inside")).unwrap();
        let err = write_atomic(&target, b"data").unwrap_err();
        assert!(matches!(err, Error::Io { .. }), "{err}");
        assert!(err.to_string().contains("occupied"), "{err}");
        assert_eq!(entries(&dir), vec!["occupied".to_string()]);
        fs::remove_dir_all(&dir).unwrap();
    }

    /// A link to an output is kept, and the file it names gets the new bytes.
    #[test]
    fn symbolic_links_are_kept() {
        let dir = scratch_dir("atomic-link");
        let real = dir.join("real.png");
        fs::write(&real, b"old").unwrap();
        let link = dir.join("link.png");
        std::os::unix::fs::symlink("real.png", &link).unwrap();
        write_atomic(&link, b"new").unwrap();
        assert!(
            fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(fs::read(&real).unwrap(), b"new");
        assert_eq!(
            entries(&dir),
            vec!["link.png".to_string(), "real.png".to_string()]
        );
        fs::remove_dir_all(&dir).unwrap();
    }

    /// A special file (here a named pipe, as /dev/null is a device) is written through and
    /// stays what it was, never replaced by a regular file.
    #[test]
    fn special_files_are_written_through() {
        use std::os::unix::fs::FileTypeExt;
        let dir = scratch_dir("atomic-fifo");
        let fifo = dir.join("pipe");
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(made.success(), "mkfifo failed");
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || fs::read(fifo).unwrap())
        };
        write_atomic(&fifo, b"through the pipe").unwrap();
        // Checked before joining: a replaced pipe would leave the reader waiting.
        assert!(fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo());
        assert_eq!(reader.join().unwrap(), b"through the pipe");
        assert_eq!(entries(&dir), vec!["pipe".to_string()]);
        fs::remove_dir_all(&dir).unwrap();
    }

    /// The longest valid file name works: the temporary name is shortened to fit.
    #[test]
    fn a_255_byte_name_works() {
        let dir = scratch_dir("atomic-long");
        let target = dir.join(format!("{}.png", "g".repeat(251)));
        write_atomic(&target, b"data").unwrap();
        assert_eq!(fs::read(&target).unwrap(), b"data");
        assert_eq!(entries(&dir).len(), 1);
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
