use factor_core::{Factor, Scalar};
use nalgebra::Vector2;

trait Real {}

#[derive(Clone, Factor)]
#[factor(residual = prior, dim = 2)]
struct Prior<S: Scalar + Copy + Real = f64> {
    #[variable]
    x: Vector2<S>,
}

fn prior<S: Scalar>(f: &Prior<S>) -> Vector2<S> {
    f.x
}

fn main() {}
