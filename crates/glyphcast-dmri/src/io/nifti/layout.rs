//! What a header says about its voxels, checked before any is read: the shape (dim),
//! the type (datatype, bitpix), the scaling (scl_slope, scl_inter) and where the data
//! starts (vox_offset). Sizes are computed with overflow checks, and every message shows
//! the header's own numbers.
use super::datatype::{name, voxel_type};
use super::header::{EXTENSION_FLAG_SIZE, NiftiHeader};
use crate::io::datatype::DataType;
use glyphcast::{Error, Result};

/// Where and how the voxels are stored.
#[derive(Clone, Debug, PartialEq)]
pub struct DataLayout {
    /// `dim[1..=dim[0]]`.
    pub shape: Vec<usize>,
    /// The product of `shape`.
    pub count: usize,
    /// The stored number type and byte order (from `datatype`, `bitpix` and the header's order).
    pub datatype: DataType,
    /// `count` voxels of `datatype`, in bytes.
    pub data_bytes: u64,
    /// Byte offset of the first voxel in the data file.
    pub offset: u64,
    /// (slope, inter) when the values are scaled.
    pub scaling: Option<(f64, f64)>,
}

impl DataLayout {
    /// Checks `header` and derives the layout; `pair` when the data lies in a separate
    /// `.img` (where vox_offset may be 0). Errors name `file` and the field.
    pub fn of(header: &NiftiHeader, pair: bool, file: &str) -> Result<Self> {
        let shape = shape(header, file)?;
        let datatype = voxel_type(header.datatype, header.bitpix, header.big_endian, file)?;
        let too_big = || {
            Error::input(
                file,
                "dim",
                format!(
                    "{} voxels of {} are too many to address",
                    shape_text(&shape),
                    name(datatype)
                ),
            )
        };
        let count = shape
            .iter()
            .try_fold(1usize, |n, &d| n.checked_mul(d))
            .ok_or_else(too_big)?;
        let data_bytes = u64::try_from(count)
            .ok()
            .and_then(|n| n.checked_mul(datatype.width() as u64))
            .ok_or_else(too_big)?;
        Ok(Self {
            shape,
            count,
            datatype,
            data_bytes,
            offset: offset(header, pair, file)?,
            scaling: scaling(header, file)?,
        })
    }

    /// Bytes from the start of the data file to the end of the last voxel.
    pub fn end(&self) -> u64 {
        self.offset.saturating_add(self.data_bytes)
    }

    /// `2x3x4x45 float32`, for messages.
    pub fn describe(&self) -> String {
        format!("{} {}", shape_text(&self.shape), name(self.datatype))
    }
}

/// dim[1..=dim[0]], with dim[0] in 1..=7 and every used length at least 1.
fn shape(header: &NiftiHeader, file: &str) -> Result<Vec<usize>> {
    let dim = header.dim;
    let shown = format!("dim = {dim:?}");
    let rank = dim[0];
    if !(1..=7).contains(&rank) {
        return Err(Error::input(
            file,
            "dim",
            format!("dim[0] = {rank} is not a number of dimensions from 1 to 7 ({shown})"),
        ));
    }
    let mut shape = Vec::with_capacity(rank as usize);
    for (axis, &length) in dim.iter().enumerate().take(rank as usize + 1).skip(1) {
        let length = usize::try_from(length).ok().filter(|&n| n >= 1);
        let Some(length) = length else {
            return Err(Error::input(
                file,
                "dim",
                format!(
                    "dim[{axis}] = {} but each of dim[1..={rank}] must be at least 1 ({shown})",
                    dim[axis]
                ),
            ));
        };
        shape.push(length);
    }
    Ok(shape)
}

/// vox_offset as a byte position: whole, not negative, and for a single file past the
/// header and its extension flag.
fn offset(header: &NiftiHeader, pair: bool, file: &str) -> Result<u64> {
    let value = header.vox_offset;
    let minimum = if pair {
        0
    } else {
        header.version.header_size() + EXTENSION_FLAG_SIZE
    };
    let whole = value.is_finite() && value.fract() == 0.0 && value >= 0.0 && value < 2f64.powi(63);
    if !whole || value < minimum as f64 {
        let place = if pair {
            "a byte position in the .img".to_string()
        } else {
            format!("at least {minimum} (the header and its 4 extension bytes come first)")
        };
        return Err(Error::input(
            file,
            "vox_offset",
            format!("{value} is not a valid data offset: expected a whole number, {place}"),
        ));
    }
    Ok(value as u64)
}

/// nifti1.h: values are scaled by y = scl_slope x + scl_inter unless scl_slope is 0.
/// A slope of exactly 1 with no intercept is no scaling either.
fn scaling(header: &NiftiHeader, file: &str) -> Result<Option<(f64, f64)>> {
    let (slope, inter) = (header.scl_slope, header.scl_inter);
    if slope == 0.0 {
        return Ok(None);
    }
    for (field, value) in [("scl_slope", slope), ("scl_inter", inter)] {
        if !value.is_finite() {
            return Err(Error::input(
                file,
                field,
                format!(
                    "{value}: the scaling of the stored values must be finite (scl_slope \
                     {slope}, scl_inter {inter})"
                ),
            ));
        }
    }
    Ok((slope != 1.0 || inter != 0.0).then_some((slope, inter)))
}

/// `10x10x10x65`.
pub fn shape_text(shape: &[usize]) -> String {
    shape
        .iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join("x")
}
