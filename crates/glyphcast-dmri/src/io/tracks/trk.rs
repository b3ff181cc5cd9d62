//! TrackVis `.trk` tractograms: a 1000-byte header, then per streamline its point
//! count (int32), its points (x, y, z and `n_scalars` values, float32 each) and
//! `n_properties` float32 values. Byte order is the one in which `hdr_size` reads 1000,
//! as nibabel decides it. Points are in "voxel millimetres" from the corner of the first
//! voxel; the `trk_affine` module turns them into RAS+ millimetres as nibabel does.
//!
//! Written here rather than taken from the `trk-io` crate: its reader unwraps on a
//! truncated file (a panic, where glyphcast owes an error naming the field), reads past
//! a disagreeing `n_count` without a word, and reports with `anyhow` strings, not
//! this crate's file-and-field errors; the format is a fixed header and one loop.
//!
//! Stricter than nibabel where a file contradicts itself: a non-zero `n_count` must be
//! the number of streamlines the data hold (nibabel stops after `n_count` and ignores
//! the rest), data ending inside a streamline is refused, and so is a point that is not
//! finite. `n_count` 0 means "not recorded": the streamlines run to the end of the file.
use std::path::Path;

use nalgebra::{Matrix4, Vector4};

use super::trk_affine::{TrackvisGeometry, trackvis_to_rasmm};
use super::{Tractogram, TractogramBuilder};
use glyphcast::{Error, Result};

/// The header's size, and the value of its `hdr_size` field.
pub const HEADER_SIZE: usize = 1000;

/// The fields of a TrackVis header that the reader uses.
#[derive(Clone, Debug, PartialEq)]
pub struct TrkHeader {
    /// `dim`: the voxel grid the streamlines were tracked in.
    pub dims: [i16; 3],
    /// `voxel_size` in millimetres.
    pub voxel_size: [f32; 3],
    /// `vox_to_ras` (row-major), None when not recorded (version 1, or a zero `[3][3]`).
    pub vox_to_ras: Option<[[f32; 4]; 4]>,
    /// `voxel_order` up to its first NUL (empty: not recorded, TrackVis's LPS).
    pub voxel_order: Vec<u8>,
    /// The per-point scalars: name and values per point, in file order.
    pub scalars: Vec<(String, usize)>,
    /// `n_scalars`: values after x, y, z in each point.
    pub n_scalars: usize,
    /// `n_properties`: values after each streamline's points.
    pub n_properties: usize,
    /// `n_count`: streamlines in the file; 0 when not recorded.
    pub n_count: usize,
    /// `version`: 1 or 2 (3 is read as 2, as nibabel does).
    pub version: i32,
    /// Most significant byte first.
    pub big_endian: bool,
}

/// Reads a TrackVis `.trk` file, its points in RAS+ millimetres.
pub fn read_trk(path: &Path) -> Result<Tractogram> {
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|err| Error::io(path, err))?;
    let header = TrkHeader::parse(&bytes, &file)?;
    let affine = trackvis_to_rasmm(
        &TrackvisGeometry {
            dims: header.dims,
            voxel_size: header.voxel_size,
            vox_to_ras: header.vox_to_ras,
            voxel_order: &header.voxel_order,
        },
        &file,
    )?;
    read_streamlines(&bytes[HEADER_SIZE..], &header, &affine, &file)
}

/// Reads numbers in the header's byte order.
struct Fields<'a> {
    bytes: &'a [u8],
    big_endian: bool,
}

impl Fields<'_> {
    fn word(&self, at: usize) -> [u8; 4] {
        let mut word = [0; 4];
        word.copy_from_slice(&self.bytes[at..at + 4]);
        word
    }

    fn i32(&self, at: usize) -> i32 {
        let word = self.word(at);
        if self.big_endian {
            i32::from_be_bytes(word)
        } else {
            i32::from_le_bytes(word)
        }
    }

    fn f32(&self, at: usize) -> f32 {
        let word = self.word(at);
        if self.big_endian {
            f32::from_be_bytes(word)
        } else {
            f32::from_le_bytes(word)
        }
    }

    fn i16(&self, at: usize) -> i16 {
        let pair = [self.bytes[at], self.bytes[at + 1]];
        if self.big_endian {
            i16::from_be_bytes(pair)
        } else {
            i16::from_le_bytes(pair)
        }
    }
}

