//! TRX tractograms (tee-ar-ex/trx-spec): a zip archive (stored or deflated) holding
//! `header.json` (`VOXEL_TO_RASMM`, `DIMENSIONS`, `NB_STREAMLINES`, `NB_VERTICES`),
//! `positions.3.<dtype>` (float16, float32 or float64, little-endian, already RAS+
//! millimetres), `offsets.<dtype>` (uint32 or uint64: where each streamline starts) and
//! optional folders: `dpv/` (values per vertex, `NAME.<dtype>` or `NAME.<width>.<dtype>`),
//! read as [`PointValues`]; `dps/`, `dpg/` and `groups/`, not read yet.
//!
//! `offsets` holds `NB_STREAMLINES + 1` entries, the last `NB_VERTICES` (trx-python's
//! files since 0.3), or `NB_STREAMLINES` (the specification's first writers); anything
//! else disagrees with the header and is refused, as are unknown dtypes, an entry whose
//! size is not the one the header implies, offsets that decrease or run past the
//! vertices, and positions that are not finite. Each error names the entry.
use std::io::Read;
use std::path::Path;

use serde::Deserialize;

use super::{PointValues, Tractogram, f16_to_f32};
use crate::io::input_limit::{MAX_INPUT_BYTES_VARIABLE, max_input_bytes};
use glyphcast::{Error, Result};

/// The keys of `header.json` the reader uses.
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub struct TrxHeader {
    /// The reference image's voxel-to-RAS+ affine (positions are already RAS+ mm).
    #[serde(rename = "VOXEL_TO_RASMM")]
    pub voxel_to_rasmm: [[f64; 4]; 4],
    /// The reference image's grid.
    #[serde(rename = "DIMENSIONS")]
    pub dimensions: [u64; 3],
    /// Streamlines in the file.
    #[serde(rename = "NB_STREAMLINES")]
    pub nb_streamlines: u64,
    /// Points in the file, all streamlines together.
    #[serde(rename = "NB_VERTICES")]
    pub nb_vertices: u64,
}

/// A stored number type, named as TRX names it in file endings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Dtype {
    Float(usize),
    Int(usize),
    Uint(usize),
}

impl Dtype {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "float16" => Dtype::Float(2),
            "float32" => Dtype::Float(4),
            "float64" => Dtype::Float(8),
            "int8" => Dtype::Int(1),
            "int16" => Dtype::Int(2),
            "int32" => Dtype::Int(4),
            "int64" => Dtype::Int(8),
            "uint8" => Dtype::Uint(1),
            "uint16" => Dtype::Uint(2),
            "uint32" => Dtype::Uint(4),
            "uint64" => Dtype::Uint(8),
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Dtype::Float(size) | Dtype::Int(size) | Dtype::Uint(size) => size,
        }
    }

    /// One little-endian value as f64 (exact for every type but 64-bit integers beyond
    /// 2^53, which no offset or vertex value reaches).
    fn value(self, bytes: &[u8]) -> f64 {
        let mut word = [0u8; 8];
        word[..bytes.len()].copy_from_slice(bytes);
        let unsigned = u64::from_le_bytes(word);
        match self {
            Dtype::Float(2) => f64::from(f16_to_f32(unsigned as u16)),
            Dtype::Float(4) => f64::from(f32::from_bits(unsigned as u32)),
            Dtype::Float(_) => f64::from_bits(unsigned),
            Dtype::Uint(_) => unsigned as f64,
            Dtype::Int(size) => {
                // Sign-extend from `size` bytes.
                let shift = 64 - 8 * size as u32;
                ((unsigned << shift) as i64 >> shift) as f64
            }
        }
    }
}

/// One array of the archive, by its name's parts: `NAME[.WIDTH].DTYPE`.
struct ArrayName<'a> {
    base: &'a str,
    width: usize,
    dtype: Dtype,
}

