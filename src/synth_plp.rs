//! `slamjac synth-plp`: a seeded point-line-plane room
//! ([`slamjac_problem::synthetic_room`]) written as a problem file, read by
//! `slamjac solve FILE.json`.

use std::path::Path;

use slamjac_io::Role;
use slamjac_problem::field_path::shown_path;
pub use slamjac_problem::synthetic_room::{Kinds, RoomRequest};

use crate::error::CliError;
use crate::outputs;

/// Generates the room and writes the problem file to `output`; describes
/// it in one line.
///
/// # Errors
///
/// Settings the generator refuses, a problem it would write that is not
/// observable, or an output that cannot be written ([`CliError::Usage`],
/// exit 2); nothing is written then.
pub fn run(request: &RoomRequest, output: &Path) -> Result<String, CliError> {
    outputs::check(&[], &[Role::new("--output", output)])?;
    let room = slamjac_problem::synthetic_room::generate(request)
        .map_err(|e| CliError::Usage(e.to_string()))?;
    let summary = format!(
        "wrote {}: {} cameras, {} points, {} lines, {} planes, {} factors, seed {}",
        shown_path(output),
        room.cameras,
        room.points,
        room.lines,
        room.planes,
        room.factors,
        request.seed
    );
    outputs::write(output, crate::pretty::to_string(&room.file) + "\n")?;
    Ok(summary)
}
