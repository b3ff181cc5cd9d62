//! Writing a volume as a single-file MRtrix image (`.mif`, or gzip-compressed `.mif.gz`):
//! float32 little-endian, layout `+0,+1,...` (the first axis fastest, as NIfTI stores
//! it), the data after the header at an offset rounded up to 16 bytes. `vox` holds the
//! world length of each voxel axis and `transform` the affine's columns divided by those
//! lengths (unit axes, as MRtrix expects) with the affine's offset; axes past the third
//! get `vox` 1. The bytes are written atomically (`io::atomic`).
//!
//! This is the format's encoder; outputs go through `io::image::write_image`, which
//! chooses the format by the name and sets the keys glyphcast records.
use std::fmt::Write as _;
use std::path::Path;

use ndarray::{ArrayD, ArrayViewD};

use super::header::MAGIC;
use super::{DataType, MifKind};
use crate::io::gzip::gzip;
use crate::io::nifti::VoxelToWorld;
use glyphcast::io::atomic::write_atomic;
use glyphcast::{Error, Result};

/// Data start at a multiple of this many bytes.
const DATA_ALIGNMENT: usize = 16;

/// What to write: the values (any rank, the first three axes spatial), their geometry
/// and extra header keys (written as `key: value` lines, one per entry).
pub struct MifWrite<'a> {
    /// The values, written as `Float32LE` with the first axis fastest.
    pub data: &'a ArrayD<f64>,
    /// The voxel-to-world map, written as `vox` and `transform`.
    pub voxel_to_world: &'a VoxelToWorld,
    /// Extra `key: value` lines, written after `transform`; no key or value may hold a newline.
    pub keys: &'a [(&'a str, String)],
}

/// Writes `image` to `path`, compressed when the name ends in `.mif.gz`.
pub fn write_mif(path: &Path, image: &MifWrite) -> Result<()> {
    write_atomic(path, &mif_file_bytes(path, image)?)
}

/// The bytes [`write_mif`] writes to `path` (compressed for a `.mif.gz` name), for a
/// caller that writes several files as one set (`io::atomic::write_all_atomic`).
pub fn mif_file_bytes(path: &Path, image: &MifWrite) -> Result<Vec<u8>> {
    let bytes = mif_bytes(image)?;
    if MifKind::of(path) == Some(MifKind::MifGz) {
        gzip(bytes, &path.display().to_string())
    } else {
        Ok(bytes)
    }
}

/// The file's bytes: header, padding, float32 values.
pub fn mif_bytes(image: &MifWrite) -> Result<Vec<u8>> {
    encode_mif(image.data.view(), image.voxel_to_world, image.keys)
}

/// [`mif_bytes`] of a view: `data` with `voxel_to_world` and the `keys` lines.
pub(crate) fn encode_mif(
    data: ArrayViewD<'_, f64>,
    voxel_to_world: &VoxelToWorld,
    keys: &[(&str, String)],
) -> Result<Vec<u8>> {
    let shape = data.shape();
    for (key, value) in keys {
        if key.contains([':', '\n']) || value.contains('\n') {
            return Err(Error::Call {
                call: "mif_bytes",
                expected: "header keys without a colon or newline, values without a newline",
            });
        }
    }
    let mut text = format!("{MAGIC}\n");
    let join = |values: Vec<String>| values.join(",");
    let linear = voxel_to_world.linear();
    let sizes = voxel_to_world.voxel_sizes();
    let _ = writeln!(
        text,
        "dim: {}",
        join(shape.iter().map(usize::to_string).collect())
    );
    let vox = (0..shape.len())
        .map(|axis| {
            if axis < 3 {
                sizes[axis].to_string()
            } else {
                "1".to_string()
            }
        })
        .collect();
    let _ = writeln!(text, "vox: {}", join(vox));
    let layout = (0..shape.len()).map(|axis| format!("+{axis}")).collect();
    let _ = writeln!(text, "layout: {}", join(layout));
    let _ = writeln!(text, "datatype: {}", DataType::FLOAT32_LE.name());
    let offset = voxel_to_world.affine.w_axis;
    for row in 0..3 {
        let unit = |c: usize| linear.col(c)[row] / sizes[c];
        let values = vec![
            unit(0).to_string(),
            unit(1).to_string(),
            unit(2).to_string(),
            offset[row].to_string(),
        ];
        let _ = writeln!(text, "transform: {}", join(values));
    }
    for (key, value) in keys {
        let _ = writeln!(text, "{key}: {value}");
    }
    // The offset is part of the header whose length it gives: find the fixed point.
    let mut data_offset = 0;
    loop {
        let length = text.len() + format!("file: . {data_offset}\nEND\n").len();
        let aligned = length.div_ceil(DATA_ALIGNMENT) * DATA_ALIGNMENT;
        if aligned == data_offset {
            break;
        }
        data_offset = aligned;
    }
    let _ = write!(text, "file: . {data_offset}\nEND\n");
    let mut bytes = text.into_bytes();
    bytes.resize(data_offset, 0);
    bytes.reserve(4 * data.len());
    // Reversing the axes and iterating in logical order makes the first axis fastest.
    for &value in data.t().iter() {
        bytes.extend_from_slice(&(value as f32).to_le_bytes());
    }
    Ok(bytes)
}
