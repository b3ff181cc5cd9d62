//! A folder of outputs written all or nothing (`glyphcast qc`'s figure set): the files
//! are written into a hidden temporary folder beside the target, `.NAME.PID.N.tmp`, and
//! the folder is renamed into place once every file is complete. A reader (a workflow
//! engine waiting for `index.html`, a person) sees no folder or the whole set.
//!
//! A target that exists is replaced only when it is empty or when the caller recognises
//! it as an earlier output of the same kind (`replaceable`): the old folder is renamed
//! aside first, the new one renamed in, and the old one removed. Between the two renames
//! the name is briefly absent, never half-filled. Anything else there is refused before
//! any work ([`check_folder_output`]): glyphcast never deletes a folder it did not write.
//!
//! The temporary folder is entered in the registry of `io::atomic`, so an interrupt
//! removes it (with its contents), and the renames run under that registry's lock.
use std::fs;
use std::path::{Path, PathBuf};

use super::atomic::{live_temporaries, temporary_serial, write_synced};
use crate::{Error, Result};

/// Checks, before any work, that the folder `dir` can be written: its parent exists,
/// and `dir` is missing, an empty folder, or a folder `replaceable` accepts (a missing
/// parent or a file or foreign folder at `dir` is an error naming `dir`).
pub fn check_folder_output(dir: &Path, replaceable: impl Fn(&Path) -> bool) -> Result<()> {
    let parent = parent_of(dir)?;
    if !parent.is_dir() {
        return Err(Error::io(
            dir,
            format!("the folder {} does not exist", parent.display()),
        ));
    }
    match fs::symlink_metadata(dir) {
        Err(_) => Ok(()),
        Ok(meta) if meta.is_dir() => {
            if is_empty(dir)? || replaceable(dir) {
                Ok(())
            } else {
                Err(Error::io(
                    dir,
                    "exists and holds other files: give a new or empty folder (an earlier \
                     set of the same command is replaced)",
                ))
            }
        }
        Ok(_) => Err(Error::io(dir, "exists and is not a folder")),
    }
}

/// Writes `files` (plain names and their bytes) as the folder `dir`, all or nothing
/// (see the module notes); `replaceable` as for [`check_folder_output`], which this
/// checks again.
pub fn write_folder_atomic(
    dir: &Path,
    files: &[(&str, &[u8])],
    replaceable: impl Fn(&Path) -> bool,
) -> Result<()> {
    for (name, _) in files {
        if name.is_empty() || name.contains('/') || *name == "." || *name == ".." {
            return Err(Error::input(
                dir.display().to_string(),
                format!("'{}'", crate::error::quoted(name)),
                "is no plain file name",
            ));
        }
    }
    check_folder_output(dir, &replaceable)?;
    let temporary = temporary_folder(dir)?;
    let written = fill(&temporary, files);
    let mut live = live_temporaries();
    let outcome = written.and_then(|()| put_in_place(&temporary, dir, &replaceable));
    if outcome.is_err() {
        let _ = fs::remove_dir_all(&temporary);
    }
    live.retain(|path| path != &temporary);
    drop(live);
    match outcome {
        Ok(Some(old)) => {
            // The set is in place; the old one is gone from view. Best effort.
            let _ = fs::remove_dir_all(old);
            Ok(())
        }
        Ok(None) => Ok(()),
        Err(err) => Err(err),
    }
}

/// Creates the hidden temporary folder beside `dir`, entered in the registry first.
fn temporary_folder(dir: &Path) -> Result<PathBuf> {
    let name = dir
        .file_name()
        .ok_or_else(|| Error::io(dir, "not a folder path"))?
        .to_string_lossy()
        .into_owned();
    let temporary = parent_of(dir)?.join(format!(
        ".{name}.{}.{}.tmp",
        std::process::id(),
        temporary_serial()
    ));
    let mut live = live_temporaries();
    live.push(temporary.clone());
    if let Err(err) = fs::create_dir(&temporary) {
        live.retain(|path| path != &temporary);
        return Err(Error::io(dir, err));
    }
    Ok(temporary)
}

