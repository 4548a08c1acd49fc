//! A variable type with no mapping onto a host's manifolds: the factor is
//! not a `HostFactor` of that host, and the error names the type and the
//! trait to implement.

use factor_core::host::{Apex, HostFactor};
use factor_core::{Factor, Layout, Manifold, Perturbation, Scalar, Storage};

/// A scalar on a circle, a manifold of the user's own.
#[derive(Clone, Copy, Debug)]
struct Angle<S>(S);

impl<S: Scalar> Storage<S> for Angle<S> {
    type With<T: Scalar> = Angle<T>;
    const SCALARS: usize = 1;
    fn layout() -> Layout {
        Layout::Scalar
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> Angle<T> {
        Angle(f(self.0))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        Angle(next())
    }
}

impl<S: Scalar> Manifold<S> for Angle<S> {
    const DIM: usize = 1;
    fn retract(&self, delta: &[S], _side: Perturbation) -> Self {
        Angle(self.0 + delta[0])
    }
    fn tangent_description(_side: Perturbation) -> &'static str {
        "additive"
    }
}

#[derive(Clone, Factor)]
#[factor(residual = heading, dim = 1)]
struct Heading<S: Scalar = f64> {
    measured: S,
    #[variable]
    angle: Angle<S>,
}

fn heading<S: Scalar>(f: &Heading<S>) -> nalgebra::Vector1<S> {
    nalgebra::Vector1::new(f.angle.0 - f.measured)
}

fn served<F: HostFactor<Apex>>() {}

fn main() {
    served::<Heading>();
}
