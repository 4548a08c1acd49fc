//! Reading an input source, a file or standard input: at most a cap of
//! bytes, checked to be UTF-8 as it is read ([`Checked`]), so that an
//! endless or binary source (`/dev/zero`, `/dev/urandom`) is refused after
//! at most the cap, and at its first invalid byte. `eval` and `audit` read
//! their input whole ([`read_source`], [`MAX_INPUT_BYTES`]); problem files
//! are parsed as they stream in ([`open_problem_file`],
//! [`MAX_PROBLEM_FILE_BYTES`]), so that the JSON parser stops at the first
//! byte that is not JSON too.

use std::io::{self, Read};
use std::path::Path;

use crate::error::InputError;
use crate::field_path::escape_unprintable;

/// The largest input `eval` reads: 16 MiB, some thousand times the largest
/// meaningful request; nothing beyond it is read.
pub const MAX_INPUT_BYTES: usize = 16 * 1024 * 1024;

/// The largest problem file `solve` and `track` read: 1 GiB, four times
/// the largest `synth-plp` writes (200 cameras, 10 000 points, 1 000
/// lines); nothing beyond it is read.
pub const MAX_PROBLEM_FILE_BYTES: usize = 1 << 30;

/// Bytes asked of the source per read.
const CHUNK_BYTES: usize = 64 * 1024;

/// The name errors use for an input source: the path (unprintable characters
/// escaped), or `<stdin>` for `-`.
pub fn source_name(source: &str) -> String {
    if source == "-" {
        "<stdin>".into()
    } else {
        escape_unprintable(source).into_owned()
    }
}

/// Reads a file, or standard input for `-`, as UTF-8 text of at most
/// [`MAX_INPUT_BYTES`].
pub fn read_source(source: &str) -> Result<String, InputError> {
    let name = source_name(source);
    let cannot_read = |e: std::io::Error| InputError::new(&name, format!("cannot read input: {e}"));
    if source == "-" {
        read_bounded(std::io::stdin().lock(), &name)
    } else {
        read_bounded(std::fs::File::open(source).map_err(cannot_read)?, &name)
    }
}

/// Opens the problem file `path` for [`crate::strict_json::parse_json_from`]:
/// read through [`Checked`] with the cap [`MAX_PROBLEM_FILE_BYTES`].
///
/// # Errors
///
/// The file cannot be opened, named by its printable path.
pub fn open_problem_file(path: &Path) -> Result<Checked<std::fs::File>, InputError> {
    let name = escape_unprintable(&path.display().to_string()).into_owned();
    let file = std::fs::File::open(path)
        .map_err(|e| InputError::new(&name, format!("cannot read: {e}")))?;
    Ok(Checked::new(file, MAX_PROBLEM_FILE_BYTES))
}

/// A source read through a cap and a UTF-8 check: past `cap` bytes, or at
/// the first byte that is not UTF-8, a read fails (`InvalidData`) with the
/// one-line reason, the byte's offset from the start included; a character
/// split between reads is checked once it is whole.
pub struct Checked<R> {
    inner: R,
    cap: usize,
    /// Bytes handed out so far.
    read: usize,
    /// The start of a character the last read cut (at most 3 bytes).
    carry: Vec<u8>,
}

impl<R: Read> Checked<R> {
    /// `inner` read through the checks, at most `cap` bytes.
    pub fn new(inner: R, cap: usize) -> Self {
        Checked {
            inner,
            cap,
            read: 0,
            carry: Vec::new(),
        }
    }

    fn invalid(at: usize) -> io::Error {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!("invalid UTF-8 at byte {at}: input must be UTF-8"),
        )
    }
}

