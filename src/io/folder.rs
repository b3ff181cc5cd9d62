//! A folder of outputs written all or nothing (`glyphcast qc`'s figure set): the files
//! are written into a hidden temporary folder beside the target, `.NAME.PID.N.tmp`, and
//! the folder is renamed into place once every file is complete. A reader (a workflow
//! engine waiting for `index.html`, a person) sees no folder or the whole set.
//!
//! A target that exists is replaced only when it is empty or holds nothing but an
//! earlier output of the same kind: the caller's `earlier` reads the folder's own record
//! of its files (`qc.json`'s list) and returns their names, or `None` when the folder
//! holds no such record. Every entry must be one of those names and a plain file (no
//! link, no folder); any other entry is refused before any work, naming it
//! ([`check_folder_output`]). The old folder is renamed aside first, the new one renamed
//! in, and then only the listed files are removed from the old one and the emptied
//! folder with them: glyphcast never deletes a file it did not write. Between the two
//! renames the name is briefly absent, never half-filled.
//!
//! Missing folders above the target (`sub-01/` of `sub-01/qc`) are created when the set
//! is written, not before: a run that fails before then leaves nothing behind, and one
//! that fails while writing removes the folders it created (those still empty).
//!
//! The temporary folder is entered in the registry of `io::atomic`, so an interrupt
//! removes it (with its contents), and the renames run under that registry's lock.
use std::fs;
use std::path::{Path, PathBuf};

use super::atomic::{live_temporaries, temporary_serial, write_synced};
use crate::{Error, Result};

/// What a refused folder's error suggests.
const NEW_FOLDER: &str =
    "give a new or empty folder (an earlier set is replaced, nothing else is removed)";

/// The names an earlier output folder of a command lists as its own files (see the
/// module notes); `None` where the folder holds no such record.
pub(crate) type EarlierSet<'a> = &'a dyn Fn(&Path) -> Option<Vec<String>>;

/// Checks, before any work, that the folder `dir` can be written: its parent exists or
/// can be created (the nearest existing folder above it is a folder, not a file), and
/// `dir` is missing, an empty folder, or a folder of nothing but an earlier set's files
/// (`earlier`); a file in the way of the parent or at `dir` is an error naming `dir`, a
/// folder with any other entry an [`Error::ForeignEntry`] naming one.
pub fn check_folder_output(dir: &Path, earlier: EarlierSet) -> Result<()> {
    let parent = parent_of(dir)?;
    if !parent.is_dir() {
        let blocking = missing_folders(&parent)
            .last()
            .and_then(|top| top.parent().map(Path::to_path_buf))
            .filter(|above| !above.as_os_str().is_empty() && !above.is_dir());
        if let Some(above) = blocking.or_else(|| parent.exists().then(|| parent.clone())) {
            return Err(Error::io(
                dir,
                format!("{} is not a folder", above.display()),
            ));
        }
        return Ok(());
    }
    match fs::symlink_metadata(dir) {
        Err(_) => Ok(()),
        Ok(meta) if meta.is_dir() => match foreign_entry(dir, earlier)? {
            None => Ok(()),
            Some(entry) => Err(Error::ForeignEntry {
                folder: dir.display().to_string(),
                entry,
                remedy: NEW_FOLDER,
            }),
        },
        Ok(_) => Err(Error::io(dir, "exists and is not a folder")),
    }
}

/// The first entry of `dir` (in name order) that is not a plain file listed by the
/// earlier set there; `None` when every entry is one (or the folder is empty).
fn foreign_entry(dir: &Path, earlier: EarlierSet) -> Result<Option<String>> {
    let mut entries: Vec<(String, fs::FileType)> = Vec::new();
    for entry in fs::read_dir(dir).map_err(|err| Error::io(dir, err))? {
        let entry = entry.map_err(|err| Error::io(dir, err))?;
        let kind = entry.file_type().map_err(|err| Error::io(dir, err))?;
        entries.push((entry.file_name().to_string_lossy().into_owned(), kind));
    }
    if entries.is_empty() {
        return Ok(None);
    }
    entries.sort_by(|a, b| a.0.cmp(&b.0));
    let listed = earlier(dir).unwrap_or_default();
    Ok(entries
        .into_iter()
        .find(|(name, kind)| !kind.is_file() || !listed.contains(name))
        .map(|(name, _)| name))
}

