use factor_apex::Kernels;
use factor_apex::problems::{BuildOptions, FactorChoice, build};
use std::time::Instant;

fn main() {
    let data = slam_data::Problem::read(
        std::path::Path::new("/work/main/data/VO_camera_poses_large.txt"),
        None,
    )
    .unwrap();
    for choice in [FactorChoice::Ours(Kernels::Generated), FactorChoice::Apex] {
        let built = build(
            &data,
            &BuildOptions {
                factors: choice,
                robust: None,
                keep_blocks: true,
            },
        )
        .unwrap();
        let blocks = built.kept.unwrap();
        let mut residual = [0.0; 16];
        let mut jacobian = [0.0; 512];
        let mut nan = 0;
        let start = Instant::now();
        for _ in 0..20 {
            for block in &blocks {
                let (rows, cols) = block.factor.jacobian_shape();
                let params: Vec<&[f64]> = block.params.iter().map(Vec::as_slice).collect();
                let (r, j) = (&mut residual[..rows], &mut jacobian[..rows * cols]);
                block.factor.linearize(
                    &params,
                    r,
                    Some(faer::mat::MatMut::from_column_major_slice_mut(
                        j, rows, cols,
                    )),
                );
                if r[0].is_nan() {
                    nan += 1;
                }
            }
        }
        println!(
            "{:?}: {:.1} ns/obs, {nan} NaN",
            choice,
            start.elapsed().as_nanos() as f64 / (20 * blocks.len()) as f64
        );
    }
}