impl TrkHeader {
    /// Parses and checks the header at the start of `bytes`.
    pub fn parse(bytes: &[u8], file: &str) -> Result<Self> {
        if bytes.len() < HEADER_SIZE {
            return Err(Error::input(
                file,
                "header",
                format!(
                    "truncated: a TrackVis header takes {HEADER_SIZE} bytes, the file has {}",
                    bytes.len()
                ),
            ));
        }
        if &bytes[..5] != b"TRACK" {
            return Err(Error::input(
                file,
                "id_string",
                format!(
                    "{:?}: not a TrackVis file (expected 'TRACK')",
                    String::from_utf8_lossy(&bytes[..6])
                ),
            ));
        }
        let mut fields = Fields {
            bytes,
            big_endian: false,
        };
        if fields.i32(996) != HEADER_SIZE as i32 {
            fields.big_endian = true;
            if fields.i32(996) != HEADER_SIZE as i32 {
                return Err(Error::input(
                    file,
                    "hdr_size",
                    format!(
                        "{} (little-endian) or {} (big-endian): expected {HEADER_SIZE} in \
                         either byte order",
                        Fields {
                            bytes,
                            big_endian: false
                        }
                        .i32(996),
                        fields.i32(996)
                    ),
                ));
            }
        }
        let version = fields.i32(992);
        if !(1..=3).contains(&version) {
            return Err(Error::input(
                file,
                "version",
                format!("{version}: TrackVis files have version 1 or 2"),
            ));
        }
        let count = |at: usize, field: &str| -> Result<usize> {
            let value = fields.i16(at);
            usize::try_from(value).map_err(|_| {
                Error::input(file, field, format!("{value}: a count cannot be negative"))
            })
        };
        let n_scalars = count(36, "n_scalars")?;
        let n_properties = count(238, "n_properties")?;
        let n_count = usize::try_from(fields.i32(988)).map_err(|_| {
            Error::input(
                file,
                "n_count",
                format!("{}: a count cannot be negative", fields.i32(988)),
            )
        })?;
        let mut vox_to_ras = [[0f32; 4]; 4];
        for (r, row) in vox_to_ras.iter_mut().enumerate() {
            for (c, entry) in row.iter_mut().enumerate() {
                *entry = fields.f32(440 + 4 * (4 * r + c));
            }
        }
        let recorded = version != 1 && vox_to_ras[3][3] != 0.0;
        let voxel_order = bytes[948..952]
            .iter()
            .copied()
            .take_while(|&b| b != 0)
            .collect();
        Ok(Self {
            dims: [fields.i16(6), fields.i16(8), fields.i16(10)],
            voxel_size: [fields.f32(12), fields.f32(16), fields.f32(20)],
            vox_to_ras: recorded.then_some(vox_to_ras),
            voxel_order,
            scalars: scalar_names(&bytes[38..238], n_scalars),
            n_scalars,
            n_properties,
            n_count,
            version,
            big_endian: fields.big_endian,
        })
    }
}

/// The names in `scalar_name` (ten slots of 20 bytes) and the values each takes per
/// point: nibabel writes a quantity of several values as `NAME\0N`. Values the names do
/// not cover are called `scalars`, as nibabel calls them.
fn scalar_names(slots: &[u8], n_scalars: usize) -> Vec<(String, usize)> {
    let mut names = Vec::new();
    let mut covered = 0;
    for slot in slots.chunks_exact(20) {
        let mut parts = slot.split(|&b| b == 0).filter(|part| !part.is_empty());
        let Some(name) = parts.next() else { continue };
        let width = parts
            .next()
            .and_then(|text| std::str::from_utf8(text).ok()?.parse().ok())
            .unwrap_or(1);
        names.push((String::from_utf8_lossy(name).into_owned(), width));
        covered += width;
    }
    if covered > n_scalars {
        // Names left over from an editor that lowered n_scalars: they do not describe
        // the data, so the values are kept unnamed.
        names.clear();
        covered = 0;
    }
    if covered < n_scalars {
        names.push(("scalars".to_string(), n_scalars - covered));
    }
    names
}

fn read_streamlines(
    data: &[u8],
    header: &TrkHeader,
    affine: &Matrix4<f64>,
    file: &str,
) -> Result<Tractogram> {
    let fields = Fields {
        bytes: data,
        big_endian: header.big_endian,
    };
    let per_point = 3 + header.n_scalars;
    let mut builder = TractogramBuilder::with_point_values(header.scalars.clone());
    let mut values = vec![0f32; header.n_scalars];
    let mut at = 0usize;
    let mut read = 0usize;
    while at < data.len() && (header.n_count == 0 || read < header.n_count) {
        let truncated = |what: &str, at: usize| {
            Error::input(
                file,
                "data",
                format!(
                    "truncated: the file ends inside streamline {read} ({what}, at byte {})",
                    HEADER_SIZE + at
                ),
            )
        };
        if data.len() - at < 4 {
            return Err(truncated("its point count", at));
        }
        let points = usize::try_from(fields.i32(at)).map_err(|_| {
            Error::input(
                file,
                "data",
                format!("streamline {read} declares {} points", fields.i32(at)),
            )
        })?;
        at += 4;
        let needed = points
            .checked_mul(per_point)
            .and_then(|floats| floats.checked_add(header.n_properties))
            .and_then(|floats| floats.checked_mul(4));
        if needed.is_none_or(|needed| needed > data.len() - at) {
            return Err(truncated(&format!("{points} points"), at));
        }
        builder.start();
        for _ in 0..points {
            let voxel_mm = [fields.f32(at), fields.f32(at + 4), fields.f32(at + 8)];
            if voxel_mm.iter().any(|v| !v.is_finite()) {
                return Err(Error::input(
                    file,
                    "data",
                    format!(
                        "streamline {read} has the point {voxel_mm:?} at byte {}: every \
                         coordinate must be finite",
                        HEADER_SIZE + at
                    ),
                ));
            }
            for (k, value) in values.iter_mut().enumerate() {
                *value = fields.f32(at + 12 + 4 * k);
            }
            let [x, y, z] = voxel_mm.map(f64::from);
            let ras = affine * Vector4::new(x, y, z, 1.0);
            builder.push([ras.x as f32, ras.y as f32, ras.z as f32], &values);
            at += 4 * per_point;
        }
        at += 4 * header.n_properties;
        read += 1;
    }
    if header.n_count != 0 && (read != header.n_count || at != data.len()) {
        let found = if read == header.n_count {
            format!(
                "the data hold more ({} bytes follow streamline {read})",
                data.len() - at
            )
        } else {
            format!("the data hold {read}")
        };
        return Err(Error::input(
            file,
            "n_count",
            format!("{} streamlines declared, but {found}", header.n_count),
        ));
    }
    Ok(builder.finish())
}
