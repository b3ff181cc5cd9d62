"""A DIPY user's first hour (issue 28): DIPY's own CSD fit of small_64D drawn with the
basis names as DIPY means them, arrays as DIPY hands them over (views, Fortran order,
float32), NaN voxels left out as on the command line, warnings at the caller's line,
the underlay behind the glyphs, a robust default size, and the CLI's figure options as
keywords."""
import pathlib
import subprocess
import warnings
from collections import deque

import nibabel as nib
import numpy as np
import pytest

import glyphcast
from conftest import ROOT, assert_same_depth

dipy = pytest.importorskip("dipy")
from dipy.core.gradients import gradient_table  # noqa: E402
from dipy.reconst.csdeconv import (  # noqa: E402
    ConstrainedSphericalDeconvModel,
    auto_response_ssst,
)

DATA = ROOT / "tests" / "data" / "dipy"
SIZE = dict(width=128, height=128)


@pytest.fixture(scope="module")
def csd():
    """DIPY's CSD (band 8, its default basis: descoteaux07, legacy=True) of three axial
    slices of small_64D, with the response from auto_response_ssst; and the affine."""
    image = nib.load(DATA / "small_64D.nii")
    data = np.asarray(image.dataobj, dtype=np.float64)
    bvecs = np.nan_to_num(np.loadtxt(DATA / "small_64D.bvec"))
    bvecs = bvecs.T if bvecs.shape[0] == 3 else bvecs
    gtab = gradient_table(np.loadtxt(DATA / "small_64D.bval"), bvecs=bvecs)
    response, _ = auto_response_ssst(gtab, data, roi_radii=10, fa_thr=0.7)
    model = ConstrainedSphericalDeconvModel(gtab, response, sh_order_max=8)
    fit = model.fit(data[:, :, 4:7])
    return fit.shm_coeff, image.affine


def test_a_bare_descoteaux07_is_refused_and_the_choices_are_dipys(csd):
    """descoteaux07 alone names two bases (DIPY's default legacy one and its legacy=False
    one): refused without legacy=, naming both choices; basis="dipy" and legacy=True
    draw DIPY's default, basis="dipy-new" and legacy=False the other."""
    coeffs, affine = csd
    for name in ("descoteaux07", "Descoteaux07"):
        refusal = r"(?i)^basis='descoteaux07': names two bases"
        with pytest.raises(ValueError, match=refusal) as refused:
            glyphcast.render_sh(coeffs, affine, basis=name, **SIZE)
        message = str(refused.value)
        for choice in ("basis=dipy ", "legacy=True", "basis=dipy-new"):
            assert choice in message, message
    dipy_default = glyphcast.render_sh(coeffs, affine, basis="dipy", **SIZE)
    assert np.isfinite(dipy_default.depth).sum() > 200
    for name in ("DIPY", "dipy"):
        ours = glyphcast.render_sh(coeffs, affine, basis=name, **SIZE)
        assert_same_depth(ours.depth, dipy_default.depth)
    # legacy=True says the same; legacy=False is the other basis (glyphs differ).
    same = glyphcast.render_sh(coeffs, affine, basis="descoteaux07", legacy=True, **SIZE)
    assert_same_depth(same.depth, dipy_default.depth)
    other = glyphcast.render_sh(coeffs, affine, basis="descoteaux07", legacy=False, **SIZE)
    new = glyphcast.render_sh(coeffs, affine, basis="dipy-new", **SIZE)
    assert_same_depth(other.depth, new.depth)
    assert not np.array_equal(other.depth, dipy_default.depth, equal_nan=True)
    with pytest.raises(ValueError, match=r"^basis='dipy': names the legacy descoteaux07 "
                                         r"basis .*give basis=dipy-new$"):
        glyphcast.render_sh(coeffs, affine, basis="dipy", legacy=False)


