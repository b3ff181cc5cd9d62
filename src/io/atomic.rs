//! Atomic file output: every image and depth map is written to a temporary file in the
//! target's own directory and then renamed over the target. A rename within one
//! directory is atomic on POSIX file systems, so a reader (or a crash) sees either the
//! old file or the complete new one, never a half-written output (STYLE.md, Errors).
//!
//! An interrupt (SIGINT, SIGTERM) must not leave temporaries or a half-replaced set:
//! every temporary is entered in `LIVE_TEMPORARIES` before it is created, and the
//! renames of a set run with that registry locked. [`exit_removing_temporaries`], which
//! the binary's signal handler calls, takes the same lock, so it either waits for a set's
//! renames to finish (all new) or removes the temporaries before any rename (all old).
//!
//! What the user's path names is kept: a symbolic link is followed and the file it names
//! is replaced (the link stays), and a special file (`/dev/null`, `/dev/stdout`, a named
//! pipe) is written through, never replaced by a regular file.
use std::fs::{self, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

use crate::{Error, Result};

/// Distinguishes temporary files of concurrent writes from one process.
static TEMPORARY_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Temporary files that exist (or are about to) and are not yet renamed or removed.
static LIVE_TEMPORARIES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The registry, also after a panic in another thread (a list of paths cannot be left
/// inconsistent by one).
pub(super) fn live_temporaries() -> MutexGuard<'static, Vec<PathBuf>> {
    LIVE_TEMPORARIES
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
}

/// Removes every temporary of a write in progress and ends the process with `code`;
/// waits first for a set whose renames have begun, so that the set ends all new. For
/// the binary's SIGINT/SIGTERM handler: the process ends at once (`_exit`), without the
/// exit handlers of libraries whose other threads may still be working (the Vulkan
/// driver's).
pub fn exit_removing_temporaries(code: i32) -> ! {
    // Held until the process ends: no write can start or rename after this point.
    let live = live_temporaries();
    for temporary in live.iter() {
        // A temporary folder (`io::folder`) is removed with its contents.
        let _ = fs::remove_file(temporary).or_else(|_| fs::remove_dir_all(temporary));
    }
    signal_hook::low_level::exit(code)
}

/// A number no other temporary of this process has.
pub(super) fn temporary_serial() -> u64 {
    TEMPORARY_COUNTER.fetch_add(1, Ordering::Relaxed)
}

/// Forgets `temporaries` (renamed or removed).
fn forget(temporaries: &[(PathBuf, PathBuf)]) {
    live_temporaries().retain(|live| !temporaries.iter().any(|(t, _)| t == live));
}

/// Writes `bytes` to `path` atomically; on failure the target is untouched and the
/// temporary file is removed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_all_atomic(&[(path, bytes)])
}

/// Writes a set of outputs so that either all are new or all are as they were: every
/// regular file is first written in full to a temporary beside it, special files are
/// written through, and only then are the temporaries renamed over their targets. A
/// failure before the renames removes every temporary and leaves the targets untouched
/// (a special file cannot take its bytes back: those are written first, so that a
/// failing one stops the set before anything is replaced).
pub fn write_all_atomic(outputs: &[(&Path, &[u8])]) -> Result<()> {
    let mut regular = Vec::new();
    let mut special = Vec::new();
    for (path, bytes) in outputs {
        let path = follow_links(path)?;
        match fs::metadata(&path) {
            Ok(meta) if meta.is_dir() => return Err(Error::io(&path, "is a directory")),
            Ok(meta) if !meta.is_file() => special.push((path, *bytes)),
            _ => regular.push((path, *bytes)),
        }
    }
    let mut temporaries: Vec<(PathBuf, PathBuf)> = Vec::with_capacity(regular.len());
    let remove_all = |temporaries: &[(PathBuf, PathBuf)]| {
        for (temporary, _) in temporaries {
            // Best effort: the original error is the one worth reporting.
            let _ = fs::remove_file(temporary);
        }
        forget(temporaries);
    };
    for (path, bytes) in &regular {
        let temporary = match temporary_path(path) {
            Ok(t) => t,
            Err(e) => {
                remove_all(&temporaries);
                return Err(e);
            }
        };
        temporaries.push((temporary.clone(), path.clone()));
        if let Err(err) = write_synced(&temporary, bytes) {
            remove_all(&temporaries);
            return Err(Error::io(path, err));
        }
    }
    for (path, bytes) in &special {
        // A device or a pipe: written through, in place.
        let written = OpenOptions::new()
            .write(true)
            .open(path)
            .and_then(|mut file| file.write_all(bytes).and_then(|()| file.flush()));
        if let Err(err) = written {
            remove_all(&temporaries);
            return Err(Error::io(path, err));
        }
    }
    // An interrupt waits for the renames (see the module notes).
    let mut live = live_temporaries();
    let renamed = rename_all(&temporaries);
    live.retain(|l| !temporaries.iter().any(|(t, _)| t == l));
    renamed
}

