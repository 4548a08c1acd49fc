//! The vectorised elementary functions against the scalar `std` functions of
//! the lane scalar, in ulp, over 2¹⁸ random inputs per range and at least
//! four ranges per function (so ≥ 10⁶ inputs per function and lane type),
//! edge ranges included; and the special values, which must match `std`
//! exactly (signed zeros, infinities, NaN).
//!
//! The bounds asserted are the ones the crate documentation states; the run
//! prints the worst input of every range (`--nocapture`).

#[path = "support/lanes.rs"]
mod lanes;
// `nudged` and `identical` serve the kernel tests.
#[allow(dead_code)]
#[path = "support/ulp.rs"]
mod ulp;

use core::f64::consts::{FRAC_PI_2, PI};

use factor_lanes::{F32x8, F64x4, F64x8};
use lanes::Lanes;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use ulp::Ulp;

const PER_RANGE: usize = 1 << 18;

/// Draws one input pair (the second ignored by unary functions).
type Draw = Box<dyn FnMut(&mut StdRng) -> (f64, f64)>;
/// Named input ranges of one function.
type Ranges = Vec<(&'static str, Draw)>;

/// Uniform in `[lo, hi)`, sign chosen at random when `signed`.
fn uniform(s: &mut StdRng, lo: f64, hi: f64, signed: bool) -> f64 {
    let v = s.random_range(lo..hi);
    if signed && s.random_range(0.0..1.0) < 0.5 {
        -v
    } else {
        v
    }
}

/// Log-uniform magnitude in `[lo, hi)`, sign chosen at random when `signed`.
fn log_uniform(s: &mut StdRng, lo: f64, hi: f64, signed: bool) -> f64 {
    let v = s.random_range(lo.ln()..hi.ln()).exp();
    if signed && s.random_range(0.0..1.0) < 0.5 {
        -v
    } else {
        v
    }
}

/// A double within 4 ulp of `k·π/2` for a random `k < kmax`: the inputs
/// whose sine or cosine is nearly zero, where argument reduction loses most.
fn near_multiple(s: &mut StdRng, kmax: f64) -> f64 {
    let x = s.random_range(1.0..kmax).floor() * FRAC_PI_2;
    f64::from_bits((x.to_bits() as i64 + s.random_range(-4i64..=4)) as u64)
}

/// `k·π/2 ± d` for a random `k < 2²⁷` and `d/k` log-uniform in
/// `[2⁻⁴⁵, 2⁻²⁰]`: the inputs just outside the ones `sin`/`cos` send to
/// `std` (`|r| < k·2⁻⁴⁶`), where the vectorised reduction loses most.
fn near_threshold(s: &mut StdRng) -> f64 {
    let k = s.random_range(1.0..2f64.powi(27)).floor();
    k * FRAC_PI_2 + k * log_uniform(s, 2f64.powi(-45), 2f64.powi(-20), true)
}

/// The worst ulp distance of `lane` from `reference` over `PER_RANGE` inputs
/// drawn by `draw` (rounded to the scalar), with the worst input.
fn worst<L: Lanes>(
    seed: u64,
    mut draw: impl FnMut(&mut StdRng) -> (f64, f64),
    lane: impl Fn(L, L) -> L,
    reference: impl Fn(L::S, L::S) -> L::S,
) -> (u64, (f64, f64)) {
    let mut sampler = StdRng::seed_from_u64(seed);
    let mut worst = (0, (0.0, 0.0));
    for _ in 0..PER_RANGE / L::N {
        let inputs: Vec<(L::S, L::S)> = (0..L::N)
            .map(|_| {
                let (a, b) = draw(&mut sampler);
                (L::scalar(a), L::scalar(b))
            })
            .collect();
        let a: Vec<_> = inputs.iter().map(|p| p.0).collect();
        let b: Vec<_> = inputs.iter().map(|p| p.1).collect();
        let out = lane(L::from_lanes(&a), L::from_lanes(&b)).lanes();
        for (k, &(a, b)) in inputs.iter().enumerate() {
            let u = out[k].ulps_from(reference(a, b));
            if u > worst.0 {
                worst = (u, (a.into(), b.into()));
            }
        }
    }
    worst
}

/// Checks every range of one function against `bound` ulp.
fn check_ranges<L: Lanes>(
    function: &str,
    bound: u64,
    ranges: Ranges,
    lane: impl Fn(L, L) -> L + Copy,
    reference: impl Fn(L::S, L::S) -> L::S + Copy,
) {
    assert!(ranges.len() >= 4, "at least 4 × 2¹⁸ inputs per function");
    let mut failures = Vec::new();
    for (seed, (range, draw)) in ranges.into_iter().enumerate() {
        let (u, at) = worst::<L>(seed as u64, draw, lane, reference);
        println!(
            "{} {function:5} {range:38} max {u:>3} ulp at {at:?}",
            core::any::type_name::<L>()
        );
        if u > bound {
            failures.push(format!(
                "{function} on {range}: {u} ulp at {at:?} (bound {bound})"
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The special values of one function: within `bound` ulp of `std`, and
/// where `std` gives a zero or an infinity, that value with its sign (NaN
/// where `std` gives NaN).
fn check_special<L: Lanes>(
    function: &str,
    bound: u64,
    inputs: &[(f64, f64)],
    lane: impl Fn(L, L) -> L,
    reference: impl Fn(L::S, L::S) -> L::S,
) {
    for &(a, b) in inputs {
        let (a, b) = (L::scalar(a), L::scalar(b));
        let got = lane(L::from_lanes(&vec![a; L::N]), L::from_lanes(&vec![b; L::N])).lanes();
        let want = reference(a, b);
        let exact = want.into() == 0.0 || want.into().is_infinite();
        for g in got {
            let ok = g.ulps_from(want) <= bound
                && (!exact || g.into().to_bits() == want.into().to_bits());
            assert!(ok, "{function}{:?}: {g:?}, std {want:?}", (a, b));
        }
    }
}

const SPECIAL: [f64; 12] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    -0.5,
    5e-324,
    -5e-324,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::NAN,
    1e300,
];

/// One accuracy suite per lane type: the bounds of the crate documentation.
macro_rules! suite {
    ($module:ident, $t:ty, $s:ty, bounds: sin $b_sin:literal, cos $b_cos:literal, atan2 $b_atan2:literal,
     atan $b_atan:literal, asin $b_asin:literal, acos $b_acos:literal, exp $b_exp:literal, ln $b_ln:literal) => {
        mod $module {
            use super::*;

            type L = $t;
            /// The largest finite scalar and the smallest positive subnormal.
            const MAX: f64 = <$s>::MAX as f64;
            const TINY: f64 = <$s>::from_bits(1) as f64;
            const MIN_NORMAL: f64 = <$s>::MIN_POSITIVE as f64;

            fn unary(f: impl FnMut(&mut StdRng) -> f64 + 'static) -> Draw {
                let mut f = f;
                Box::new(move |s| (f(s), 0.0))
            }

            fn trig_ranges() -> Ranges {
                vec![
                    ("[−π, π]", unary(|s| uniform(s, 0.0, PI, true))),
                    ("[−1000, 1000]", unary(|s| uniform(s, 0.0, 1000.0, true))),
                    (
                        "|x| log-uniform in [1, 2²⁸]",
                        unary(|s| log_uniform(s, 1.0, 2f64.powi(28), true)),
                    ),
                    (
                        "|x| log-uniform in [tiny, 1e-3] (subnormals)",
                        unary(|s| log_uniform(s, TINY, 1e-3, true)),
                    ),
                    (
                        "within 4 ulp of k·π/2, k < 2²⁷",
                        unary(|s| near_multiple(s, 2f64.powi(27))),
                    ),
                    (
                        "k·π/2 ± d, k < 2²⁷, d/k log-uniform in [2⁻⁴⁵, 2⁻²⁰]",
                        unary(near_threshold),
                    ),
                    (
                        "|x| log-uniform in [2²⁸, max] (std path)",
                        unary(|s| log_uniform(s, 2f64.powi(28), MAX, true)),
                    ),
                ]
            }

            #[test]
            fn sin() {
                check_ranges::<L>("sin", $b_sin, trig_ranges(), |x, _| x.sin(), |x, _| x.sin());
                check_special::<L>(
                    "sin",
                    $b_sin,
                    &SPECIAL.map(|x| (x, 0.0)),
                    |x, _| x.sin(),
                    |x, _| x.sin(),
                );
            }

            #[test]
            fn cos() {
                check_ranges::<L>("cos", $b_cos, trig_ranges(), |x, _| x.cos(), |x, _| x.cos());
                check_special::<L>(
                    "cos",
                    $b_cos,
                    &SPECIAL.map(|x| (x, 0.0)),
                    |x, _| x.cos(),
                    |x, _| x.cos(),
                );
            }

            #[test]
            fn sin_cos_matches_sin_and_cos() {
                let x = L::from_lanes(
                    &(0..L::N)
                        .map(|k| L::scalar(k as f64 * 0.7 - 2.0))
                        .collect::<Vec<_>>(),
                );
                let (s, c) = x.sin_cos();
                assert_eq!(s.lanes(), x.sin().lanes());
                assert_eq!(c.lanes(), x.cos().lanes());
            }

            #[test]
            fn atan2() {
                let ranges: Ranges = vec![
                    (
                        "four quadrants, [−1, 1]²",
                        Box::new(|s| (uniform(s, 0.0, 1.0, true), uniform(s, 0.0, 1.0, true))),
                    ),
                    (
                        "|y|, |x| log-uniform over all normals",
                        Box::new(|s| {
                            (
                                log_uniform(s, MIN_NORMAL, MAX, true),
                                log_uniform(s, MIN_NORMAL, MAX, true),
                            )
                        }),
                    ),
                    (
                        "|y|, |x| subnormal",
                        Box::new(|s| {
                            (
                                log_uniform(s, TINY, MIN_NORMAL, true),
                                log_uniform(s, TINY, MIN_NORMAL, true),
                            )
                        }),
                    ),
                    (
                        "near the axes: |y/x| or |x/y| < 1e-6",
                        Box::new(|s| {
                            let (big, small) = (
                                uniform(s, 0.5, 2.0, true),
                                log_uniform(s, 1e-30, 1e-6, true),
                            );
                            if s.random_range(0.0..1.0) < 0.5 {
                                (big, small * big)
                            } else {
                                (small * big, big)
                            }
                        }),
                    ),
                    (
                        "on the axes: x = ±0 or y = ±0",
                        Box::new(|s| {
                            let (v, z) = (
                                uniform(s, 0.0, 10.0, true),
                                if s.random_range(0.0..1.0) < 0.5 {
                                    0.0
                                } else {
                                    -0.0
                                },
                            );
                            if s.random_range(0.0..1.0) < 0.5 {
                                (v, z)
                            } else {
                                (z, v)
                            }
                        }),
                    ),
                ];
                check_ranges::<L>(
                    "atan2",
                    $b_atan2,
                    ranges,
                    |y, x| y.atan2(x),
                    |y, x| y.atan2(x),
                );
                let pairs: Vec<(f64, f64)> = SPECIAL
                    .iter()
                    .flat_map(|&y| SPECIAL.map(|x| (y, x)))
                    .collect();
                check_special::<L>(
                    "atan2",
                    $b_atan2,
                    &pairs,
                    |y, x| y.atan2(x),
                    |y, x| y.atan2(x),
                );
            }

            #[test]
            fn atan() {
                let ranges = vec![
                    ("[−10, 10]", unary(|s| uniform(s, 0.0, 10.0, true))),
                    (
                        "|x| log-uniform over all normals",
                        unary(|s| log_uniform(s, MIN_NORMAL, MAX, true)),
                    ),
                    (
                        "|x| subnormal",
                        unary(|s| log_uniform(s, TINY, MIN_NORMAL, true)),
                    ),
                    (
                        "|x| in [0.4, 2.5] (reduction switches)",
                        unary(|s| uniform(s, 0.4, 2.5, true)),
                    ),
                ];
                check_ranges::<L>("atan", $b_atan, ranges, |x, _| x.atan(), |x, _| x.atan());
                check_special::<L>(
                    "atan",
                    $b_atan,
                    &SPECIAL.map(|x| (x, 0.0)),
                    |x, _| x.atan(),
                    |x, _| x.atan(),
                );
            }

            fn inverse_sine_ranges() -> Ranges {
                vec![
                    ("[−1, 1]", unary(|s| uniform(s, 0.0, 1.0, true))),
                    (
                        "|x| log-uniform in [tiny, 1e-3]",
                        unary(|s| log_uniform(s, TINY, 1e-3, true)),
                    ),
                    (
                        "±(1 − d), d log-uniform in [1e-17, 1e-2]",
                        unary(|s| {
                            let x = 1.0 - log_uniform(s, 1e-17, 1e-2, false);
                            if s.random_range(0.0..1.0) < 0.5 {
                                -x
                            } else {
                                x
                            }
                        }),
                    ),
                    (
                        "|x| in [0.4, 0.7] (reduction switches)",
                        unary(|s| uniform(s, 0.4, 0.7, true)),
                    ),
                    (
                        "outside [−1, 1]",
                        unary(|s| log_uniform(s, 1.0 + 1e-6, 1e10, true)),
                    ),
                ]
            }

            #[test]
            fn asin() {
                check_ranges::<L>(
                    "asin",
                    $b_asin,
                    inverse_sine_ranges(),
                    |x, _| x.asin(),
                    |x, _| x.asin(),
                );
                check_special::<L>(
                    "asin",
                    $b_asin,
                    &SPECIAL.map(|x| (x, 0.0)),
                    |x, _| x.asin(),
                    |x, _| x.asin(),
                );
            }

            #[test]
            fn acos() {
                check_ranges::<L>(
                    "acos",
                    $b_acos,
                    inverse_sine_ranges(),
                    |x, _| x.acos(),
                    |x, _| x.acos(),
                );
                check_special::<L>(
                    "acos",
                    $b_acos,
                    &SPECIAL.map(|x| (x, 0.0)),
                    |x, _| x.acos(),
                    |x, _| x.acos(),
                );
            }

            #[test]
            fn exp() {
                let (lo, hi) = ((TINY).ln() - 0.5, MAX.ln() + 0.5);
                let ranges = vec![
                    ("[−10, 10]", unary(|s| uniform(s, 0.0, 10.0, true))),
                    (
                        "[ln tiny − 0.5, ln max + 0.5] (subnormal, overflow)",
                        unary(move |s| s.random_range(lo..hi)),
                    ),
                    (
                        "|x| log-uniform in [tiny, 1e-3]",
                        unary(|s| log_uniform(s, TINY, 1e-3, true)),
                    ),
                    (
                        "[ln tiny − 0.5, ln min normal] (subnormal results)",
                        unary(move |s| s.random_range(lo..MIN_NORMAL.ln())),
                    ),
                ];
                check_ranges::<L>("exp", $b_exp, ranges, |x, _| x.exp(), |x, _| x.exp());
                check_special::<L>(
                    "exp",
                    $b_exp,
                    &SPECIAL.map(|x| (x, 0.0)),
                    |x, _| x.exp(),
                    |x, _| x.exp(),
                );
            }

            #[test]
            fn ln() {
                let ranges = vec![
                    (
                        "log-uniform over all normals",
                        unary(|s| log_uniform(s, MIN_NORMAL, MAX, false)),
                    ),
                    (
                        "subnormals",
                        unary(|s| log_uniform(s, TINY, MIN_NORMAL, false)),
                    ),
                    (
                        "1 ± d, d log-uniform in [1e-17, 0.5]",
                        unary(|s| 1.0 + log_uniform(s, 1e-17, 0.5, true)),
                    ),
                    ("[0.5, 2]", unary(|s| s.random_range(0.5..2.0))),
                    ("negative", unary(|s| -log_uniform(s, TINY, MAX, false))),
                ];
                check_ranges::<L>("ln", $b_ln, ranges, |x, _| x.ln(), |x, _| x.ln());
                check_special::<L>(
                    "ln",
                    $b_ln,
                    &SPECIAL.map(|x| (x, 0.0)),
                    |x, _| x.ln(),
                    |x, _| x.ln(),
                );
            }
        }
    };
}

suite!(f64x4, F64x4, f64, bounds: sin 2, cos 2, atan2 2, atan 2, asin 2, acos 2, exp 2, ln 2);
suite!(f64x8, F64x8, f64, bounds: sin 2, cos 2, atan2 2, atan 2, asin 2, acos 2, exp 2, ln 2);
suite!(f32x8, F32x8, f32, bounds: sin 1, cos 1, atan2 3, atan 3, asin 2, acos 2, exp 2, ln 2);
