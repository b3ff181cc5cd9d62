//! The NIfTI-1 (348-byte) and NIfTI-2 (540-byte) headers, in either byte order, as one
//! struct with the wider NIfTI-2 field types (a NIfTI-1 header's float32 and int16 fields
//! widen exactly), and the checks a header must pass before any voxel is read.
//!
//! The version and byte order come from `sizeof_hdr`: 348 or 540, read little-endian or
//! byte-swapped. The magic then says whether the voxels follow in the same file
//! (`n+1`, `n+2`) or lie in a separate `.img` (`ni1`, `ni2`); a 348-byte header with
//! neither is an Analyze 7.5 header. Field offsets are those of `nifti1.h` and `nifti2.h`.
use glyphcast::{Error, Result};

/// Bytes of a NIfTI-1 header; the voxels of a single file start at 352 at the earliest
/// (the header and the 4-byte extension flag).
pub const NIFTI1_HEADER_SIZE: usize = 348;
/// Bytes of a NIfTI-2 header; the voxels of a single file start at 544 at the earliest.
pub const NIFTI2_HEADER_SIZE: usize = 540;
/// The extension flag that follows the header in a single file.
pub const EXTENSION_FLAG_SIZE: usize = 4;

/// Which standard a header follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum NiftiVersion {
    /// NIfTI-1: a 348-byte header, magic `n+1` or `ni1`, float32 and int16 fields.
    #[default]
    One,
    /// NIfTI-2: a 540-byte header, magic `n+2` or `ni2`, float64 and int64 fields.
    Two,
}

impl NiftiVersion {
    /// The header's size in bytes (its `sizeof_hdr`).
    pub fn header_size(self) -> usize {
        match self {
            NiftiVersion::One => NIFTI1_HEADER_SIZE,
            NiftiVersion::Two => NIFTI2_HEADER_SIZE,
        }
    }
}

