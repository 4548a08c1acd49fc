//! Writing a file, or a directory of files, so that it ends up either
//! complete or untouched.
//!
//! [`AtomicFile::create`] opens a temporary file `.NAME.XXXXXX` in the
//! destination's directory (crate `tempfile`): a new file gets `0666` less
//! the umask, a replaced one keeps the permissions (and, where allowed, the
//! owner) of the file it replaces. [`AtomicFile::commit`] flushes it to
//! disk and renames it over the destination, then flushes the directory.
//! Dropped without a commit (an error, a panic), the temporary file is
//! removed and the destination keeps its old contents: a full disk or a
//! file-size limit costs the new output, never the old file. An
//! interruption (`SIGINT`, `SIGTERM`, `SIGHUP`) removes the temporaries too
//! ([`crate::temporaries`]).
//!
//! Where the destination is ([`crate::destination::resolve`]): a symbolic
//! link has its target written and stays a link (a dangling link's target
//! is created); a path ending in `/`, or whose directory is missing, is
//! refused; a destination that is not a regular file (`/dev/null`, a FIFO,
//! a terminal) is written directly, as there is nothing to replace; a
//! directory is refused.
//!
//! Several files written together (the three files of a KITTI VO problem)
//! are all written before the first is committed, so a failure while writing
//! any of them leaves all of them untouched. A whole directory of files
//! (`slamjac init`'s project) is written by [`write_tree`]: staged in a
//! temporary directory beside it and renamed into place at once.

use std::ffi::OsString;
use std::fs::{File, Metadata, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use tempfile::NamedTempFile;

use crate::destination::{directory, resolve};
use crate::temporaries;

/// A file being written: nothing reaches the destination before
/// [`AtomicFile::commit`].
#[derive(Debug)]
pub struct AtomicFile {
    target: Target,
}

#[derive(Debug)]
enum Target {
    /// A temporary file beside the destination.
    Staged(Staged),
    /// A destination that is not a regular file, written in place.
    Direct(File),
}

/// A registered temporary file and the destination it is renamed to.
#[derive(Debug)]
struct Staged {
    /// `None` once committed.
    temp: Option<NamedTempFile>,
    destination: PathBuf,
    /// Its number in [`temporaries`].
    number: u64,
}

/// `.NAME.`: the prefix of the temporaries staged for `name`.
fn hidden_prefix(name: &Path) -> OsString {
    let mut prefix = OsString::from(".");
    prefix.push(name.file_name().unwrap_or_default());
    prefix.push(".");
    prefix
}

/// The permissions a new file or directory is created with, before the
/// umask: `0666` for a file, `0777` for a directory.
#[cfg(unix)]
fn creation_mode(builder: &mut tempfile::Builder<'_, '_>, mode: u32) {
    use std::os::unix::fs::PermissionsExt;
    builder.permissions(std::fs::Permissions::from_mode(mode));
}

#[cfg(not(unix))]
fn creation_mode(_builder: &mut tempfile::Builder<'_, '_>, _mode: u32) {}

impl Staged {
    /// A temporary file beside `destination`, with the permissions and
    /// owner of `existing`, the file it will replace, if any.
    fn new(destination: PathBuf, existing: Option<&Metadata>) -> io::Result<Staged> {
        let prefix = hidden_prefix(&destination);
        let (temp, number) = temporaries::register(false, || {
            let mut builder = tempfile::Builder::new();
            builder.prefix(&prefix).rand_bytes(6);
            creation_mode(&mut builder, 0o666);
            let temp = builder.tempfile_in(directory(&destination))?;
            let path = temp.path().to_path_buf();
            Ok((temp, path))
        })?;
        let staged = Staged {
            temp: Some(temp),
            destination,
            number,
        };
        if let Some(existing) = existing {
            let file = staged.temp.as_ref().expect("staged").as_file();
            file.set_permissions(existing.permissions())?;
            #[cfg(unix)]
            {
                use std::os::unix::fs::MetadataExt;
                // Only the owner's superuser may give a file away: elsewhere
                // the new file is the writer's, as any new file is.
                let _ = std::os::unix::fs::fchown(file, Some(existing.uid()), Some(existing.gid()));
            }
        }
        Ok(staged)
    }

    fn file(&mut self) -> &mut File {
        self.temp
            .as_mut()
            .expect("a staged file is open until committed")
            .as_file_mut()
    }

    /// Flushes the file, renames it over the destination and flushes the
    /// directory; on failure the temporary is removed.
    fn commit(mut self) -> io::Result<()> {
        let temp = self.temp.take().expect("committed once");
        let destination = std::mem::take(&mut self.destination);
        temporaries::locked(self.number, || {
            temp.as_file().sync_all()?;
            temp.persist(&destination).map_err(|e| e.error)?;
            // The rename is done; a directory that cannot be flushed (some
            // file systems refuse it) loses nothing written.
            if let Ok(dir) = File::open(directory(&destination)) {
                let _ = dir.sync_all();
            }
            Ok(())
        })
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        if let Some(temp) = self.temp.take() {
            temporaries::locked(self.number, || drop(temp));
        }
    }
}

impl AtomicFile {
    /// Starts writing `path` (see the module documentation).
    ///
    /// # Errors
    ///
    /// `path` does not name a file, is a directory, its directory (or its
    /// link's target's) does not exist or cannot be written, or the file
    /// cannot be opened.
    pub fn create(path: impl AsRef<Path>) -> io::Result<AtomicFile> {
        let destination = resolve(path.as_ref())?;
        let target = match std::fs::metadata(&destination) {
            Ok(meta) if meta.is_dir() => {
                return Err(io::Error::new(
                    io::ErrorKind::IsADirectory,
                    "is a directory",
                ));
            }
            Ok(meta) if !meta.is_file() => {
                Target::Direct(OpenOptions::new().write(true).open(&destination)?)
            }
            Ok(meta) => Target::Staged(Staged::new(destination, Some(&meta))?),
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                Target::Staged(Staged::new(destination, None)?)
            }
            Err(e) => return Err(e),
        };
        Ok(AtomicFile { target })
    }

    /// Puts the written contents in place: flushed to disk and renamed over
    /// the destination.
    ///
    /// # Errors
    ///
    /// Flushing or renaming failed; the destination is then unchanged.
    pub fn commit(self) -> io::Result<()> {
        match self.target {
            Target::Staged(staged) => staged.commit(),
            Target::Direct(mut file) => file.flush(),
        }
    }

    fn file(&mut self) -> &mut File {
        match &mut self.target {
            Target::Staged(staged) => staged.file(),
            Target::Direct(file) => file,
        }
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.file().write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.file().flush()
    }
}

