//! Writing a file so that it ends up either complete or untouched.
//!
//! [`AtomicFile::create`] opens a temporary file in the destination's
//! directory (crate `atomic-write-file`: permissions `0666` less the umask,
//! or those of the file it replaces); [`AtomicFile::commit`] flushes it to
//! disk and renames it over the destination. Dropped without a commit (an
//! error, a panic), the temporary file is removed and the destination keeps
//! its old contents: a full disk or a file-size limit costs the new output,
//! never the old file. A destination that is a symbolic link has its target
//! replaced (the link stays); one that is not a regular file (`/dev/null`,
//! a FIFO, a terminal) is written directly, as there is nothing to replace.
//! A directory is refused.
//!
//! Several files written together (the three files of a KITTI VO problem)
//! are all written before the first is committed, so a failure while writing
//! any of them leaves all of them untouched.

use std::fs::{File, OpenOptions};
use std::io::{self, Write};
use std::path::Path;

use atomic_write_file::AtomicWriteFile;

/// A file being written: nothing reaches the destination before
/// [`AtomicFile::commit`].
#[derive(Debug)]
pub struct AtomicFile {
    target: Target,
}

#[derive(Debug)]
enum Target {
    /// A temporary file beside the destination.
    Staged(AtomicWriteFile),
    /// A destination that is not a regular file, written in place.
    Direct(File),
}

impl AtomicFile {
    /// Starts writing `path` (see the module documentation).
    ///
    /// # Errors
    ///
    /// `path` is a directory, its directory does not exist or cannot be
    /// written, or the file cannot be opened.
    pub fn create(path: impl AsRef<Path>) -> io::Result<AtomicFile> {
        let path = path.as_ref();
        let target = match std::fs::metadata(path) {
            Ok(meta) if meta.is_dir() => {
                return Err(io::Error::new(
                    io::ErrorKind::IsADirectory,
                    "is a directory",
                ));
            }
            Ok(meta) if !meta.is_file() => {
                Target::Direct(OpenOptions::new().write(true).open(path)?)
            }
            Ok(_) if path.is_symlink() => {
                Target::Staged(AtomicWriteFile::open(std::fs::canonicalize(path)?)?)
            }
            Ok(_) => Target::Staged(AtomicWriteFile::open(path)?),
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                Target::Staged(AtomicWriteFile::open(path)?)
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
            Target::Staged(file) => file.commit(),
            Target::Direct(mut file) => file.flush(),
        }
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match &mut self.target {
            Target::Staged(file) => file.write(buf),
            Target::Direct(file) => file.write(buf),
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        match &mut self.target {
            Target::Staged(file) => file.flush(),
            Target::Direct(file) => file.flush(),
        }
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
