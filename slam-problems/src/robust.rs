//! [`Robust`]: a robust loss on every block, as the command line and the
//! problem files name it (`huber:δ`, `cauchy:δ`). Each solver evaluates it
//! its own way (the adapter through apex-solver's loss functions, the
//! Schur-complement solver as IRLS weights).

use std::fmt;
use std::str::FromStr;

/// A robust loss on every block: `½ ρ(‖r‖²)` instead of `½ ‖r‖²`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Robust {
    /// Huber: quadratic up to `‖r‖ = δ`, linear beyond.
    Huber(f64),
    /// Cauchy: `δ² log(1 + ‖r‖²/δ²)`.
    Cauchy(f64),
}

/// The range of a robust loss's δ: the readers' range of magnitudes
/// (`slam_data::MAX_MAGNITUDE`), so that `δ²` stays within `f64`.
pub const ROBUST_SCALES: (f64, f64) = (1e-100, 1e100);

/// `huber:δ` or `cauchy:δ`.
impl fmt::Display for Robust {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Robust::Huber(delta) => write!(f, "huber:{delta}"),
            Robust::Cauchy(delta) => write!(f, "cauchy:{delta}"),
        }
    }
}

/// Reads `huber:δ` or `cauchy:δ` with `δ` in [`ROBUST_SCALES`].
impl FromStr for Robust {
    type Err = String;
    fn from_str(text: &str) -> Result<Self, String> {
        let (name, delta) = text
            .split_once(':')
            .ok_or_else(|| format!("`{text}`: expected huber:δ or cauchy:δ"))?;
        let (low, high) = ROBUST_SCALES;
        let delta: f64 = delta
            .parse()
            .ok()
            .filter(|d: &f64| (low..=high).contains(d))
            .ok_or_else(|| {
                format!("`{text}`: δ must be a number above 0, from {low:e} to {high:e}")
            })?;
        match name {
            "huber" => Ok(Robust::Huber(delta)),
            "cauchy" => Ok(Robust::Cauchy(delta)),
            _ => Err(format!("`{text}`: unknown loss `{name}` (huber or cauchy)")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What `Display` writes, `FromStr` reads back.
    #[test]
    fn a_loss_reads_back_what_it_writes() {
        for robust in [
            Robust::Huber(1.5),
            Robust::Cauchy(1e-100),
            Robust::Huber(1e100),
        ] {
            assert_eq!(robust.to_string().parse::<Robust>(), Ok(robust));
        }
        assert_eq!("cauchy:0.25".parse::<Robust>(), Ok(Robust::Cauchy(0.25)));
    }

    /// A missing scale, one outside [`ROBUST_SCALES`] (0, negative, NaN,
    /// infinite, beyond 1e100) or an unknown name is refused with the text.
    #[test]
    fn bad_losses_are_refused_by_name() {
        for text in [
            "huber",
            "huber:",
            "huber:0",
            "huber:-1",
            "cauchy:NaN",
            "cauchy:inf",
            "huber:1e101",
            "tukey:1",
        ] {
            let error = text.parse::<Robust>().expect_err(text);
            assert!(error.starts_with(&format!("`{text}`")), "{text}: {error}");
        }
    }
}
