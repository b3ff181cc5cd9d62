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
//! The NIfTI file is encoded in memory (`io::nifti::write`) and written with
//! `io::atomic`: to a temporary beside the target, flushed, then renamed over it.
use ndarray::{Array4, Axis};
use std::path::Path;

use super::FitModel;
use super::dwi::Dwi;
use crate::io::mif::{MifKind, MifWrite, mif_file_bytes};
use crate::io::nifti::NiftiHeader;
use crate::io::nifti::VoxelToWorld;
use crate::io::nifti::write::nifti1_bytes;
use crate::volume::{Reorientation, tensor_description};
use glyphcast::glyph::sh::ShBasis;
use glyphcast::glyph::tensor_order::{DTI_COUNT, TensorOrder, negate_x};
use glyphcast::io::atomic::write_atomic;
use glyphcast::{Error, Result, Setting};

/// The NIfTI endings written.
const ENDINGS: [&str; 2] = [".nii.gz", ".nii"];

/// Checks that `path` names a `.nii`, `.nii.gz`, `.mif` or `.mif.gz` file (before any
/// work is done); an [`Error::OutputName`] naming `option` (the front end's name for the
/// output) otherwise.
pub fn check_output_path(path: &Path, option: &'static str) -> Result<()> {
    match MifKind::of(path) {
        Some(MifKind::Mif | MifKind::MifGz) => Ok(()),
        _ => nifti_ending(path, option).map(|_| ()),
    }
}

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
    matches!(MifKind::of(path), Some(MifKind::Mif | MifKind::MifGz))
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
    write_atomic(
        path,
        &output_bytes(path, coeffs, dwi, model, stored, &description)?,
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
    let description = description.to_string();
    match MifKind::of(path) {
        Some(MifKind::Mif | MifKind::MifGz) => {
            let voxel_to_world = dwi.voxel_to_world()?;
            let mut keys = vec![("comments", description)];
            match *model {
                FitModel::Sh { basis, legacy, .. }
                | FitModel::Odf(super::OdfModel { basis, legacy, .. }) => {
                    let legacy = if legacy { " legacy" } else { "" };
                    keys.push(("glyphcast_sh_basis", format!("{}{legacy}", basis.name())));
                }
                FitModel::Tensor { order } => {
                    keys.push(("glyphcast_tensor_order", order.to_string()));
                }
            }
            let world = to_world_frame(coeffs, &voxel_to_world, model, &dwi.file)?;
            // A .mif holds MRtrix's order in scanner axes: no FSL frame to turn into.
            let data = stored_in(world, stored, 0.0).into_dyn();
            mif_file_bytes(
                path,
                &MifWrite {
                    data: &data,
                    voxel_to_world: &voxel_to_world,
                    keys: &keys,
                },
            )
        }
        _ => coefficient_bytes(
            path,
            &stored_in(
                coeffs.clone(),
                stored,
                dwi.voxel_to_world()?.linear().determinant(),
            ),
            &dwi.header,
            &description,
        ),
    }
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

/// Writes `coeffs` ([x, y, z, coefficient]) as float32, copying `reference`'s header
/// apart from the fields that describe the data (dim, datatype, scaling, intent,
/// display range), with `description` in `descrip`.
pub fn write_coefficients(
    path: &Path,
    coeffs: &Array4<f64>,
    reference: &NiftiHeader,
    description: &str,
) -> Result<()> {
    write_atomic(
        path,
        &coefficient_bytes(path, coeffs, reference, description)?,
    )
}

/// The bytes [`write_coefficients`] writes.
fn coefficient_bytes(
    path: &Path,
    coeffs: &Array4<f64>,
    reference: &NiftiHeader,
    description: &str,
) -> Result<Vec<u8>> {
    let ending = nifti_ending(path, "output")?;
    let mut header = reference.clone();
    header.intent_code = 0;
    header.intent_name = [0; 16];
    (header.intent_p1, header.intent_p2, header.intent_p3) = (0.0, 0.0, 0.0);
    (header.cal_min, header.cal_max) = (0.0, 0.0);
    header.set_description(description);
    let file = path.display().to_string();
    nifti1_bytes(
        &header,
        coeffs.view().into_dyn(),
        ending == ".nii.gz",
        &file,
    )
}

fn nifti_ending(path: &Path, option: &'static str) -> Result<&'static str> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    ENDINGS
        .into_iter()
        .find(|e| name.len() > e.len() && name.ends_with(e))
        .ok_or_else(|| Error::OutputName {
            option,
            path: path.display().to_string(),
            format: "NIfTI or MRtrix images".into(),
            endings: [".nii", ".nii.gz", ".mif", ".mif.gz"]
                .map(String::from)
                .to_vec(),
        })
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
