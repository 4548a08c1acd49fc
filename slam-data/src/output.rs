//! Writing text output: exact number formatting, and files written to a
//! temporary file renamed into place.

use std::fmt;
use std::io::BufWriter;
use std::path::Path;

use slamjac_io::AtomicFile;

use crate::error::Error;

/// A double written so that it reads back bit for bit: the shortest decimal
/// that round-trips, with an exponent when it is very small or very large.
pub(crate) struct Real(pub(crate) f64);

impl fmt::Display for Real {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let magnitude = self.0.abs();
        if magnitude == 0.0 || (1e-5..1e16).contains(&magnitude) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

/// Writes `path` through `write`, buffered, into a temporary file beside it
/// renamed into place once complete (`slamjac_io::AtomicFile`): on any
/// failure the file keeps its old contents. Every failure is an [`Error`]
/// naming the file.
pub(crate) fn write_file<T>(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<AtomicFile>, &str) -> Result<T, Error>,
) -> Result<T, Error> {
    let mut out = create(path)?;
    let written = write(&mut out.0, &out.1)?;
    commit(out)?;
    Ok(written)
}

/// A file being written, buffered, and its name for errors.
pub(crate) type Staged = (BufWriter<AtomicFile>, String);

/// Starts writing `path` ([`write_file`] in two steps, for files written
/// together and committed only once all are written).
pub(crate) fn create(path: &Path) -> Result<Staged, Error> {
    let name = path.display().to_string();
    let file =
        AtomicFile::create(path).map_err(|e| Error::file(&name, format!("cannot create: {e}")))?;
    Ok((BufWriter::with_capacity(1 << 16, file), name))
}

/// Puts a file started by [`create`] in place.
pub(crate) fn commit((out, name): Staged) -> Result<(), Error> {
    let file = out
        .into_inner()
        .map_err(|e| io_error(&name, e.into_error()))?;
    file.commit().map_err(|e| io_error(&name, e))
}

/// A failed write to `file`.
pub(crate) fn io_error(file: &str, error: std::io::Error) -> Error {
    Error::file(file, format!("cannot write: {error}"))
}

#[cfg(test)]
mod tests {
    use super::Real;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig {
            cases: 20_000,
            rng_seed: proptest::test_runner::RngSeed::Fixed(1),
            failure_persistence: None,
            ..ProptestConfig::default()
        })]

        /// Any finite double, whatever its bits, reads back identical.
        #[test]
        fn written_doubles_read_back_bit_for_bit(bits in any::<u64>()) {
            let value = f64::from_bits(bits);
            prop_assume!(value.is_finite());
            let text = Real(value).to_string();
            let back: f64 = text.parse().unwrap();
            prop_assert_eq!(back.to_bits(), value.to_bits(), "{}", text);
        }
    }

    /// The BAL file's 17-digit `3.2377569465570913e-14` is written in its
    /// 16-digit shortest form.
    #[test]
    #[allow(clippy::excessive_precision)]
    fn small_and_large_values_use_an_exponent() {
        let shown: Vec<String> = [
            0.0,
            -0.0,
            1.0,
            1430.031943271168,
            1e-5,
            3.2377569465570913e-14,
            1e16,
            -7.5e300,
        ]
        .iter()
        .map(|v| Real(*v).to_string())
        .collect();
        assert_eq!(
            shown,
            [
                "0",
                "-0",
                "1",
                "1430.031943271168",
                "0.00001",
                "3.237756946557091e-14",
                "1e16",
                "-7.5e300"
            ]
        );
    }
}
