//! numpy arrays in and out. Coefficients come as (X, Y, Z, K) float32 or float64 arrays
//! in any layout: C or Fortran order (nibabel's `get_fdata()` gives Fortran order),
//! strided or reversed views (`shm_coeff[..., :28]`, `C[::-1]`), each copied once into
//! the float64 C-order volume the library reads; another dtype or shape is a
//! `ValueError` that says what was given and what is needed. A voxel with a NaN or
//! infinite coefficient is left out with a warning, as on the command line
//! (`volume::VolumeReport::warnings`). Images go out as arrays that own the rendered
//! pixels (no copy).
use glam::DMat4;
use glyphcast::render::headless::RenderedImage;
use glyphcast::render::underlay::UnderlayVolume;
use glyphcast_dmri::io::nifti::{AffineSource, VoxelToWorld};
use glyphcast_dmri::io::tracks::Tractogram;
use glyphcast_dmri::volume::{Mask, PeakArray};
use ndarray::{Array3, Array4, Ix3, Ix4};
use numpy::{
    PyArray1, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::errors::{to_py, value_error};

/// The coefficient volume `coeffs`, checked and converted to float64.
pub fn coefficients(coeffs: &Bound<'_, PyAny>) -> PyResult<Array4<f64>> {
    let what = "coeffs";
    let array = numpy_array(what, coeffs)?;
    if array.ndim() != 4 {
        return Err(value_error(
            what,
            format!(
                "a {}D array of shape {:?} where a 4D array (X, Y, Z, K) of coefficients per \
                 voxel is needed",
                array.ndim(),
                array.shape()
            ),
        ));
    }
    let data = floats(what, coeffs)?;
    data.into_dimensionality::<Ix4>()
        .map_err(|err| value_error(what, err))
}

/// The mask: any numeric (X, Y, Z) array; nonzero keeps a voxel.
pub fn mask(mask: &Bound<'_, PyAny>) -> PyResult<Mask> {
    let what = "mask";
    let array = numpy_array(what, mask)?;
    if array.ndim() != 3 {
        return Err(value_error(
            what,
            format!(
                "a {}D array of shape {:?} where a 3D array (X, Y, Z) is needed",
                array.ndim(),
                array.shape()
            ),
        ));
    }
    let values = mask
        .call_method1("astype", ("float64",))?
        .cast_into::<PyArrayDyn<f64>>()?
        .readonly()
        .as_array()
        .to_owned();
    let values: Array3<f64> = values
        .into_dimensionality::<Ix3>()
        .map_err(|err| value_error(what, err))?;
    Ok(Mask::new(what, &values))
}

/// An underlay in memory: a numeric (X, Y, Z) array (scalar: FA, T1) or (X, Y, Z, 3)
/// (RGB: colour-FA), placed by `voxel_to_world`; NaN where there is no value.
pub fn underlay(values: &Bound<'_, PyAny>, voxel_to_world: DMat4) -> PyResult<UnderlayVolume> {
    let what = "underlay";
    let array = numpy_array(what, values)?;
    let shape = array.shape().to_vec();
    let channels = match shape.len() {
        3 => 1,
        4 if shape[3] == 3 => 3,
        _ => {
            return Err(value_error(
                what,
                format!(
                    "a {}D array of shape {shape:?} where (X, Y, Z) or (X, Y, Z, 3) is needed",
                    shape.len()
                ),
            ));
        }
    };
    let values = values
        .call_method1("astype", ("float32",))?
        .cast_into::<PyArrayDyn<f32>>()?
        .readonly()
        .as_array()
        .to_owned();
    let dims = [shape[0], shape[1], shape[2]];
    // Channels interleaved, i fastest, then j, then k (the underlay's layout).
    let mut interleaved = Vec::new();
    interleaved
        .try_reserve_exact(values.len())
        .map_err(|_| value_error(what, "does not fit in memory"))?;
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                for c in 0..channels {
                    let index: &[usize] = if channels == 1 {
                        &[i, j, k]
                    } else {
                        &[i, j, k, c]
                    };
                    interleaved.push(values[index]);
                }
            }
        }
    }
    UnderlayVolume::new(what, dims, channels, interleaved, voxel_to_world).map_err(to_py)
}

/// A peak array `what` (`peaks`: directions, (X, Y, Z, 3N) or (X, Y, Z, N, 3);
/// `peak_values`: amplitudes, (X, Y, Z, N)) on the coefficients' grid, placed by
/// `voxel_to_world`: float32 or float64, NaN where a peak is absent; the layouts and
/// shapes are checked by `PeakVolume::from_arrays`.
pub fn peaks(what: &str, values: &Bound<'_, PyAny>, voxel_to_world: DMat4) -> PyResult<PeakArray> {
    numpy_array(what, values)?;
    Ok(PeakArray {
        file: what.to_string(),
        data: floats(what, values)?,
        voxel_to_world: VoxelToWorld::new(voxel_to_world, AffineSource::Sform, what, "matrix")
            .map_err(to_py)?,
    })
}

/// The voxel-to-world affine: a 4x4 array (nibabel's `img.affine`), or the identity.
pub fn affine(affine: Option<&Bound<'_, PyAny>>) -> PyResult<VoxelToWorld> {
    affine_named("affine", affine)
}