impl<R: Read> Read for Checked<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if buf.is_empty() {
            return Ok(0);
        }
        // One byte past the cap tells an input of exactly the cap from a
        // longer one.
        let room = (self.cap + 1 - self.read).min(buf.len());
        let n = loop {
            match self.inner.read(&mut buf[..room]) {
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                other => break other?,
            }
        };
        if n == 0 {
            // The end: a character still incomplete is invalid.
            return if self.carry.is_empty() {
                Ok(0)
            } else {
                Err(Self::invalid(self.read - self.carry.len()))
            };
        }
        if self.read + n > self.cap {
            let cap = self.cap;
            return Err(io::Error::new(
                io::ErrorKind::InvalidData,
                format!(
                    "input is larger than {} MiB ({cap} bytes), the limit; nothing beyond it \
                     was read",
                    cap >> 20
                ),
            ));
        }
        let start = self.read - self.carry.len();
        let mut pending = std::mem::take(&mut self.carry);
        pending.extend_from_slice(&buf[..n]);
        match std::str::from_utf8(&pending) {
            Ok(_) => {}
            Err(e) if e.error_len().is_none() => {
                self.carry = pending[e.valid_up_to()..].to_vec();
            }
            Err(e) => return Err(Self::invalid(start + e.valid_up_to())),
        }
        self.read += n;
        Ok(n)
    }
}

/// Reads `reader` to its end through [`Checked`] with the cap
/// [`MAX_INPUT_BYTES`]; errors name `name`.
fn read_bounded(reader: impl Read, name: &str) -> Result<String, InputError> {
    let mut bytes = Vec::new();
    let mut checked = Checked::new(reader, MAX_INPUT_BYTES);
    let mut chunk = vec![0; CHUNK_BYTES];
    loop {
        match checked.read(&mut chunk) {
            Ok(0) => break,
            Ok(n) => bytes.extend_from_slice(&chunk[..n]),
            Err(e) if e.kind() == io::ErrorKind::InvalidData => {
                return Err(InputError::new(name, e.to_string()));
            }
            Err(e) => return Err(InputError::new(name, format!("cannot read input: {e}"))),
        }
    }
    Ok(String::from_utf8(bytes).expect("checked as it was read"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A reader that hands out its bytes `step` at a time.
    struct Trickle<'a> {
        bytes: &'a [u8],
        step: usize,
    }

    impl Read for Trickle<'_> {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            let n = self.step.min(buf.len()).min(self.bytes.len());
            buf[..n].copy_from_slice(&self.bytes[..n]);
            self.bytes = &self.bytes[n..];
            Ok(n)
        }
    }

    #[test]
    fn characters_split_between_reads_are_accepted() {
        let text = "{\"é\": \"ü€😀\"}";
        for step in 1..=4 {
            let reader = Trickle {
                bytes: text.as_bytes(),
                step,
            };
            assert_eq!(read_bounded(reader, "x").unwrap(), text, "step {step}");
        }
    }

    #[test]
    fn invalid_and_truncated_utf8_is_reported_at_its_byte() {
        let error = read_bounded(&b"ab\xffcd"[..], "in").unwrap_err();
        assert_eq!(error.path, "in");
        assert!(
            error.message.starts_with("invalid UTF-8 at byte 2"),
            "{error}"
        );
        let error = read_bounded(&b"ab\xe2\x82"[..], "in").unwrap_err();
        assert!(
            error.message.starts_with("invalid UTF-8 at byte 2"),
            "{error}"
        );
    }

    #[test]
    fn the_cap_is_exact_and_nothing_past_it_is_read() {
        let at_cap = vec![b' '; MAX_INPUT_BYTES];
        assert_eq!(
            read_bounded(&at_cap[..], "x").unwrap().len(),
            MAX_INPUT_BYTES
        );
        let error = read_bounded(std::io::repeat(b' '), "endless").unwrap_err();
        assert_eq!(error.path, "endless");
        assert!(error.message.contains("larger than 16 MiB"), "{error}");
    }

    #[test]
    fn unprintable_file_names_are_escaped() {
        assert_eq!(source_name("a\nb.json"), "a\\nb.json");
        assert_eq!(source_name("-"), "<stdin>");
    }
}
