//! NumPy `.npy` depth maps (format version 1.0): the magic `\x93NUMPY`, the version
//! bytes, a little-endian u16 header length, then an ASCII Python dict literal padded
//! with spaces and ended by `\n` so that the data starts at a multiple of 64 bytes,
//! then the raw values. We write only `<f4` in C order, exactly as `numpy.save` would,
//! and the reader accepts exactly that, so a test can never pass on a file NumPy would
//! read differently.
use std::path::Path;

use crate::error::quoted;
pub use crate::io::atomic::write_atomic;
use crate::{Error, Result};

const MAGIC: &[u8; 6] = b"\x93NUMPY";
/// Magic, two version bytes and the u16 header length.
const PREAMBLE_LEN: usize = MAGIC.len() + 2 + 2;
/// The format's alignment of the data start.
const ALIGNMENT: usize = 64;
const F32_DESCR: &str = "<f4";

/// Writes a depth map of `height` rows and `width` columns (row 0 at the top) as a
/// `.npy` file of shape (height, width), atomically.
pub fn write_depth_npy(path: &Path, width: u32, height: u32, depth: &[f32]) -> Result<()> {
    write_atomic(path, &encode_depth_npy(path, width, height, depth)?)
}

/// The `.npy` file [`write_depth_npy`] writes, as bytes (for a set of outputs written
/// together); `path` names it in errors.
pub fn encode_depth_npy(path: &Path, width: u32, height: u32, depth: &[f32]) -> Result<Vec<u8>> {
    let shape = [height as usize, width as usize];
    let expected = shape[0].checked_mul(shape[1]);
    if expected != Some(depth.len()) {
        return Err(Error::input(
            path.display().to_string(),
            "depth map",
            format!("{} values, expected {width} x {height}", depth.len()),
        ));
    }
    encode_f32(&shape, depth).ok_or_else(|| Error::OutOfMemory {
        what: "the encoded depth map",
        file: Some(path.display().to_string()),
        bytes: Some(4 * depth.len() as u64),
        settings: &[],
    })
}

/// Reads a `.npy` file of little-endian f32 values in C order, as written by
/// [`write_depth_npy`]; returns the shape and the values.
pub fn read_npy_f32(path: &Path) -> Result<(Vec<usize>, Vec<f32>)> {
    let bytes = std::fs::read(path).map_err(|err| Error::io(path, err))?;
    decode_f32(&bytes, &path.display().to_string())
}

/// The complete file: header and values.
/// The file's bytes; None when their buffer cannot be allocated.
fn encode_f32(shape: &[usize], values: &[f32]) -> Option<Vec<u8>> {
    let header = header_text(shape);
    let mut bytes = Vec::new();
    bytes
        .try_reserve_exact(PREAMBLE_LEN + header.len() + 4 * values.len())
        .ok()?;
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&[1, 0]);
    // header_text keeps PREAMBLE_LEN + len a multiple of 64 and far below u16::MAX for
    // any shape of a few dimensions.
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    for value in values {
        bytes.extend_from_slice(&value.to_le_bytes());
    }
    Some(bytes)
}

/// The dict literal as `numpy.save` writes it, padded with spaces and ended by `\n`.
fn header_text(shape: &[usize]) -> String {
    let dims: Vec<String> = shape.iter().map(usize::to_string).collect();
    // Python's tuple repr: a 1-tuple needs its trailing comma.
    let tuple = match dims.as_slice() {
        [single] => format!("({single},)"),
        _ => format!("({})", dims.join(", ")),
    };
    let mut text =
        format!("{{'descr': '{F32_DESCR}', 'fortran_order': False, 'shape': {tuple}, }}");
    let unpadded = PREAMBLE_LEN + text.len() + 1;
    let padding = (ALIGNMENT - unpadded % ALIGNMENT) % ALIGNMENT;
    text.extend(std::iter::repeat_n(' ', padding));
    text.push('\n');
    text
}

fn decode_f32(bytes: &[u8], file: &str) -> Result<(Vec<usize>, Vec<f32>)> {
    let header_error = |message: String| Error::input(file, "header", message);
    let text = header_slice(bytes).map_err(header_error)?;
    let shape = parse_header(text).map_err(header_error)?;
    let data = &bytes[PREAMBLE_LEN + text.len()..];
    let count = shape
        .iter()
        .try_fold(1usize, |acc, &dim| acc.checked_mul(dim))
        .and_then(|count| count.checked_mul(4))
        .ok_or_else(|| header_error(format!("shape {shape:?} is too large")))?;
    if data.len() != count {
        return Err(Error::input(
            file,
            "data",
            format!(
                "shape {shape:?} needs {count} bytes of float32 data, found {}",
                data.len()
            ),
        ));
    }
    let (chunks, _) = data.as_chunks::<4>();
    let values = chunks
        .iter()
        .map(|&chunk| f32::from_le_bytes(chunk))
        .collect();
    Ok((shape, values))
}