/// Writes `files` (plain names and their bytes) as the folder `dir`, all or nothing
/// (see the module notes); `earlier` as for [`check_folder_output`], which this
/// checks again.
pub fn write_folder_atomic(dir: &Path, files: &[(&str, &[u8])], earlier: EarlierSet) -> Result<()> {
    for (name, _) in files {
        if name.is_empty() || name.contains('/') || *name == "." || *name == ".." {
            return Err(Error::input(
                dir.display().to_string(),
                format!("'{}'", crate::error::quoted(name)),
                "is no plain file name",
            ));
        }
    }
    check_folder_output(dir, earlier)?;
    let created = create_parents(dir)?;
    let temporary = match temporary_folder(dir) {
        Ok(temporary) => temporary,
        Err(err) => {
            remove_created(&created);
            return Err(err);
        }
    };
    let written = fill(&temporary, files);
    let mut live = live_temporaries();
    let outcome = written.and_then(|()| put_in_place(&temporary, dir, earlier));
    if outcome.is_err() {
        let _ = fs::remove_dir_all(&temporary);
    }
    live.retain(|path| path != &temporary);
    drop(live);
    if outcome.is_err() {
        remove_created(&created);
    }
    match outcome {
        Ok(Some((old, names))) => {
            // The set is in place; the old one is gone from view. Only its listed files
            // are removed, and the folder only once empty (best effort: a file someone
            // put there since the check stays, in the hidden old folder).
            for name in names {
                let _ = fs::remove_file(old.join(name));
            }
            let _ = fs::remove_dir(old);
            Ok(())
        }
        Ok(None) => Ok(()),
        Err(err) => Err(err),
    }
}

/// The folders from `folder` up that do not exist, deepest first.
fn missing_folders(folder: &Path) -> Vec<PathBuf> {
    folder
        .ancestors()
        .filter(|a| !a.as_os_str().is_empty())
        .take_while(|a| fs::symlink_metadata(a).is_err())
        .map(Path::to_path_buf)
        .collect()
}

/// Creates the missing folders above `dir` and returns them, deepest first.
fn create_parents(dir: &Path) -> Result<Vec<PathBuf>> {
    let parent = parent_of(dir)?;
    let missing = missing_folders(&parent);
    if let Some(top) = missing.last()
        && let Err(err) = fs::create_dir_all(&parent)
    {
        remove_created(&missing);
        return Err(Error::io(dir, format!("creating {}: {err}", top.display())));
    }
    Ok(missing)
}

