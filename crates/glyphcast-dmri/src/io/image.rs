//! Volumes from any supported file format, chosen by the file name: MRtrix (`.mif`,
//! `.mif.gz`, `.mih`, see `io::mif`) or else NIfTI-1 or NIfTI-2 (`io::nifti`). Both give the voxel
//! values as f64 indexed by the file's voxel axes and the voxel-to-world affine, so every
//! consumer (`--sh`, `--tensor`, `--mask`, the DWI of `fit`) takes either.
//!
//! Written the same way, by [`write_image`], the one writer every output of this crate
//! and the command line goes through (`fit`, multi-tissue `fit`, `peaks`): the format
//! comes from the name (`.nii`, `.nii.gz`, `.mif`, `.mif.gz`; [`OutputFormat`]), the
//! values are float32 little-endian with the first axis fastest, and the file is written
//! atomically (`glyphcast::io::atomic`: a temporary beside it, renamed over it), so a
//! failed write leaves no partial file. Each format's conventions live here:
//! - NIfTI-1: the geometry (pixdim, qform and sform with their codes, units) and text of
//!   a reference header, the input's own where it was NIfTI, so a NIfTI output keeps the
//!   input's affine exactly as stored; otherwise a header built from the voxel-to-world
//!   map (sform code 1, scanner; qform unset; millimetres). The fields that describe the
//!   data (dim, datatype, scaling) are set, and intent and display range cleared. The
//!   description goes into `descrip` (79 ASCII bytes).
//! - MRtrix: `vox` and `transform` from the voxel-to-world map (unit columns, the offset),
//!   layout `+0,+1,...`, `datatype: Float32LE`, the description as `comments` lines (one
//!   per line of it) before any further keys.
use std::path::Path;

use ndarray::{ArrayD, ArrayViewD};

use crate::io::gzip::gzip;
use crate::io::mif::write::encode_mif;
use crate::io::mif::{MifHeader, MifKind, read_mif};
use crate::io::nifti::write::{nifti_header_for, nifti1_bytes};
use crate::io::nifti::{NiftiHeader, NiftiImage, VoxelToWorld, read_nifti};
use glyphcast::io::atomic::write_atomic;
use glyphcast::{Error, Result};

/// What the header said besides the geometry.
#[derive(Clone, Debug)]
pub enum ImageHeader {
    /// A NIfTI-1 or NIfTI-2 header.
    Nifti(Box<NiftiHeader>),
    /// An MRtrix header.
    Mrtrix(Box<MifHeader>),
}

/// One volume in memory.
#[derive(Clone, Debug)]
pub struct Image {
    /// The path as given, for messages.
    pub file: String,
    /// Voxel values, shape [x, y, z, t, ...].
    pub data: ArrayD<f64>,
    /// Voxel indices to world coordinates, whichever format the file is.
    pub voxel_to_world: VoxelToWorld,
    /// The format's own header, for the fields only it has (intent, `dw_scheme`, ...).
    pub header: ImageHeader,
}

/// Whether `path` names an MRtrix image (else it is read as NIfTI).
pub fn is_mrtrix(path: &Path) -> bool {
    MifKind::of(path).is_some()
}

/// Reads `path` as MRtrix or NIfTI, by its name.
pub fn read_image(path: &Path) -> Result<Image> {
    if is_mrtrix(path) {
        let image = read_mif(path)?;
        Ok(Image {
            file: image.file,
            data: image.data,
            voxel_to_world: image.voxel_to_world,
            header: ImageHeader::Mrtrix(Box::new(image.header)),
        })
    } else {
        let NiftiImage {
            file,
            header,
            data,
            voxel_to_world,
        } = read_nifti(path)?;
        Ok(Image {
            file,
            data,
            voxel_to_world,
            header: ImageHeader::Nifti(Box::new(header)),
        })
    }
}

/// The image formats [`write_image`] writes, by the name's ending.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    /// `.nii`: NIfTI-1, one file.
    Nifti,
    /// `.nii.gz`: the same, gzip-compressed.
    NiftiGz,
    /// `.mif` (any case): MRtrix, header and data in one file.
    Mif,
    /// `.mif.gz` (any case): the same, gzip-compressed.
    MifGz,
}

