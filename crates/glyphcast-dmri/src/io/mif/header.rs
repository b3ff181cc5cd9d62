//! The text header of an MRtrix image: the line `mrtrix image`, then `key: value` lines
//! up to a line `END` or the end of the file, read as MRtrix reads them (`split_lines`).
//! Keys are matched without regard to case; `transform`, `dw_scheme` and `file` may
//! repeat (one line each per row, volume or data file); keys glyphcast does not use are
//! kept in `other`.
use crate::io::datatype::DataType;
use glyphcast::error::quoted;
use glyphcast::{Error, Result};

/// The first line of every MRtrix image header.
pub const MAGIC: &str = "mrtrix image";

/// One axis of `layout`: its rank among the strides (0 = fastest) and its direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AxisLayout {
    /// Position among the strides: 0 is the axis that varies fastest in the file.
    pub rank: usize,
    /// `-`: increasing voxel index runs backwards through the file.
    pub reversed: bool,
}

/// Where the voxel values are: `.` (the header's own file) or a file beside the header.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DataFile {
    /// The data file's path, relative to the header's folder; `.` is the header's own file.
    pub name: String,
    /// Byte offset of the first voxel in that file.
    pub offset: u64,
}

/// A parsed and checked MRtrix header.
#[derive(Clone, Debug, PartialEq)]
pub struct MifHeader {
    /// `dim`: the length of each axis, in the header's axis order.
    pub dims: Vec<usize>,
    /// Voxel sizes, one per axis (non-spatial axes may be NaN).
    pub vox: Vec<f64>,
    /// `layout`: how each axis is stored, one entry per axis of `dims`.
    pub layout: Vec<AxisLayout>,
    /// `datatype`: the stored number type and byte order.
    pub datatype: DataType,
    /// The first three rows of the voxel-to-scanner transform (unit axes, mm), if given.
    pub transform: Option<[[f64; 4]; 3]>,
    /// Stored value v reads as offset + scale v.
    pub scaling: (f64, f64),
    /// `file`: where the voxel values are stored.
    pub file: DataFile,
    /// One row gx, gy, gz, b per volume, if given (directions in scanner coordinates).
    pub dw_scheme: Option<Vec<[f64; 4]>>,
    /// Every other key, in file order.
    pub other: Vec<(String, String)>,
    /// Bytes up to and including the `END` line.
    pub length: usize,
}

/// The raw lines, before the values are checked.
#[derive(Default)]
struct Entries {
    dim: Option<String>,
    vox: Option<String>,
    layout: Option<String>,
    datatype: Option<String>,
    scaling: Option<String>,
    transform: Vec<String>,
    files: Vec<String>,
    dw_scheme: Vec<String>,
    other: Vec<(String, String)>,
}

impl MifHeader {
    /// Parses the header at the start of `bytes` (binary data may follow `END`).
    pub fn parse(bytes: &[u8], file: &str) -> Result<Self> {
        let (entries, length) = split_lines(bytes, file)?;
        let dims = parse_dims(entries.dim.as_deref(), file)?;
        let vox = parse_vox(entries.vox.as_deref(), dims.len(), file)?;
        let layout = parse_layout(entries.layout.as_deref(), dims.len(), file)?;
        let datatype = match entries.datatype.as_deref() {
            Some(text) => DataType::parse(text, file)?,
            None => return Err(missing(file, "datatype")),
        };
        let transform = parse_transform(&entries.transform, file)?;
        let scaling = parse_scaling(entries.scaling.as_deref(), file)?;
        let data_file = parse_file(&entries.files, file)?;
        let dw_scheme = parse_dw_scheme(&entries.dw_scheme, file)?;
        Ok(Self {
            dims,
            vox,
            layout,
            datatype,
            transform,
            scaling,
            file: data_file,
            dw_scheme,
            other: entries.other,
            length,
        })
    }

    /// Voxels in the image.
    pub fn voxel_count(&self) -> Option<usize> {
        self.dims.iter().try_fold(1usize, |n, &d| n.checked_mul(d))
    }
}

fn missing(file: &str, key: &str) -> Error {
    Error::input(file, key, "missing from the header (a required key)")
}

