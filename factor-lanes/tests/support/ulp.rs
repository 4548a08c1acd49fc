//! Distances in units in the last place between a lane result and the scalar
//! `std` result.

/// A float whose ulp distances can be measured.
pub trait Ulp: Copy + PartialEq {
    /// The number of representable values from `reference` to `self` (0 when
    /// equal, including `+0` against `−0` and NaN against NaN; `u64::MAX`
    /// when exactly one is NaN).
    fn ulps_from(self, reference: Self) -> u64;
    /// The value `steps` representable values above `self` (below when
    /// negative); NaN stays NaN.
    fn nudged(self, steps: i64) -> Self;
    /// Bit for bit the same value (any NaN for any NaN; `−0` is not `+0`).
    fn identical(self, other: Self) -> bool;
}

macro_rules! ulp_impl {
    ($s:ty, $i:ty) => {
        impl Ulp for $s {
            fn ulps_from(self, reference: Self) -> u64 {
                match (self.is_nan(), reference.is_nan()) {
                    (true, true) => return 0,
                    (false, false) => {}
                    _ => return u64::MAX,
                }
                (ordered(self) as i128 - ordered(reference) as i128).unsigned_abs() as u64
            }

            fn nudged(self, steps: i64) -> Self {
                if self.is_nan() {
                    return self;
                }
                let line = ordered(self) as i128 + steps as i128;
                let bits = if line < 0 {
                    <$i>::MIN as i128 - line
                } else {
                    line
                };
                <$s>::from_bits(bits as $i as _)
            }

            fn identical(self, other: Self) -> bool {
                (self.is_nan() && other.is_nan()) || self.to_bits() == other.to_bits()
            }
        }
    };
}

/// Sign-magnitude bits to a monotone integer line (±0 both 0).
fn ordered<S: Bits>(x: S) -> i64 {
    let bits = x.signed_bits();
    if bits < 0 { S::MIN_LINE - bits } else { bits }
}

/// The bits of a float as a signed integer of its width, widened.
trait Bits {
    /// `iN::MIN` of the float's width.
    const MIN_LINE: i64;
    fn signed_bits(self) -> i64;
}

impl Bits for f64 {
    const MIN_LINE: i64 = i64::MIN;
    fn signed_bits(self) -> i64 {
        self.to_bits() as i64
    }
}

impl Bits for f32 {
    const MIN_LINE: i64 = i32::MIN as i64;
    fn signed_bits(self) -> i64 {
        self.to_bits() as i32 as i64
    }
}

ulp_impl!(f64, i64);
ulp_impl!(f32, i32);
