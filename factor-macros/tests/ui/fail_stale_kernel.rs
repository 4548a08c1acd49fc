use factor_core::{Factor, Scalar};
use nalgebra::Vector3;

// The factor gained a dimension since its kernel was generated: the kernel's
// module still describes a 2-vector.
#[derive(Clone, Factor)]
#[factor(
    residual = prior,
    dim = 3,
    kernel = prior_kernel::prior,
    regenerate = "cargo run -p my-factors --no-default-features --bin generate-kernels"
)]
struct Prior<S: Scalar = f64> {
    #[variable]
    x: Vector3<S>,
}

fn prior<S: Scalar>(f: &Prior<S>) -> Vector3<S> {
    f.x
}

/// What the generator wrote for the old `Prior` with `x: Vector2<S>`.
mod prior_kernel {
    pub struct Kernel;

    pub struct Shape {
        pub inputs: &'static [usize],
        pub residual: usize,
        pub blocks: &'static [usize],
    }

    pub const SHAPE: Shape = Shape {
        inputs: &[2],
        residual: 2,
        blocks: &[4],
    };

    pub fn prior_slices(
        _inputs: &[&[f64]],
        _residual: &mut [f64],
        _blocks: &mut [Option<&mut [f64]>],
    ) -> bool {
        false
    }
}

fn main() {}
