//! Shared pieces of the text readers: lines and tokens with their 1-based line numbers,
//! number parsing that rejects non-finite values, and capacity bounds for declared counts;
//! and of the text writers: floats in their shortest round-trip form and [`TextOut`],
//! which builds lines without `core::fmt`.
use crate::error::{Error, Result};
use std::io::Write;

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

/// Append `x` in Rust's shortest round-trip form, the text of `format!("{x:?}")` byte
/// for byte. `ryu` gives the same digits (the shortest string that reads back as `x`,
/// and of those the nearest to `x`) except on a tie between two nearest, which it
/// breaks to even where Rust rounds up; and the same text for 0 and for
/// 10⁻⁴ ≤ |x| < 10¹⁶, written without an exponent by both. So `ryu` is used there
/// unless its string could be one side of a tie: x's exact decimal expansion ending
/// one digit after it (x = m · 2^e with m odd ends at the digit of 10^e). Everything
/// else (exponents, where `ryu` switches form at 10⁻⁵ and Rust at 10⁻⁴; the ties; the
/// non-finite values, which no mesh writer writes) goes through `{:?}`.
/// Property-tested against `{:?}` below.
#[inline]
pub(crate) fn push_f64(out: &mut Vec<u8>, x: f64, b: &mut ryu::Buffer) {
    let a = x.abs();
    if a == 0.0 || (1e-4..1e16).contains(&a) {
        let t = b.format_finite(x);
        // Digits after the point (ryu writes one here, and ".0" for an integer).
        let after = t.len() - 1 - t.bytes().rposition(|c| c == b'.').unwrap_or(t.len() - 1);
        if a == 0.0 || exact_exponent(a) != -(after as i32) - 1 {
            out.extend_from_slice(t.as_bytes());
            return;
        }
    }
    // Writing into a Vec cannot fail.
    let _ = write!(out, "{x:?}");
}

/// e with a = m · 2^e, m odd (a finite and non-zero).
#[inline]
fn exact_exponent(a: f64) -> i32 {
    let bits = a.to_bits();
    let (biased, frac) = ((bits >> 52) as i32, bits & ((1u64 << 52) - 1));
    let (m, e) = if biased == 0 {
        (frac, -1074)
    } else {
        (frac | (1u64 << 52), biased - 1075)
    };
    e + m.trailing_zeros() as i32
}

/// Bytes gathered before they are handed to the writer.
const CHUNK: usize = 1 << 16;

/// The mesh writers' output: lines built from floats (in the form of [`f`], the same
/// bytes), integers and fixed text without `core::fmt` (`ryu`, `itoa`), or the raw
/// bytes of binary records ([`TextOut::bytes`], [`TextOut::end`]), handed to the
/// writer in chunks of [`CHUNK`] bytes. Call [`TextOut::finish`] at the end: what is
/// still gathered is written then.
pub(crate) struct TextOut<'w, W: Write + ?Sized> {
    w: &'w mut W,
    buf: Vec<u8>,
    fb: ryu::Buffer,
    ib: itoa::Buffer,
}

impl<'w, W: Write + ?Sized> TextOut<'w, W> {
    pub(crate) fn new(w: &'w mut W) -> Self {
        TextOut {
            w,
            buf: Vec::with_capacity(CHUNK + 256),
            fb: ryu::Buffer::new(),
            ib: itoa::Buffer::new(),
        }
    }
    /// A float (as [`f`] writes it).
    #[inline]
    pub(crate) fn f(&mut self, x: f64) -> &mut Self {
        push_f64(&mut self.buf, x, &mut self.fb);
        self
    }
    /// An integer.
    #[inline]
    pub(crate) fn int(&mut self, x: impl itoa::Integer) -> &mut Self {
        self.buf.extend_from_slice(self.ib.format(x).as_bytes());
        self
    }
    /// Fixed text.
    #[inline]
    pub(crate) fn s(&mut self, t: &str) -> &mut Self {
        self.buf.extend_from_slice(t.as_bytes());
        self
    }
    /// Floats separated by single spaces.
    #[inline]
    pub(crate) fn fs(&mut self, xs: &[f64]) -> &mut Self {
        self.spaced(xs, Self::f)
    }
    /// Integers separated by single spaces.
    #[inline]
    pub(crate) fn ints<I: itoa::Integer + Copy>(&mut self, xs: &[I]) -> &mut Self {
        self.spaced(xs, Self::int)
    }
    #[inline]
    fn spaced<T: Copy>(&mut self, xs: &[T], put: impl Fn(&mut Self, T) -> &mut Self) -> &mut Self {
        for (i, &x) in xs.iter().enumerate() {
            if i > 0 {
                self.buf.push(b' ');
            }
            put(self, x);
        }
        self
    }
    /// Raw bytes (a field of a binary record).
    #[inline]
    pub(crate) fn bytes(&mut self, b: &[u8]) -> &mut Self {
        self.buf.extend_from_slice(b);
        self
    }
    /// End the line.
    #[inline]
    pub(crate) fn nl(&mut self) -> Result<()> {
        self.buf.push(b'\n');
        self.end()
    }
    /// End a record (a line, or a binary record): hand the gathered bytes to the
    /// writer when a chunk is full.
    #[inline]
    pub(crate) fn end(&mut self) -> Result<()> {
        if self.buf.len() >= CHUNK {
            self.w.write_all(&self.buf).map_err(io_err)?;
            self.buf.clear();
        }
        Ok(())
    }
    /// Write what is still gathered (the writer is not flushed).
    pub(crate) fn finish(mut self) -> Result<()> {
        self.w.write_all(&self.buf).map_err(io_err)?;
        self.buf.clear();
        Ok(())
    }
}

