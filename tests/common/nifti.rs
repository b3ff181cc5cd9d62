//! NIfTI test files built byte by byte: a NIfTI-2 image from a header and data, edits of
//! single header fields of a NIfTI-1 file, and gzip.
use glyphcast_dmri::io::nifti::NiftiHeader;
use ndarray::ArrayD;
use std::io::Write;

/// `bytes` gzip-compressed (one member).
pub fn gzip(bytes: &[u8]) -> Vec<u8> {
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    encoder.write_all(bytes).expect("compressing");
    encoder.finish().expect("compressing")
}

/// Overwrites the little-endian int16 at `at` (a NIfTI-1 field: datatype at 70, bitpix
/// at 72, dim[i] at 40 + 2i).
pub fn set_i16(bytes: &mut [u8], at: usize, value: i16) {
    bytes[at..at + 2].copy_from_slice(&value.to_le_bytes());
}

/// Overwrites the little-endian float32 at `at` (vox_offset at 108, scl_slope at 112).
pub fn set_f32(bytes: &mut [u8], at: usize, value: f32) {
    bytes[at..at + 4].copy_from_slice(&value.to_le_bytes());
}

/// A single-file NIfTI-1 `file` (uncompressed, data at 352) with its data moved to
/// `offset`, the gap filled with bytes a reader must not take for voxels.
pub fn with_vox_offset(file: &[u8], offset: usize) -> Vec<u8> {
    let mut moved = file[..352].to_vec();
    set_f32(&mut moved, 108, offset as f32);
    moved.resize(offset, 0x7f);
    moved.extend_from_slice(&file[352..]);
    moved
}

/// A single-file NIfTI-2 image (540-byte header, 4 extension bytes, data at 544) of
/// `data` as float32 in Fortran order, with `header`'s geometry and descrip, laid out
/// from nifti2.h field by field, in either byte order.
pub fn nifti2_bytes(header: &NiftiHeader, data: &ArrayD<f64>, big_endian: bool) -> Vec<u8> {
    let mut out = vec![0u8; 544];
    let mut put = |at: usize, mut word: Vec<u8>| {
        if big_endian {
            word.reverse();
        }
        out[at..at + word.len()].copy_from_slice(&word);
    };
    let f64s = |put: &mut dyn FnMut(usize, Vec<u8>), at: usize, values: &[f64]| {
        for (i, v) in values.iter().enumerate() {
            put(at + 8 * i, v.to_le_bytes().to_vec());
        }
    };
    put(0, 540i32.to_le_bytes().to_vec());
    put(12, 16i16.to_le_bytes().to_vec());
    put(14, 32i16.to_le_bytes().to_vec());
    let mut dim = [1i64; 8];
    dim[0] = data.ndim() as i64;
    for (slot, &length) in dim[1..].iter_mut().zip(data.shape()) {
        *slot = length as i64;
    }
    for (i, d) in dim.iter().enumerate() {
        put(16 + 8 * i, d.to_le_bytes().to_vec());
    }
    f64s(&mut put, 104, &header.pixdim);
    put(168, 544i64.to_le_bytes().to_vec());
    f64s(&mut put, 176, &[1.0, 0.0]);
    put(344, header.qform_code.to_le_bytes().to_vec());
    put(348, header.sform_code.to_le_bytes().to_vec());
    let quatern = [
        header.quatern_b,
        header.quatern_c,
        header.quatern_d,
        header.quatern_x,
        header.quatern_y,
        header.quatern_z,
    ];
    f64s(&mut put, 352, &quatern);
    f64s(&mut put, 400, &header.srow_x);
    f64s(&mut put, 432, &header.srow_y);
    f64s(&mut put, 464, &header.srow_z);
    put(500, header.xyzt_units.to_le_bytes().to_vec());
    out[4..12].copy_from_slice(b"n+2\0\r\n\x1a\n");
    out[240..320].copy_from_slice(&header.descrip);
    for &value in data.t().iter() {
        let mut word = (value as f32).to_le_bytes();
        if big_endian {
            word.reverse();
        }
        out.extend_from_slice(&word);
    }
    out
}
