//! Splitting a byte stream into trace lines without allocating per line.
//!
//! A line ends at `\n`, at `\r`, or at either pair `\r\n` / `\n\r` (the pair is one line
//! end, so Windows, old Mac and RISC OS files number their lines as a text editor does).
//! A line longer than [`MAX_LINE`] bytes is reported as [`Line::TooLong`] and skipped up to
//! its end, in bounded memory; input with no line end for [`MAX_SKIP`] bytes ends the
//! reading with an error, so that a device such as `/dev/zero` is not read for ever. Any
//! other bytes (NUL included) are the decoder's to judge: a garbled line is a malformed
//! sample, and a monitor reads on.
//!
//! The pair rule never waits for a byte: a line is returned as soon as its first end byte
//! arrives, and the partner byte, if it is the next one read, is dropped then. A live
//! monitor thus sees every sample the moment its line is complete.

use std::io::{self, Read};

/// Longest line accepted (bytes); a longer one is [`Line::TooLong`] and skipped.
pub const MAX_LINE: usize = 1 << 20;

/// Longest line skipped (bytes): input without a line end for this long (`/dev/zero`) is
/// not a trace, and reading it would never end.
pub const MAX_SKIP: u64 = 64 << 20;

/// Bytes asked of the input per read.
const CHUNK: usize = 1 << 20;

/// One line of the input.
#[derive(Debug, PartialEq, Eq)]
pub enum Line<'a> {
    /// The line's bytes, without its end.
    Text(&'a [u8]),
    /// A line longer than [`MAX_LINE`] bytes (skipped).
    TooLong,
}

/// The lines of a byte stream, numbered from 1.
pub struct Lines<R> {
    inner: R,
    buf: Vec<u8>,
    start: usize,
    end: usize,
    eof: bool,
    /// Skipping the rest of a too-long line.
    skipping: bool,
    /// The byte that, read next, completes the last line end as a pair (`\n` after `\r`,
    /// `\r` after `\n`) and is dropped.
    partner: Option<u8>,
    /// 1-based number of the last line returned.
    number: u64,
    /// Bytes of the too-long line skipped so far.
    skipped: u64,
}

/// Position of the first `\n` or `\r` in `s`, eight bytes at a time.
#[inline]
fn find_line_end(s: &[u8]) -> Option<usize> {
    const LO: u64 = 0x0101_0101_0101_0101;
    const HI: u64 = 0x8080_8080_8080_8080;
    const NL: u64 = LO * b'\n' as u64;
    const CR: u64 = LO * b'\r' as u64;
    let mut chunks = s.chunks_exact(8);
    let mut base = 0;
    for c in &mut chunks {
        let word = u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]);
        let (n, r) = (word ^ NL, word ^ CR);
        let zero = (n.wrapping_sub(LO) & !n | r.wrapping_sub(LO) & !r) & HI;
        if zero != 0 {
            return Some(base + (zero.trailing_zeros() / 8) as usize);
        }
        base += 8;
    }
    chunks
        .remainder()
        .iter()
        .position(|&b| b == b'\n' || b == b'\r')
        .map(|k| base + k)
}

impl<R: Read> Lines<R> {
    /// Lines of `inner`.
    pub fn new(inner: R) -> Self {
        Lines {
            inner,
            buf: vec![0; CHUNK + MAX_LINE],
            start: 0,
            end: 0,
            eof: false,
            skipping: false,
            partner: None,
            number: 0,
            skipped: 0,
        }
    }

    /// The reader, for what it knows after reading (e.g. an interruption).
    pub fn inner(&self) -> &R {
        &self.inner
    }

