//! The affine from TrackVis "voxel millimetres" to RAS+ millimetres, built step by step
//! as nibabel's `get_affine_trackvis_to_rasmm` builds it (nibabel 5,
//! `nibabel/streamlines/trk.py`), with its helpers from `nibabel/orientations.py`
//! (`io_orientation`, `axcodes2ornt`, `ornt_transform`, `inv_ornt_aff`):
//!
//! 1. divide by the voxel size (voxel millimetres to voxel indices of the corner);
//! 2. subtract half a voxel (TrackVis puts 0 at the corner of the first voxel, RAS+ voxel
//!    coordinates at its centre);
//! 3. flip and permute the axes from the header's `voxel_order` to the order the
//!    `vox_to_ras` matrix implies (its axis codes, from the closest rotation);
//! 4. apply `vox_to_ras` (the identity when not recorded: version 1, or a zero last entry).
use nalgebra::{Matrix3, Matrix4};

use glyphcast::{Error, Result};

/// One axis of an orientation: the world axis (0 = L/R, 1 = P/A, 2 = I/S) it runs
/// along and its direction (+1 towards R, A or S).
type Orientation = [(usize, f64); 3];

/// What the affine needs from a TrackVis header.
pub(crate) struct TrackvisGeometry<'a> {
    pub dims: [i16; 3],
    pub voxel_size: [f32; 3],
    /// Row-major, as stored; None when not recorded.
    pub vox_to_ras: Option<[[f32; 4]; 4]>,
    /// As stored, up to the first NUL.
    pub voxel_order: &'a [u8],
}

/// nibabel's `get_affine_trackvis_to_rasmm`, in float64.
pub(crate) fn trackvis_to_rasmm(geometry: &TrackvisGeometry, file: &str) -> Result<Matrix4<f64>> {
    let mut scale = Matrix4::identity();
    for axis in 0..3 {
        let size = f64::from(geometry.voxel_size[axis]);
        if size == 0.0 || !size.is_finite() {
            return Err(Error::input(
                file,
                "voxel_size",
                format!(
                    "{:?}: every voxel size must be a finite non-zero number of millimetres",
                    geometry.voxel_size
                ),
            ));
        }
        scale[(axis, axis)] = 1.0 / size;
    }
    let mut half_voxel = Matrix4::identity();
    for axis in 0..3 {
        half_voxel[(axis, 3)] = -0.5;
    }
    let vox_to_ras = match geometry.vox_to_ras {
        Some(rows) => Matrix4::from_fn(|r, c| f64::from(rows[r][c])),
        None => Matrix4::identity(),
    };
    let affine_orientation = io_orientation(&vox_to_ras).ok_or_else(|| {
        Error::input(
            file,
            "vox_to_ras",
            "the axis directions cannot be determined from it (a singular matrix)",
        )
    })?;
    let header_orientation = axis_codes(geometry.voxel_order, file)?;
    let transform = orientation_transform(&header_orientation, &affine_orientation);
    let reorder = inverse_orientation_affine(&transform, geometry.dims);
    Ok(vox_to_ras * reorder * half_voxel * scale)
}

/// nibabel's `io_orientation`: for each voxel axis, the world axis it is closest to in
/// the nearest rotation of the matrix (its polar decomposition), taken greedily so that
/// no world axis is used twice. None when an axis has no direction.
fn io_orientation(affine: &Matrix4<f64>) -> Option<Orientation> {
    let mut rs = Matrix3::from_fn(|r, c| affine[(r, c)]);
    for c in 0..3 {
        let zoom = rs.column(c).norm();
        if zoom != 0.0 {
            rs.column_mut(c).unscale_mut(zoom);
        }
    }
    let svd = rs.svd(true, true);
    let (u, v_t) = (svd.u?, svd.v_t?);
    let largest = svd.singular_values.max();
    // nibabel's threshold on the singular values, with float32's epsilon: the header's
    // matrix is float32, and numpy's SVD keeps that type.
    let tolerance = largest * 3.0 * f64::from(f32::EPSILON);
    let mut rotation = Matrix3::zeros();
    for k in 0..3 {
        if svd.singular_values[k] > tolerance {
            rotation += u.column(k) * v_t.row(k);
        }
    }
    let mut orientation = [(0, 0.0); 3];
    for (input, entry) in orientation.iter_mut().enumerate() {
        let column = rotation.column(input).into_owned();
        // numpy's allclose(col, 0): every entry within 1e-8 of zero.
        if column.iter().all(|v| v.abs() <= 1e-8) {
            return None;
        }
        let output = column.iamax();
        *entry = (output, column[output].signum());
        rotation.row_mut(output).fill(0.0);
    }
    Some(orientation)
}

