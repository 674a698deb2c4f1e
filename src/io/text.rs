//! Shared pieces of the text readers: lines and tokens with their 1-based line numbers,
//! number parsing that rejects non-finite values, and capacity bounds for declared counts.
use crate::error::{Error, Result};

/// The placeholder path of i/o errors on in-memory streams (replaced by the real path
/// when the dispatch functions of [`crate::io`] write a file).
pub(crate) const STREAM: &str = "<stream>";

pub(crate) fn io_err(e: std::io::Error) -> Error {
    Error::io(STREAM, e)
}

pub(crate) fn fmt_err(format: &'static str, line: usize, message: impl Into<String>) -> Error {
    Error::Format {
        format,
        line,
        message: message.into(),
    }
}

/// A capacity for `declared` items when the remaining input has `remaining` bytes and
/// every item takes at least `min_bytes`: never trust a count read from a file.
pub(crate) fn capacity(declared: usize, remaining: usize, min_bytes: usize) -> usize {
    declared.min(remaining / min_bytes.max(1))
}

/// Lines of a byte buffer, with `\r\n` or `\n` endings, numbered from 1.
pub(crate) struct Lines<'a> {
    pub(crate) format: &'static str,
    data: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Lines<'a> {
    pub(crate) fn new(format: &'static str, data: &'a [u8]) -> Self {
        Lines {
            format,
            data,
            pos: 0,
            line: 0,
        }
    }
    /// Bytes not yet read.
    pub(crate) fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }
    /// The number of the last line returned (0 before the first).
    pub(crate) fn line(&self) -> usize {
        self.line
    }
    /// The next raw line (without its ending), or None at the end of the input.
    pub(crate) fn next_raw(&mut self) -> Option<(usize, &'a [u8])> {
        if self.pos >= self.data.len() {
            return None;
        }
        let rest = &self.data[self.pos..];
        let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        self.pos += (end + 1).min(rest.len());
        self.line += 1;
        let mut l = &rest[..end];
        if let [head @ .., b'\r'] = l {
            l = head;
        }
        Some((self.line, l))
    }
    /// The next line as text with everything from `comment` on removed (if given),
    /// trimmed; blank lines are skipped. Non-UTF-8 bytes (outside comments) are an error.
    pub(crate) fn next_content(&mut self, comment: Option<u8>) -> Result<Option<(usize, &'a str)>> {
        while let Some((n, raw)) = self.next_raw() {
            let raw = match comment.and_then(|c| raw.iter().position(|&b| b == c)) {
                Some(k) => &raw[..k],
                None => raw,
            };
            let s = to_str(self.format, n, raw)?.trim();
            if !s.is_empty() {
                return Ok(Some((n, s)));
            }
        }
        Ok(None)
    }
    /// Like [`Lines::next_content`] but running out of input is an error naming `what`.
    pub(crate) fn expect_content(
        &mut self,
        comment: Option<u8>,
        what: &str,
    ) -> Result<(usize, &'a str)> {
        let fmt = self.format;
        match self.next_content(comment)? {
            Some(x) => Ok(x),
            None => Err(fmt_err(
                fmt,
                self.line + 1,
                format!("unexpected end of file: expected {what}"),
            )),
        }
    }
}

pub(crate) fn to_str<'a>(format: &'static str, line: usize, bytes: &'a [u8]) -> Result<&'a str> {
    std::str::from_utf8(bytes).map_err(|e| {
        fmt_err(
            format,
            line,
            format!("invalid UTF-8 at byte {} of the line", e.valid_up_to() + 1),
        )
    })
}

/// Parse a finite coordinate.
pub(crate) fn parse_coord(format: &'static str, line: usize, tok: &str) -> Result<f64> {
    match tok.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(fmt_err(
            format,
            line,
            format!("coordinate '{}' is not a finite number", clip(tok)),
        )),
        Err(_) => Err(fmt_err(
            format,
            line,
            format!("expected a number, found '{}'", clip(tok)),
        )),
    }
}

/// Parse a non-negative integer (a count or an index).
pub(crate) fn parse_usize(
    format: &'static str,
    line: usize,
    tok: &str,
    what: &str,
) -> Result<usize> {
    tok.parse::<usize>().map_err(|_| {
        fmt_err(
            format,
            line,
            format!(
                "expected {what} (a non-negative integer), found '{}'",
                clip(tok)
            ),
        )
    })
}

/// A vertex index (0-based, already shifted) checked against the vertex count.
pub(crate) fn index(format: &'static str, line: usize, i: usize, n: usize) -> Result<u32> {
    if i < n {
        if let Ok(v) = u32::try_from(i) {
            return Ok(v);
        }
    }
    Err(fmt_err(
        format,
        line,
        format!("vertex index {i} out of range: {n} vertices"),
    ))
}

/// Shorten a token for an error message (it may be a megabyte of garbage).
pub(crate) fn clip(tok: &str) -> String {
    const MAX: usize = 40;
    if tok.chars().count() <= MAX {
        tok.to_string()
    } else {
        let s: String = tok.chars().take(MAX).collect();
        format!("{s}...")
    }
}

/// Whitespace-separated tokens of a text file with their line numbers, `comment` to the
/// end of a line ignored (free-format files: VTK, MEDIT).
pub(crate) struct Tokens<'a> {
    lines: Lines<'a>,
    comment: Option<u8>,
    current: Option<(usize, std::str::SplitAsciiWhitespace<'a>)>,
}

impl<'a> Tokens<'a> {
    pub(crate) fn new(lines: Lines<'a>, comment: Option<u8>) -> Self {
        Tokens {
            lines,
            comment,
            current: None,
        }
    }
    pub(crate) fn format(&self) -> &'static str {
        self.lines.format
    }
    pub(crate) fn remaining(&self) -> usize {
        self.lines.remaining()
    }
    pub(crate) fn next(&mut self) -> Result<Option<(usize, &'a str)>> {
        loop {
            if let Some((n, it)) = &mut self.current {
                if let Some(t) = it.next() {
                    return Ok(Some((*n, t)));
                }
            }
            match self.lines.next_content(self.comment)? {
                Some((n, s)) => self.current = Some((n, s.split_ascii_whitespace())),
                None => return Ok(None),
            }
        }
    }
    pub(crate) fn expect(&mut self, what: &str) -> Result<(usize, &'a str)> {
        match self.next()? {
            Some(t) => Ok(t),
            None => Err(fmt_err(
                self.format(),
                self.lines.line() + 1,
                format!("unexpected end of file: expected {what}"),
            )),
        }
    }
    pub(crate) fn coord(&mut self) -> Result<f64> {
        let (n, t) = self.expect("a coordinate")?;
        parse_coord(self.format(), n, t)
    }
    pub(crate) fn usize(&mut self, what: &str) -> Result<(usize, usize)> {
        let (n, t) = self.expect(what)?;
        Ok((n, parse_usize(self.format(), n, t, what)?))
    }
}

/// Write a float so that it reads back bit for bit (Rust's shortest round-trip form).
#[inline]
pub(crate) fn f(x: f64) -> impl std::fmt::Display {
    Shortest(x)
}

struct Shortest(f64);

impl std::fmt::Display for Shortest {
    fn fmt(&self, w: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(w, "{:?}", self.0)
    }
}
