//! A directory of generated files, written or compared with the disk: the
//! Rust crate's `src/` ([`crate::GeneratedCrate`]) and its C++ library's
//! `cpp/` ([`crate::cpp::CppLibrary`]).
//!
//! The directory holds generated files of one extension only: writing
//! rewrites those whose contents differ (each to a temporary file renamed
//! into place) and removes the ones with that extension that are not
//! generated; checking reports every differing, missing or extra one.

use std::io;
use std::path::{Path, PathBuf};

/// The files of extension `ext` in `dir` (and, when `recursive`, in its
/// subdirectories), sorted; none when `dir` does not exist.
fn files_with(dir: &Path, ext: &str, recursive: bool) -> io::Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let entries = match std::fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(files),
        Err(e) => return Err(e),
    };
    for entry in entries {
        let path = entry?.path();
        if path.is_file() && path.extension().is_some_and(|e| e == ext) {
            files.push(path);
        } else if recursive && path.is_dir() {
            files.extend(files_with(&path, ext, true)?);
        }
    }
    files.sort();
    Ok(files)
}

/// Whether `path` is one of `files` (paths relative to `dir`).
fn generated(dir: &Path, files: &[(String, String)], path: &Path) -> bool {
    files.iter().any(|(name, _)| dir.join(name) == path)
}

/// Writes `files` (`(path relative to dir, contents)`) under `dir`, creating
/// directories as needed, and removes the other files of extension `ext`
/// (looked for in subdirectories too when `recursive`).
///
/// # Errors
///
/// Any I/O error.
pub fn write(dir: &Path, files: &[(String, String)], ext: &str, recursive: bool) -> io::Result<()> {
    std::fs::create_dir_all(dir)?;
    for (name, contents) in files {
        let path = dir.join(name);
        if std::fs::read(&path).ok().as_deref() != Some(contents.as_bytes()) {
            if let Some(parent) = path.parent() {
                std::fs::create_dir_all(parent)?;
            }
            // A temporary file renamed into place: an interrupted or failed
            // write leaves the old file whole.
            slamjac_io::atomic::write(&path, contents)?;
        }
    }
    for path in files_with(dir, ext, recursive)? {
        if !generated(dir, files, &path) {
            std::fs::remove_file(&path)?;
        }
    }
    Ok(())
}

/// Compares `dir` with what [`write`] would write: `Ok` when identical,
/// else every differing, missing or extra file, sorted.
pub fn check(
    dir: &Path,
    files: &[(String, String)],
    ext: &str,
    recursive: bool,
) -> Result<(), Vec<PathBuf>> {
    let mut stale = Vec::new();
    for (name, contents) in files {
        let path = dir.join(name);
        if std::fs::read(&path).ok().as_deref() != Some(contents.as_bytes()) {
            stale.push(path);
        }
    }
    // An unreadable directory is reported as its expected files, above.
    for path in files_with(dir, ext, recursive).unwrap_or_default() {
        if !generated(dir, files, &path) {
            stale.push(path);
        }
    }
    stale.sort();
    if stale.is_empty() { Ok(()) } else { Err(stale) }
}
