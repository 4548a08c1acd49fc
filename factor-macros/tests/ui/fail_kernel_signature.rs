use factor_core::{Factor, Scalar};
use nalgebra::Vector2;

#[derive(Clone, Factor)]
#[factor(residual = prior, dim = 2, kernel = prior_kernel)]
struct Prior<S: Scalar = f64> {
    #[variable]
    x: Vector2<S>,
}

fn prior<S: Scalar>(f: &Prior<S>) -> Vector2<S> {
    f.x
}

// The block of a 2-dimensional residual w.r.t. a 2-vector has 4 entries, not 2.
fn prior_kernel(x: &[f64; 2], residual: &mut [f64; 2], d_x: Option<&mut [f64; 2]>) {
    *residual = *x;
    if let Some(d) = d_x {
        *d = [1.0, 1.0];
    }
}

fn main() {}
