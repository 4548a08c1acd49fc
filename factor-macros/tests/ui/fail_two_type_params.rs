use factor_core::{Factor, Scalar};
use nalgebra::Vector2;

#[derive(Clone, Factor)]
#[factor(residual = prior, dim = 2)]
struct Prior<S: Scalar, T: Scalar> {
    #[variable]
    x: Vector2<S>,
    y: Vector2<T>,
}

fn prior<S: Scalar, T: Scalar>(f: &Prior<S, T>) -> Vector2<S> {
    f.x
}

fn main() {}