fn array_name<'a>(entry: &'a str, file: &str) -> Result<ArrayName<'a>> {
    let refuse = |what: &str| {
        Error::input(
            file,
            entry,
            format!(
                "{what}: expected NAME.DTYPE or NAME.WIDTH.DTYPE, DTYPE one of float16, float32, float64, (u)int8 to (u)int64"
            ),
        )
    };
    let (stem, ending) = entry
        .rsplit_once('.')
        .ok_or_else(|| refuse("no dtype in the name"))?;
    let dtype = Dtype::parse(ending).ok_or_else(|| refuse(&format!("unknown dtype '{ending}'")))?;
    let (base, width) = match stem.rsplit_once('.') {
        Some((base, width)) => match width.parse::<usize>() {
            Ok(width) if width > 0 => (base, width),
            _ => return Err(refuse(&format!("'{width}' is not a width"))),
        },
        None => (stem, 1),
    };
    Ok(ArrayName { base, width, dtype })
}

/// Reads a TRX file (a zip archive).
pub fn read_trx(path: &Path) -> Result<Tractogram> {
    let file = path.display().to_string();
    let opened = std::fs::File::open(path).map_err(|err| Error::io(path, err))?;
    let mut archive = zip::ZipArchive::new(opened)
        .map_err(|err| Error::input(&file, "zip", format!("not a readable zip archive: {err}")))?;
    let names = archive
        .file_names()
        .map(|name| name.map(|name| name.into_owned()))
        .collect::<std::result::Result<Vec<String>, _>>()
        .map_err(|err| Error::input(&file, "zip", format!("an entry's name: {err}")))?;
    let header_bytes = read_entry(&mut archive, "header.json", None, &file)?;
    let header: TrxHeader = serde_json::from_slice(&header_bytes)
        .map_err(|err| Error::input(&file, "header.json", err.to_string()))?;
    if header.nb_streamlines == 0 {
        return Ok(Tractogram::default());
    }
    let limit = max_input_bytes()?;
    if header.nb_vertices.saturating_mul(12) > limit {
        return Err(Error::input(
            &file,
            "NB_VERTICES",
            format!(
                "{} points would take more memory than the input limit of {limit} bytes \
                 ({MAX_INPUT_BYTES_VARIABLE})",
                header.nb_vertices
            ),
        ));
    }
    let top_level = |prefix: &str| names.iter().find(|name| name.starts_with(prefix)).cloned();
    let missing = |what: &str| {
        Error::input(
            &file,
            what,
            format!("the archive has no {what}.* entry (a TRX file needs one)"),
        )
    };
    let positions_name = top_level("positions.").ok_or_else(|| missing("positions"))?;
    let offsets_name = top_level("offsets.").ok_or_else(|| missing("offsets"))?;
    let points = read_positions(&mut archive, &positions_name, &header, &file)?;
    let offsets = read_offsets(&mut archive, &offsets_name, &header, &file)?;
    let mut point_values = Vec::new();
    for name in names
        .iter()
        .filter(|name| name.starts_with("dpv/") && !name.ends_with('/'))
    {
        point_values.push(read_point_values(&mut archive, name, &header, &file)?);
    }
    Ok(Tractogram {
        points,
        offsets,
        point_values,
    })
}

type Archive = zip::ZipArchive<std::fs::File>;

/// The bytes of `entry`; when `expected` is given, its size must be that (checked on
/// the declared size before anything is read or inflated).
fn read_entry(
    archive: &mut Archive,
    entry: &str,
    expected: Option<u64>,
    file: &str,
) -> Result<Vec<u8>> {
    let mut opened = archive.by_name(entry).map_err(|err| {
        Error::input(file, entry, format!("not readable from the archive: {err}"))
    })?;
    if let Some(expected) = expected
        && opened.size() != expected
    {
        return Err(Error::input(
            file,
            entry,
            format!(
                "{} bytes, but the header's NB_STREAMLINES and NB_VERTICES make it {expected}",
                opened.size()
            ),
        ));
    }
    let mut bytes = Vec::new();
    opened
        .by_ref()
        .take(expected.unwrap_or(1 << 20))
        .read_to_end(&mut bytes)
        .map_err(|err| Error::input(file, entry, format!("not readable: {err}")))?;
    Ok(bytes)
}

