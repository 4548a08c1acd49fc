use factor_core::{Factor, Scalar};
use nalgebra::Vector2;

#[derive(Clone, Factor)]
#[factor(dim = 2)]
struct Prior<S: Scalar = f64> {
    #[variable]
    x: Vector2<S>,
}

fn main() {}
