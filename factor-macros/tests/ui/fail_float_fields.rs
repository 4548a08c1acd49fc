use factor_core::{Factor, Scalar};
use nalgebra::{Vector2, Vector3};

// Constants written over `f64` instead of the scalar.
#[derive(Clone, Factor)]
#[factor(residual = prior, dim = 2)]
struct Prior<S: Scalar = f64> {
    weight: f64,
    offsets: [f64; 2],
    gravity: Vector3<f64>,
    #[variable]
    x: Vector2<S>,
}

fn prior<S: Scalar>(f: &Prior<S>) -> Vector2<S> {
    f.x
}

fn main() {}