def test_the_command_line_refuses_a_bare_descoteaux07_too(csd, cli_binary, tmp_path):
    """On a NIfTI that records no basis the command line refuses descoteaux07 alone as
    Python does, naming the file and both choices, and draws the aliases."""
    coeffs, affine = csd
    path = tmp_path / "fod.nii.gz"
    nib.save(nib.Nifti1Image(coeffs.astype(np.float32), affine), path)

    def run(*basis):
        depth = tmp_path / "d.npy"
        return depth, subprocess.run(
            [str(cli_binary), "render", "--sh", str(path), *basis, "--width", "64",
             "-o", str(tmp_path / "x.png"), "--depth-out", str(depth), "--validation"],
            capture_output=True, text=True,
        )

    _, refused = run("--basis", "descoteaux07")
    assert refused.returncode == 2, refused.stderr
    for word in ("fod.nii.gz", "--basis dipy ", "--legacy", "--basis dipy-new"):
        assert word in refused.stderr, refused.stderr
    drawn = {}
    for name, variant in (("Dipy", "descoteaux07, legacy"), ("DIPY-new", "descoteaux07")):
        depth, done = run("--basis", name)
        assert done.returncode == 0, done.stderr
        assert f"SH basis: {path}: {variant}\n" in done.stderr, done.stderr
        drawn[name] = np.load(depth)
    assert not np.array_equal(drawn["Dipy"], drawn["DIPY-new"], equal_nan=True)


def test_sh_order_max_is_lmax(csd):
    coeffs, affine = csd
    lmax = glyphcast.render_sh(coeffs, affine, basis="dipy", lmax=4, **SIZE)
    dipy_name = glyphcast.render_sh(coeffs, affine, basis="dipy", sh_order_max=4, **SIZE)
    assert_same_depth(dipy_name.depth, lmax.depth)
    full = glyphcast.render_sh(coeffs, affine, basis="dipy", **SIZE)
    assert not np.array_equal(full.depth, lmax.depth, equal_nan=True)
    with pytest.raises(ValueError, match=r"^sh_order_max: is DIPY's name for lmax"):
        glyphcast.render_sh(coeffs, affine, basis="dipy", lmax=4, sh_order_max=4)


def test_views_of_arrays_equal_their_copies(csd):
    coeffs, affine = csd
    # Wider than band 8 by a slab of zeros, so that [..., :45] is a strided view.
    padded = np.concatenate([coeffs, np.zeros(coeffs.shape[:3] + (5,))], axis=3)
    views = {
        "shm_coeff[..., :45]": padded[..., :45],
        "shm_coeff[..., :28]": coeffs[..., :28],
        "C[::-1]": coeffs[::-1],
        "C[:, :, 1:2]": coeffs[:, :, 1:2],
        "C[:, ::-1, ::2]": coeffs[:, ::-1, ::2],
        "Fortran order": np.asfortranarray(coeffs),
        "float32 view": coeffs.astype(np.float32)[:, ::-1],
    }
    for what, view in views.items():
        assert not view.flags.c_contiguous, what
        ours = glyphcast.render_sh(view, affine, basis="dipy", slice="axial:0", **SIZE)
        copy = glyphcast.render_sh(np.ascontiguousarray(view), affine, basis="dipy",
                                   slice="axial:0", **SIZE)
        assert_same_depth(ours.depth, copy.depth)
        assert np.array_equal(ours.rgba, copy.rgba), what
    # A cropped image encodes as its copy does.
    image = glyphcast.render_sh(coeffs, affine, basis="dipy", **SIZE)
    crop = image.rgba[10:50, 5:60]
    assert glyphcast.encode_png(crop) == glyphcast.encode_png(crop.copy())


def _warning_of(call, *args, **kwargs):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = call(*args, **kwargs)
    return result, caught


