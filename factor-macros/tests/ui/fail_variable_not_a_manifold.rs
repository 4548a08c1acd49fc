use factor_core::{Factor, Layout, Manifold, Perturbation, Scalar, Storage};
use nalgebra::Vector2;

/// A landmark whose retraction exists for `f64` only: dual numbers (and any
/// other scalar) cannot perturb it.
#[derive(Clone)]
struct Landmark<S>(Vector2<S>);

impl<S: Scalar> Storage<S> for Landmark<S> {
    type With<T: Scalar> = Landmark<T>;
    const SCALARS: usize = 2;
    fn layout() -> Layout {
        Layout::array(&["x", "y"])
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> Landmark<T> {
        Landmark(self.0.map_scalars(f))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        Landmark(Vector2::read_scalars(next))
    }
}

impl Manifold<f64> for Landmark<f64> {
    const DIM: usize = 2;
    fn retract(&self, delta: &[f64], side: Perturbation) -> Self {
        Landmark(self.0.retract(delta, side))
    }
    fn tangent_description(_: Perturbation) -> &'static str {
        "additive"
    }
}

#[derive(Clone, Factor)]
#[factor(residual = prior, dim = 2)]
struct Prior<S: Scalar = f64> {
    #[variable]
    landmark: Landmark<S>,
}

fn prior<S: Scalar>(f: &Prior<S>) -> Vector2<S> {
    f.landmark.0
}

fn main() {}
