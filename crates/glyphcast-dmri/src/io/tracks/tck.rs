//! MRtrix `.tck` tractograms, as MRtrix3 writes them ("Tracks file format (.tck)" in its
//! documentation): a text header (`mrtrix tracks`, then `key: value` lines up to `END`),
//! then from the byte `file: . OFFSET` names, point triplets in scanner millimetres of
//! the `datatype` given (`Float32LE`, `Float32BE`, `Float64LE`, `Float64BE`; no suffix
//! means this machine's order, as in MRtrix). A triplet of NaNs ends each streamline and
//! a triplet of infinities ends the data.
//!
//! Stricter than nibabel where a file contradicts itself: `count`, when given, must be
//! the number of streamlines found; a point with some but not all coordinates NaN (or
//! infinite) is refused, not taken as a point or a delimiter; data that stops before
//! the infinity triplet is a truncated file. An empty streamline (two NaN triplets in a
//! row) is skipped, as nibabel skips it and MRtrix's writer never writes one.
use std::path::Path;

use super::{Tractogram, TractogramBuilder};
use crate::io::datatype::{DataType, Number};
use crate::io::mif::header::{KeyLines, key_value_lines};
use glyphcast::error::quoted;
use glyphcast::{Error, Result};

/// The first line of every `.tck` header.
pub const MAGIC: &str = "mrtrix tracks";

/// The keys of a `.tck` header that the reader uses.
#[derive(Clone, Debug, PartialEq)]
pub struct TckHeader {
    /// `datatype`: `Float32` or `Float64` and a byte order.
    pub datatype: DataType,
    /// `file: . OFFSET`: the byte where the first point starts.
    pub offset: u64,
    /// `count`: the number of streamlines the writer says it wrote, if given.
    pub count: Option<u64>,
    /// Every other key, in file order.
    pub other: Vec<(String, String)>,
    /// Bytes up to and including the `END` line.
    pub length: usize,
}

/// Reads an MRtrix `.tck` file.
pub fn read_tck(path: &Path) -> Result<Tractogram> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|err| Error::io(path, err))?;
    let header = TckHeader::parse(&bytes, &file)?;
    let data = usize::try_from(header.offset)
        .ok()
        .and_then(|start| bytes.get(start..))
        .unwrap_or(&[]);
    let (tractogram, found) = decode(data, header.datatype, header.offset, &file)?;
    if let Some(count) = header.count
        && count != found
    {
        return Err(Error::input(
            &file,
            "count",
            format!("{count} streamlines declared, but the data hold {found}"),
        ));
    }
    Ok(tractogram)
}

impl TckHeader {
    /// Parses the header at the start of `bytes` (binary data follow `END`).
    pub fn parse(bytes: &[u8], file: &str) -> Result<Self> {
        let (entries, length) = split_lines(bytes, file)?;
        let value = |key: &str| {
            entries
                .iter()
                .rev()
                .find(|(k, _)| k == key)
                .map(|(_, v)| v.as_str())
        };
        let datatype = parse_datatype(value("datatype"), file)?;
        let offset = parse_file(value("file"), length, file)?;
        let count = value("count")
            .map(|text| {
                text.parse::<u64>().map_err(|_| {
                    Error::input(
                        file,
                        "count",
                        format!("'{}' is not a number of streamlines", quoted(text)),
                    )
                })
            })
            .transpose()?;
        let other = entries
            .into_iter()
            .filter(|(key, _)| !matches!(key.as_str(), "datatype" | "file" | "count"))
            .collect();
        Ok(Self {
            datatype,
            offset,
            count,
            other,
            length,
        })
    }
}

