//! Point files (`.xyz`, `.txt`, `.pts`): one point per line, three whitespace- or
//! comma-separated numbers `x y z`; blank lines and `#` comments are skipped. The
//! input of `certmesh delaunay`. Anything else on a line (a fourth column, a word, a
//! non-finite number) is an error naming the line.
use super::text::{clip, fmt_err, parse_coord, Lines};
use crate::error::Result;
use std::io::{BufRead, Write};

const FORMAT: &str = "points";

/// Read the points of an in-memory point file.
pub fn read(r: impl BufRead) -> Result<Vec<[f64; 3]>> {
    let data = super::slurp(r)?;
    let mut lines = Lines::new(FORMAT, &data);
    let mut out = Vec::with_capacity(super::text::capacity(data.len() / 6, data.len(), 6));
    while let Some((n, line)) = lines.next_content(Some(b'#'))? {
        let toks: Vec<&str> = line
            .split(|c: char| c.is_ascii_whitespace() || c == ',')
            .filter(|t| !t.is_empty())
            .collect();
        if toks.len() != 3 {
            return Err(fmt_err(
                FORMAT,
                n,
                format!(
                    "expected three coordinates 'x y z', found {} field{} ('{}')",
                    toks.len(),
                    if toks.len() == 1 { "" } else { "s" },
                    clip(line)
                ),
            ));
        }
        let mut p = [0.0; 3];
        for k in 0..3 {
            p[k] = parse_coord(FORMAT, n, toks[k])?;
        }
        out.push(p);
    }
    Ok(out)
}

/// Write points, one `x y z` line each (shortest round-trip decimals).
pub fn write(mut w: impl Write, points: &[[f64; 3]]) -> Result<()> {
    let mut o = super::text::TextOut::new(&mut w);
    for p in points {
        o.fs(p).nl()?;
    }
    o.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_points_and_names_bad_lines() {
        let p = read(&b"# a comment\n0 0 0\n\n1, 2, 3.5\r\n-1e-3 4 5 # tail\n"[..]).unwrap();
        assert_eq!(p, vec![[0.0, 0.0, 0.0], [1.0, 2.0, 3.5], [-1e-3, 4.0, 5.0]]);
        let e = read(&b"0 0 0\n1 2\n"[..]).unwrap_err().to_string();
        assert!(
            e.contains("line 2") && e.contains("three coordinates"),
            "{e}"
        );
        let e = read(&b"0 0 0\n1 2 x\n"[..]).unwrap_err().to_string();
        assert!(e.contains("line 2") && e.contains("'x'"), "{e}");
        let e = read(&b"0 0 nan\n"[..]).unwrap_err().to_string();
        assert!(e.contains("line 1") && e.contains("finite"), "{e}");
        let mut buf = Vec::new();
        write(&mut buf, &[[0.1, -2.0, 1e-300]]).unwrap();
        assert_eq!(read(&buf[..]).unwrap(), vec![[0.1, -2.0, 1e-300]]);
    }
}