/// The key lines up to `END`, and the header's length in bytes, read by MRtrix's rules
/// (`File::KeyValue`, documented with the format): the first line starts with `mrtrix
/// image`; text from `#` on is a comment; a line that is empty, has no colon, or has no
/// key or no value is skipped; `END` or the end of the file ends the header (a `.mih`
/// often has no `END`); a required key given twice takes its last value. Bytes that are
/// not text before an `END` are binary data the header forgot to end before: refused.
fn split_lines(bytes: &[u8], file: &str) -> Result<(Entries, usize)> {
    let (lines, length, _) = key_value_lines(bytes, file, (MAGIC, "an MRtrix image"))?;
    let mut entries = Entries::default();
    for (key, value) in lines {
        match key.as_str() {
            "dim" => entries.dim = Some(value),
            "vox" => entries.vox = Some(value),
            "layout" => entries.layout = Some(value),
            "datatype" => entries.datatype = Some(value),
            "scaling" => entries.scaling = Some(value),
            "transform" => entries.transform.push(value),
            "file" => entries.files.push(value),
            "dw_scheme" => entries.dw_scheme.push(value),
            _ => entries.other.push((key, value)),
        }
    }
    Ok((entries, length))
}

/// `key: value` lines, keys in lower case, in order.
pub(crate) type KeyLines = Vec<(String, String)>;