/// The bytes of `tractogram` as an MRtrix `.tck` (`Float32LE`, the `count` given, the
/// data from the first 4-byte boundary after the header), as MRtrix3's writer lays a
/// file out: what [`read_tck`], nibabel and `mrview` read back point for point. Point
/// values are not written: a `.tck` holds only points.
pub fn encode_tck(tractogram: &Tractogram) -> Vec<u8> {
    let mut header = format!(
        "{MAGIC}\ncount: {}\ndatatype: Float32LE\nfile: . ",
        tractogram.len()
    );
    // The offset's own digits are part of the header it points past.
    let mut offset = header.len() + "\nEND\n".len();
    while offset < header.len() + offset.to_string().len() + "\nEND\n".len() {
        offset += 1;
    }
    let offset = offset.next_multiple_of(4);
    header.push_str(&format!("{offset}\nEND\n"));
    let mut bytes = header.into_bytes();
    bytes.resize(offset, 0);
    let triplets = tractogram.points.len() + tractogram.len() + 1;
    bytes.reserve(triplets * 12);
    let triplet = |bytes: &mut Vec<u8>, p: [f32; 3]| {
        for v in p {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    };
    for line in tractogram.streamlines() {
        for &p in line {
            triplet(&mut bytes, p);
        }
        triplet(&mut bytes, [f32::NAN; 3]);
    }
    triplet(&mut bytes, [f32::INFINITY; 3]);
    bytes
}

/// Writes `tractogram` to `path` as an MRtrix `.tck` ([`encode_tck`]), whole or not at
/// all (written beside it, then renamed).
pub fn write_tck(tractogram: &Tractogram, path: &Path) -> Result<()> {
    glyphcast::io::atomic::write_atomic(path, &encode_tck(tractogram))
}

/// The `key: value` lines (keys in lower case) and the header's length up to and
/// including `END`, read by MRtrix's rules as its images' headers are
/// ([`key_value_lines`]); a tractogram's header must end with `END`.
fn split_lines(bytes: &[u8], file: &str) -> Result<(KeyLines, usize)> {
    let (lines, length, ended) = key_value_lines(bytes, file, (MAGIC, "an MRtrix tractogram"))?;
    if !ended {
        return Err(Error::input(file, "END", "no 'END' line ends the header"));
    }
    Ok((lines, length))
}

fn parse_datatype(text: Option<&str>, file: &str) -> Result<DataType> {
    let text = text.ok_or_else(|| {
        Error::input(
            file,
            "datatype",
            "missing from the header (a required key: Float32LE, Float32BE, Float64LE or \
             Float64BE)",
        )
    })?;
    let refuse = || {
        Error::input(
            file,
            "datatype",
            format!(
                "'{}': track points are stored as Float32LE, Float32BE, Float64LE or \
                 Float64BE",
                quoted(text)
            ),
        )
    };
    let datatype = DataType::parse(text, file).map_err(|_| refuse())?;
    match datatype.number {
        Number::F32 | Number::F64 => Ok(datatype),
        _ => Err(refuse()),
    }
}

/// `. OFFSET`: the points follow the header in the same file.
fn parse_file(text: Option<&str>, header_length: usize, file: &str) -> Result<u64> {
    let text = text.ok_or_else(|| {
        Error::input(
            file,
            "file",
            "missing from the header (a required key: '. OFFSET')",
        )
    })?;
    let mut parts = text.split_whitespace();
    let offset = match (parts.next(), parts.next().map(str::parse::<u64>)) {
        (Some("."), Some(Ok(offset))) => offset,
        _ => {
            return Err(Error::input(
                file,
                "file",
                format!(
                    "'{}': expected '. OFFSET' (the points in this file from byte OFFSET)",
                    quoted(text)
                ),
            ));
        }
    };
    if offset < header_length as u64 {
        return Err(Error::input(
            file,
            "file",
            format!("offset {offset} points inside the header, which ends at byte {header_length}"),
        ));
    }
    Ok(offset)
}

/// The streamlines in `data` (which starts at byte `offset` of the file) and their count.
fn decode(data: &[u8], datatype: DataType, offset: u64, file: &str) -> Result<(Tractogram, u64)> {
    let size = if datatype.number == Number::F64 { 8 } else { 4 };
    let coordinate = |bytes: &[u8]| -> f64 {
        match (size, datatype.big_endian) {
            (4, false) => f64::from(f32::from_le_bytes(bytes.try_into().unwrap_or_default())),
            (4, true) => f64::from(f32::from_be_bytes(bytes.try_into().unwrap_or_default())),
            (_, false) => f64::from_le_bytes(bytes.try_into().unwrap_or_default()),
            (_, true) => f64::from_be_bytes(bytes.try_into().unwrap_or_default()),
        }
    };
    let mut builder = TractogramBuilder::default();
    let mut open = false;
    let mut count = 0u64;
    for (index, triplet) in data.chunks_exact(3 * size).enumerate() {
        let xyz: Vec<f64> = triplet.chunks_exact(size).map(coordinate).collect();
        let byte = offset + (index * 3 * size) as u64;
        if xyz.iter().all(|v| v.is_nan()) {
            open = false;
        } else if xyz.iter().all(|v| v.is_infinite()) {
            if open {
                return Err(Error::input(
                    file,
                    "data",
                    format!(
                        "streamline {count} has no NaN triplet before the end marker at \
                         byte {byte}"
                    ),
                ));
            }
            return Ok((builder.finish(), count));
        } else if xyz.iter().all(|v| v.is_finite()) {
            if !open {
                builder.start();
                open = true;
                count += 1;
            }
            builder.push([xyz[0] as f32, xyz[1] as f32, xyz[2] as f32], &[]);
        } else {
            return Err(Error::input(
                file,
                "data",
                format!(
                    "the triplet at byte {byte} is ({}, {}, {}): inside a streamline every \
                     coordinate must be finite (only a whole NaN triplet ends a streamline, \
                     only a whole infinite one the data)",
                    xyz[0], xyz[1], xyz[2]
                ),
            ));
        }
    }
    Err(Error::input(
        file,
        "data",
        format!(
            "truncated: no triplet of infinities ends the data ({count} streamlines in {} \
             bytes from offset {offset})",
            data.len()
        ),
    ))
}
