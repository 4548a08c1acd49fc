use factor_core::{Factor, Scalar};
use nalgebra::Vector2;

// `f.x.x < S::zero()` in the residual made rustc suggest `PartialOrd`, first
// on the residual function, then on the struct.
#[derive(Clone, Factor)]
#[factor(residual = folded, dim = 2)]
struct Folded<S: Scalar + PartialOrd = f64> {
    #[variable]
    x: Vector2<S>,
}

fn folded<S: Scalar + PartialOrd>(f: &Folded<S>) -> Vector2<S> {
    if f.x.x < S::zero() { -f.x } else { f.x }
}

// The same bound in a `where` clause.
#[derive(Clone, Factor)]
#[factor(residual = clamped, dim = 2)]
struct Clamped<S: Scalar = f64>
where
    S: Ord,
{
    #[variable]
    x: Vector2<S>,
}

fn clamped<S: Scalar + Ord>(f: &Clamped<S>) -> Vector2<S> {
    f.x
}

fn main() {}