def test_nan_voxels_are_left_out_as_on_the_command_line(csd, cli_binary, tmp_path):
    coeffs, affine = csd
    bad = coeffs.astype(np.float32)
    bad[3, 4, 1, 7] = np.nan
    bad[5, 5, 1, :] = np.inf
    path = tmp_path / "fod.nii.gz"
    nib.save(nib.Nifti1Image(bad, affine), path)
    depth = tmp_path / "depth.npy"
    done = subprocess.run(
        [str(cli_binary), "render", "--sh", str(path), "--basis", "dipy", "--width", "128",
         "--height", "128", "-o", str(tmp_path / "x.png"), "--depth-out", str(depth),
         "--validation"],
        capture_output=True, text=True,
    )
    assert done.returncode == 0, done.stderr
    cli_warnings = [line for line in done.stderr.splitlines() if line.startswith("warning: ")]
    assert cli_warnings == [f"warning: {path}: 2 voxel(s) with NaN or infinite coefficients "
                            "left out"], done.stderr
    ours, caught = _warning_of(glyphcast.render_sh, bad, affine, basis="dipy", **SIZE)
    assert_same_depth(ours.depth, np.load(depth))
    messages = [str(w.message) for w in caught]
    assert messages == ["coeffs: 2 voxel(s) with NaN or infinite coefficients left out"]
    # The warning points at this file's line, not at glyphcast's own code.
    assert pathlib.Path(caught[0].filename).resolve() == pathlib.Path(__file__).resolve()
    # Through a Renderer too (another depth of calls inside the package).
    renderer = glyphcast.Renderer(validation=True)
    _, caught = _warning_of(renderer.render_sh, bad, affine, basis="dipy", **SIZE)
    assert pathlib.Path(caught[0].filename).resolve() == pathlib.Path(__file__).resolve()


def test_the_underlay_no_longer_hides_glyph_halves(csd):
    coeffs, affine = csd
    fa_like = np.linalg.norm(coeffs[..., 1:6], axis=-1)
    plain = glyphcast.render_sh(coeffs, affine, basis="dipy", **SIZE)
    behind = glyphcast.render_sh(coeffs, affine, basis="dipy", underlay=fa_like, **SIZE)
    centre = glyphcast.render_sh(coeffs, affine, basis="dipy", underlay=fa_like,
                                 underlay_plane="centre", **SIZE)
    glyphs = np.isfinite(plain.depth)
    assert glyphs.sum() > 200
    # Every glyph pixel stays a glyph pixel, at the same depth.
    assert np.isfinite(behind.depth[glyphs]).all()
    assert np.array_equal(behind.depth[glyphs], plain.depth[glyphs])
    # The plane through the centres hides the far halves.
    assert (~np.isfinite(centre.depth[glyphs])).sum() > 50
    # The underlay is drawn around the glyphs.
    assert not np.array_equal(behind.rgba[~glyphs], plain.rgba[~glyphs])


def _blob_sizes(mask):
    """Pixel counts of the 4-connected regions of `mask`."""
    seen = np.zeros_like(mask, dtype=bool)
    sizes = []
    for start in zip(*np.nonzero(mask)):
        if seen[start]:
            continue
        seen[start] = True
        queue, size = deque([start]), 0
        while queue:
            y, x = queue.popleft()
            size += 1
            for ny, nx in ((y + 1, x), (y - 1, x), (y, x + 1), (y, x - 1)):
                if (0 <= ny < mask.shape[0] and 0 <= nx < mask.shape[1] and mask[ny, nx]
                        and not seen[ny, nx]):
                    seen[ny, nx] = True
                    queue.append((ny, nx))
        sizes.append(size)
    return np.array(sizes)


def test_an_outlier_leaves_the_others_size():
    # Band-0 spheres of radius 1 on a 6x6 slice, one of radius 10 (CSF-like).
    coeffs = np.zeros((6, 6, 1, 1))
    coeffs[..., 0] = 1.0
    spiked = coeffs.copy()
    spiked[2, 3, 0, 0] = 10.0
    size = dict(width=120, height=120)

    def typical_diameter(volume, **options):
        image = glyphcast.render_sh(volume, basis="dipy", **size, **options)
        sizes = _blob_sizes(np.isfinite(image.depth))
        assert len(sizes) == 36, len(sizes)
        return np.sqrt(np.median(sizes))

    before = typical_diameter(coeffs)
    after = typical_diameter(spiked)
    assert abs(before / after - 1.0) < 0.02, (before, after)
    # Global normalisation (the old default) shrinks them 10x.
    assert before / typical_diameter(spiked, norm="global") > 5.0


