//! Output paths checked before any work: none may name an input or another
//! output of the same run, and each must be writable.
//!
//! Two paths name the same file when they lead to the same device and inode
//! (links, `..`, symbolic links and other spellings included); a path that
//! does not exist yet (a dangling symbolic link: the target it would
//! create) names the file its canonical directory and its name give. Character devices are exempt (`--plot /dev/null --output
//! /dev/null` destroys nothing). An output is writable when it is not a
//! directory and a temporary file can be created beside it (it is created
//! and removed, as [`crate::AtomicFile`] will create the real one).

use std::io;
use std::path::{Path, PathBuf};

use crate::atomic::AtomicFile;
use crate::destination::{directory, resolve};
use crate::printable::escape;

/// A path and the part it plays in the run, as messages name it:
/// `input`, `--output`, `--plot`, `DOCUMENT`.
#[derive(Debug, Clone, Copy)]
pub struct Role<'a> {
    /// The option or argument that gave the path.
    pub name: &'a str,
    /// The path as given.
    pub path: &'a Path,
}

impl<'a> Role<'a> {
    /// `path`, given as `name`.
    pub fn new(name: &'a str, path: &'a Path) -> Self {
        Role { name, path }
    }
}

/// Why the outputs of a run are refused; one line, `PATH: what`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PathError {
    /// An output names the same file as an input or another output.
    #[error("{path}: {output} names the same file as {other}{shown}; refused before any work")]
    Same {
        /// The output's path, printable.
        path: String,
        /// The output's role.
        output: String,
        /// The other path's role.
        other: String,
        /// ` (PATH)` when the other path is spelled differently.
        shown: String,
    },
    /// An output cannot be written.
    #[error("{path}: {output}: cannot write here: {why}")]
    NotWritable {
        /// The output's path, printable.
        path: String,
        /// The output's role.
        output: String,
        /// Why, one line.
        why: String,
    },
}

/// What a path names, to compare paths by.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Identity {
    /// An existing file: its device and inode.
    #[cfg(unix)]
    Inode(u64, u64),
    /// A file by its canonical path (one that does not exist yet; on other
    /// systems, any file).
    Path(PathBuf),
}

/// What `path` names, and whether it is a character device; `None` for a
/// path that cannot name a file (its directory does not exist).
fn identity(path: &Path) -> Option<(Identity, bool)> {
    match std::fs::metadata(path) {
        Ok(meta) => {
            #[cfg(unix)]
            {
                use std::os::unix::fs::{FileTypeExt, MetadataExt};
                Some((
                    Identity::Inode(meta.dev(), meta.ino()),
                    meta.file_type().is_char_device(),
                ))
            }
            #[cfg(not(unix))]
            {
                let _ = meta;
                Some((Identity::Path(std::fs::canonicalize(path).ok()?), false))
            }
        }
        Err(_) => {
            // A dangling symbolic link names the file it would create.
            let path = resolve(path).ok()?;
            let parent = std::fs::canonicalize(directory(&path)).ok()?;
            Some((Identity::Path(parent.join(path.file_name()?)), false))
        }
    }
}

/// Fails unless `output` can be written (see the module documentation).
fn check_writable(output: &Role<'_>) -> Result<(), PathError> {
    let refuse = |why: String| PathError::NotWritable {
        path: escape(&output.path.display().to_string()).into_owned(),
        output: output.name.to_owned(),
        why: escape(&why).into_owned(),
    };
    match std::fs::metadata(output.path) {
        Ok(meta) if meta.is_dir() => return Err(refuse("it is a directory".into())),
        Ok(meta) if !meta.is_file() => return Ok(()),
        _ => {}
    }
    // The probe: a temporary file beside the output, removed on drop.
    AtomicFile::create(output.path)
        .map(drop)
        .map_err(|e: io::Error| refuse(e.to_string()))
}

/// Refuses, before any work, an output that names an input or another
/// output, or that cannot be written.
///
/// # Errors
///
/// The first output at fault, as [`PathError`].
pub fn check_paths(inputs: &[Role<'_>], outputs: &[Role<'_>]) -> Result<(), PathError> {
    let known: Vec<(Role<'_>, Option<(Identity, bool)>)> =
        inputs.iter().map(|r| (*r, identity(r.path))).collect();
    let mut seen = known;
    for output in outputs {
        let id = identity(output.path);
        if let Some((id, device)) = &id
            && !device
            && let Some((other, _)) = seen
                .iter()
                .find(|(_, other)| other.as_ref().is_some_and(|(o, _)| o == id))
        {
            let shown = if other.path == output.path {
                String::new()
            } else {
                format!(" ({})", escape(&other.path.display().to_string()))
            };
            return Err(PathError::Same {
                path: escape(&output.path.display().to_string()).into_owned(),
                output: output.name.to_owned(),
                other: other.name.to_owned(),
                shown,
            });
        }
        check_writable(output)?;
        seen.push((*output, id));
    }
    Ok(())
}