    /// The next line and its 1-based number, or `None` at the end of the input.
    /// `before_read` runs before every read of the input, which may block (a monitor
    /// flushes its output there, so earlier verdicts go out before it waits). Input with no
    /// line end for `MAX_SKIP` bytes is an [`io::ErrorKind::InvalidData`] error.
    pub fn next_line(
        &mut self,
        mut before_read: impl FnMut() -> io::Result<()>,
    ) -> io::Result<Option<(u64, Line<'_>)>> {
        loop {
            if let Some(partner) = self.partner
                && self.start < self.end
            {
                if self.buf[self.start] == partner {
                    self.start += 1;
                }
                self.partner = None;
            }
            if let Some(k) = find_line_end(&self.buf[self.start..self.end]) {
                let line = self.start..self.start + k;
                self.partner = Some(match self.buf[self.start + k] {
                    b'\n' => b'\r',
                    _ => b'\n',
                });
                self.start += k + 1;
                if std::mem::take(&mut self.skipping) {
                    continue;
                }
                self.number += 1;
                if line.len() > MAX_LINE {
                    return Ok(Some((self.number, Line::TooLong)));
                }
                return Ok(Some((self.number, Line::Text(&self.buf[line]))));
            }
            if self.skipping {
                self.skipped += (self.end - self.start) as u64;
                self.start = self.end;
                if self.skipped > MAX_SKIP {
                    return Err(io::Error::new(
                        io::ErrorKind::InvalidData,
                        format!(
                            "line {} has no end in {} MiB: this is not a line-oriented trace",
                            self.number,
                            MAX_SKIP >> 20
                        ),
                    ));
                }
            }
            if self.eof {
                if self.start < self.end {
                    let line = self.start..self.end;
                    self.start = self.end;
                    self.number += 1;
                    if line.len() > MAX_LINE {
                        return Ok(Some((self.number, Line::TooLong)));
                    }
                    return Ok(Some((self.number, Line::Text(&self.buf[line]))));
                }
                return Ok(None);
            }
            if self.end - self.start >= MAX_LINE {
                self.skipped = (self.end - self.start) as u64;
                self.start = self.end;
                self.skipping = true;
                self.number += 1;
                return Ok(Some((self.number, Line::TooLong)));
            }
            self.buf.copy_within(self.start..self.end, 0);
            self.end -= self.start;
            self.start = 0;
            before_read()?;
            let n = loop {
                match self.inner.read(&mut self.buf[self.end..]) {
                    Ok(n) => break n,
                    Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                    Err(e) => return Err(e),
                }
            };
            if n == 0 {
                self.eof = true;
            }
            self.end += n;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(input: &[u8]) -> Vec<String> {
        let mut lines = Lines::new(input);
        let mut out = Vec::new();
        while let Some((n, line)) = lines.next_line(|| Ok(())).unwrap() {
            match line {
                Line::Text(t) => out.push(format!("{n}:{}", String::from_utf8_lossy(t))),
                Line::TooLong => out.push(format!("{n}:too long")),
            }
        }
        out
    }

    #[test]
    fn every_line_ending_convention_numbers_lines_as_an_editor_does() {
        let want = ["1:a", "2:b", "3:", "4:c"];
        for text in [
            &b"a\nb\n\nc\n"[..],
            b"a\r\nb\r\n\r\nc\r\n",
            b"a\rb\r\rc\r",
            b"a\n\rb\n\r\n\rc\n\r",
            b"a\nb\n\nc",
        ] {
            assert_eq!(all(text), want, "{:?}", String::from_utf8_lossy(text));
        }
    }

    #[test]
    fn a_pair_split_between_reads_is_one_line_end() {
        // A reader that hands out one byte at a time: the `\n` of `\r\n` arrives alone.
        struct Trickle<'a>(&'a [u8]);
        impl Read for Trickle<'_> {
            fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
                let n = self.0.len().min(1).min(buf.len());
                buf[..n].copy_from_slice(&self.0[..n]);
                self.0 = &self.0[n..];
                Ok(n)
            }
        }
        let mut lines = Lines::new(Trickle(b"ab\r\ncd\r\n"));
        let mut got = Vec::new();
        while let Some((n, Line::Text(t))) = lines.next_line(|| Ok(())).unwrap() {
            got.push((n, t.to_vec()));
        }
        assert_eq!(got, vec![(1, b"ab".to_vec()), (2, b"cd".to_vec())]);
    }

    #[test]
    fn endless_input_without_a_line_end_ends_the_reading() {
        let mut lines = Lines::new(std::io::repeat(0));
        assert_eq!(
            lines.next_line(|| Ok(())).unwrap(),
            Some((1, Line::TooLong))
        );
        assert!(lines.next_line(|| Ok(())).is_err_and(|e| {
            e.kind() == io::ErrorKind::InvalidData
                && e.to_string().contains("line 1 has no end in 64 MiB")
        }));
    }

    #[test]
    fn a_nul_byte_is_the_decoders_to_judge() {
        assert_eq!(
            all(b"t,x\n\x00\xffgarbage\n1,2\n"),
            ["1:t,x", "2:\u{0}\u{fffd}garbage", "3:1,2"]
        );
    }

    #[test]
    fn a_too_long_line_is_reported_once_and_skipped() {
        let mut text = vec![b'x'; MAX_LINE + 10];
        text.extend_from_slice(b"\nok\n");
        assert_eq!(all(&text), ["1:too long", "2:ok"]);
    }
}