/// Renames each temporary over its target; after a failure removes the rest.
fn rename_all(temporaries: &[(PathBuf, PathBuf)]) -> Result<()> {
    for (index, (temporary, path)) in temporaries.iter().enumerate() {
        if let Err(err) = fs::rename(temporary, path) {
            for (rest, _) in &temporaries[index..] {
                let _ = fs::remove_file(rest);
            }
            return Err(Error::io(path, err));
        }
    }
    Ok(())
}

/// Checks that an output's name ends in one of `endings` (`.png`), so that `-o out.jpg`
/// does not get PNG bytes under a JPEG name: a usage error naming `option`. A name
/// without an ending and a special file (`/dev/null`, a pipe) pass.
pub fn check_ending(path: &Path, option: &'static str, endings: &[&str]) -> Result<()> {
    let Some(ending) = path.extension() else {
        return Ok(());
    };
    let special = fs::metadata(path).is_ok_and(|meta| !meta.is_file() && !meta.is_dir());
    let known = endings
        .iter()
        .any(|e| ending.eq_ignore_ascii_case(e.trim_start_matches('.')));
    if known || special {
        return Ok(());
    }
    Err(Error::OutputName {
        option,
        path: path.display().to_string(),
        format: endings[0].trim_start_matches('.').to_uppercase(),
        endings: endings.iter().map(|e| (*e).to_owned()).collect(),
    })
}

/// Checks a command's output paths before any work: each names a file (not a
/// directory) in an existing directory, no two name the same file (links followed),
/// and none names a file the command reads (`inputs`, see [`check_not_inputs`]). The
/// same file twice is a usage error.
pub fn check_outputs(paths: &[&Path], inputs: &[&Path]) -> Result<()> {
    check_paths(paths)?;
    check_not_inputs(paths, inputs)
}

/// Checks, before any work, that no output is one of the command's input files, which
/// writing it would destroy: an output that exists as a regular file is compared with
/// every input that exists by device and inode, so a symbolic link, a hard link or
/// another spelling of an input's path is caught; an output folder (`qc`'s) must hold
/// no input. Special files (`/dev/null`) are written through and never compared. A
/// usage error naming both paths.
pub fn check_not_inputs(outputs: &[&Path], inputs: &[&Path]) -> Result<()> {
    for output in outputs {
        let Ok(meta) = fs::metadata(output) else {
            // Nothing there yet: no input can be lost.
            continue;
        };
        let folder = if meta.is_dir() {
            fs::canonicalize(output).ok()
        } else if meta.is_file() {
            None
        } else {
            continue;
        };
        for input in inputs {
            let Ok(input_meta) = fs::metadata(input) else {
                continue;
            };
            let clash = match &folder {
                Some(folder) => {
                    fs::canonicalize(input).is_ok_and(|input| input.starts_with(folder))
                }
                None => same_file((output, &meta), (input, &input_meta)),
            };
            if clash {
                return Err(Error::OutputIsInput {
                    output: output.display().to_string(),
                    input: input.display().to_string(),
                    folder: folder.is_some(),
                });
            }
        }
    }
    Ok(())
}

/// Whether two existing paths name one file (the same device and inode).
#[cfg(unix)]
fn same_file(a: (&Path, &fs::Metadata), b: (&Path, &fs::Metadata)) -> bool {
    use std::os::unix::fs::MetadataExt;
    a.1.dev() == b.1.dev() && a.1.ino() == b.1.ino()
}

