//! Reading an input once. Telling a format from content means reading the
//! start of the input; a pipe (`cat file | slamjac solve /dev/stdin`) cannot
//! be opened again to read that start a second time. [`sniff`] hands the
//! sniffer a reader that keeps every byte it consumes (at most `limit`), and
//! returns a reader that replays them in front of the rest: the parser then
//! reads the whole input from its first byte, which was read from the source
//! exactly once.

use std::io::{self, BufRead, Chain, Cursor, Read};

/// The input after sniffing: the bytes the sniffer read, then the rest.
pub type Replayed<R> = Chain<Cursor<Vec<u8>>, R>;

/// Runs `look` on the start of `reader` (at most `limit` bytes of it: past
/// them the sniffer sees the end of its input) and returns its verdict with
/// the whole input, from its first byte.
pub fn sniff<R: BufRead, T>(
    mut reader: R,
    limit: usize,
    look: impl FnOnce(&mut Recorder<'_, R>) -> T,
) -> (T, Replayed<R>) {
    let mut recorder = Recorder {
        inner: &mut reader,
        seen: Vec::new(),
        limit,
    };
    let verdict = look(&mut recorder);
    let seen = recorder.seen;
    (verdict, Cursor::new(seen).chain(reader))
}

/// The reader a sniffer reads through: it keeps what it hands out.
#[derive(Debug)]
pub struct Recorder<'a, R> {
    inner: &'a mut R,
    seen: Vec<u8>,
    limit: usize,
}

impl<R: BufRead> Read for Recorder<'_, R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let available = self.fill_buf()?;
        let n = available.len().min(buf.len());
        buf[..n].copy_from_slice(&available[..n]);
        self.consume(n);
        Ok(n)
    }
}

impl<R: BufRead> BufRead for Recorder<'_, R> {
    fn fill_buf(&mut self) -> io::Result<&[u8]> {
        let room = self.limit.saturating_sub(self.seen.len());
        if room == 0 {
            return Ok(&[]);
        }
        let available = self.inner.fill_buf()?;
        Ok(&available[..available.len().min(room)])
    }

    fn consume(&mut self, amount: usize) {
        // `amount` bytes of what `fill_buf` returned, which the inner reader
        // still holds: asking for them again does no I/O.
        if let Ok(available) = self.inner.fill_buf() {
            let amount = amount.min(available.len());
            self.seen.extend_from_slice(&available[..amount]);
            self.inner.consume(amount);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A source that can be read once, in pieces of `step` bytes.
    struct Once<'a> {
        bytes: &'a [u8],
        step: usize,
    }

    impl Read for Once<'_> {
        fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
            let n = self.step.min(buf.len()).min(self.bytes.len());
            buf[..n].copy_from_slice(&self.bytes[..n]);
            self.bytes = &self.bytes[n..];
            Ok(n)
        }
    }

    #[test]
    fn the_sniffed_start_is_read_again_in_front_of_the_rest() {
        let text = b"# comment\n\nVERTEX 1 2 3\nEDGE 4 5\n";
        for step in [1, 3, 64] {
            let reader = io::BufReader::with_capacity(4, Once { bytes: text, step });
            let (first, mut replayed) = sniff(reader, 1 << 20, |r| {
                r.lines().map_while(Result::ok).find(|l| l.starts_with('V'))
            });
            assert_eq!(first.as_deref(), Some("VERTEX 1 2 3"));
            let mut all = Vec::new();
            replayed.read_to_end(&mut all).unwrap();
            assert_eq!(all, text, "step {step}");
        }
    }

    #[test]
    fn the_sniffer_sees_no_more_than_the_limit() {
        let text = vec![b'x'; 1000];
        let (seen, mut replayed) = sniff(&text[..], 10, |r| {
            let mut seen = Vec::new();
            r.read_to_end(&mut seen).unwrap();
            seen.len()
        });
        assert_eq!(seen, 10);
        let mut all = Vec::new();
        replayed.read_to_end(&mut all).unwrap();
        assert_eq!(all, text);
    }
}
