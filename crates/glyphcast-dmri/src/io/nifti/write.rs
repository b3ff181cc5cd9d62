//! NIfTI-1 output: a single file of the 348-byte header, the 4-byte extension flag (no
//! extensions) and float32 voxels in Fortran order, little-endian, gzip-compressed on
//! request. The geometry (pixdim, qform, sform, units) and text fields come from a
//! reference header; the fields that describe the data are set here. This is the
//! format's encoder; outputs go through `io::image::write_image`, which chooses the
//! reference header and clears the fields of the input's data (intent, display range).
use glam::DMat3;
use ndarray::ArrayViewD;

use super::VoxelToWorld;
use super::header::{EXTENSION_FLAG_SIZE, NIFTI1_HEADER_SIZE, NiftiHeader, NiftiVersion};
use glyphcast::{Error, Result};

/// The file's bytes: `data` as float32 with `reference`'s geometry and text; `file`
/// names errors (a shape a NIfTI-1 header cannot hold).
pub fn nifti1_bytes(
    reference: &NiftiHeader,
    data: ArrayViewD<'_, f64>,
    gzip: bool,
    file: &str,
) -> Result<Vec<u8>> {
    let header = NiftiHeader {
        version: NiftiVersion::One,
        big_endian: false,
        magic: b"n+1\0".to_vec(),
        dim: dim_of(data.shape(), file)?,
        datatype: 16,
        bitpix: 32,
        vox_offset: (NIFTI1_HEADER_SIZE + EXTENSION_FLAG_SIZE) as f64,
        scl_slope: 1.0,
        scl_inter: 0.0,
        ..reference.clone()
    };
    let mut bytes = Vec::with_capacity(NIFTI1_HEADER_SIZE + 4 + 4 * data.len());
    bytes.extend_from_slice(&encode_nifti1(&header));
    bytes.extend_from_slice(&[0; EXTENSION_FLAG_SIZE]);
    // The reversed-axes view iterates the first axis fastest: Fortran order.
    for &value in data.t().iter() {
        bytes.extend_from_slice(&(value as f32).to_le_bytes());
    }
    if gzip {
        crate::io::gzip::gzip(bytes, file)
    } else {
        Ok(bytes)
    }
}

/// A NIfTI-1 header holding `map` as its sform (code 1, scanner), with the voxel sizes
/// in pixdim and millimetre units; the qform is left unset.
pub fn nifti_header_for(map: &VoxelToWorld) -> NiftiHeader {
    let rows = map.affine.transpose();
    let sizes = map.voxel_sizes();
    let mut header = NiftiHeader {
        sform_code: 1,
        qform_code: 0,
        srow_x: rows.x_axis.to_array(),
        srow_y: rows.y_axis.to_array(),
        srow_z: rows.z_axis.to_array(),
        xyzt_units: 2,
        ..NiftiHeader::default()
    };
    header.pixdim[0] = if DMat3::from_mat4(map.affine).determinant() < 0.0 {
        -1.0
    } else {
        1.0
    };
    header.pixdim[1..4].copy_from_slice(&sizes.to_array());
    header
}

/// dim for `shape`: rank 1 to 7, each length within int16.
fn dim_of(shape: &[usize], file: &str) -> Result<[i64; 8]> {
    let fits = (1..=7).contains(&shape.len()) && shape.iter().all(|&d| d <= i16::MAX as usize);
    if !fits {
        return Err(Error::input(
            file,
            "dim",
            format!("a NIfTI-1 file cannot hold an array of shape {shape:?}"),
        ));
    }
    let mut dim = [1i64; 8];
    dim[0] = shape.len() as i64;
    for (slot, &length) in dim[1..].iter_mut().zip(shape) {
        *slot = length as i64;
    }
    Ok(dim)
}

/// The 348 bytes of `header` as NIfTI-1, little-endian (wide fields narrowed to the
/// NIfTI-1 types; the magic is `header`'s when it is a NIfTI-1 one, else `n+1`).
pub fn encode_nifti1(h: &NiftiHeader) -> [u8; NIFTI1_HEADER_SIZE] {
    let mut out = [0u8; NIFTI1_HEADER_SIZE];
    let mut put = |at: usize, bytes: &[u8]| out[at..at + bytes.len()].copy_from_slice(bytes);
    let f32s = |values: &[f64]| -> Vec<u8> {
        values
            .iter()
            .flat_map(|&v| (v as f32).to_le_bytes())
            .collect()
    };
    let i16_of = |v: i64| (v.clamp(i16::MIN.into(), i16::MAX.into()) as i16).to_le_bytes();
    put(0, &(NIFTI1_HEADER_SIZE as i32).to_le_bytes());
    put(38, b"r");
    put(39, &[h.dim_info]);
    let dims: Vec<u8> = h.dim.iter().flat_map(|&d| i16_of(d)).collect();
    put(40, &dims);
    put(56, &f32s(&[h.intent_p1, h.intent_p2, h.intent_p3]));
    put(68, &i16_of(h.intent_code.into()));
    put(70, &h.datatype.to_le_bytes());
    put(72, &h.bitpix.to_le_bytes());
    put(74, &i16_of(h.slice_start));
    put(76, &f32s(&h.pixdim));
    put(108, &f32s(&[h.vox_offset, h.scl_slope, h.scl_inter]));
    put(120, &i16_of(h.slice_end));
    put(122, &[h.slice_code as u8, h.xyzt_units as u8]);
    put(
        124,
        &f32s(&[h.cal_max, h.cal_min, h.slice_duration, h.toffset]),
    );
    put(148, &h.descrip);
    put(228, &h.aux_file);
    put(252, &i16_of(h.qform_code.into()));
    put(254, &i16_of(h.sform_code.into()));
    put(
        256,
        &f32s(&[
            h.quatern_b,
            h.quatern_c,
            h.quatern_d,
            h.quatern_x,
            h.quatern_y,
            h.quatern_z,
        ]),
    );
    put(280, &f32s(&h.srow_x));
    put(296, &f32s(&h.srow_y));
    put(312, &f32s(&h.srow_z));
    put(328, &h.intent_name);
    let magic: &[u8] = if h.magic.len() == 4 {
        &h.magic
    } else {
        b"n+1\0"
    };
    put(344, magic);
    out
}
