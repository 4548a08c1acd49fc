//! `slamjac synth-bal`: a seeded synthetic bundle-adjustment problem with
//! realistic noise and outliers, written as a BAL file (the generator is
//! `slam_data::synthetic`).

use std::path::Path;

use slam_data::bal;
use slam_data::synthetic::{SyntheticConfig, Visibility, generate};

use crate::error::CliError;

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

/// Generates the problem, writes it to `output` and describes it in one line.
///
/// # Errors
///
/// Settings the generator refuses ([`CliError::Usage`]), or the file cannot
/// be written ([`CliError::Data`]).
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
    let synthetic = generate(&config).map_err(|e| CliError::Usage(e.to_string()))?;
    bal::write(&synthetic.problem, output)?;
    let p = &synthetic.problem;
    Ok(format!(
        "wrote {}: {} cameras, {} points, {} observations ({} outliers), seed {}",
        output.display(),
        p.cameras.len(),
        p.points.len(),
        p.observations.len(),
        synthetic.outliers.len(),
        args.seed
    ))
}
