//! Comparisons for input validation that treat NaN as failing, and the
//! notation of numbers in validation messages ([`number_text`]).
//!
//! `value > bound` is false for a NaN, so `!exceeds(x, b)` rejects NaN inputs
//! along with small ones; these names say so where `!(x > b)` would not.

/// `value > bound`; false when either is NaN.
pub fn exceeds(value: f64, bound: f64) -> bool {
    value > bound
}

/// `|value| ≤ bound`; false when either is NaN.
pub fn within(value: f64, bound: f64) -> bool {
    value.abs() <= bound
}

/// `x` as messages print it: the shortest digits that read back as `x`, in
/// plain notation (`-3`, `0.001`) when `1e-5 ≤ |x| < 1e16` or `x` is zero,
/// in scientific notation (`1.5e-12`, `1e300`) otherwise.
pub fn number_text(x: f64) -> String {
    if x == 0.0 || (1e-5..1e16).contains(&x.abs()) || !x.is_finite() {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// A magnitude computed without overflow ([`crate::linalg::scaled_norm`]) as
/// messages print it: [`number_text`], or `above 1.8e308` when even the
/// magnitude exceeds the `f64` range.
pub fn magnitude_text(x: f64) -> String {
    if x.is_finite() {
        number_text(x)
    } else {
        format!("above {}", number_text(f64::MAX))
    }
}

#[cfg(test)]
mod tests {
    use super::number_text;

    #[test]
    fn numbers_are_plain_unless_tiny_or_huge() {
        let cases = [
            (-3.0, "-3"),
            (0.001, "0.001"),
            (0.1 + 0.2, "0.30000000000000004"),
            (1e-5, "0.00001"),
            (9.9e-6, "9.9e-6"),
            (-1.5e-12, "-1.5e-12"),
            (1e15, "1000000000000000"),
            (1e16, "1e16"),
            (1e300, "1e300"),
            (0.0, "0"),
            (-0.0, "-0"),
            (f64::NAN, "NaN"),
            (f64::NEG_INFINITY, "-inf"),
        ];
        for (x, text) in cases {
            assert_eq!(number_text(x), text, "{x:?}");
        }
    }
}
