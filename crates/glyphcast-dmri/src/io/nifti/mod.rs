//! NIfTI input and output, our own: NIfTI-1 and NIfTI-2 in either byte order, as a single
//! `.nii` or `.nii.gz`, or as a `.hdr`/`.img` pair (either part may be gzipped). Voxels
//! are read as f64 with `scl_slope`/`scl_inter` applied ([`layout`]), with the
//! voxel-to-world affine ([`affine`]); [`write`](mod@write) writes NIfTI-1 float32.
//!
//! Reading is strict and bounded: the header is checked in full before any voxel is read
//! (every error names the file and the header field, with the header's numbers), the
//! declared size is compared with what the file can hold and with the input memory cap
//! (`io::input_limit`) before anything is allocated, the data is streamed into the one
//! f64 buffer the image keeps, and a gzip stream is read to its end so that its CRC-32 is
//! checked. Extensions are skipped: the data starts at `vox_offset`, always.
use std::path::{Path, PathBuf};

use ndarray::{ArrayD, IxDyn, ShapeBuilder};

use crate::io::input_limit::{check_input_size, try_vec};
use glyphcast::{Error, Result};

pub mod affine;
pub mod datatype;
pub mod header;
pub mod layout;
pub mod stream;
#[cfg(test)]
mod tests;
pub mod write;

pub use affine::{AffineSource, VoxelToWorld};
pub use header::{NiftiHeader, NiftiVersion};
use layout::DataLayout;
use stream::ByteStream;

/// Bytes decoded at a time.
const CHUNK_BYTES: usize = 1 << 16;

/// One NIfTI image in memory.
#[derive(Clone, Debug)]
pub struct NiftiImage {
    /// The path as given, for messages.
    pub file: String,
    /// The header as read, for copying its fields into outputs.
    pub header: NiftiHeader,
    /// Voxel values, shape [x, y, z, t, ...] (Fortran memory order, as the file stores it).
    pub data: ArrayD<f64>,
    /// Voxel indices to world coordinates (sform, else qform, else pixdim).
    pub voxel_to_world: VoxelToWorld,
}

impl NiftiImage {
    /// The shape with trailing dimensions of size 1 dropped down to `rank` entries, and a
    /// 1D or 2D image padded to 3 ([x, y] is [x, y, 1]).
    pub fn shape(&self, rank: usize) -> Vec<usize> {
        crate::io::image::trimmed_shape(self.data.shape(), rank)
    }
}

/// Reads `path`: a `.hdr` (or `.hdr.gz`) with the `.img` beside it, else a single file
/// (compressed if the name ends in `.gz`). An `.img` given alone is an error that asks
/// for its `.hdr`.
pub fn read_nifti(path: &Path) -> Result<NiftiImage> {
    let file = path.display().to_string();
    let lower = file.to_ascii_lowercase();
    if lower.ends_with(".img") || lower.ends_with(".img.gz") {
        return Err(Error::input(
            &file,
            "file",
            "an .img holds only the voxels of a .hdr/.img pair (NIfTI or Analyze): give its \
             .hdr instead",
        ));
    }
    if lower.ends_with(".hdr") || lower.ends_with(".hdr.gz") {
        let mut stream = ByteStream::open(path)?;
        let header = read_header(&mut stream, true)?;
        stream.finish()?;
        let data = ByteStream::open(&image_path(path)?)?;
        return read_data(file, header, true, data);
    }
    read_single(ByteStream::open(path)?)
}

/// Reads a single-file NIfTI image from memory; `name` is used in messages and its `.gz`
/// ending says whether `bytes` are compressed.
pub fn read_nifti_bytes(bytes: &[u8], name: &str) -> Result<NiftiImage> {
    read_single(ByteStream::from_bytes(bytes, name))
}

fn read_single(mut stream: ByteStream) -> Result<NiftiImage> {
    let header = read_header(&mut stream, false)?;
    read_data(stream.file.clone(), header, false, stream)
}

/// The `.img` (or `.img.gz`) beside a `.hdr` (or `.hdr.gz`), whichever exists.
fn image_path(header: &Path) -> Result<PathBuf> {
    let name = header.display().to_string();
    let stem_length = name
        .to_ascii_lowercase()
        .rfind(".hdr")
        .unwrap_or(name.len());
    let stem = &name[..stem_length];
    let upper = name[stem_length..].starts_with(".HDR");
    let candidates: Vec<PathBuf> = [".img", ".img.gz"]
        .iter()
        .map(|ending| {
            let ending = if upper {
                ending.to_ascii_uppercase()
            } else {
                ending.to_string()
            };
            PathBuf::from(format!("{stem}{ending}"))
        })
        .collect();
    candidates
        .iter()
        .find(|path| path.is_file())
        .cloned()
        .ok_or_else(|| {
            Error::input(
                name,
                "file",
                format!(
                    "the voxels of this .hdr belong in {} (or {}), which does not exist",
                    candidates[0].display(),
                    candidates[1].display()
                ),
            )
        })
}

