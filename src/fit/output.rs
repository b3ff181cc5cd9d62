//! Writing a coefficient volume, atomically: as a 4D float32 NIfTI-1 file with the DWI's
//! header (affine, qform/sform codes, voxel size, units), or, when the name ends in
//! `.mif` or `.mif.gz`, as an MRtrix image with the DWI's affine (`io::mif::write`) and
//! the model in its header (`comments`, `glyphcast_sh_basis` or `glyphcast_tensor_order`,
//! and `glyphcast_frame: voxel`: the coefficients are in voxel axes, see `gradients`).
//!
//! The `nifti` crate writes only to a path, and derives compression and the final file
//! name from that path's extension, so the temporary file keeps the target's `.nii` or
//! `.nii.gz` ending (`.NAME-PID-N-tmp.nii.gz` in the target's directory). It is flushed
//! to disk and renamed over the target, as `io::atomic` does for byte buffers; on any
//! failure it is removed.
use ndarray::Array4;
use nifti::NiftiHeader;
use nifti::writer::WriterOptions;
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use super::dwi::Dwi;
use super::{FitModel, basis_name};
use crate::io::mif::{MifKind, MifWrite, write_mif};
use crate::{Error, Result};

static TEMPORARY_COUNTER: AtomicU64 = AtomicU64::new(0);

/// The NIfTI endings the writer understands; anything else would be renamed by it.
const ENDINGS: [&str; 2] = [".nii.gz", ".nii"];

/// Checks that `path` names a `.nii`, `.nii.gz`, `.mif` or `.mif.gz` file (before any
/// work is done).
pub fn check_output_path(path: &Path) -> Result<()> {
    match MifKind::of(path) {
        Some(MifKind::Mif | MifKind::MifGz) => Ok(()),
        _ => nifti_ending(path).map(|_| ()),
    }
}

/// Writes the fitted `coeffs` of `dwi` to `path`, as MRtrix or NIfTI by its name.
pub fn write_output(path: &Path, coeffs: &Array4<f64>, dwi: &Dwi, model: &FitModel) -> Result<()> {
    match MifKind::of(path) {
        Some(MifKind::Mif | MifKind::MifGz) => {
            let voxel_to_world = dwi.voxel_to_world()?;
            let mut keys = vec![("comments", model.description())];
            match *model {
                FitModel::Sh { basis, legacy, .. } => {
                    let legacy = if legacy { " legacy" } else { "" };
                    keys.push((
                        "glyphcast_sh_basis",
                        format!("{}{legacy}", basis_name(basis)),
                    ));
                }
                FitModel::Tensor { order } => {
                    keys.push(("glyphcast_tensor_order", order.to_string()));
                }
            }
            keys.push(("glyphcast_frame", "voxel".to_string()));
            let data = coeffs.clone().into_dyn();
            write_mif(
                path,
                &MifWrite {
                    data: &data,
                    voxel_to_world: &voxel_to_world,
                    keys: &keys,
                },
            )
        }
        _ => write_coefficients(path, coeffs, &dwi.header, &model.description()),
    }
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
    let ending = nifti_ending(path)?;
    let mut header = reference.clone();
    header.intent_code = 0;
    header.intent_name = [0; 16];
    (header.intent_p1, header.intent_p2, header.intent_p3) = (0.0, 0.0, 0.0);
    (header.cal_min, header.cal_max, header.glmin, header.glmax) = (0.0, 0.0, 0, 0);
    let mut text: String = description.chars().filter(char::is_ascii).collect();
    text.truncate(79);
    header
        .set_description_str(text)
        .map_err(|err| Error::io(path, err))?;
    let data = coeffs.mapv(|v| v as f32);
    let temporary = temporary_path(path, ending)?;
    let written = WriterOptions::new(&temporary)
        .reference_header(&header)
        .write_nifti(&data)
        .map_err(|err| err.to_string())
        .and_then(|()| sync_and_rename(&temporary, path).map_err(|err| err.to_string()));
    written.map_err(|err| {
        // Best effort: the original error is the one worth reporting.
        let _ = fs::remove_file(&temporary);
        Error::io(path, err)
    })
}

fn sync_and_rename(temporary: &Path, path: &Path) -> std::io::Result<()> {
    fs::File::open(temporary)?.sync_all()?;
    fs::rename(temporary, path)
}

fn nifti_ending(path: &Path) -> Result<&'static str> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    ENDINGS
        .into_iter()
        .find(|e| name.len() > e.len() && name.ends_with(e))
        .ok_or_else(|| {
            Error::input(
                path.display().to_string(),
                "output",
                "expected a file name ending in .nii, .nii.gz, .mif or .mif.gz",
            )
        })
}

/// `.NAME-PID-N-tmp.nii(.gz)` with the dots of NAME replaced: the writer strips the
/// last extension and appends its own, which leaves such a name unchanged and would
/// rename one with inner dots.
fn temporary_path(path: &Path, ending: &str) -> Result<PathBuf> {
    let name = path
        .file_name()
        .ok_or_else(|| Error::io(path, "not a file path"))?
        .to_string_lossy()
        .replace('.', "_");
    let serial = TEMPORARY_COUNTER.fetch_add(1, Ordering::Relaxed);
    let temporary_name = format!(".{name}-{}-{serial}-tmp{ending}", std::process::id());
    Ok(path.with_file_name(temporary_name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporary_names_survive_the_writers_renaming() {
        for target in ["out.nii", "out.nii.gz", "a.b.c.nii.gz", "dir/x.y.nii"] {
            let path = Path::new(target);
            let ending = nifti_ending(path).unwrap();
            let temporary = temporary_path(path, ending).unwrap();
            // What nifti's WriterOptions::output_paths does to a .nii / .nii.gz path.
            let mut stripped = temporary.clone();
            stripped.set_extension("");
            assert_eq!(stripped.with_extension(&ending[1..]), temporary, "{target}");
            assert_eq!(temporary.parent(), path.parent());
        }
        for good in ["out.nii.gz", "out.mif", "out.mif.gz", "OUT.MIF"] {
            assert!(check_output_path(Path::new(good)).is_ok(), "{good}");
        }
        for bad in ["out.png", "out", ".nii", "out.nii.bak", "out.mih", ".mif"] {
            assert!(check_output_path(Path::new(bad)).is_err(), "{bad}");
        }
    }
}