/// A NIfTI header with the fields glyphcast reads or copies.
#[derive(Clone, Debug, PartialEq)]
pub struct NiftiHeader {
    /// NIfTI-1 or NIfTI-2, from `sizeof_hdr`.
    pub version: NiftiVersion,
    /// Stored big-endian (the data then is too).
    pub big_endian: bool,
    /// The magic as stored: `n+1\0`, `ni1\0`, `n+2\0\r\n\x1a\n`, ... (4 bytes for NIfTI-1).
    pub magic: Vec<u8>,
    /// `dim_info`: the frequency, phase and slice encoding axes, two bits each (not used; a
    /// fit's output keeps it).
    pub dim_info: u8,
    /// `dim[0]` is the number of dimensions, `dim[1..=dim[0]]` their lengths.
    pub dim: [i64; 8],
    /// `intent_p1`: the first parameter of the intent (not used; a fit's output clears it).
    pub intent_p1: f64,
    /// `intent_p2`: the second parameter of the intent (not used; a fit's output clears
    /// it).
    pub intent_p2: f64,
    /// `intent_p3`: the third parameter of the intent (not used; a fit's output clears it).
    pub intent_p3: f64,
    /// `intent_code`: what the values mean (`NIFTI_INTENT_*`); 1005 (symmetric matrix)
    /// marks a tensor volume when glyphcast guesses a volume's kind; a fit's output clears
    /// it.
    pub intent_code: i32,
    /// `datatype`: the stored voxel type (`DT_*`: 2 uint8, 4 int16, 8 int32, 16 float32,
    /// 64 float64, ...); real types are read as f64, complex and RGB types are refused.
    pub datatype: i16,
    /// `bitpix`: bits per voxel; it must agree with `datatype`.
    pub bitpix: i16,
    /// `slice_start`: the first slice of the acquisition order (not used; a fit's output
    /// keeps it).
    pub slice_start: i64,
    /// `pixdim[0]` is qfac (its sign flips the third axis of the qform), `pixdim[1..]` the
    /// voxel sizes.
    pub pixdim: [f64; 8],
    /// Byte offset of the first voxel in the data file.
    pub vox_offset: f64,
    /// `scl_slope`: stored values are multiplied by it on reading; 0 (or 1 with no
    /// intercept) means no scaling.
    pub scl_slope: f64,
    /// `scl_inter`: added to the stored values after `scl_slope` on reading.
    pub scl_inter: f64,
    /// `slice_end`: the last slice of the acquisition order (not used; a fit's output keeps
    /// it).
    pub slice_end: i64,
    /// `slice_code`: the slice timing pattern (`NIFTI_SLICE_*`; not used; a fit's output
    /// keeps it).
    pub slice_code: i32,
    /// `xyzt_units`: the spatial unit in bits 0-2 (2 mm) and the temporal unit in bits 3-5
    /// (not used: the affine is taken in the file's own units; a fit's output keeps it).
    pub xyzt_units: i32,
    /// `cal_max`: the display maximum the writer suggests (not used; a fit's output clears
    /// it).
    pub cal_max: f64,
    /// `cal_min`: the display minimum the writer suggests (not used; a fit's output clears
    /// it).
    pub cal_min: f64,
    /// `slice_duration`: seconds per slice acquisition (not used; a fit's output keeps it).
    pub slice_duration: f64,
    /// `toffset`: the time of the first volume, in `xyzt_units` (not used; a fit's output
    /// keeps it).
    pub toffset: f64,
    /// `descrip`: free ASCII text, NUL-padded; see [`NiftiHeader::description`].
    pub descrip: [u8; 80],
    /// `aux_file`: the name of an auxiliary file, NUL-padded (not used; a fit's output
    /// keeps it).
    pub aux_file: [u8; 24],
    /// `qform_code`: what the quaternion transform maps to (0 unset, 1 scanner, 2 aligned,
    /// 3 Talairach, 4 MNI); it is used when `sform_code` is 0.
    pub qform_code: i32,
    /// `sform_code`: what the `srow_*` affine maps to (same codes); when above 0 it wins
    /// over the qform.
    pub sform_code: i32,
    /// `quatern_b`: the qform rotation's quaternion, i component (a = sqrt(1 - b² - c² -
    /// d²)).
    pub quatern_b: f64,
    /// `quatern_c`: the qform rotation's quaternion, j component.
    pub quatern_c: f64,
    /// `quatern_d`: the qform rotation's quaternion, k component.
    pub quatern_d: f64,
    /// `qoffset_x`: world x of voxel (0, 0, 0) under the qform.
    pub quatern_x: f64,
    /// `qoffset_y`: world y of voxel (0, 0, 0) under the qform.
    pub quatern_y: f64,
    /// `qoffset_z`: world z of voxel (0, 0, 0) under the qform.
    pub quatern_z: f64,
    /// `srow_x`: the first row of the sform affine (world x = srow_x · (i, j, k, 1)).
    pub srow_x: [f64; 4],
    /// `srow_y`: the second row of the sform affine.
    pub srow_y: [f64; 4],
    /// `srow_z`: the third row of the sform affine.
    pub srow_z: [f64; 4],
    /// `intent_name`: a name for the intent, NUL-padded (not used; a fit's output clears
    /// it).
    pub intent_name: [u8; 16],
}

impl Default for NiftiHeader {
    /// A NIfTI-1 single-file header of a 1x1x1 float32 image with unit voxels and no
    /// transform set.
    fn default() -> Self {
        Self {
            version: NiftiVersion::One,
            big_endian: false,
            magic: b"n+1\0".to_vec(),
            dim_info: 0,
            dim: [3, 1, 1, 1, 1, 1, 1, 1],
            intent_p1: 0.0,
            intent_p2: 0.0,
            intent_p3: 0.0,
            intent_code: 0,
            datatype: 16,
            bitpix: 32,
            slice_start: 0,
            pixdim: [1.0; 8],
            vox_offset: 352.0,
            scl_slope: 1.0,
            scl_inter: 0.0,
            slice_end: 0,
            slice_code: 0,
            xyzt_units: 0,
            cal_max: 0.0,
            cal_min: 0.0,
            slice_duration: 0.0,
            toffset: 0.0,
            descrip: [0; 80],
            aux_file: [0; 24],
            qform_code: 0,
            sform_code: 0,
            quatern_b: 0.0,
            quatern_c: 0.0,
            quatern_d: 0.0,
            quatern_x: 0.0,
            quatern_y: 0.0,
            quatern_z: 0.0,
            srow_x: [0.0; 4],
            srow_y: [0.0; 4],
            srow_z: [0.0; 4],
            intent_name: [0; 16],
        }
    }
}

