//! The text layer the OBJ and MTL readers share: decoding, lines and
//! finite numbers (rules in [`crate::mesh`]'s module docs). A leaf, so
//! that `mesh` and `mtl` do not depend on each other; `decode_text` and
//! `split_lines` are public as `mesh::decode_text` and `mesh::split_lines`.

use std::path::Path;

use crate::Error;

/// Parses finite `f32`s; the message names the keyword and the bad token.
pub(crate) fn parse_numbers<'a>(
    toks: impl Iterator<Item = &'a str>,
    line: usize,
    kw: &str,
    path: &Path,
) -> Result<Vec<f32>, Error> {
    let mut out = Vec::with_capacity(4);
    for t in toks {
        match t.parse::<f32>() {
            Ok(x) if x.is_finite() => out.push(x),
            Ok(_) => {
                return Err(Error::Parse {
                    path: path.to_owned(),
                    line,
                    message: format!(
                        "`{kw}`: `{t}` is not a finite 32-bit number (NaN, infinite or beyond ±3.4e38)"
                    ),
                });
            }
            Err(_) => {
                return Err(Error::Parse {
                    path: path.to_owned(),
                    line,
                    message: format!("`{kw}`: `{t}` is not a number"),
                });
            }
        }
    }
    Ok(out)
}

/// Decodes the text of an OBJ or MTL file as the loader reads it: UTF-8
/// (BOM skipped), UTF-16 with BOM, or lossy bytes. `path` only names the
/// file in the error (UTF-16 with an odd number of bytes). Public for the
/// offline pass, which hashes the MTL files an OBJ names.
pub fn decode_text(bytes: &[u8], path: &Path) -> Result<String, Error> {
    let utf16 = |be: bool| -> Result<String, Error> {
        let body = &bytes[2..];
        if !body.len().is_multiple_of(2) {
            return Err(Error::InvalidMesh {
                path: path.to_owned(),
                message: "UTF-16 text (byte-order mark) with an odd number of bytes".into(),
            });
        }
        let units: Vec<u16> = body
            .chunks_exact(2)
            .map(|c| {
                if be {
                    u16::from_be_bytes([c[0], c[1]])
                } else {
                    u16::from_le_bytes([c[0], c[1]])
                }
            })
            .collect();
        Ok(String::from_utf16_lossy(&units))
    };
    match bytes {
        [0xFF, 0xFE, ..] => utf16(false),
        [0xFE, 0xFF, ..] => utf16(true),
        [0xEF, 0xBB, 0xBF, rest @ ..] => Ok(String::from_utf8_lossy(rest).into_owned()),
        _ => Ok(String::from_utf8_lossy(bytes).into_owned()),
    }
}

/// Splits on `\n`, `\r\n` and lone `\r`, keeping line numbers right (the
/// loader's lines; public with [`decode_text`]).
pub fn split_lines(text: &str) -> impl Iterator<Item = &str> {
    let mut rest = Some(text);
    std::iter::from_fn(move || {
        let s = rest?;
        match s.find(['\n', '\r']) {
            Some(i) => {
                let skip = if s[i..].starts_with("\r\n") { 2 } else { 1 };
                rest = Some(&s[i + skip..]);
                Some(&s[..i])
            }
            None => {
                rest = None;
                if s.is_empty() { None } else { Some(s) }
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_lines_handles_endings() {
        let v: Vec<&str> = split_lines("a\r\nb\rc\n\nd").collect();
        assert_eq!(v, ["a", "b", "c", "", "d"]);
    }
}