fn read_positions(
    archive: &mut Archive,
    entry: &str,
    header: &TrxHeader,
    file: &str,
) -> Result<Vec<[f32; 3]>> {
    let name = array_name(entry, file)?;
    if name.width != 3 || !matches!(name.dtype, Dtype::Float(_)) {
        return Err(Error::input(
            file,
            entry,
            "positions are stored as positions.3.float16, positions.3.float32 or \
             positions.3.float64",
        ));
    }
    let size = name.dtype.size() as u64;
    let bytes = read_entry(archive, entry, Some(header.nb_vertices * 3 * size), file)?;
    let mut points = Vec::with_capacity(header.nb_vertices as usize);
    for (index, point) in bytes.chunks_exact(3 * size as usize).enumerate() {
        let xyz: Vec<f64> = point
            .chunks_exact(size as usize)
            .map(|value| name.dtype.value(value))
            .collect();
        if xyz.iter().any(|v| !v.is_finite()) {
            return Err(Error::input(
                file,
                entry,
                format!("vertex {index} is {xyz:?}: every coordinate must be finite"),
            ));
        }
        points.push([xyz[0] as f32, xyz[1] as f32, xyz[2] as f32]);
    }
    Ok(points)
}

fn read_offsets(
    archive: &mut Archive,
    entry: &str,
    header: &TrxHeader,
    file: &str,
) -> Result<Vec<u64>> {
    let name = array_name(entry, file)?;
    if name.width != 1 || !matches!(name.dtype, Dtype::Uint(4 | 8)) {
        return Err(Error::input(
            file,
            entry,
            "offsets are stored as offsets.uint32 or offsets.uint64",
        ));
    }
    let size = name.dtype.size() as u64;
    let declared = archive
        .by_name(entry)
        .map(|opened| opened.size())
        .unwrap_or_default();
    // With or without the closing entry (NB_VERTICES); see the module's note.
    let count = if declared == (header.nb_streamlines + 1) * size {
        header.nb_streamlines + 1
    } else {
        header.nb_streamlines
    };
    let bytes = read_entry(archive, entry, Some(count * size), file)?;
    let mut offsets: Vec<u64> = bytes
        .chunks_exact(size as usize)
        .map(|value| name.dtype.value(value) as u64)
        .collect();
    if count > header.nb_streamlines && offsets.pop() != Some(header.nb_vertices) {
        return Err(Error::input(
            file,
            entry,
            format!(
                "the last offset is not NB_VERTICES ({}), where the points end",
                header.nb_vertices
            ),
        ));
    }
    let in_order = offsets.first() == Some(&0)
        && offsets.windows(2).all(|pair| pair[0] <= pair[1])
        && offsets
            .last()
            .is_some_and(|&last| last <= header.nb_vertices);
    if !in_order {
        return Err(Error::input(
            file,
            entry,
            format!(
                "offsets must start at 0, never decrease and stay within NB_VERTICES ({})",
                header.nb_vertices
            ),
        ));
    }
    Ok(offsets)
}

fn read_point_values(
    archive: &mut Archive,
    entry: &str,
    header: &TrxHeader,
    file: &str,
) -> Result<PointValues> {
    let stem = entry.trim_start_matches("dpv/");
    let name = array_name(stem, file).map_err(|_| {
        Error::input(
            file,
            entry,
            "expected dpv/NAME.DTYPE or dpv/NAME.WIDTH.DTYPE with a known dtype",
        )
    })?;
    let size = name.dtype.size() as u64;
    let expected = header.nb_vertices * name.width as u64 * size;
    let bytes = read_entry(archive, entry, Some(expected), file)?;
    let values = bytes
        .chunks_exact(size as usize)
        .map(|value| name.dtype.value(value) as f32)
        .collect();
    Ok(PointValues {
        name: name.base.to_string(),
        width: name.width,
        values,
    })
}