/// The endings of the files [`write_image`] writes, as a usage error lists them.
pub const OUTPUT_ENDINGS: [&str; 4] = [".nii", ".nii.gz", ".mif", ".mif.gz"];

impl OutputFormat {
    /// The format `path` names; a usage error ([`Error::OutputName`]) naming `option`
    /// (the front end's name for the output) and the path for any other name: `.mih`
    /// (whose data lies in a second file) and `.hdr`/`.img` pairs are read, not written.
    pub fn of(path: &Path, option: &'static str) -> Result<Self> {
        match MifKind::of(path) {
            Some(MifKind::Mif) => return Ok(Self::Mif),
            Some(MifKind::MifGz) => return Ok(Self::MifGz),
            _ => {}
        }
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        [(".nii.gz", Self::NiftiGz), (".nii", Self::Nifti)]
            .into_iter()
            .find(|(ending, _)| name.len() > ending.len() && name.ends_with(ending))
            .map(|(_, format)| format)
            .ok_or_else(|| Error::OutputName {
                option,
                path: path.display().to_string(),
                format: "NIfTI or MRtrix images".into(),
                endings: OUTPUT_ENDINGS.map(String::from).to_vec(),
            })
    }

    /// Whether the format is MRtrix's (`.mif`, `.mif.gz`).
    pub fn is_mrtrix(self) -> bool {
        matches!(self, Self::Mif | Self::MifGz)
    }

    /// Whether the file is gzip-compressed.
    pub fn is_gzip(self) -> bool {
        matches!(self, Self::NiftiGz | Self::MifGz)
    }
}

/// Checks, before any work is done, that `path` names a file [`write_image`] writes
/// (`.nii`, `.nii.gz`, `.mif`, `.mif.gz`); a usage error naming `option` otherwise.
pub fn check_output_path(path: &Path, option: &'static str) -> Result<()> {
    OutputFormat::of(path, option).map(|_| ())
}

/// What [`write_image`] writes (borrowed: a clone is cheap).
#[derive(Clone)]
pub struct ImageWrite<'a> {
    /// The values, any rank from 1 to 7, the first three axes spatial; written as float32.
    pub data: ArrayViewD<'a, f64>,
    /// Voxel indices to world coordinates: an MRtrix file's `vox` and `transform`, and a
    /// NIfTI file's sform where `nifti_reference` is `None`.
    pub voxel_to_world: &'a VoxelToWorld,
    /// The header whose geometry and text a NIfTI file keeps (the input's own, so its
    /// qform, sform and codes stay as they were); it must describe `voxel_to_world`.
    /// `None`: a header built from `voxel_to_world`. MRtrix files ignore it.
    pub nifti_reference: Option<&'a NiftiHeader>,
    /// The file's description: NIfTI `descrip` (cut to 79 ASCII bytes), MRtrix `comments`
    /// (a line each); read back by [`Image::description`]. Empty: none.
    pub description: &'a str,
    /// Further MRtrix header keys (`glyphcast_sh_basis`, ...), written after `comments`;
    /// NIfTI has no place for them. No key may hold a colon or a newline, no value a
    /// newline.
    pub mrtrix_keys: &'a [(&'a str, String)],
}

/// Writes `image` to `path` in the format its name gives ([`OutputFormat`]), atomically:
/// on any error no file is left at `path` (an earlier file there stays as it was).
/// Errors name the file: a name of no written format, a shape the format cannot hold, a
/// bad header key, a file system failure.
pub fn write_image(path: &Path, image: &ImageWrite) -> Result<()> {
    write_atomic(path, &image_bytes(path, image)?)
}

/// The bytes [`write_image`] writes to `path`, for a caller that writes several files as
/// one set (`glyphcast::io::atomic::write_all_atomic`: multi-tissue CSD's three images).
pub fn image_bytes(path: &Path, image: &ImageWrite) -> Result<Vec<u8>> {
    let format = OutputFormat::of(path, "output")?;
    let file = path.display().to_string();
    let bytes = if format.is_mrtrix() {
        mrtrix_bytes(image, &file)?
    } else {
        nifti_bytes(image, &file)?
    };
    if format.is_gzip() {
        gzip(bytes, &file)
    } else {
        Ok(bytes)
    }
}

