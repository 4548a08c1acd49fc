use factor_core::{Factor, Scalar};
use nalgebra::{Vector2, Vector3};

#[derive(Clone, Factor)]
#[factor(residual = prior, dim = 2)]
struct Prior<S: Scalar = f64> {
    #[variable]
    x: Vector3<S>,
}

fn prior<S: Scalar>(f: &Prior<S>) -> Vector3<S> {
    f.x
}

fn main() {
    let _: Vector2<f64> = Prior {
        x: Vector3::zeros(),
    }
    .residual()
    .unwrap();
}
