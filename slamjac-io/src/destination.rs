//! The file a write to a path reaches, told before anything is written.
//!
//! A symbolic link is followed to its target, through any chain of links
//! (a relative target read from the link's own directory), so that the
//! target is written and the link stays — a dangling link included: its
//! target is created. A path whose last component cannot name a file (it
//! ends in `/`, `.` or `..`) is refused, as is one whose directory does not
//! exist (for a link, the directory of its target).

use std::io;
use std::path::{Path, PathBuf};

use crate::printable::escape;

/// Links followed before giving up (Linux's `MAXSYMLINKS`).
const MAX_LINKS: usize = 40;

/// The path a write to `path` creates or replaces (see the module
/// documentation).
///
/// # Errors
///
/// `path` is empty or ends in `/`, `.` or `..` (`InvalidInput`); a link
/// chain longer than 40 or a loop; the directory of the file reached does
/// not exist (`NotFound`, naming it); any other error reading the links.
pub fn resolve(path: &Path) -> io::Result<PathBuf> {
    if !names_a_file(path) {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "the path does not name a file (it is empty or ends in `/`, `.` or `..`)",
        ));
    }
    let mut current = path.to_path_buf();
    for _ in 0..=MAX_LINKS {
        match std::fs::symlink_metadata(&current) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let target = std::fs::read_link(&current)?;
                current = match current.parent() {
                    Some(dir) if target.is_relative() => dir.join(target),
                    _ => target,
                };
                if !names_a_file(&current) {
                    return Err(io::Error::new(
                        io::ErrorKind::InvalidInput,
                        format!(
                            "the symbolic link leads to {}, which does not name a file",
                            escape(&current.display().to_string())
                        ),
                    ));
                }
            }
            Ok(_) => return Ok(current),
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                let dir = directory(&current);
                return match std::fs::metadata(dir) {
                    Ok(meta) if meta.is_dir() => Ok(current),
                    _ => Err(io::Error::new(
                        io::ErrorKind::NotFound,
                        format!(
                            "{}the directory {} does not exist",
                            if current == path {
                                String::new()
                            } else {
                                format!(
                                    "the symbolic link leads to {}: ",
                                    escape(&current.display().to_string())
                                )
                            },
                            escape(&dir.display().to_string())
                        ),
                    )),
                };
            }
            Err(e) => return Err(e),
        }
    }
    Err(io::Error::other(format!(
        "more than {MAX_LINKS} symbolic links in a chain (or a loop)"
    )))
}

/// The directory `path` is in (`.` for a bare name).
pub(crate) fn directory(path: &Path) -> &Path {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    }
}

/// Whether the last component of `path`, as written, can name a file: not
/// empty, not a trailing separator, `.` or `..` (which `Path` would
/// otherwise read past: `o.json/` has the file name `o.json`).
fn names_a_file(path: &Path) -> bool {
    let bytes = path.as_os_str().as_encoded_bytes();
    let last = bytes
        .rsplit(|b| std::path::is_separator(char::from(*b)))
        .next()
        .unwrap_or_default();
    !matches!(last, b"" | b"." | b"..")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_last_component_that_is_a_name_names_a_file() {
        for good in ["o.json", "./o.json", "a/b", "/tmp/x", ".hidden", "..x"] {
            assert!(names_a_file(Path::new(good)), "{good}");
        }
        for bad in ["", "o.json/", "a/.", "a/..", ".", "..", "/"] {
            assert!(!names_a_file(Path::new(bad)), "{bad}");
        }
    }
}
