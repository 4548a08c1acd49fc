//! `slamjac synth-bal`: a seeded synthetic bundle-adjustment problem with
//! realistic noise and outliers, streamed to a BAL file (the generator is
//! `slam_data::synthetic`: memory holds the cameras, at most 10⁶, whatever
//! the number of points).

use std::path::Path;

use slam_data::synthetic::{self, SyntheticConfig, Visibility};
use slamjac_io::Role;
use slamjac_problem::field_path::shown_path;

use crate::error::CliError;
use crate::outputs;

/// What to generate, as the command line gives it.
#[derive(Debug, Clone, PartialEq)]
pub struct SynthArgs {
    /// Cameras on the ring.
    pub cameras: usize,
    /// Points in the scene.
    pub points: usize,
    /// Cameras that see each point.
    pub views: usize,
    /// Which cameras see a point: spread around the ring, or consecutive.
    pub visibility: Visibility,
    /// Seed of the random generator.
    pub seed: u64,
    /// Fraction of observations that are outliers.
    pub outliers: f64,
    /// Pixel noise of inliers (standard deviation, px).
    pub noise: f64,
}

/// Checks the settings and the output path, then streams the problem to
/// `output` (only the cameras are held in memory) and describes it in one
/// line. Nothing is written, and an existing file is left as it was, when
/// anything fails.
///
/// # Errors
///
/// Settings the generator refuses, or an output that cannot be written
/// ([`CliError::Usage`], before anything is generated); a generated value
/// a reader would refuse or a failed write ([`CliError::Data`]).
pub fn run(args: &SynthArgs, output: &Path) -> Result<String, CliError> {
    let config = SyntheticConfig {
        cameras: args.cameras,
        points: args.points,
        views_per_point: args.views,
        visibility: args.visibility,
        seed: args.seed,
        pixel_sigma: args.noise,
        outlier_fraction: args.outliers,
        ..SyntheticConfig::with_observations(0, args.seed)
    };
    config.check().map_err(|e| CliError::Usage(e.to_string()))?;
    outputs::check(&[], &[Role::new("--output", output)])?;
    let written = synthetic::write(&config, output)?;
    Ok(format!(
        "wrote {}: {} cameras, {} points, {} observations ({} outliers), seed {}",
        shown_path(output),
        written.cameras,
        written.points,
        written.observations,
        written.outliers,
        args.seed
    ))
}
