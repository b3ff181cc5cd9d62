//! Writing a coefficient volume, atomically: as a 4D float32 NIfTI-1 file with the DWI's
//! header (affine, qform/sform codes, voxel size, units), or, when the name ends in
//! `.mif` or `.mif.gz`, as an MRtrix image with the DWI's affine (`io::mif::write`) and
//! the model in its header (`comments`, `glyphcast_sh_basis` or `glyphcast_tensor_order`).
//! A DTI tensor's six entries go into a `.mif` in MRtrix's order (xx, yy, zz, xy, xz,
//! yz), into NIfTI in the order asked for (glyphcast's by default, which is FSL's); the
//! description records it ("... in mrtrix order").
//! The fit's coefficients are in the DWI's voxel axes (see `gradients`); a NIfTI keeps
//! them so (DIPY's convention), while a `.mif` gets them turned into scanner axes, the
//! frame MRtrix stores and mrview draws (the same rotation `render` applies to a
//! voxel-frame volume, `volume::reorient`).
//!
//! The file is written by `io::image::write_image`, which owns both formats'
//! conventions and writes atomically; this module decides only what goes in it.
use ndarray::{Array4, Axis};
use std::path::Path;

use super::FitModel;
use super::dwi::Dwi;
use crate::io::image::{ImageWrite, OutputFormat, image_bytes, write_image};
use crate::io::nifti::VoxelToWorld;
use crate::volume::{Reorientation, tensor_description};
use glyphcast::glyph::sh::ShBasis;
use glyphcast::glyph::tensor_order::{DTI_COUNT, TensorOrder, negate_x};
use glyphcast::{Error, Result, Setting};

/// Refuses an SH or ODF fit written to a `.mif` (`path`, the output `option`) in any
/// basis but MRtrix's own (tournier07, not legacy): every MRtrix command reads a `.mif`'s
/// coefficients in that basis, whatever glyphcast records beside them. Checked before
/// any work.
pub fn check_output_basis(path: &Path, option: &'static str, model: &FitModel) -> Result<()> {
    let (FitModel::Sh { basis, legacy, .. } | FitModel::Odf(super::OdfModel { basis, legacy, .. })) =
        *model
    else {
        return Ok(());
    };
    if !is_mif(path) || (basis == ShBasis::Tournier07 && !legacy) {
        return Ok(());
    }
    let legacy = if legacy { " --legacy" } else { "" };
    Err(Error::setting_value(
        Setting::Basis,
        format!("{}{legacy}", basis.name()),
        format!(
            "{option} {} is an MRtrix image, whose SH coefficients MRtrix reads in its own \
             basis (tournier07) only: fit in tournier07 (--basis mrtrix) for a .mif, or write \
             NIfTI (.nii, .nii.gz) for this basis",
            path.display()
        ),
    ))
}

/// Whether `path` names an MRtrix image (`.mif`, `.mif.gz`).
fn is_mif(path: &Path) -> bool {
    OutputFormat::of(path, "output").is_ok_and(OutputFormat::is_mrtrix)
}

/// The stored order of a tensor fit's entries written to `path`: MRtrix's for an order-2
/// `.mif` (as `dwi2tensor` writes and every MRtrix command reads it), `given` (the
/// tensor order setting) or glyphcast's for NIfTI; every other tensor in glyphcast's
/// order. Checked before any work: an order `.mif` cannot hold is refused.
pub fn output_tensor_order(
    path: &Path,
    model: &FitModel,
    given: Option<TensorOrder>,
) -> Result<TensorOrder> {
    let FitModel::Tensor { order } = *model else {
        return match given {
            Some(_) => Err(Error::setting(
                Setting::TensorOrder,
                "orders the entries of a tensor fit, not of an SH or ODF fit",
            )),
            None => Ok(TensorOrder::Glyphcast),
        };
    };
    if let Some(given) = given {
        given.check_applies(order, true)?;
    }
    match (is_mif(path) && order == 2, given) {
        (true, Some(given)) if !given.stores_like(TensorOrder::Mrtrix) => {
            Err(Error::setting_value(
                Setting::TensorOrder,
                given,
                format!(
                    "a .mif tensor is stored in MRtrix's order ({}), which every MRtrix command \
                 reads; write NIfTI for {}'s order",
                    TensorOrder::Mrtrix.entries(),
                    given.owner()
                ),
            ))
        }
        (true, _) => Ok(TensorOrder::Mrtrix),
        (false, given) => Ok(given.unwrap_or_default()),
    }
}

/// `coeffs` with each voxel's six entries moved from glyphcast's order into `stored`, and
/// from the voxel axes into its frame on an image whose voxel-to-world map has this
/// `determinant` (FSL's negates x on a positive one: [`TensorOrder::negates_x`]).
fn stored_in(mut coeffs: Array4<f64>, stored: TensorOrder, determinant: f64) -> Array4<f64> {
    let negates_x = stored.negates_x(determinant);
    if (stored.is_glyphcast() && !negates_x) || coeffs.shape()[3] != DTI_COUNT {
        return coeffs;
    }
    for mut lane in coeffs.lanes_mut(Axis(3)) {
        let mut values: [f64; DTI_COUNT] = std::array::from_fn(|k| lane[k]);
        if negates_x {
            negate_x(&mut values);
        }
        for (out, value) in lane.iter_mut().zip(stored.from_glyphcast(&values)) {
            *out = value;
        }
    }
    coeffs
}