/// Reads fixed-offset fields in one byte order.
struct Fields<'a> {
    bytes: &'a [u8],
    big_endian: bool,
}

impl Fields<'_> {
    fn array<const N: usize>(&self, at: usize) -> [u8; N] {
        let mut out = [0; N];
        out.copy_from_slice(&self.bytes[at..at + N]);
        if self.big_endian {
            out.reverse();
        }
        out
    }
    fn raw<const N: usize>(&self, at: usize) -> [u8; N] {
        let mut out = [0; N];
        out.copy_from_slice(&self.bytes[at..at + N]);
        out
    }
    fn i16(&self, at: usize) -> i16 {
        i16::from_le_bytes(self.array(at))
    }
    fn i32(&self, at: usize) -> i32 {
        i32::from_le_bytes(self.array(at))
    }
    fn i64(&self, at: usize) -> i64 {
        i64::from_le_bytes(self.array(at))
    }
    fn f32(&self, at: usize) -> f64 {
        f32::from_le_bytes(self.array(at)).into()
    }
    fn f64(&self, at: usize) -> f64 {
        f64::from_le_bytes(self.array(at))
    }
    fn f32s<const N: usize>(&self, at: usize) -> [f64; N] {
        std::array::from_fn(|i| self.f32(at + 4 * i))
    }
    fn f64s<const N: usize>(&self, at: usize) -> [f64; N] {
        std::array::from_fn(|i| self.f64(at + 8 * i))
    }
}

/// The version and byte order that the first four bytes (`sizeof_hdr`) announce, or an
/// error naming `sizeof_hdr` with the value found.
pub fn detect(first: [u8; 4], file: &str) -> Result<(NiftiVersion, bool)> {
    for (version, size) in [(NiftiVersion::One, 348), (NiftiVersion::Two, 540)] {
        if i32::from_le_bytes(first) == size {
            return Ok((version, false));
        }
        if i32::from_be_bytes(first) == size {
            return Ok((version, true));
        }
    }
    let message = if first[..2] == [0x1f, 0x8b] {
        "not a NIfTI file as it stands: it is gzip-compressed, but its name does not end in \
         .gz"
        .to_string()
    } else {
        format!(
            "not a NIfTI file: sizeof_hdr is {} (a NIfTI-1 header has 348, a NIfTI-2 header \
             540, in either byte order)",
            i32::from_le_bytes(first)
        )
    };
    Err(Error::input(file, "sizeof_hdr", message))
}

impl NiftiHeader {
    /// Parses a whole header (`bytes` holds exactly `version.header_size()` bytes). Only
    /// the layout is read here; [`NiftiHeader::check_magic`] and the checks of
    /// `io::nifti::layout` judge the values.
    pub fn parse(bytes: &[u8], version: NiftiVersion, big_endian: bool) -> Self {
        let f = Fields { bytes, big_endian };
        match version {
            NiftiVersion::One => Self::parse_nifti1(&f),
            NiftiVersion::Two => Self::parse_nifti2(&f),
        }
    }

    fn parse_nifti1(f: &Fields) -> Self {
        Self {
            version: NiftiVersion::One,
            big_endian: f.big_endian,
            magic: f.raw::<4>(344).to_vec(),
            dim_info: f.bytes[39],
            dim: std::array::from_fn(|i| f.i16(40 + 2 * i).into()),
            intent_p1: f.f32(56),
            intent_p2: f.f32(60),
            intent_p3: f.f32(64),
            intent_code: f.i16(68).into(),
            datatype: f.i16(70),
            bitpix: f.i16(72),
            slice_start: f.i16(74).into(),
            pixdim: f.f32s(76),
            vox_offset: f.f32(108),
            scl_slope: f.f32(112),
            scl_inter: f.f32(116),
            slice_end: f.i16(120).into(),
            slice_code: f.bytes[122].into(),
            xyzt_units: f.bytes[123].into(),
            cal_max: f.f32(124),
            cal_min: f.f32(128),
            slice_duration: f.f32(132),
            toffset: f.f32(136),
            descrip: f.raw(148),
            aux_file: f.raw(228),
            qform_code: f.i16(252).into(),
            sform_code: f.i16(254).into(),
            quatern_b: f.f32(256),
            quatern_c: f.f32(260),
            quatern_d: f.f32(264),
            quatern_x: f.f32(268),
            quatern_y: f.f32(272),
            quatern_z: f.f32(276),
            srow_x: f.f32s(280),
            srow_y: f.f32s(296),
            srow_z: f.f32s(312),
            intent_name: f.raw(328),
        }
    }

