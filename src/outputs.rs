//! The files a command writes besides its report: checked before any work
//! ([`check()`]: none names an input or another output, each is writable)
//! and written to a temporary file renamed into place ([`write()`]), so a
//! command never destroys a file it reads and a failed write leaves the
//! old file as it was (crate `slamjac-io`).

use std::path::Path;

use slamjac_io::Role;
use slamjac_problem::field_path::escape_unprintable;

use crate::error::CliError;

/// Refuses, before any work, an output that names one of the `inputs` or
/// another output, or that cannot be written (exit 2).
///
/// # Errors
///
/// [`CliError::Usage`] naming the output and what it collides with.
pub fn check(inputs: &[Role<'_>], outputs: &[Role<'_>]) -> Result<(), CliError> {
    slamjac_io::check_paths(inputs, outputs).map_err(|e| CliError::Usage(e.to_string()))
}

/// Writes `contents` to `path`, whole or not at all.
///
/// # Errors
///
/// [`CliError::Usage`] naming the file, when it cannot be written.
pub fn write(path: &Path, contents: impl AsRef<[u8]>) -> Result<(), CliError> {
    slamjac_io::atomic::write(path, contents).map_err(|e| {
        CliError::Usage(format!(
            "{}: cannot write: {e}",
            escape_unprintable(&path.display().to_string())
        ))
    })
}