/// Writes `contents` to `path` through an [`AtomicFile`].
///
/// # Errors
///
/// As [`AtomicFile::create`], writing and [`AtomicFile::commit`]; the
/// destination is unchanged on any of them.
pub fn write(path: impl AsRef<Path>, contents: impl AsRef<[u8]>) -> io::Result<()> {
    let mut file = AtomicFile::create(path)?;
    file.write_all(contents.as_ref())?;
    file.commit()
}

/// Writes the directory `dir` with `files` (paths relative to it, and
/// their contents), whole or not at all: every file is written into a
/// temporary directory `.NAME.XXXXXX` beside `dir` (created `0777` less the
/// umask, or with the permissions of the empty directory it replaces),
/// which is then renamed to `dir`. On any failure, or an interruption, the
/// temporary directory is removed and `dir` is as it was.
///
/// # Errors
///
/// `dir` exists and is not an empty directory, its parent is missing, a
/// file cannot be written (a name too long, a file-size limit, a full
/// disk), or the rename fails; the error names the file at fault.
pub fn write_tree(dir: &Path, files: &[(PathBuf, Vec<u8>)]) -> io::Result<()> {
    let dir = resolve(dir)?;
    let existing = match std::fs::metadata(&dir) {
        Ok(meta) if !meta.is_dir() => {
            return Err(io::Error::new(
                io::ErrorKind::AlreadyExists,
                "exists and is not a directory",
            ));
        }
        Ok(meta) => Some(meta),
        Err(e) if e.kind() == io::ErrorKind::NotFound => None,
        Err(e) => return Err(e),
    };
    let prefix = hidden_prefix(&dir);
    let (temp, number) = temporaries::register(true, || {
        let mut builder = tempfile::Builder::new();
        builder.prefix(&prefix).rand_bytes(6);
        creation_mode(&mut builder, 0o777);
        let temp = builder.tempdir_in(directory(&dir))?;
        let path = temp.path().to_path_buf();
        Ok((temp, path))
    })?;
    let written = fill(temp.path(), files, existing.as_ref());
    // The temporary is removed (on a failure) or renamed under the lock.
    temporaries::locked(number, move || {
        written?;
        std::fs::rename(temp.path(), &dir)?;
        // In place: nothing left to remove.
        let _ = temp.keep();
        if let Ok(parent) = File::open(directory(&dir)) {
            let _ = parent.sync_all();
        }
        Ok(())
    })
}

/// Writes `files` into the new directory `root`, with the permissions of
/// `existing`, if given; errors name the file at fault.
fn fill(root: &Path, files: &[(PathBuf, Vec<u8>)], existing: Option<&Metadata>) -> io::Result<()> {
    for (path, contents) in files {
        let at = root.join(path);
        let named = |e: io::Error| io::Error::new(e.kind(), format!("{}: {e}", path.display()));
        if let Some(parent) = at.parent() {
            std::fs::create_dir_all(parent).map_err(named)?;
        }
        let mut file = File::create(&at).map_err(named)?;
        file.write_all(contents).map_err(named)?;
        file.sync_all().map_err(named)?;
    }
    if let Some(existing) = existing {
        std::fs::set_permissions(root, existing.permissions())?;
    }
    Ok(())
}

/// Makes a write past the file-size limit (`ulimit -f`) fail as an error of
/// that write (`EFBIG`, "File too large") instead of killing the process:
/// the default action of `SIGXFSZ` ends the run without a message and
/// leaves the temporary file of an [`AtomicFile`] behind. A program that
/// writes files calls it once, first thing. Elsewhere than on Unix it does
/// nothing.
pub fn fail_writes_past_the_file_size_limit() {
    #[cfg(unix)]
    // SAFETY: `SIG_IGN` installs no handler code: it only sets `SIGXFSZ`'s
    // disposition, which no other part of the program relies on.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}
