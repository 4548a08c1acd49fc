use factor_core::Factor;
use nalgebra::Vector2;

#[derive(Clone, Factor)]
#[factor(residual = prior, dim = 2)]
struct Prior {
    #[variable]
    x: Vector2<f64>,
}

fn prior(f: &Prior) -> Vector2<f64> {
    f.x
}

fn main() {}