/// Writes the fitted `coeffs` of `dwi` to `path`, as MRtrix or NIfTI by its name; a
/// tensor's entries in `stored` order ([`output_tensor_order`]), recorded in the
/// description.
pub fn write_output(
    path: &Path,
    coeffs: &Array4<f64>,
    dwi: &Dwi,
    model: &FitModel,
    stored: TensorOrder,
) -> Result<()> {
    let description = match *model {
        FitModel::Tensor { order } => tensor_description(order, stored),
        _ => model.description(),
    };
    let (data, keys, voxel_to_world) = output_content(path, coeffs, dwi, model, stored)?;
    write_image(
        path,
        &output_image(&data, &keys, &voxel_to_world, dwi, &description),
    )
}

/// The bytes [`write_output`] writes, with `description` in the header, for outputs
/// written as one set (`io::atomic::write_all_atomic`: multi-tissue CSD's three images).
pub fn output_bytes(
    path: &Path,
    coeffs: &Array4<f64>,
    dwi: &Dwi,
    model: &FitModel,
    stored: TensorOrder,
    description: &str,
) -> Result<Vec<u8>> {
    let (data, keys, voxel_to_world) = output_content(path, coeffs, dwi, model, stored)?;
    image_bytes(
        path,
        &output_image(&data, &keys, &voxel_to_world, dwi, description),
    )
}

/// The image a fit writes: its values in the DWI's geometry (a NIfTI output keeps the
/// DWI's header).
fn output_image<'a>(
    data: &'a Array4<f64>,
    keys: &'a [(&'a str, String)],
    voxel_to_world: &'a VoxelToWorld,
    dwi: &'a Dwi,
    description: &'a str,
) -> ImageWrite<'a> {
    ImageWrite {
        data: data.view().into_dyn(),
        voxel_to_world,
        nifti_reference: Some(&dwi.header),
        description,
        mrtrix_keys: keys,
    }
}

/// What a fit stores in `path`'s format: the values (a `.mif`'s in scanner axes and a
/// tensor's in `stored` order), the MRtrix keys recording the model, the geometry.
type OutputContent = (Array4<f64>, Vec<(&'static str, String)>, VoxelToWorld);

fn output_content(
    path: &Path,
    coeffs: &Array4<f64>,
    dwi: &Dwi,
    model: &FitModel,
    stored: TensorOrder,
) -> Result<OutputContent> {
    let voxel_to_world = dwi.voxel_to_world()?;
    if !OutputFormat::of(path, "output")?.is_mrtrix() {
        let determinant = voxel_to_world.linear().determinant();
        let data = stored_in(coeffs.clone(), stored, determinant);
        return Ok((data, Vec::new(), voxel_to_world));
    }
    let key = match *model {
        FitModel::Sh { basis, legacy, .. }
        | FitModel::Odf(super::OdfModel { basis, legacy, .. }) => {
            let legacy = if legacy { " legacy" } else { "" };
            ("glyphcast_sh_basis", format!("{}{legacy}", basis.name()))
        }
        FitModel::Tensor { order } => ("glyphcast_tensor_order", order.to_string()),
    };
    let world = to_world_frame(coeffs, &voxel_to_world, model, &dwi.file)?;
    // A .mif holds MRtrix's order in scanner axes: no FSL frame to turn into.
    let data = stored_in(world, stored, 0.0);
    Ok((data, vec![key], voxel_to_world))
}

/// `coeffs` ([x, y, z, coefficient], in the DWI's voxel axes) turned into scanner axes:
/// each voxel's glyph g(u) = f(R^T u), R the orthogonal factor of `map`.
fn to_world_frame(
    coeffs: &Array4<f64>,
    map: &VoxelToWorld,
    model: &FitModel,
    dwi: &str,
) -> Result<Array4<f64>> {
    let rotation = map.orthogonal_factor().ok_or_else(|| {
        Error::input(
            dwi,
            "affine",
            "the polar decomposition of the affine did not converge",
        )
    })?;
    let rotate = Reorientation::new(rotation).for_kind(model.glyph_kind())?;
    let mut world = coeffs.clone();
    for mut glyph in world.lanes_mut(Axis(3)) {
        if glyph.iter().all(|&c| c == 0.0) {
            continue;
        }
        let voxel: Vec<f64> = glyph.iter().copied().collect();
        for (out, value) in glyph.iter_mut().zip(rotate.apply(&voxel)?) {
            *out = value;
        }
    }
    Ok(world)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// FSL's order goes into FSL's frame: xy and xz negated on an image with a positive
    /// determinant only; glyphcast's order is never turned.
    #[test]
    fn fsl_tensors_are_written_in_fsl_frame() {
        let entries = [1.0, 0.2, 0.3, 2.0, 0.4, 3.0];
        let coeffs = Array4::from_shape_vec((1, 1, 1, 6), entries.to_vec()).unwrap();
        let written = |order, determinant| {
            stored_in(coeffs.clone(), order, determinant)
                .iter()
                .copied()
                .collect::<Vec<f64>>()
        };
        assert_eq!(
            written(TensorOrder::Fsl, 8.0),
            [1.0, -0.2, -0.3, 2.0, 0.4, 3.0]
        );
        assert_eq!(written(TensorOrder::Fsl, -8.0), entries);
        assert_eq!(written(TensorOrder::Glyphcast, 8.0), entries);
    }
}
