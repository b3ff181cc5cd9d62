"""The demo cohort's subjects: DIPY's small_64D (tests/data/dipy) with Gaussian noise of
3 % of the mean b=0 signal seeded by the subject's number, so every run makes the same
cohort. Used by tools/cohort_demo.py (Nipype) and tools/cohort_slurm.py (job arrays);
needs numpy and nibabel.
"""
import os
import pathlib
import shutil

import nibabel as nib
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
DIPY = ROOT / "tests" / "data" / "dipy"
NOISE_FRACTION = 0.03


def make_subject(number, inputs):
    """Subject `number`'s DWI: small_64D plus seeded Gaussian noise, with its tables, in
    inputs/sub-XX/dwi/; returns the path stem (without .nii.gz). An existing complete
    subject folder is kept; a new one is written beside its place and renamed into it,
    so an interrupted run leaves no half-written subject."""
    subject = f"sub-{number:02d}"
    folder = inputs / subject / "dwi"
    stem = f"{subject}_dwi"
    if all((folder / f"{stem}{ext}").is_file() for ext in (".nii.gz", ".bval", ".bvec")):
        return folder / stem
    if (inputs / subject).exists():
        raise SystemExit(f"error: {inputs / subject} exists without a complete DWI "
                         f"({stem}.nii.gz, .bval, .bvec); remove it or give another OUTDIR")
    staging = inputs / f".{subject}.{os.getpid()}.tmp"
    shutil.rmtree(staging, ignore_errors=True)
    (staging / "dwi").mkdir(parents=True)
    source = nib.load(str(DIPY / "small_64D.nii"))
    data = np.asarray(source.dataobj, dtype=np.float32)
    bvals = np.loadtxt(DIPY / "small_64D.bval")
    sigma = NOISE_FRACTION * float(data[..., bvals <= 50].mean())
    noise = np.random.default_rng(number).normal(0.0, sigma, data.shape)
    noisy = np.clip(data + noise, 0.0, None).astype(np.float32)
    image = nib.Nifti1Image(noisy, source.affine, source.header)
    image.set_data_dtype(np.float32)
    nib.save(image, str(staging / "dwi" / f"{stem}.nii.gz"))
    shutil.copyfile(DIPY / "small_64D.bval", staging / "dwi" / f"{stem}.bval")
    shutil.copyfile(DIPY / "small_64D.bvec", staging / "dwi" / f"{stem}.bvec")
    staging.rename(inputs / subject)
    return folder / stem