/// Checks the preamble and returns the header text (padding and `\n` included).
fn header_slice(bytes: &[u8]) -> std::result::Result<&str, String> {
    if bytes.len() < PREAMBLE_LEN || &bytes[..MAGIC.len()] != MAGIC {
        return Err("not a NumPy .npy file (missing \\x93NUMPY magic)".into());
    }
    let version = (bytes[6], bytes[7]);
    if version != (1, 0) {
        return Err(format!(
            "format version {}.{} is not supported; expected 1.0",
            version.0, version.1
        ));
    }
    let header_len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let end = PREAMBLE_LEN + header_len;
    if bytes.len() < end {
        return Err(format!(
            "header of {header_len} bytes runs past the end of the file"
        ));
    }
    if !end.is_multiple_of(ALIGNMENT) {
        return Err(format!(
            "data starts at byte {end}, not a multiple of {ALIGNMENT}"
        ));
    }
    let text = std::str::from_utf8(&bytes[PREAMBLE_LEN..end])
        .ok()
        .filter(|text| text.is_ascii())
        .ok_or("header is not ASCII")?;
    if !text.ends_with('\n') {
        return Err("header does not end with a newline".into());
    }
    Ok(text)
}

/// Parses the dict literal; accepts only `<f4` in C order and returns the shape.
fn parse_header(text: &str) -> std::result::Result<Vec<usize>, String> {
    let mut cursor = HeaderCursor { rest: text };
    let (mut descr, mut fortran_order, mut shape) = (None, None, None);
    cursor.expect_char('{')?;
    while !cursor.eat('}') {
        let key = cursor.quoted()?;
        cursor.expect_char(':')?;
        let duplicate = match key {
            "descr" => descr.replace(cursor.quoted()?).is_some(),
            "fortran_order" => fortran_order.replace(cursor.word()).is_some(),
            "shape" => shape.replace(cursor.tuple()?).is_some(),
            other => return Err(format!("unexpected key '{}'", quoted(other))),
        };
        if duplicate {
            return Err(format!("duplicate key '{}'", quoted(key)));
        }
        if !cursor.eat(',') {
            cursor.expect_char('}')?;
            break;
        }
    }
    let padding = cursor.rest.strip_suffix('\n').unwrap_or(cursor.rest);
    if !padding.trim_matches(' ').is_empty() {
        return Err("unexpected text after the header dict".into());
    }
    match (descr, fortran_order, shape) {
        (Some(F32_DESCR), Some("False"), Some(shape)) => Ok(shape),
        (Some(F32_DESCR), Some("False"), None) => Err("missing key 'shape'".into()),
        (Some(F32_DESCR), Some(order), _) => Err(format!(
            "fortran_order {} is not supported; expected False (C order)",
            quoted(order)
        )),
        (Some(F32_DESCR), None, _) => Err("missing key 'fortran_order'".into()),
        (Some(other), _, _) => Err(format!(
            "dtype '{}' is not supported; expected '{F32_DESCR}' (little-endian float32)",
            quoted(other)
        )),
        (None, _, _) => Err("missing key 'descr'".into()),
    }
}

/// A cursor over the subset of Python literal syntax that `.npy` headers use.
struct HeaderCursor<'h> {
    rest: &'h str,
}

impl<'h> HeaderCursor<'h> {
    fn skip_spaces(&mut self) {
        self.rest = self.rest.trim_start_matches(' ');
    }

    /// Consumes `token` (after spaces) if it comes next.
    fn eat(&mut self, token: char) -> bool {
        self.skip_spaces();
        match self.rest.strip_prefix(token) {
            Some(rest) => {
                self.rest = rest;
                true
            }
            None => false,
        }
    }

    fn expect_char(&mut self, token: char) -> std::result::Result<(), String> {
        if self.eat(token) {
            Ok(())
        } else {
            Err(format!(
                "expected '{token}' at \"{}\"",
                quoted(self.rest.trim_end())
            ))
        }
    }

