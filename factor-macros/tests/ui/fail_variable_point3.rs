use factor_core::{Factor, Scalar};
use nalgebra::{Point3, Vector3};

// A variable of nalgebra's `Point3<S>`, neither stored as scalars nor a
// manifold: one error per missing trait, at the type, and none from the
// generated code.
#[derive(Clone, Factor)]
#[factor(residual = prior, dim = 3)]
struct Prior<S: Scalar = f64> {
    #[variable]
    p: Point3<S>,
}

fn prior<S: Scalar>(f: &Prior<S>) -> Vector3<S> {
    f.p.coords
}

fn main() {}
