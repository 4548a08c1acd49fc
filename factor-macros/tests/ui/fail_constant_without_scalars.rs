use factor_core::{Factor, Scalar};
use nalgebra::Vector2;

// A constant of a type that is not stored as scalars.
#[derive(Clone, Factor)]
#[factor(residual = prior, dim = 2)]
struct Prior<S: Scalar = f64> {
    count: usize,
    #[variable]
    x: Vector2<S>,
}

fn prior<S: Scalar>(f: &Prior<S>) -> Vector2<S> {
    f.x
}

fn main() {}