    /// A string in single or double quotes, without escapes.
    fn quoted(&mut self) -> std::result::Result<&'h str, String> {
        self.skip_spaces();
        let quote = self
            .rest
            .chars()
            .next()
            .filter(|c| *c == '\'' || *c == '"')
            .ok_or_else(|| format!("expected a quoted string at \"{}\"", self.rest.trim_end()))?;
        let body = &self.rest[1..];
        let end = body
            .find(quote)
            .ok_or_else(|| "unterminated string".to_string())?;
        self.rest = &body[end + 1..];
        Ok(&body[..end])
    }

    /// A bare word such as `False`.
    fn word(&mut self) -> &'h str {
        self.skip_spaces();
        let end = self
            .rest
            .find(|c: char| !c.is_ascii_alphanumeric())
            .unwrap_or(self.rest.len());
        let (word, rest) = self.rest.split_at(end);
        self.rest = rest;
        word
    }

    /// A tuple of non-negative integers: `()`, `(3,)`, `(2, 3)`.
    fn tuple(&mut self) -> std::result::Result<Vec<usize>, String> {
        self.expect_char('(')?;
        let mut dims = Vec::new();
        while !self.eat(')') {
            let word = self.word();
            let dim = word.parse::<usize>().map_err(|_| {
                format!(
                    "shape entry '{}' is not a non-negative integer",
                    quoted(word)
                )
            })?;
            dims.push(dim);
            if !self.eat(',') {
                self.expect_char(')')?;
                break;
            }
        }
        Ok(dims)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::atomic::tests::scratch_dir;

    #[test]
    fn header_bytes_match_numpy_save() {
        let bytes = encode_f32(&[2, 3], &[0.0; 6]).unwrap();
        let dict = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }";
        // 10 preamble bytes + 59 + 58 spaces + '\n' = 128: the data starts at 2 x 64.
        let mut expected = b"\x93NUMPY\x01\x00\x76\x00".to_vec();
        expected.extend_from_slice(dict.as_bytes());
        expected.extend_from_slice(&[b' '; 58]);
        expected.push(b'\n');
        assert_eq!(dict.len(), 59);
        assert_eq!(&bytes[..128], expected.as_slice());
        assert_eq!(bytes.len(), 128 + 6 * 4);
    }

    #[test]
    fn header_of_other_ranks_is_aligned_and_parses_back() {
        for shape in [
            vec![],
            vec![7],
            vec![4, 5],
            vec![1, 2, 3],
            vec![123456, 654321],
        ] {
            let text = header_text(&shape);
            assert_eq!((PREAMBLE_LEN + text.len()) % ALIGNMENT, 0, "{text:?}");
            assert_eq!(parse_header(&text).unwrap(), shape);
        }
        assert!(header_text(&[7]).contains("'shape': (7,), }"));
        assert!(header_text(&[]).contains("'shape': (), }"));
    }

    #[test]
    fn depth_round_trip_keeps_nan_and_layout() {
        let dir = scratch_dir("npy-round-trip");
        let path = dir.join("depth.npy");
        let depth = [1.5, f32::NAN, -0.0, 3.25e-8, f32::INFINITY, 7.0];
        write_depth_npy(&path, 3, 2, &depth).unwrap();
        let (shape, values) = read_npy_f32(&path).unwrap();
        assert_eq!(shape, vec![2, 3]);
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&values), bits(&depth));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn wrong_length_is_refused_and_writes_nothing() {
        let dir = scratch_dir("npy-wrong-length");
        let path = dir.join("depth.npy");
        let err = write_depth_npy(&path, 3, 2, &[0.0; 5]).unwrap_err();
        assert!(matches!(err, Error::Input { .. }), "{err}");
        assert!(err.to_string().contains("depth.npy"), "{err}");
        assert!(!path.exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    fn decode_error(bytes: &[u8]) -> String {
        let err = decode_f32(bytes, "d.npy").unwrap_err();
        assert!(matches!(err, Error::Input { .. }), "{err}");
        let text = err.to_string();
        assert!(text.starts_with("d.npy: "), "{text}");
        text
    }

    fn with_header(dict: &str, data_bytes: usize) -> Vec<u8> {
        let mut text = dict.to_string();
        while !(PREAMBLE_LEN + text.len() + 1).is_multiple_of(ALIGNMENT) {
            text.push(' ');
        }
        text.push('\n');
        let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
        bytes.extend_from_slice(&(text.len() as u16).to_le_bytes());
        bytes.extend_from_slice(text.as_bytes());
        bytes.extend(std::iter::repeat_n(0u8, data_bytes));
        bytes
    }

    #[test]
    fn reader_validates_the_header_strictly() {
        let good = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }";
        assert!(decode_f32(&with_header(good, 24), "d.npy").is_ok());
        let cases = [
            (
                "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }",
                "'<f8'",
            ),
            (
                "{'descr': '>f4', 'fortran_order': False, 'shape': (2, 3), }",
                "'>f4'",
            ),
            (
                "{'descr': '<f4', 'fortran_order': True, 'shape': (2, 3), }",
                "fortran_order",
            ),
            (
                "{'descr': '<f4', 'fortran_order': False, }",
                "missing key 'shape'",
            ),
            (
                "{'descr': '<f4', 'fortran_order': False, 'shape': (2, x), }",
                "'x'",
            ),
            (
                "{'descr': '<f4', 'shape': (2, 3), 'extra': 1, }",
                "unexpected key",
            ),
            ("{'descr': '<f4', 'descr': '<f4', }", "duplicate key"),
            (
                "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), } x",
                "after",
            ),
        ];
        for (dict, expected) in cases {
            let text = decode_error(&with_header(dict, 24));
            assert!(text.contains("header") && text.contains(expected), "{text}");
        }
    }

    #[test]
    fn reader_validates_preamble_and_data_length() {
        let good = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }";
        assert!(decode_error(&with_header(good, 20)).contains("data"));
        assert!(decode_error(&with_header(good, 28)).contains("data"));
        assert!(decode_error(b"\x93NUMPX\x01\x00").contains("magic"));
        let mut version_two = with_header(good, 24);
        version_two[6] = 2;
        assert!(decode_error(&version_two).contains("version 2.0"));
        let mut truncated = with_header(good, 0);
        truncated.truncate(40);
        assert!(decode_error(&truncated).contains("past the end"));
    }
}
