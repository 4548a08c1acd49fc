use factor_core::{Factor, Scalar};
use nalgebra::Vector2;

#[derive(Clone, Factor)]
#[factor(residual = prior, dim = 2, validate = check)]
struct Prior<S: Scalar = f64> {
    #[variable]
    x: Vector2<S>,
}

fn prior<S: Scalar>(f: &Prior<S>) -> Vector2<S> {
    f.x
}

fn check(f: &Prior<f64>) -> bool {
    f.x.norm() > 0.0
}

fn main() {}
