//! Comparisons for input validation that treat NaN as failing.
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
