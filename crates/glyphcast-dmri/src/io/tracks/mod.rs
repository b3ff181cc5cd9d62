//! Tractograms (streamlines) read as their writers meant them, into one type in the
//! frame glyphcast draws in: scanner RAS+ millimetres, as the NIfTI and MRtrix image
//! readers place voxels.
//!
//! - MRtrix `.tck` ([`tck`]): points already in scanner millimetres.
//! - TrackVis `.trk` ([`trk`]): points in "voxel millimetres" from the corner of the
//!   first voxel, turned into RAS+ millimetres by the same affine nibabel builds
//!   (`get_affine_trackvis_to_rasmm`), voxel order and half-voxel shift included.
//! - TRX `.trx` ([`trx`]): a zip whose positions are already RAS+ millimetres.
//!
//! [`read_tractogram`] picks the reader by the file's ending. Every reader checks what
//! its header declares against the data and refuses a file that disagrees with itself
//! with an error naming the file and the field, never a panic: a count that does not
//! match, a truncation, a point that is not finite.
//!
//! The streamlines are stored flat (all points, then where each streamline starts), as
//! TRX and nibabel's `ArraySequence` keep them, so that a GPU upload is one copy.
use std::path::Path;

use glyphcast::{Error, Result};

pub mod select;
pub mod tck;
pub mod trk;
mod trk_affine;
pub mod trx;

/// Streamlines in scanner RAS+ millimetres, stored flat.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tractogram {
    /// Every point of every streamline, streamline after streamline.
    pub points: Vec<[f32; 3]>,
    /// Where each streamline starts in `points`; the streamline ends where the next one
    /// starts (the last at the end of `points`). Non-decreasing, first entry 0.
    pub offsets: Vec<u64>,
    /// Values stored per point (TrackVis scalars, TRX `dpv/`), each with one entry (or
    /// `width` entries) per point.
    pub point_values: Vec<PointValues>,
}

/// One named quantity stored for every point.
#[derive(Clone, Debug, PartialEq)]
pub struct PointValues {
    /// The name the file gives it (`dpv/NAME.*`, a TrackVis scalar name).
    pub name: String,
    /// Values per point (1 for a scalar, 3 for a colour).
    pub width: usize,
    /// `width` values per point, point after point: `points.len() * width` in all.
    pub values: Vec<f32>,
}

/// The tractogram formats glyphcast reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TrackFormat {
    /// MRtrix `.tck`.
    Tck,
    /// TrackVis `.trk`.
    Trk,
    /// TRX `.trx` (a zip archive).
    Trx,
}

impl TrackFormat {
    /// The format of a file by its ending (any case), else None.
    pub fn of(path: &Path) -> Option<Self> {
        let ending = path.extension()?.to_string_lossy().to_ascii_lowercase();
        match ending.as_str() {
            "tck" => Some(TrackFormat::Tck),
            "trk" => Some(TrackFormat::Trk),
            "trx" => Some(TrackFormat::Trx),
            _ => None,
        }
    }
}

/// Reads the tractogram at `path` with the reader its ending names (`.tck`, `.trk`,
/// `.trx`); any other ending is refused naming the file.
pub fn read_tractogram(path: &Path) -> Result<Tractogram> {
    match TrackFormat::of(path) {
        Some(TrackFormat::Tck) => tck::read_tck(path),
        Some(TrackFormat::Trk) => trk::read_trk(path),
        Some(TrackFormat::Trx) => trx::read_trx(path),
        None => Err(Error::input(
            path.display().to_string(),
            "file name",
            "not a tractogram glyphcast reads: expected a name ending in .tck (MRtrix), \
             .trk (TrackVis) or .trx (TRX)",
        )),
    }
}

impl Tractogram {
    /// The number of streamlines.
    pub fn len(&self) -> usize {
        self.offsets.len()
    }

    /// Whether there are no streamlines.
    pub fn is_empty(&self) -> bool {
        self.offsets.is_empty()
    }

    /// The range of `points` that streamline `index` holds.
    pub fn range(&self, index: usize) -> std::ops::Range<usize> {
        let start = self.offsets[index] as usize;
        let end = self
            .offsets
            .get(index + 1)
            .map_or(self.points.len(), |&next| next as usize);
        start..end
    }

    /// The points of streamline `index`.
    pub fn streamline(&self, index: usize) -> &[[f32; 3]] {
        &self.points[self.range(index)]
    }

    /// Every streamline's points, in order.
    pub fn streamlines(&self) -> impl Iterator<Item = &[[f32; 3]]> {
        (0..self.len()).map(|index| self.streamline(index))
    }
}

/// Builds a [`Tractogram`] one streamline at a time (what the readers and the
/// selections share).
#[derive(Default)]
pub(crate) struct TractogramBuilder {
    tractogram: Tractogram,
}

impl TractogramBuilder {
    /// A builder whose points carry these quantities (names and widths; no values yet).
    pub(crate) fn with_point_values(names: impl IntoIterator<Item = (String, usize)>) -> Self {
        let point_values = names
            .into_iter()
            .map(|(name, width)| PointValues {
                name,
                width,
                values: Vec::new(),
            })
            .collect();
        Self {
            tractogram: Tractogram {
                point_values,
                ..Tractogram::default()
            },
        }
    }

    /// Starts a new streamline (its points follow with `push`).
    pub(crate) fn start(&mut self) {
        self.tractogram
            .offsets
            .push(self.tractogram.points.len() as u64);
    }

    /// Appends one point to the current streamline, with its values for each quantity
    /// in order (`values` holds the widths' sum).
    pub(crate) fn push(&mut self, point: [f32; 3], values: &[f32]) {
        self.tractogram.points.push(point);
        let mut rest = values;
        for quantity in &mut self.tractogram.point_values {
            let (mine, others) = rest.split_at(quantity.width);
            quantity.values.extend_from_slice(mine);
            rest = others;
        }
    }

    pub(crate) fn finish(self) -> Tractogram {
        self.tractogram
    }
}

/// Decodes IEEE 754 half precision (TRX `float16` positions) exactly into single.
pub(crate) fn f16_to_f32(bits: u16) -> f32 {
    let sign = u32::from(bits >> 15) << 31;
    let exponent = u32::from((bits >> 10) & 0x1f);
    let mantissa = u32::from(bits & 0x3ff);
    let magnitude = match (exponent, mantissa) {
        (0, 0) => 0,
        // Subnormal: mantissa * 2^-24, exact in f32.
        (0, _) => {
            let value = mantissa as f32 * 2f32.powi(-24);
            return if sign == 0 { value } else { -value };
        }
        (0x1f, 0) => 0xff << 23,
        (0x1f, _) => (0xff << 23) | (mantissa << 13),
        _ => ((exponent + 127 - 15) << 23) | (mantissa << 13),
    };
    f32::from_bits(sign | magnitude)
}

#[cfg(test)]
mod tests;