def test_figure_keywords_as_users_pass_them(csd, cli_binary, tmp_path):
    coeffs, affine = csd
    # slice=1: the default plane's (axial) index 1.
    as_int = glyphcast.render_sh(coeffs, affine, basis="dipy", slice=1, **SIZE)
    as_text = glyphcast.render_sh(coeffs, affine, basis="dipy", slice="axial:1", **SIZE)
    assert_same_depth(as_int.depth, as_text.depth)
    # norm=True: FURY's per-glyph normalisation; False: none.
    fury = glyphcast.render_sh(coeffs, affine, basis="dipy", norm=True, **SIZE)
    named = glyphcast.render_sh(coeffs, affine, basis="dipy", norm="per-glyph", **SIZE)
    assert_same_depth(fury.depth, named.depth)
    # colorbar=True: the CLI's --colorbar, the image grows by the bar's strip.
    path = tmp_path / "fod.nii.gz"
    nib.save(nib.Nifti1Image(coeffs.astype(np.float32), affine), path)
    png, depth = tmp_path / "bar.png", tmp_path / "bar.npy"
    done = subprocess.run(
        [str(cli_binary), "render", "--sh", str(path), "--basis", "dipy", "--width", "128",
         "--height", "128", "--color", "magnitude", "--colorbar", "--colorbar-label", "fODF",
         "-o", str(png), "--depth-out", str(depth), "--validation"],
        capture_output=True, text=True,
    )
    assert done.returncode == 0, done.stderr
    ours = glyphcast.render_sh(coeffs.astype(np.float32), affine, basis="dipy",
                               color="magnitude", colorbar=True, colorbar_label="fODF",
                               **SIZE)
    assert ours.rgba.shape[1] > 128
    assert_same_depth(ours.depth, np.load(depth))
    assert ours.png() == png.read_bytes()
    with pytest.raises(ValueError, match=r"^colorbar: shows the magnitude colour map: it "
                                         r"needs color=magnitude$"):
        glyphcast.render_sh(coeffs, affine, basis="dipy", colorbar=True)


def test_a_three_view_figure_with_an_underlay_matches_the_cli(csd, cli_binary, tmp_path):
    coeffs, affine = csd
    fa_like = np.linalg.norm(coeffs[..., 1:6], axis=-1).astype(np.float32)
    path, fa = tmp_path / "fod.nii.gz", tmp_path / "fa.nii.gz"
    nib.save(nib.Nifti1Image(coeffs.astype(np.float32), affine), path)
    nib.save(nib.Nifti1Image(fa_like, affine), fa)
    for flags, keywords in [
        (["--views", "axial,coronal,sagittal"], dict(views=["axial", "coronal", "sagittal"])),
        (["--lightbox", "3"], dict(lightbox=3)),
    ]:
        png, depth = tmp_path / "m.png", tmp_path / "m.npy"
        done = subprocess.run(
            [str(cli_binary), "render", "--sh", str(path), "--basis", "dipy", "--width", "64",
             "--height", "64", "--underlay", str(fa), *flags, "-o", str(png),
             "--depth-out", str(depth), "--validation"],
            capture_output=True, text=True,
        )
        assert done.returncode == 0, done.stderr
        ours = glyphcast.render_sh(coeffs.astype(np.float32), affine, basis="dipy",
                                   width=64, height=64, underlay=fa, **keywords)
        assert_same_depth(ours.depth, np.load(depth))
        assert ours.png() == png.read_bytes()
