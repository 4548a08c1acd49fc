use factor_core::{Factor, Scalar};
use nalgebra::Vector2;

// The residual takes the generic factor but returns a vector over `f64`.
#[derive(Clone, Factor)]
#[factor(residual = prior, dim = 2)]
struct Prior<S: Scalar = f64> {
    #[variable]
    x: Vector2<S>,
}

fn prior<S: Scalar>(_f: &Prior<S>) -> Vector2<f64> {
    Vector2::zeros()
}

fn main() {}
