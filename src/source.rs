//! Reading an input source, a file or standard input, into text: at most
//! [`MAX_INPUT_BYTES`], checked to be UTF-8 as it is read, so that an endless
//! or binary source (`/dev/zero`, `/dev/urandom`) is refused after at most
//! the cap, and at its first invalid byte.

use std::io::Read;

use crate::error::InputError;
use crate::field_path::escape_unprintable;

/// The largest input `eval` reads: 16 MiB, some thousand times the largest
/// meaningful request; nothing beyond it is read.
pub const MAX_INPUT_BYTES: usize = 16 * 1024 * 1024;

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

/// Reads `reader` to its end, checking each chunk as it arrives: past
/// [`MAX_INPUT_BYTES`] or at the first byte that is not UTF-8 it stops with
/// an error naming `name`.
fn read_bounded(reader: impl Read, name: &str) -> Result<String, InputError> {
    let invalid_utf8 = |at: usize| {
        InputError::new(
            name,
            format!("invalid UTF-8 at byte {at}: input must be UTF-8"),
        )
    };
    let mut bytes = Vec::new();
    // One byte past the cap tells an input of exactly the cap from a longer one.
    let mut reader = reader.take(MAX_INPUT_BYTES as u64 + 1);
    // Bytes before `checked` are valid UTF-8; a character split by a chunk
    // boundary waits after it for the next chunk.
    let mut checked = 0;
    loop {
        let start = bytes.len();
        bytes.resize(start + CHUNK_BYTES, 0);
        let read = loop {
            match reader.read(&mut bytes[start..]) {
                Ok(read) => break read,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(InputError::new(name, format!("cannot read input: {e}"))),
            }
        };
        bytes.truncate(start + read);
        if bytes.len() > MAX_INPUT_BYTES {
            return Err(InputError::new(
                name,
                format!(
                    "input is larger than {} MiB ({MAX_INPUT_BYTES} bytes), the limit; \
                     nothing beyond it was read",
                    MAX_INPUT_BYTES >> 20
                ),
            ));
        }
        if read == 0 {
            // The end: a character still incomplete is invalid.
            return String::from_utf8(bytes)
                .map_err(|e| invalid_utf8(e.utf8_error().valid_up_to()));
        }
        match std::str::from_utf8(&bytes[checked..]) {
            Ok(_) => checked = bytes.len(),
            Err(e) if e.error_len().is_none() => checked += e.valid_up_to(),
            Err(e) => return Err(invalid_utf8(checked + e.valid_up_to())),
        }
    }
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
