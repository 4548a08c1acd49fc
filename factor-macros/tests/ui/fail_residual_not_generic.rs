use factor_core::{Factor, Scalar};
use nalgebra::Vector2;

#[derive(Clone, Factor)]
#[factor(residual = prior, dim = 2)]
struct Prior<S: Scalar = f64> {
    #[variable]
    x: Vector2<S>,
}

fn prior(f: &Prior<f64>) -> Vector2<f64> {
    f.x
}

fn main() {}
