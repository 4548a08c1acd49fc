use factor_core::{Factor, Scalar};
use nalgebra::Vector2;

#[derive(Clone, Factor)]
#[factor(residual = prior, dim = 2)]
enum Prior<S: Scalar = f64> {
    Point(Vector2<S>),
}

fn prior<S: Scalar>(_: &Prior<S>) -> Vector2<S> {
    Vector2::zeros()
}

fn main() {}