    fn parse_nifti2(f: &Fields) -> Self {
        Self {
            version: NiftiVersion::Two,
            big_endian: f.big_endian,
            magic: f.raw::<8>(4).to_vec(),
            datatype: f.i16(12),
            bitpix: f.i16(14),
            dim: std::array::from_fn(|i| f.i64(16 + 8 * i)),
            intent_p1: f.f64(80),
            intent_p2: f.f64(88),
            intent_p3: f.f64(96),
            pixdim: f.f64s(104),
            vox_offset: f.i64(168) as f64,
            scl_slope: f.f64(176),
            scl_inter: f.f64(184),
            cal_max: f.f64(192),
            cal_min: f.f64(200),
            slice_duration: f.f64(208),
            toffset: f.f64(216),
            slice_start: f.i64(224),
            slice_end: f.i64(232),
            descrip: f.raw(240),
            aux_file: f.raw(320),
            qform_code: f.i32(344),
            sform_code: f.i32(348),
            quatern_b: f.f64(352),
            quatern_c: f.f64(360),
            quatern_d: f.f64(368),
            quatern_x: f.f64(376),
            quatern_y: f.f64(384),
            quatern_z: f.f64(392),
            srow_x: f.f64s(400),
            srow_y: f.f64s(432),
            srow_z: f.f64s(464),
            slice_code: f.i32(496),
            xyzt_units: f.i32(500),
            intent_code: f.i32(504),
            intent_name: f.raw(508),
            dim_info: f.bytes[524],
        }
    }

    /// Whether the magic says the voxels follow in the same file (`n+1`, `n+2`); Err
    /// naming `magic` when it is no NIfTI magic, or says the other kind of file than
    /// `pair` (a `.hdr` is read with its `.img`).
    pub fn check_magic(&self, pair: bool, file: &str) -> Result<()> {
        let (single, separate): (&[u8], &[u8]) = match self.version {
            NiftiVersion::One => (b"n+1\0", b"ni1\0"),
            NiftiVersion::Two => (b"n+2\0\r\n\x1a\n", b"ni2\0\r\n\x1a\n"),
        };
        let shown =
            String::from_utf8_lossy(self.magic.get(..3).unwrap_or(&self.magic)).into_owned();
        let message = if self.magic == single && pair {
            format!(
                "\"{shown}\" marks a single-file .nii, but this is the header of a .hdr/.img pair"
            )
        } else if self.magic == separate && !pair {
            format!(
                "\"{shown}\" marks the header of a .hdr/.img pair: name the file .hdr, with \
                 its .img beside it"
            )
        } else if self.magic == single || self.magic == separate {
            return Ok(());
        } else if self.version == NiftiVersion::One {
            format!(
                "Analyze 7.5, not NIfTI: the magic is {shown:?}, not \"n+1\" or \"ni1\" \
                 (without it the orientation is undefined; convert the file to NIfTI)"
            )
        } else {
            format!("not a NIfTI-2 file: the magic is {shown:?}, not \"n+2\" or \"ni2\"")
        };
        Err(Error::input(file, "magic", message))
    }

    /// The `descrip` text up to its first NUL.
    pub fn description(&self) -> String {
        self.descrip
            .iter()
            .take_while(|&&b| b != 0)
            .map(|&b| b as char)
            .collect()
    }

    /// Sets `descrip` to the ASCII characters of `text`, at most 79 of them (the field
    /// ends with a NUL).
    pub fn set_description(&mut self, text: &str) {
        self.descrip = [0; 80];
        for (slot, byte) in self.descrip[..79]
            .iter_mut()
            .zip(text.bytes().filter(u8::is_ascii))
        {
            *slot = byte;
        }
    }
}
