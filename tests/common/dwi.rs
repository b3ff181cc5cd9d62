//! The DWI fixtures the fit tests share: DIPY's small_64D and the multi-shell mixtures of
//! tests/data/msmt, loaded as `fit` reads them or given to the command, and the small
//! readers of their JSON fixtures.
use super::{dipy_data, glyphcast, test_data, text};
use glam::DVec3;
use glyphcast_dmri::fit::{FitFiles, FitInputs};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Output;

/// A DWI with its b-value and b-vector files.
pub struct DwiFiles {
    /// The diffusion-weighted image.
    pub dwi: PathBuf,
    /// Its `.bval` file.
    pub bval: PathBuf,
    /// Its `.bvec` file (FSL layout).
    pub bvec: PathBuf,
}

impl DwiFiles {
    /// DIPY's small_64D (tests/data/dipy): one shell of 64 directions at b = 1000.
    pub fn small_64d() -> Self {
        DwiFiles {
            dwi: dipy_data("small_64D.nii"),
            bval: dipy_data("small_64D.bval"),
            bvec: dipy_data("small_64D.bvec"),
        }
    }

    /// tests/data/msmt: a 5x5x3 DWI of known WM/GM/CSF mixtures at b = 0, 1000, 2000 and
    /// 3000 (`tools/msmt_fixtures.py`).
    pub fn msmt() -> Self {
        DwiFiles {
            dwi: test_data("msmt", "dwi.nii.gz"),
            bval: test_data("msmt", "dwi.bval"),
            bvec: test_data("msmt", "dwi.bvec"),
        }
    }

    /// The inputs of `fit`, the b-vectors taken as stored (in the voxel axes, as DIPY
    /// reads them: no `--bvec-convention` transform), without a mask.
    pub fn inputs(&self) -> FitInputs {
        FitInputs::load(FitFiles {
            dwi: self.dwi.clone(),
            bval: Some(self.bval.clone()),
            bvec: Some(self.bvec.clone()),
            mask: None,
        })
        .unwrap_or_else(|e| panic!("loading {}: {e}", self.dwi.display()))
    }

    /// The arguments of `glyphcast fit` on this DWI with the model options `args`, into
    /// `out`.
    pub fn fit_args<'a>(&'a self, args: &[&'a str], out: &'a Path) -> Vec<&'a str> {
        let mut all = vec![
            "fit",
            text(&self.dwi),
            "--bval",
            text(&self.bval),
            "--bvec",
            text(&self.bvec),
        ];
        all.extend_from_slice(args);
        all.extend_from_slice(&["-o", text(out)]);
        all
    }
}

/// `glyphcast fit` of DIPY's small_64D (its b-values and b-vectors) with `args` (the
/// model: `--odf csd`, `--order`, `--basis` ...) into `out`; the run's output.
pub fn fit_small_64d(args: &[&str], out: &Path) -> Output {
    glyphcast(&DwiFiles::small_64d().fit_args(args, out))
}

/// `glyphcast fit --order 2` on DIPY's small_64D into `dir/dti.nii.gz`: the DTI volume
/// the ellipsoid and montage tests draw. Fails the test when the fit fails.
pub fn fit_dti_small_64d(dir: &Path) -> PathBuf {
    let out = dir.join("dti.nii.gz");
    let run = fit_small_64d(&["--order", "2", "--quiet"], &out);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    out
}

/// The numbers of a JSON array of a fixture.
pub fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("an array")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}

/// The angle in degrees between the axis `a` (either sign) and `b`.
pub fn axis_angle(a: DVec3, b: DVec3) -> f64 {
    a.normalize()
        .dot(b.normalize())
        .abs()
        .min(1.0)
        .acos()
        .to_degrees()
}

/// The largest difference between `ours` and `theirs` coefficient by coefficient, and the
/// largest magnitude among `theirs`: the scale a difference is judged against.
pub fn largest_difference(ours: &[f64], theirs: &[f64]) -> (f64, f64) {
    assert_eq!(ours.len(), theirs.len(), "coefficient counts differ");
    let scale = theirs.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let error = ours
        .iter()
        .zip(theirs)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    (error, scale)
}
