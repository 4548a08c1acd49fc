//! The guards every command of the toolchain puts between itself and the
//! user's files and terminal. One small module each, callable from any
//! crate that reads or writes files:
//!
//! - [`atomic`]: a file is written to a temporary file beside it and renamed
//!   into place only once complete ([`AtomicFile`], [`atomic::write`]; a
//!   directory of files at once, [`atomic::write_tree`]), so a failed or
//!   interrupted write leaves the old file as it was (and
//!   [`atomic::fail_writes_past_the_file_size_limit`] makes `ulimit -f` an
//!   error of the write rather than a signal that kills the writer);
//! - [`destination`]: the file a write to a path reaches (a symbolic link's
//!   target; a path ending in `/` or in a missing directory refused);
//! - [`temporaries`]: the temporaries being written, removed when the
//!   process is interrupted (`SIGINT`, `SIGTERM`, `SIGHUP`);
//! - [`distinct`]: before any work, an output path that names an input or
//!   another output of the same run is refused, and each output's directory
//!   is checked writable ([`check_paths`]);
//! - [`replay`]: an input stream (a pipe, `/dev/stdin`) is read once: the
//!   bytes read to sniff its format are put back in front of the rest
//!   ([`replay::sniff`]), so no source is opened twice;
//! - [`printable`]: text echoed from the input made one printable line
//!   (control, format and separator characters escaped).

pub mod atomic;
pub mod destination;
pub mod distinct;
pub mod printable;
pub mod replay;
pub mod temporaries;

pub use atomic::AtomicFile;
pub use distinct::{PathError, Role, check_paths};
