//! `Manifold::local` against the retraction it inverts.

use factor_core::{Manifold, Perturbation, Storage};

/// Panics, naming the side and the error, unless `x.local` inverts
/// `x.retract` on both sides to `tolerance` ([`local_inverse_errors`] at
/// `y` and `delta`).
#[track_caller]
pub fn assert_local_inverts<M: Manifold<f64> + Storage<f64>>(
    x: &M,
    y: &M,
    delta: &[f64],
    tolerance: f64,
) {
    for side in [Perturbation::Left, Perturbation::Right] {
        let (on_tangent, on_point) = local_inverse_errors(x, y, delta, side);
        assert!(
            on_tangent <= tolerance && on_point <= tolerance,
            "{side:?}: local(retract(δ)) − δ = {on_tangent:e}, retract(local(y)) − y = \
             {on_point:e} at δ = {delta:?} (tolerance {tolerance:e})"
        );
    }
}

/// How far `x.local` is from inverting `x.retract` on `side`: the largest
/// absolute error of `local(x, retract(x, δ)) − δ` (a tangent), and of
/// `retract(x, local(x, y)) − y` (stored scalars, so a quaternion that
/// comes back negated counts).
///
/// # Panics
///
/// When the type gives no `local`.
pub fn local_inverse_errors<M: Manifold<f64> + Storage<f64>>(
    x: &M,
    y: &M,
    delta: &[f64],
    side: Perturbation,
) -> (f64, f64) {
    let largest = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
    };
    let mut back = vec![0.0; delta.len()];
    x.local(&x.retract(delta, side), side, &mut back)
        .expect("the type gives `local`");
    let mut coordinates = vec![0.0; delta.len()];
    x.local(y, side, &mut coordinates)
        .expect("the type gives `local`");
    let reached = x.retract(&coordinates, side).to_scalars();
    (largest(&back, delta), largest(&reached, &y.to_scalars()))
}