/// nibabel's `axcodes2ornt` with the labels (L, R), (P, A), (I, S); an empty voxel order
/// is TrackVis's default, LPS (as nibabel assumes).
fn axis_codes(voxel_order: &[u8], file: &str) -> Result<Orientation> {
    let text: String = voxel_order.iter().map(|&b| char::from(b)).collect();
    let code = if text.is_empty() {
        "LPS".to_string()
    } else {
        text.to_ascii_uppercase()
    };
    let refuse = || {
        Error::input(
            file,
            "voxel_order",
            format!(
                "{text:?}: expected three letters, one of L or R, one of P or A, one of I or S \
                 (as LAS)"
            ),
        )
    };
    let letters: Vec<char> = code.chars().collect();
    if letters.len() != 3 {
        return Err(refuse());
    }
    let mut orientation = [(0, 0.0); 3];
    for (entry, letter) in orientation.iter_mut().zip(&letters) {
        *entry = match letter {
            'L' => (0, -1.0),
            'R' => (0, 1.0),
            'P' => (1, -1.0),
            'A' => (1, 1.0),
            'I' => (2, -1.0),
            'S' => (2, 1.0),
            _ => return Err(refuse()),
        };
    }
    let mut used = [false; 3];
    for (axis, _) in orientation {
        if std::mem::replace(&mut used[axis], true) {
            return Err(refuse());
        }
    }
    Ok(orientation)
}

/// nibabel's `ornt_transform(start, end)`: for each axis of `start`, the axis of `end`
/// along the same world axis, and whether the direction flips.
fn orientation_transform(start: &Orientation, end: &Orientation) -> Orientation {
    let mut result = [(0, 1.0); 3];
    for (end_input, &(end_output, end_flip)) in end.iter().enumerate() {
        if let Some(start_input) = start.iter().position(|&(out, _)| out == end_output) {
            let flip = if start[start_input].1 == end_flip {
                1.0
            } else {
                -1.0
            };
            result[start_input] = (end_input, flip);
        }
    }
    result
}

/// nibabel's `inv_ornt_aff(ornt, shape)`: undoes the permutation, then the flips about
/// the centre of the voxel grid.
fn inverse_orientation_affine(orientation: &Orientation, dims: [i16; 3]) -> Matrix4<f64> {
    let mut undo_reorder = Matrix4::zeros();
    for (row, &(axis, _)) in orientation.iter().enumerate() {
        undo_reorder[(row, axis)] = 1.0;
    }
    undo_reorder[(3, 3)] = 1.0;
    let mut undo_flip = Matrix4::identity();
    for (axis, &(_, flip)) in orientation.iter().enumerate() {
        let centre = -(f64::from(dims[axis]) - 1.0) / 2.0;
        undo_flip[(axis, axis)] = flip;
        undo_flip[(axis, 3)] = flip * centre - centre;
    }
    undo_flip * undo_reorder
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orientation_of_a_flipped_permuted_matrix() {
        // Voxel axis 0 along -y, axis 1 along +x, axis 2 along +z, with shear and zooms.
        let affine = Matrix4::new(
            0.1, 2.0, 0.0, 0.0, //
            -1.5, 0.05, 0.0, 0.0, //
            0.0, 0.0, 3.0, 0.0, //
            0.0, 0.0, 0.0, 1.0,
        );
        assert_eq!(
            io_orientation(&affine),
            Some([(1, -1.0), (0, 1.0), (2, 1.0)])
        );
        assert_eq!(io_orientation(&Matrix4::zeros()), None);
    }

    #[test]
    fn lps_to_ras_flips_two_axes_about_the_grid_centre() {
        let lps = axis_codes(b"LPS", "f").unwrap();
        let ras = [(0, 1.0), (1, 1.0), (2, 1.0)];
        let transform = orientation_transform(&lps, &ras);
        assert_eq!(transform, [(0, -1.0), (1, -1.0), (2, 1.0)]);
        let m = inverse_orientation_affine(&transform, [10, 20, 30]);
        // Voxel 0 of a flipped axis of 10 voxels is voxel 9.
        assert_eq!(m[(0, 0)], -1.0);
        assert_eq!(m[(0, 3)], 9.0);
        assert_eq!(m[(1, 3)], 19.0);
        assert_eq!(m[(2, 3)], 0.0);
    }

    #[test]
    fn bad_voxel_orders_are_refused_naming_the_field() {
        for order in [&b"LPX"[..], b"LLS", b"LP"] {
            let err = axis_codes(order, "a.trk").unwrap_err().to_string();
            assert!(
                err.contains("a.trk") && err.contains("voxel_order"),
                "{err}"
            );
        }
    }
}