/// Reads and parses the header at the start of `stream`, checking its magic.
fn read_header(stream: &mut ByteStream, pair: bool) -> Result<NiftiHeader> {
    let mut first = [0u8; 4];
    let got = stream.fill(&mut first)?;
    if got < first.len() {
        return Err(too_short(&stream.file, got as u64));
    }
    let (version, big_endian) = header::detect(first, &stream.file)?;
    let mut bytes = vec![0u8; version.header_size()];
    bytes[..4].copy_from_slice(&first);
    let got = stream.fill(&mut bytes[4..])?;
    if got + 4 < bytes.len() {
        return Err(too_short(&stream.file, got as u64 + 4));
    }
    let header = NiftiHeader::parse(&bytes, version, big_endian);
    header.check_magic(pair, &stream.file)?;
    Ok(header)
}

fn too_short(file: &str, length: u64) -> Error {
    Error::input(
        file,
        "sizeof_hdr",
        format!("not a NIfTI file: it ends after {length} bytes, within the header"),
    )
}

/// Checks what `header` (of `file`) declares against `stream` (the rest of the same
/// file, or the `.img` of a pair) and reads the voxels.
fn read_data(
    file: String,
    header: NiftiHeader,
    pair: bool,
    mut stream: ByteStream,
) -> Result<NiftiImage> {
    let layout = DataLayout::of(&header, pair, &file)?;
    check_room(&layout, &stream, &file)?;
    check_input_size(
        &file,
        (layout.count as u64).saturating_mul(8),
        &format!("{} voxels as float64", layout.describe()),
    )?;
    let voxel_to_world = VoxelToWorld::from_header(&header, &file)?;
    let reached = stream.skip_to(layout.offset)?;
    if reached < layout.offset {
        return Err(offset_beyond_end(&stream.file, layout.offset, reached));
    }
    let values = read_values(&mut stream, &layout)?;
    stream.finish()?;
    let data = ArrayD::from_shape_vec(IxDyn(&layout.shape).f(), values)
        .map_err(|err| Error::input(&file, "dim", err.to_string()))?;
    Ok(NiftiImage {
        file,
        header,
        data,
        voxel_to_world,
    })
}

/// Err when the data cannot fit in the stream: vox_offset past its end, or fewer bytes
/// after it than declared (exact for an uncompressed file, a bound for gzip).
fn check_room(layout: &DataLayout, stream: &ByteStream, file: &str) -> Result<()> {
    let capacity = stream.capacity();
    if layout.offset > capacity && stream.is_exact() {
        return Err(offset_beyond_end(&stream.file, layout.offset, capacity));
    }
    if layout.end() > capacity {
        let held = if stream.is_exact() {
            format!("only {} follow", capacity.saturating_sub(layout.offset))
        } else {
            format!("the compressed file cannot hold that many ({capacity} at most)")
        };
        return Err(Error::input(
            &stream.file,
            "data",
            format!(
                "truncated: the header of {file} declares {} voxels ({} bytes from byte {}), \
                 but {held}",
                layout.describe(),
                layout.data_bytes,
                layout.offset
            ),
        ));
    }
    Ok(())
}

fn offset_beyond_end(file: &str, offset: u64, length: u64) -> Error {
    Error::input(
        file,
        "vox_offset",
        format!("the data is said to start at byte {offset}, but the file ends at {length}"),
    )
}

/// The voxels as f64 (scaled), read in chunks into one buffer of the final size.
fn read_values(stream: &mut ByteStream, layout: &DataLayout) -> Result<Vec<f64>> {
    let mut values = try_vec(layout.count, &stream.file)?;
    let size = layout.datatype.width();
    let mut chunk = vec![0u8; CHUNK_BYTES - CHUNK_BYTES % size];
    let mut remaining = layout.data_bytes;
    while remaining > 0 {
        let want = remaining.min(chunk.len() as u64) as usize;
        let got = stream.fill(&mut chunk[..want])?;
        if got < want {
            let have = layout.data_bytes - remaining + got as u64;
            return Err(Error::input(
                &stream.file,
                "data",
                format!(
                    "truncated: {} voxels need {} bytes from byte {}, but the data ends \
                     after {have}",
                    layout.describe(),
                    layout.data_bytes,
                    layout.offset
                ),
            ));
        }
        layout.datatype.decode_into(&chunk[..want], &mut values);
        remaining -= want as u64;
    }
    if let Some((slope, inter)) = layout.scaling {
        values.iter_mut().for_each(|v| *v = *v * slope + inter);
    }
    Ok(values)
}
