"""The same input through the Python module and through `glyphcast render` gives the same
depth map, bit for bit, and the same colours."""
import json

import nibabel as nib
import numpy as np
import pytest

import glyphcast
from conftest import assert_same_depth


@pytest.mark.parametrize("method", [None, "affine", "fixed"])
def test_scene_file_and_dict_match_cli(scenes, cli_depth, method):
    scene = scenes / "order4_pair.json"
    options = [] if method is None else ["--method", method]
    cli = cli_depth(scene, "--width", 96, "--height", 72, *options)
    from_path = glyphcast.render_scene(scene, width=96, height=72, method=method)
    from_dict = glyphcast.render_scene(
        json.loads(scene.read_text()), width=96, height=72, method=method
    )
    assert_same_depth(from_path.depth, cli)
    assert_same_depth(from_dict.depth, cli)
    assert from_path.rgba.shape == (72, 96, 4) and from_path.rgba.dtype == np.uint8
    assert np.array_equal(from_path.rgba, from_dict.rgba)


def test_render_options_reach_the_renderer(scenes, cli_depth):
    scene = scenes / "order4_pair.json"
    cli = cli_depth(scene, "--width", 64, "--height", 48, "--method", "affine", "--offset", "0.2")
    ours = glyphcast.render_scene(scene, width=64, height=48, method="affine", offset=0.2)
    plain = glyphcast.render_scene(scene, width=64, height=48, method="affine")
    assert_same_depth(ours.depth, cli)
    # The offset makes the glyphs larger: more pixels hit than without it.
    assert np.isfinite(ours.depth).sum() > np.isfinite(plain.depth).sum()


@pytest.mark.parametrize("slice_", ["axial:mid", "coronal:1", "sagittal:0"])
def test_render_sh_on_func_coef_matches_cli(func_coef, cli_depth, slice_):
    image = nib.load(func_coef)
    coeffs = image.get_fdata()
    cli_slice = slice_.replace(":mid", "")
    cli = cli_depth(
        "--sh", func_coef, "--basis", "dipy", "--slice", cli_slice, "--width", 120
    )
    ours = glyphcast.render_sh(coeffs, image.affine, basis="dipy", slice=slice_, width=120)
    assert_same_depth(ours.depth, cli)
    # float32 input, as a fit may store it, draws the same glyphs as the file's float32
    # values promoted to float64 (func_coef holds float32 values).
    as_f32 = glyphcast.render_sh(
        coeffs.astype(np.float32), image.affine, basis="dipy", slice=slice_, width=120
    )
    assert_same_depth(as_f32.depth, cli)


def test_render_sh_mask_and_scale_match_cli(func_coef, cli_depth, tmp_path):
    image = nib.load(func_coef)
    mask = np.zeros(image.shape[:3], dtype=np.uint8)
    mask[0, :, :] = 1
    mask_file = tmp_path / "mask.nii.gz"
    nib.save(nib.Nifti1Image(mask, image.affine), mask_file)
    cli = cli_depth(
        "--sh", func_coef, "--basis", "dipy", "--mask", mask_file, "--scale", "0.3",
        "--norm", "per-glyph", "--width", 100,
    )
    ours = glyphcast.render_sh(
        image.get_fdata(), image.affine, basis="dipy", mask=mask, scale=0.3,
        norm="per-glyph", width=100,
    )
    assert_same_depth(ours.depth, cli)


def test_render_tensor_matches_cli(cli_depth, tmp_path):
    # Order-2 tensors, diagonal with a varying anisotropy, on a 3x2x1 grid with 2 mm
    # voxels: xx, xy, xz, yy, yz, zz.
    coeffs = np.zeros((3, 2, 1, 6), dtype=np.float32)
    for i in range(3):
        for j in range(2):
            coeffs[i, j, 0] = [1.0 + i, 0.1 * j, 0.0, 0.5, 0.0, 0.3 + 0.2 * j]
    affine = np.diag([2.0, 2.0, 2.0, 1.0])
    affine[:3, 3] = [-3.0, 1.0, 5.0]
    path = tmp_path / "tensors.nii.gz"
    nib.save(nib.Nifti1Image(coeffs, affine), path)
    cli = cli_depth("--tensor", path, "--order", 2, "--width", 90)
    ours = glyphcast.render_tensor(coeffs, affine, order=2, width=90)
    assert_same_depth(ours.depth, cli)


def test_samples_supersample_as_the_cli_does(scenes, cli_render):
    scene = scenes / "order4_pair.json"
    depth, png = cli_render(scene, "--width", 64, "--height", 48, "--samples", 4)
    renderer = glyphcast.Renderer(validation=True)
    ours = renderer.render_scene(scene, width=64, height=48, samples=4)
    assert_same_depth(ours.depth, depth)
    assert ours.png() == png
    # Anti-aliased: edge pixels are partly covered, unlike the one-sample image's.
    single = glyphcast.render_scene(scene, width=64, height=48)
    assert not np.array_equal(single.rgba, ours.rgba)
    # Drawn again, and from a camera.
    assert renderer.render().png() == png
    camera = json.loads(scene.read_text())["camera"]
    assert renderer.render(camera=camera).png() == png


def test_dpi_writes_the_bytes_the_cli_writes(scenes, cli_render):
    """``png(dpi=300)`` is the CLI's ``--dpi 300`` file, byte for byte, and a bad dpi is a
    ValueError naming it."""
    scene = scenes / "order4_pair.json"
    _, png = cli_render(scene, "--width", 64, "--height", 48, "--dpi", 300)
    ours = glyphcast.render_scene(scene, width=64, height=48)
    assert ours.png(dpi=300) == png
    assert ours.png() != png
    assert b"pHYs" in png
    with pytest.raises(ValueError, match=r"^dpi=0: must be above 0"):
        ours.png(dpi=0.0)
