use factor_core::{Factor, Scalar};
use nalgebra::Vector2;

#[derive(Clone, Factor)]
#[factor(residual = prior, dim = 2)]
struct Prior<'a, S: Scalar> {
    #[variable]
    x: Vector2<S>,
    label: &'a str,
}

fn prior<S: Scalar>(f: &Prior<'_, S>) -> Vector2<S> {
    f.x
}

fn main() {}