/// [`affine`] for the argument `what`.
pub fn affine_named(what: &str, affine: Option<&Bound<'_, PyAny>>) -> PyResult<VoxelToWorld> {
    let matrix = match affine {
        None => DMat4::IDENTITY,
        Some(affine) => {
            let array = numpy_array(what, affine)?;
            if array.shape() != [4, 4] {
                return Err(value_error(
                    what,
                    format!("shape {:?} where a 4x4 matrix is needed", array.shape()),
                ));
            }
            let values = floats(what, affine)?;
            // numpy's rows are glam's columns transposed.
            let rows: [[f64; 4]; 4] =
                std::array::from_fn(|r| std::array::from_fn(|c| values[[r, c]]));
            DMat4::from_cols_array_2d(&rows).transpose()
        }
    };
    VoxelToWorld::new(matrix, AffineSource::Sform, what, "matrix").map_err(to_py)
}

/// The image as numpy arrays: RGBA uint8 (H, W, 4) and the ray distance float32 (H, W),
/// NaN for misses.
pub fn image_arrays<'py>(
    py: Python<'py>,
    image: RenderedImage,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let (w, h) = (image.width as usize, image.height as usize);
    let rgba = PyArray1::from_vec(py, image.rgba).reshape([h, w, 4])?;
    let depth = PyArray1::from_vec(py, image.distance).reshape([h, w])?;
    Ok((rgba.into_any(), depth.into_any()))
}

/// `value` as a numpy array, or a `ValueError` naming its type.
fn numpy_array<'a, 'py>(
    what: &str,
    value: &'a Bound<'py, PyAny>,
) -> PyResult<&'a Bound<'py, PyUntypedArray>> {
    value.cast::<PyUntypedArray>().map_err(|_| {
        let type_name = value
            .get_type()
            .name()
            .map(|name| name.to_string())
            .unwrap_or_else(|_| "?".into());
        value_error(what, format!("a numpy array is needed, not {type_name}"))
    })
}

/// Streamlines given as arrays: a sequence of (N, 3) float arrays in RAS+ millimetres
/// (a list, nibabel's `ArraySequence`, or the `streamlines` of a nibabel `Tractogram`
/// whose points are in world millimetres), one streamline each.
pub fn tracks(value: &Bound<'_, PyAny>) -> PyResult<Tractogram> {
    let what = "tracks";
    let lines = match value.getattr("streamlines") {
        Ok(streamlines) => {
            // A nibabel Tractogram: its points are world millimetres only where its
            // affine_to_rasmm is the identity; a DIPY StatefulTractogram must be in RASMM.
            if let Ok(space) = value.getattr("space") {
                let space = space.str()?.to_string();
                if !space.ends_with("RASMM") {
                    return Err(value_error(
                        what,
                        format!(
                            "a StatefulTractogram in space {space}: call to_rasmm() on it first"
                        ),
                    ));
                }
            }
            streamlines
        }
        Err(_) => value.clone(),
    };
    let mut tractogram = Tractogram::default();
    for (n, line) in lines.try_iter()?.enumerate() {
        let line = line?;
        let points = floats(what, numpy_array(what, &line)?.as_any())?;
        if points.ndim() != 2 || points.shape()[1] != 3 {
            return Err(value_error(
                what,
                format!(
                    "streamline {n} has shape {:?} where (N, 3) points are needed",
                    points.shape()
                ),
            ));
        }
        if let Some(bad) = points
            .iter()
            .find(|v| !(v.is_finite() && v.abs() <= f32::MAX as f64))
        {
            return Err(value_error(
                what,
                format!("streamline {n} has a point coordinate {bad}: finite values only"),
            ));
        }
        tractogram.offsets.push(tractogram.points.len() as u64);
        tractogram.points.extend(
            points
                .rows()
                .into_iter()
                .map(|p| [p[0] as f32, p[1] as f32, p[2] as f32]),
        );
    }
    Ok(tractogram)
}

/// The values of a float32 or float64 array of any strides as float64, in C order, in
/// one copy: the volume code reads a voxel's coefficients together, which in Fortran
/// order (nibabel's) lie a whole volume apart (measured: a 100x100 slice of a
/// 100x100x10 band-8 volume took 1 s more).
fn floats(what: &str, value: &Bound<'_, PyAny>) -> PyResult<ndarray::ArrayD<f64>> {
    if let Ok(array) = value.cast::<PyArrayDyn<f64>>() {
        let array: PyReadonlyArrayDyn<'_, f64> = array.readonly();
        return Ok(array.as_array().as_standard_layout().into_owned());
    }
    if let Ok(array) = value.cast::<PyArrayDyn<f32>>() {
        let array: PyReadonlyArrayDyn<'_, f32> = array.readonly();
        let view = array.as_array();
        let mut values = ndarray::ArrayD::<f64>::zeros(view.raw_dim());
        values.zip_mut_with(&view, |out, &v| *out = f64::from(v));
        return Ok(values);
    }
    let dtype = value.getattr("dtype")?.str()?.to_string();
    Err(value_error(
        what,
        format!("dtype {dtype} where float32 or float64 is needed"),
    ))
}
