"""Peaks (issue 24) through the Python module: ``peaks=`` as a path or as arrays on the
coefficients' grid (sh2peaks' (X, Y, Z, 3N), DIPY's (X, Y, Z, N, 3) with ``peak_values=``)
draws what ``glyphcast render --peaks`` draws, bit for bit; bad peak arrays and options
raise ValueError naming the keyword."""
import subprocess

import nibabel as nib
import numpy as np
import pytest

import glyphcast
from conftest import assert_same_depth


def oblique_affine():
    """2 mm voxels turned 30 degrees about z and 20 about x, shifted."""
    a, b = np.radians(30.0), np.radians(20.0)
    rz = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    rx = np.array([[1, 0, 0], [0, np.cos(b), -np.sin(b)], [0, np.sin(b), np.cos(b)]])
    affine = np.eye(4)
    affine[:3, :3] = rz @ rx * 2.0
    affine[:3, 3] = [-3.0, 4.0, 1.5]
    return affine


@pytest.fixture(scope="module")
def fod_and_peaks(cli_binary, func_coef, tmp_path_factory):
    """DIPY's func_coef on an oblique grid and `glyphcast peaks` of it (float32 NIfTI)."""
    folder = tmp_path_factory.mktemp("peaks")
    image = nib.load(func_coef)
    fod = folder / "fod.nii.gz"
    nib.save(nib.Nifti1Image(image.get_fdata().astype(np.float32), oblique_affine()), fod)
    peaks = folder / "peaks.nii.gz"
    # `peaks` runs on the CPU (no --validation).
    done = subprocess.run([str(cli_binary), "peaks", str(fod), "--basis", "dipy", "-o",
                           str(peaks), "--quiet"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return fod, peaks


def dipy_layout(sh2peaks):
    """DIPY's peak_dirs (X, Y, Z, N, 3), unit or zero, and peak_values (X, Y, Z, N)."""
    x, y, z, n3 = sh2peaks.shape
    vectors = np.nan_to_num(sh2peaks.reshape(x, y, z, n3 // 3, 3), nan=0.0)
    values = np.linalg.norm(vectors, axis=-1)
    dirs = np.divide(vectors, values[..., None], out=np.zeros_like(vectors),
                     where=values[..., None] > 0)
    return dirs, values


STYLE = dict(peaks_color="yellow", peaks_norm="unit", peaks_scale=0.8, peaks_width=3)
STYLE_FLAGS = ["--peaks-color", "yellow", "--peaks-norm", "unit", "--peaks-scale", 0.8,
               "--peaks-width", 3]


def test_peak_arrays_and_paths_draw_what_the_cli_draws(fod_and_peaks, cli_render):
    fod, peaks = fod_and_peaks
    image = nib.load(fod)
    coeffs, affine = image.get_fdata(), image.affine
    sh2peaks = nib.load(peaks).get_fdata()
    assert np.isfinite(sh2peaks).any() and np.isnan(sh2peaks).any()
    common = ["--sh", fod, "--basis", "dipy", "--scale", 0.3, "--slice", "axial:1",
              "--width", 120, "--height", 100]
    depth, png = cli_render(*common, "--peaks", peaks)
    kwargs = dict(basis="dipy", scale=0.3, slice="axial:1", width=120, height=100)
    for given in (peaks, str(peaks), sh2peaks, sh2peaks.astype(np.float32)):
        ours = glyphcast.render_sh(coeffs, affine, peaks=given, **kwargs)
        assert_same_depth(ours.depth, depth)
        assert ours.png() == png
    # The peaks are drawn: without them the image differs.
    plain = glyphcast.render_sh(coeffs, affine, **kwargs)
    assert np.isfinite(depth).sum() > np.isfinite(plain.depth).sum()
    # The style keywords, as the flags.
    depth, png = cli_render(*common, "--peaks", peaks, *STYLE_FLAGS)
    ours = glyphcast.render_sh(coeffs, affine, peaks=sh2peaks, **kwargs, **STYLE)
    assert_same_depth(ours.depth, depth)
    assert ours.png() == png
    yellow = (ours.rgba[..., 0] > 100) & (ours.rgba[..., 1] > 100) & (ours.rgba[..., 2] < 60)
    assert yellow.sum() > 50


def test_dipy_arrays_draw_what_the_cli_draws_from_dipy_files(fod_and_peaks, cli_render,
                                                             tmp_path):
    fod, peaks = fod_and_peaks
    image = nib.load(fod)
    coeffs, affine = image.get_fdata(), image.affine
    dirs, values = dipy_layout(nib.load(peaks).get_fdata())
    # float64 files: the CLI reads the very values the arrays hold.
    dirs_file, values_file = tmp_path / "dirs.nii.gz", tmp_path / "values.nii.gz"
    nib.save(nib.Nifti1Image(dirs, affine), dirs_file)
    nib.save(nib.Nifti1Image(values, affine), values_file)
    depth, png = cli_render(
        "--sh", fod, "--basis", "dipy", "--scale", 0.3, "--width", 120, "--height", 100,
        "--peaks", dirs_file, "--peak-values", values_file, "--peaks-norm", "global",
    )
    kwargs = dict(basis="dipy", scale=0.3, width=120, height=100, peaks_norm="global")
    for d, v in ((dirs, values), (dirs.reshape(*dirs.shape[:3], -1), values),
                 (dirs_file, values_file)):
        ours = glyphcast.render_sh(coeffs, affine, peaks=d, peak_values=v, **kwargs)
        assert_same_depth(ours.depth, depth)
        assert ours.png() == png
    # Without the values, the DIPY directions are the peaks at one length: another image.
    unit = glyphcast.render_sh(coeffs, affine, peaks=dirs, **kwargs)
    assert not np.array_equal(unit.depth, depth, equal_nan=True)


def test_peaks_in_a_montage_draw_what_the_cli_draws(fod_and_peaks, cli_render):
    fod, peaks = fod_and_peaks
    image = nib.load(fod)
    sh2peaks = nib.load(peaks).get_fdata()
    depth, png = cli_render(
        "--sh", fod, "--basis", "dipy", "--scale", 0.3, "--width", 80, "--height", 64,
        "--views", "axial,coronal", "--peaks", peaks, "--peaks-color", "white",
    )
    ours = glyphcast.render_sh(
        image.get_fdata(), image.affine, basis="dipy", scale=0.3, width=80, height=64,
        views=["axial", "coronal"], peaks=sh2peaks, peaks_color="white",
    )
    assert_same_depth(ours.depth, depth)
    assert ours.png() == png
    white = (ours.rgba[..., :3].min(axis=-1) > 200).sum(axis=0)
    assert white[:80].sum() > 20 and white[80:].sum() > 20, "peaks in both panels"


def raises(match, **kwargs):
    def check(coeffs, affine):
        with pytest.raises(ValueError, match=match):
            glyphcast.render_sh(coeffs, affine, basis="dipy", width=64, **kwargs)
    return check


def test_bad_peak_arrays_and_options_name_the_keyword(fod_and_peaks):
    fod, peaks = fod_and_peaks
    image = nib.load(fod)
    coeffs, affine = image.get_fdata(), image.affine
    sh2peaks = nib.load(peaks).get_fdata()
    dirs, values = dipy_layout(sh2peaks)
    for check in [
        raises(r"peaks: dim\[4\]: 4 volumes is not a multiple of 3",
               peaks=sh2peaks[..., :4].copy()),
        raises(r"peaks: dim: the peaks' grid is 1x3x4 voxels and coeffs's is 2x3x4",
               peaks=sh2peaks[:1].copy()),
        raises(r"peaks: data: no peak anywhere", peaks=np.full_like(sh2peaks, np.nan)),
        raises(r"peaks: dtype int64 where float32 or float64 is needed",
               peaks=np.ones(sh2peaks.shape, dtype=np.int64)),
        raises(r"peaks: expected a path or a numpy array, got list", peaks=[1.0, 2.0]),
        raises(r"peak_values: dim: the peak values are 2x3x4x4 where",
               peaks=dirs, peak_values=np.ones((2, 3, 4, 4))),
        raises(r"peaks: data: peak 0 of voxel .* has length .*unit vectors",
               peaks=2.0 * dirs, peak_values=values),
        raises(r"peak_values: an array goes with a peaks array", peaks=peaks,
               peak_values=values),
        raises(r"peak_values: expected a numpy array \(as peaks\), got str", peaks=dirs,
               peak_values="values.nii.gz"),
        raises(r"peak_values: needs peaks", peak_values=values),
        raises(r"peaks_color='purple': expected direction", peaks=sh2peaks,
               peaks_color="purple"),
        raises(r"peaks_norm='longest': expected global, unit or none", peaks=sh2peaks,
               peaks_norm="longest"),
        raises(r"peaks_width=0: must be a number of pixels", peaks=sh2peaks, peaks_width=0),
        raises(r"peaks_scale=-1: must be a positive number", peaks=sh2peaks,
               peaks_scale=-1.0),
        raises(r"peaks_width: needs peaks", peaks_width=3),
    ]:
        check(coeffs, affine)
