use factor_core::{Factor, Scalar};
use nalgebra::Vector2;

#[derive(Clone, Factor)]
#[factor(residual = prior, dim = 2, hosts(apex))]
struct Prior<S: Scalar = f64> {
    #[variable]
    x: Vector2<S>,
}

fn prior<S: Scalar>(f: &Prior<S>) -> Vector2<S> {
    f.x
}

fn main() {}