/// Removes folders [`create_parents`] created, deepest first, each only while empty.
fn remove_created(created: &[PathBuf]) {
    for folder in created {
        if fs::remove_dir(folder).is_err() {
            break;
        }
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

/// Renames `temporary` to `dir`; an existing `dir` (empty, or an earlier set) is
/// renamed aside first and returned, with the names of its listed files, for removal.
fn put_in_place(
    temporary: &Path,
    dir: &Path,
    earlier: EarlierSet,
) -> Result<Option<(PathBuf, Vec<String>)>> {
    let existing = fs::symlink_metadata(dir).is_ok();
    if !existing || is_empty(dir)? {
        // rename(2) replaces an empty folder.
        fs::rename(temporary, dir).map_err(|err| Error::io(dir, err))?;
        return Ok(None);
    }
    if let Some(entry) = foreign_entry(dir, earlier)? {
        return Err(Error::ForeignEntry {
            folder: dir.display().to_string(),
            entry,
            remedy: NEW_FOLDER,
        });
    }
    let names = earlier(dir).unwrap_or_default();
    let old = temporary.with_extension(format!("old{}", temporary_serial()));
    fs::rename(dir, &old).map_err(|err| Error::io(dir, err))?;
    if let Err(err) = fs::rename(temporary, dir) {
        let _ = fs::rename(&old, dir);
        return Err(Error::io(dir, err));
    }
    Ok(Some((old, names)))
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

    /// A set records its files in `mark`, one name a line.
    fn marked(dir: &Path) -> Option<Vec<String>> {
        let text = fs::read_to_string(dir.join("mark")).ok()?;
        Some(text.lines().map(str::to_owned).collect())
    }

    #[test]
    fn a_folder_appears_whole_and_replaces_only_its_own_kind() {
        let root = scratch_dir("folder");
        let out = root.join("set");
        let list = b"mark\na.png\nstale.png";
        write_folder_atomic(&out, &[("mark", list), ("a.png", b"a")], &marked).expect("new");
        assert_eq!(names(&out), ["a.png", "mark"]);
        // An earlier set is replaced as a whole: a file it lists goes too.
        fs::write(out.join("stale.png"), b"old").expect("writing");
        write_folder_atomic(&out, &[("mark", b"mark")], &marked).expect("replaced");
        assert_eq!(names(&out), ["mark"]);
        // A file the set does not list is foreign: refused, nothing removed.
        fs::write(out.join("notes.txt"), b"mine").expect("writing");
        let err = write_folder_atomic(&out, &[("mark", b"mark")], &marked).expect_err("foreign");
        assert!(
            matches!(&err, Error::ForeignEntry { entry, .. } if entry == "notes.txt"),
            "{err}"
        );
        assert_eq!(names(&out), ["mark", "notes.txt"]);
        fs::remove_file(out.join("notes.txt")).expect("removing");
        assert_eq!(names(&root), ["set"], "no temporary or old folder left");
        // A folder of other files is refused before anything is written.
        let foreign = root.join("foreign");
        fs::create_dir(&foreign).expect("mkdir");
        fs::write(foreign.join("notes.txt"), b"mine").expect("writing");
        let err = write_folder_atomic(&foreign, &[("mark", b"3")], &marked).expect_err("foreign");
        assert!(err.to_string().contains("foreign"), "{err}");
        assert_eq!(names(&foreign), ["notes.txt"]);
        // An empty folder is filled; a missing parent is an error naming the folder.
        let empty = root.join("empty");
        fs::create_dir(&empty).expect("mkdir");
        write_folder_atomic(&empty, &[("mark", b"4")], &marked).expect("empty");
        assert_eq!(names(&empty), ["mark"]);
        // Missing folders above the set are created as it is written, not at the check.
        let nested = root.join("missing").join("deeper").join("set");
        check_folder_output(&nested, &marked).expect("missing parents");
        assert!(!root.join("missing").exists(), "the check creates nothing");
        write_folder_atomic(&nested, &[("mark", b"5")], &marked).expect("nested");
        assert_eq!(names(&nested), ["mark"]);
        assert_eq!(names(&root.join("missing").join("deeper")), ["set"]);
        // A file in the way of a parent is an error naming the file.
        fs::write(root.join("plain"), b"x").expect("writing");
        let blocked = root.join("plain").join("sub").join("set");
        let err = check_folder_output(&blocked, &marked).expect_err("file above");
        assert!(err.to_string().contains("is not a folder"), "{err}");
        fs::remove_file(root.join("plain")).expect("removing");
        fs::remove_dir_all(root.join("missing")).expect("removing");
        assert_eq!(names(&root), ["empty", "foreign", "set"]);
        assert!(!live_temporaries().iter().any(|p| p.starts_with(&root)));
        fs::remove_dir_all(&root).expect("cleaning up");
    }
}