/// An MRtrix file's bytes: the description as `comments` lines, then the further keys.
fn mrtrix_bytes(image: &ImageWrite, file: &str) -> Result<Vec<u8>> {
    let mut keys: Vec<(&str, String)> = image
        .description
        .lines()
        .filter(|line| !line.trim().is_empty())
        .map(|line| ("comments", line.to_string()))
        .collect();
    for (key, value) in image.mrtrix_keys {
        if key.is_empty() || key.contains([':', '\n']) || value.contains('\n') {
            return Err(Error::input(
                file,
                key.escape_debug().to_string(),
                "an MRtrix header key must be non-empty without a colon or newline, and its \
                 value without a newline",
            ));
        }
        keys.push((key, value.clone()));
    }
    encode_mif(image.data.view(), image.voxel_to_world, &keys)
}

/// A NIfTI-1 file's bytes (uncompressed), with the reference header's geometry.
fn nifti_bytes(image: &ImageWrite, file: &str) -> Result<Vec<u8>> {
    let mut header = match image.nifti_reference {
        Some(reference) => {
            check_same_geometry(reference, image.voxel_to_world, file)?;
            reference.clone()
        }
        None => nifti_header_for(image.voxel_to_world),
    };
    header.intent_code = 0;
    header.intent_name = [0; 16];
    (header.intent_p1, header.intent_p2, header.intent_p3) = (0.0, 0.0, 0.0);
    (header.cal_min, header.cal_max) = (0.0, 0.0);
    header.set_description(image.description);
    nifti1_bytes(&header, image.data.view(), false, file)
}

/// A reference header whose affine is not the voxel-to-world map the values were made
/// for would put them at the wrong place: refused, naming the file (a caller's mistake).
fn check_same_geometry(reference: &NiftiHeader, map: &VoxelToWorld, file: &str) -> Result<()> {
    let own = VoxelToWorld::from_header(reference, file)?
        .affine
        .to_cols_array();
    let given = map.affine.to_cols_array();
    let scale = given.iter().fold(1.0, |m: f64, v| m.max(v.abs()));
    let differs = own
        .iter()
        .zip(&given)
        .any(|(a, b)| (a - b).abs() > 1e-5 * scale);
    if differs {
        return Err(Error::input(
            file,
            "affine",
            "the reference NIfTI header's affine is not the image's voxel-to-world map",
        ));
    }
    Ok(())
}

impl Image {
    /// The shape with trailing dimensions of size 1 dropped down to `rank` entries, and a
    /// 1D or 2D image padded to 3 ([x, y] is [x, y, 1]).
    pub fn shape(&self, rank: usize) -> Vec<usize> {
        trimmed_shape(self.data.shape(), rank)
    }

    /// The free-text description the file carries: a NIfTI header's `descrip`, or an
    /// MRtrix header's `comments` lines joined by newlines. `None` when empty. glyphcast's
    /// `fit` records its model and SH basis here.
    pub fn description(&self) -> Option<String> {
        let text = match &self.header {
            ImageHeader::Nifti(header) => header.description(),
            ImageHeader::Mrtrix(header) => header
                .other
                .iter()
                .filter(|(key, _)| key == "comments")
                .map(|(_, value)| value.as_str())
                .collect::<Vec<_>>()
                .join("\n"),
        };
        let text = text.trim().to_string();
        (!text.is_empty()).then_some(text)
    }
}

/// `shape` with trailing 1s dropped down to `rank` entries and padded to 3 entries.
pub fn trimmed_shape(shape: &[usize], rank: usize) -> Vec<usize> {
    let mut shape = shape.to_vec();
    while shape.len() > rank && shape.last() == Some(&1) {
        shape.pop();
    }
    while shape.len() < 3 {
        shape.push(1);
    }
    shape
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn output_names_are_checked() {
        for good in [
            "out.nii",
            "out.nii.gz",
            "a.b.c.nii.gz",
            "out.mif",
            "out.mif.gz",
            "OUT.MIF",
        ] {
            assert!(check_output_path(Path::new(good), "-o").is_ok(), "{good}");
        }
        for bad in ["out.png", "out", ".nii", "out.nii.bak", "out.mih", ".mif"] {
            let err = check_output_path(Path::new(bad), "-o").unwrap_err();
            assert!(err.is_usage(), "{bad}: {err}");
            assert!(err.to_string().starts_with(&format!("-o {bad}: ")), "{err}");
        }
    }
}