#[cfg(test)]
mod out_tests {
    use super::*;
    use proptest::prelude::*;

    fn shortest(x: f64) -> String {
        let mut v = Vec::new();
        push_f64(&mut v, x, &mut ryu::Buffer::new());
        String::from_utf8(v).unwrap()
    }

    #[test]
    fn the_form_of_debug_at_the_edges() {
        let mut xs = vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.1,
            1e-4,
            1e-5,
            1.5e-5,
            9.999e-5,
            1e15,
            1e16,
            1.5e16,
            9999999999999998.0,
            123456.789,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            f64::MIN,
            f64::EPSILON,
            1.0 / 3.0,
            2.0f64.sqrt(),
            1e300,
            -1e-300,
            // Ties between two shortest strings (ryu: …593.2, Rust: …593.3).
            932222576766593.25,
            1195793925114108.25,
            -978592041658435.25,
            0.0078125,
            -0.99609375,
        ];
        for e in [1e-4f64, 1e16] {
            let mut y = e;
            for _ in 0..4 {
                y = f64::from_bits(y.to_bits() - 1);
                xs.push(y);
                xs.push(-y);
            }
            let mut y = e;
            for _ in 0..4 {
                y = f64::from_bits(y.to_bits() + 1);
                xs.push(y);
            }
        }
        for x in xs {
            assert_eq!(shortest(x), format!("{x:?}"), "{x:e}");
        }
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(shortest(x), format!("{x:?}"));
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]
        #[test]
        fn every_float_is_written_as_debug_writes_it(bits in any::<u64>()) {
            let x = f64::from_bits(bits);
            prop_assert_eq!(shortest(x), format!("{:?}", x));
        }
        #[test]
        fn coordinates_are_written_as_debug_writes_them(x in -1e3f64..1e3, s in -20i32..20) {
            let x = x * 10f64.powi(s);
            prop_assert_eq!(shortest(x), format!("{:?}", x));
        }
        #[test]
        fn short_binary_fractions_are_written_as_debug_writes_them(
            k in 0u64..(1u64 << 53), j in 0i32..70, neg in any::<bool>()
        ) {
            // k · 2^-j: the values whose exact expansion is short enough for a tie
            // (e.g. 932222576766593.25, where ryu writes …593.2 and Rust …593.3).
            let x = k as f64 * 2f64.powi(-j) * if neg { -1.0 } else { 1.0 };
            prop_assert_eq!(shortest(x), format!("{:?}", x));
        }
        #[test]
        fn floats_in_the_range_of_ryu_are_written_as_debug_writes_them(
            frac in 0u64..(1u64 << 52), biased in 1009u64..1077
        ) {
            // Every mantissa, exponents from 2^-14 to 2^53 (about 6e-5 to 1.8e16).
            let x = f64::from_bits((biased << 52) | frac);
            prop_assert_eq!(shortest(x), format!("{:?}", x));
        }
    }

    proptest! {
        #[test]
        fn lines_are_the_text_of_the_format_macros(
            v in proptest::collection::vec((any::<f64>(), any::<u32>()), 0..3000)
        ) {
            let mut a = Vec::new();
            let mut o = TextOut::new(&mut a);
            for &(x, i) in &v {
                o.s("v ").f(x).s(" ").int(i).s(" ").fs(&[x, -x]).s(" ").ints(&[i, i / 2]);
                o.nl().unwrap();
            }
            o.finish().unwrap();
            let mut b = Vec::new();
            for &(x, i) in &v {
                writeln!(b, "v {} {i} {} {} {i} {}", f(x), f(x), f(-x), i / 2).unwrap();
            }
            prop_assert_eq!(a, b);
        }
    }
}