/// The `key: value` lines of an MRtrix header (keys in lower case, in order) by MRtrix's
/// rules ([`split_lines`]), whose first line starts with `magic` (`what` names such a
/// file in an error); the header's length in bytes up to and including `END` (the whole
/// file where it has none), and whether an `END` ended it. MRtrix images and
/// tractograms (`.tck`) share these rules.
pub(crate) fn key_value_lines(
    bytes: &[u8],
    file: &str,
    (magic, what): (&str, &str),
) -> Result<(KeyLines, usize, bool)> {
    let mut lines = Vec::new();
    let mut start = 0;
    let mut number = 0;
    while start < bytes.len() {
        let end = bytes[start..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(bytes.len(), |p| start + p);
        let raw = &bytes[start..end];
        let next = (end + 1).min(bytes.len());
        number += 1;
        let not_mrtrix = || {
            Error::input(
                file,
                "line 1",
                format!("not {what} (the first line does not start with '{magic}')"),
            )
        };
        let line = match std::str::from_utf8(raw) {
            Ok(line) => line,
            Err(_) if number == 1 => return Err(not_mrtrix()),
            Err(_) => {
                return Err(Error::input(
                    file,
                    "END",
                    format!("no 'END' line before the binary data at line {number}"),
                ));
            }
        };
        start = next;
        if number == 1 {
            if !line.starts_with(magic) {
                return Err(not_mrtrix());
            }
            continue;
        }
        let line = line.split('#').next().unwrap_or_default().trim();
        if line == "END" {
            return Ok((lines, next, true));
        }
        let Some((key, value)) = line.split_once(':') else {
            continue;
        };
        let (key, value) = (key.trim().to_ascii_lowercase(), value.trim().to_string());
        if key.is_empty() || value.is_empty() {
            continue;
        }
        lines.push((key, value));
    }
    if number == 0 {
        return Err(Error::input(
            file,
            "line 1",
            format!("empty file, not {what}"),
        ));
    }
    Ok((lines, bytes.len(), false))
}

/// Comma-separated numbers of `key`.
fn numbers(text: &str, key: &str, file: &str) -> Result<Vec<f64>> {
    text.split(',')
        .map(|token| {
            let token = token.trim();
            token.parse::<f64>().map_err(|_| {
                Error::input(file, key, format!("'{}' is not a number", quoted(token)))
            })
        })
        .collect()
}

fn parse_dims(text: Option<&str>, file: &str) -> Result<Vec<usize>> {
    let text = text.ok_or_else(|| missing(file, "dim"))?;
    let dims = text
        .split(',')
        .map(|token| match token.trim().parse::<usize>() {
            Ok(d) if d > 0 => Ok(d),
            _ => Err(Error::input(
                file,
                "dim",
                format!("'{}' is not a positive whole number", quoted(token.trim())),
            )),
        })
        .collect::<Result<Vec<_>>>()?;
    if dims.len() > 16 {
        return Err(Error::input(
            file,
            "dim",
            format!("{} axes; MRtrix images have at most 16", dims.len()),
        ));
    }
    Ok(dims)
}

fn parse_vox(text: Option<&str>, axes: usize, file: &str) -> Result<Vec<f64>> {
    let text = text.ok_or_else(|| missing(file, "vox"))?;
    let mut vox = numbers(text, "vox", file)?;
    // As MRtrix: sizes for the first three axes at least; the others' may be left out
    // (NaN here) and sizes beyond dim's axes are ignored.
    if vox.len() < axes.min(3) {
        return Err(Error::input(
            file,
            "vox",
            format!("{} voxel sizes for the {axes} axes of dim", vox.len()),
        ));
    }
    vox.resize(axes, f64::NAN);
    // Only the spatial sizes are used: the others (volumes) are often NaN.
    if let Some((axis, size)) = vox
        .iter()
        .take(3)
        .enumerate()
        .find(|(_, s)| !(s.is_finite() && **s > 0.0))
    {
        return Err(Error::input(
            file,
            "vox",
            format!("the voxel size of axis {axis} must be positive and finite, got {size}"),
        ));
    }
    Ok(vox)
}

fn parse_layout(text: Option<&str>, axes: usize, file: &str) -> Result<Vec<AxisLayout>> {
    let text = text.ok_or_else(|| missing(file, "layout"))?;
    let layout = text
        .split(',')
        .map(|token| {
            let token = token.trim();
            // The sign is read as a character: "-0" is axis rank 0, reversed.
            let (reversed, digits) = match token.as_bytes().first() {
                Some(b'-') => (true, &token[1..]),
                Some(b'+') => (false, &token[1..]),
                _ => (false, token),
            };
            digits
                .parse::<usize>()
                .map(|rank| AxisLayout { rank, reversed })
                .map_err(|_| {
                    Error::input(
                        file,
                        "layout",
                        format!(
                            "'{}' is not a signed axis rank such as +0 or -2",
                            quoted(token)
                        ),
                    )
                })
        })
        .collect::<Result<Vec<_>>>()?;
    if layout.len() != axes {
        return Err(Error::input(
            file,
            "layout",
            format!("{} entries for the {axes} axes of dim", layout.len()),
        ));
    }
    let mut seen = vec![false; axes];
    for entry in &layout {
        if entry.rank >= axes || std::mem::replace(&mut seen[entry.rank], true) {
            return Err(Error::input(
                file,
                "layout",
                format!(
                    "'{}' is not an order of the axes: the ranks must be 0 to {} once each",
                    quoted(text),
                    axes - 1
                ),
            ));
        }
    }
    Ok(layout)
}

fn parse_transform(lines: &[String], file: &str) -> Result<Option<[[f64; 4]; 3]>> {
    if lines.is_empty() {
        return Ok(None);
    }
    let mut values = Vec::new();
    for line in lines {
        values.extend(numbers(line, "transform", file)?);
    }
    // The format fills the first three rows from the first 12 numbers; a fourth row
    // (0, 0, 0, 1) may follow.
    if values.len() < 12 {
        return Err(Error::input(
            file,
            "transform",
            format!(
                "{} numbers; expected 3 rows of 4 (the voxel-to-scanner transform)",
                values.len()
            ),
        ));
    }
    if let Some(bad) = values[..12].iter().find(|v| !v.is_finite()) {
        return Err(Error::input(
            file,
            "transform",
            format!("{bad} is not a finite number"),
        ));
    }
    let mut rows = [[0.0; 4]; 3];
    for (r, row) in rows.iter_mut().enumerate() {
        row.copy_from_slice(&values[4 * r..4 * r + 4]);
    }
    Ok(Some(rows))
}

fn parse_scaling(text: Option<&str>, file: &str) -> Result<(f64, f64)> {
    let Some(text) = text else {
        return Ok((0.0, 1.0));
    };
    match numbers(text, "scaling", file)?[..] {
        [offset, scale] if offset.is_finite() && scale.is_finite() => Ok((offset, scale)),
        [offset, scale] => Err(Error::input(
            file,
            "scaling",
            format!("offset {offset} and scale {scale} must be finite"),
        )),
        ref other => Err(Error::input(
            file,
            "scaling",
            format!("{} numbers; expected offset,scale", other.len()),
        )),
    }
}

fn parse_file(lines: &[String], file: &str) -> Result<DataFile> {
    let line = match lines {
        [] => return Err(missing(file, "file")),
        [line] => line,
        _ => {
            return Err(Error::input(
                file,
                "file",
                format!(
                    "the data are split over {} files; only one data file is supported",
                    lines.len()
                ),
            ));
        }
    };
    // NAME [OFFSET]: the name may hold spaces, the offset is the last word.
    let (name, offset) = match line.rsplit_once(char::is_whitespace) {
        Some((name, last)) if last.chars().all(|c| c.is_ascii_digit()) => {
            let offset = last.parse::<u64>().map_err(|_| {
                Error::input(
                    file,
                    "file",
                    format!("offset '{}' is too large", quoted(last)),
                )
            })?;
            (name.trim(), offset)
        }
        _ => (line.as_str(), 0),
    };
    if name.is_empty() {
        return Err(Error::input(file, "file", "no data file name"));
    }
    if name == "." && offset == 0 {
        return Err(Error::input(
            file,
            "file",
            "'.' needs the byte offset of the data after the header ('. OFFSET')",
        ));
    }
    Ok(DataFile {
        name: name.to_string(),
        offset,
    })
}

fn parse_dw_scheme(lines: &[String], file: &str) -> Result<Option<Vec<[f64; 4]>>> {
    if lines.is_empty() {
        return Ok(None);
    }
    lines
        .iter()
        .enumerate()
        .map(
            |(volume, line)| match numbers(line, "dw_scheme", file)?[..] {
                [x, y, z, b] => Ok([x, y, z, b]),
                ref other => Err(Error::input(
                    file,
                    "dw_scheme",
                    format!(
                        "volume {volume}: {} numbers; expected gx,gy,gz,b",
                        other.len()
                    ),
                )),
            },
        )
        .collect::<Result<Vec<_>>>()
        .map(Some)
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "mrtrix image\r\nDim: 4,5,6\nvox: 1,2,3\nlayout: -0,+2,+1\n\
        datatype: UInt8\ntransform: 1,0,0,1\ntransform: 0,1,0,2\ntransform: 0,0,1,3\n\
        mrtrix_version: 3.0\nfile: my data.dat 12\nEND\nbinary";

    #[test]
    fn keys_layout_and_file_are_read() {
        let h = MifHeader::parse(HEADER.as_bytes(), "h.mih").unwrap();
        assert_eq!(h.dims, vec![4, 5, 6]);
        let layout = [(0, true), (2, false), (1, false)]
            .map(|(rank, reversed)| AxisLayout { rank, reversed });
        assert_eq!(h.layout, layout);
        assert_eq!(h.transform.unwrap()[2], [0.0, 0.0, 1.0, 3.0]);
        assert_eq!(
            h.file,
            DataFile {
                name: "my data.dat".into(),
                offset: 12
            }
        );
        assert_eq!(h.scaling, (0.0, 1.0));
        assert_eq!(h.other, vec![("mrtrix_version".into(), "3.0".into())]);
        assert_eq!(&HEADER.as_bytes()[h.length..], b"binary");
    }

    #[test]
    fn broken_headers_name_the_key() {
        let broken = |from: &str, to: &str| {
            let text = HEADER.replace(from, to);
            MifHeader::parse(text.as_bytes(), "h.mih")
                .unwrap_err()
                .to_string()
        };
        assert!(broken("Dim: 4,5,6\n", "").contains("dim: missing"));
        assert!(broken("layout: -0,+2,+1", "layout: 0,2,x").contains("layout"));
        assert!(broken("transform: 0,0,1,3\n", "").contains("transform: 8 numbers"));
        assert!(broken("file: my data.dat 12\n", "").contains("file: missing"));
        // A line without a colon is skipped, as MRtrix skips it: the key is then missing.
        assert!(broken("datatype: UInt8", "datatype UInt8").contains("datatype: missing"));
        assert!(broken("vox: 1,2,3", "vox: 1,2").contains("vox: 2 voxel sizes"));
        assert!(broken("mrtrix image", "nrrd image").contains("line 1"));
        // Binary data where the header has not ended.
        let mut binary = HEADER.replace("END\nbinary", "").into_bytes();
        binary.extend_from_slice(&[0xff, 0xfe, 0x00, 0x3f]);
        let err = MifHeader::parse(&binary, "h.mif").unwrap_err().to_string();
        assert!(err.contains("END: no 'END' line"), "{err}");
    }

    /// What MRtrix's key/value reader accepts, glyphcast reads alike.
    #[test]
    fn mrtrix_reader_rules() {
        let read = |text: &str| MifHeader::parse(text.as_bytes(), "h.mih").unwrap();
        // A header that ends with the file, without END (a hand-written .mih).
        let no_end = HEADER.replace("END\nbinary", "");
        let h = read(&no_end);
        assert_eq!(h.dims, vec![4, 5, 6]);
        assert_eq!(h.length, no_end.len());
        // Comments, a line without a colon, an empty value, a repeated key (the last
        // wins), more text on the first line.
        let edited = HEADER
            .replace(
                "mrtrix image\r\n",
                "mrtrix image (written by hand)\n# a note\n",
            )
            .replace(
                "vox: 1,2,3",
                "vox: 9,9,9\nvox: 1,2,3 # mm\nstray words\nempty:",
            )
            .replace("END", "  END  # done");
        let h = read(&edited);
        assert_eq!(h.vox, vec![1.0, 2.0, 3.0]);
        assert_eq!(h.other, vec![("mrtrix_version".into(), "3.0".into())]);
        assert_eq!(&edited.as_bytes()[h.length..], b"binary");
        // Voxel sizes for the three spatial axes suffice; more than dim has are ignored.
        let four_d = HEADER
            .replace("Dim: 4,5,6", "dim: 4,5,6,7")
            .replace("-0,+2,+1", "-0,+2,+1,+3");
        assert!(read(&four_d).vox[3].is_nan());
        assert_eq!(
            read(&HEADER.replace("vox: 1,2,3", "vox: 1,2,3,4"))
                .vox
                .len(),
            3
        );
    }
}