/// Writes every file into `folder`, each flushed to disk.
fn fill(folder: &Path, files: &[(&str, &[u8])]) -> Result<()> {
    for (name, bytes) in files {
        let path = folder.join(name);
        write_synced(&path, bytes).map_err(|err| Error::io(&path, err))?;
        // write_synced registers each file; the folder's entry covers them.
        live_temporaries().retain(|live| live != &path);
    }
    Ok(())
}

/// Renames `temporary` to `dir`; an existing `dir` (empty, or replaceable) is renamed
/// aside first and returned for removal.
fn put_in_place(
    temporary: &Path,
    dir: &Path,
    replaceable: impl Fn(&Path) -> bool,
) -> Result<Option<PathBuf>> {
    let existing = fs::symlink_metadata(dir).is_ok();
    if !existing || is_empty(dir)? {
        // rename(2) replaces an empty folder.
        fs::rename(temporary, dir).map_err(|err| Error::io(dir, err))?;
        return Ok(None);
    }
    if !replaceable(dir) {
        return Err(Error::io(dir, "exists and holds other files"));
    }
    let old = temporary.with_extension(format!("old{}", temporary_serial()));
    fs::rename(dir, &old).map_err(|err| Error::io(dir, err))?;
    if let Err(err) = fs::rename(temporary, dir) {
        let _ = fs::rename(&old, dir);
        return Err(Error::io(dir, err));
    }
    Ok(Some(old))
}

fn parent_of(dir: &Path) -> Result<PathBuf> {
    if dir.file_name().is_none() {
        return Err(Error::io(dir, "not a folder path"));
    }
    Ok(match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    })
}

fn is_empty(dir: &Path) -> Result<bool> {
    Ok(fs::read_dir(dir)
        .map_err(|err| Error::io(dir, err))?
        .next()
        .is_none())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::atomic::tests::scratch_dir;

    fn names(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .expect("listing")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    fn marked(dir: &Path) -> bool {
        dir.join("mark").exists()
    }

    #[test]
    fn a_folder_appears_whole_and_replaces_only_its_own_kind() {
        let root = scratch_dir("folder");
        let out = root.join("set");
        write_folder_atomic(&out, &[("mark", b"1"), ("a.png", b"a")], marked).expect("new");
        assert_eq!(names(&out), ["a.png", "mark"]);
        // An earlier set is replaced as a whole: its extra file goes too.
        fs::write(out.join("stale.png"), b"old").expect("writing");
        write_folder_atomic(&out, &[("mark", b"2")], marked).expect("replaced");
        assert_eq!(names(&out), ["mark"]);
        assert_eq!(names(&root), ["set"], "no temporary or old folder left");
        // A folder of other files is refused before anything is written.
        let foreign = root.join("foreign");
        fs::create_dir(&foreign).expect("mkdir");
        fs::write(foreign.join("notes.txt"), b"mine").expect("writing");
        let err = write_folder_atomic(&foreign, &[("mark", b"3")], marked).expect_err("foreign");
        assert!(err.to_string().contains("foreign"), "{err}");
        assert_eq!(names(&foreign), ["notes.txt"]);
        // An empty folder is filled; a missing parent is an error naming the folder.
        let empty = root.join("empty");
        fs::create_dir(&empty).expect("mkdir");
        write_folder_atomic(&empty, &[("mark", b"4")], marked).expect("empty");
        assert_eq!(names(&empty), ["mark"]);
        let orphan = root.join("missing").join("set");
        let err = check_folder_output(&orphan, marked).expect_err("missing parent");
        assert!(err.to_string().contains("does not exist"), "{err}");
        assert_eq!(names(&root), ["empty", "foreign", "set"]);
        assert!(!live_temporaries().iter().any(|p| p.starts_with(&root)));
        fs::remove_dir_all(&root).expect("cleaning up");
    }
}