/// Without inodes: the same path once links are resolved (a hard link is missed).
#[cfg(not(unix))]
fn same_file(a: (&Path, &fs::Metadata), b: (&Path, &fs::Metadata)) -> bool {
    match (fs::canonicalize(a.0), fs::canonicalize(b.0)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// Each output names a file in an existing folder, and no two the same file.
fn check_paths(paths: &[&Path]) -> Result<()> {
    let mut seen: Vec<(PathBuf, &Path)> = Vec::with_capacity(paths.len());
    for path in paths {
        let resolved = follow_links(path)?;
        let Some(name) = resolved.file_name() else {
            return Err(Error::io(path, "not a file path"));
        };
        let parent = match resolved.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let folder = fs::canonicalize(&parent).map_err(|_| {
            Error::io(
                path,
                format!("the folder {} does not exist", parent.display()),
            )
        })?;
        if !folder.is_dir() {
            return Err(Error::io(
                path,
                format!("{} is not a folder", parent.display()),
            ));
        }
        if resolved.is_dir() {
            return Err(Error::io(path, "is a directory"));
        }
        let identity = folder.join(name);
        if let Some((_, first)) = seen.iter().find(|(other, _)| *other == identity) {
            return Err(Error::SameOutput {
                first: first.display().to_string(),
                second: path.display().to_string(),
            });
        }
        seen.push((identity, path));
    }
    Ok(())
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
pub(super) fn write_synced(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut file = {
        // Entered before it exists, under the lock an interrupt takes: a temporary is
        // never created after the interrupt's clean-up.
        let mut live = live_temporaries();
        live.push(path.to_path_buf());
        OpenOptions::new().write(true).create_new(true).open(path)?
    };
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

    /// A set of outputs is all or nothing: when one cannot be written, the others keep
    /// their old contents and no temporary is left.
    #[test]
    fn a_set_of_outputs_is_all_or_nothing() {
        let dir = scratch_dir("atomic-set");
        let (a, b) = (dir.join("a.png"), dir.join("b.npy"));
        fs::write(&a, b"old a").unwrap();
        fs::write(&b, b"old b").unwrap();
        let missing = dir.join("missing").join("c.json");
        let err = write_all_atomic(&[(&a, b"new a"), (&b, b"new b"), (&missing, b"c")]);
        assert!(err.is_err());
        assert_eq!(fs::read(&a).unwrap(), b"old a");
        assert_eq!(fs::read(&b).unwrap(), b"old b");
        assert_eq!(
            entries(&dir),
            vec!["a.png".to_string(), "b.npy".to_string()]
        );
        write_all_atomic(&[(&a, b"new a"), (&b, b"new b")]).unwrap();
        assert_eq!(fs::read(&a).unwrap(), b"new a");
        assert_eq!(fs::read(&b).unwrap(), b"new b");
        fs::remove_dir_all(&dir).unwrap();
    }

    /// Output paths are checked up front: a missing folder, a directory and the same
    /// file twice (also through a link) are refused, distinct files pass.
    #[test]
    fn output_paths_are_checked_before_work() {
        let dir = scratch_dir("atomic-check");
        let (a, b) = (dir.join("a.png"), dir.join("b.npy"));
        check_outputs(&[&a, &b], &[]).unwrap();
        let missing = dir.join("missing").join("c.png");
        let err = check_outputs(&[&a, &missing], &[]).unwrap_err();
        assert!(err.to_string().contains("does not exist"), "{err}");
        assert!(check_outputs(&[&dir], &[]).is_err());
        let err = check_outputs(&[&a, &dir.join(".").join("a.png")], &[]).unwrap_err();
        assert!(
            matches!(err, Error::SameOutput { .. }) && err.is_usage(),
            "{err}"
        );
        std::os::unix::fs::symlink("a.png", dir.join("link.png")).unwrap();
        let err = check_outputs(&[&a, &dir.join("link.png")], &[]).unwrap_err();
        assert!(matches!(err, Error::SameOutput { .. }), "{err}");
        fs::remove_dir_all(&dir).unwrap();
    }

    /// A name's ending must be one of the format's; none at all and special files pass.
    #[test]
    fn output_endings_name_the_format() {
        let png = [".png"];
        check_ending(Path::new("out.png"), "-o", &png).unwrap();
        check_ending(Path::new("OUT.PNG"), "-o", &png).unwrap();
        check_ending(Path::new("out"), "-o", &png).unwrap();
        check_ending(Path::new("/dev/null"), "-o", &png).unwrap();
        let err = check_ending(Path::new("out.jpg"), "-o", &png).unwrap_err();
        assert!(
            matches!(err, Error::OutputName { .. }) && err.is_usage(),
            "{err}"
        );
        let text = err.to_string();
        assert!(
            text.contains("-o") && text.contains(".png") && text.contains("jpg"),
            "{text}"
        );
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
