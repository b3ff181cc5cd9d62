"""``block=True``: every voxel of ``voxels`` drawn in 3D, as ``glyphcast render --block``
draws it, on the fODFs glyphcast fits to DIPY's small_64D (tests/data/dipy) and on
tensors; what a block does not go with raises ValueError naming both keywords."""
import nibabel as nib
import numpy as np
import pytest

import glyphcast
from conftest import ROOT, assert_same_depth

DATA = ROOT / "tests" / "data" / "dipy"


@pytest.fixture(scope="module")
def fod(tmp_path_factory, cli_binary):
    """CSD fODFs (band 8, DIPY's basis) of small_64D, fitted by ``glyphcast fit``."""
    import subprocess

    path = tmp_path_factory.mktemp("block") / "fod.nii.gz"
    done = subprocess.run(
        [str(cli_binary), "fit", str(DATA / "small_64D.nii"), "--bval",
         str(DATA / "small_64D.bval"), "--bvec", str(DATA / "small_64D.bvec"), "--odf",
         "csd", "--order", "8", "--basis", "dipy", "--quiet", "-o", str(path)],
        capture_output=True, text=True,
    )
    assert done.returncode == 0, done.stderr
    return path


def test_a_block_of_arrays_is_the_command_lines(fod, cli, tmp_path):
    image = nib.load(fod)
    coeffs = image.get_fdata()
    i, j, k = np.meshgrid(*(np.arange(n) for n in image.shape[:3]), indexing="ij")
    mask = ((i + 2 * j + 3 * k) % 5 != 0).astype(np.uint8)
    mask_file = tmp_path / "mask.nii.gz"
    nib.save(nib.Nifti1Image(mask, image.affine), mask_file)
    voxels = "2:8,1:9,3:7"
    png, depth = tmp_path / "block.png", tmp_path / "block.npy"
    done = cli(
        "render", "--sh", fod, "--block", "--voxels", voxels, "--mask", mask_file,
        "--norm", "per-glyph", "--width", 160, "--height", 120, "-o", png,
        "--depth-out", depth,
    )
    # Every voxel of the range the mask keeps, counted here.
    kept = int(mask[2:8, 1:9, 3:7].sum())
    assert f"block {voxels}: {kept} glyphs from {6 * 8 * 4} voxels" in done.stderr
    renderer = glyphcast.Renderer()
    ours = renderer.render_sh(
        coeffs.astype(np.float32), image.affine, basis="dipy", block=True, voxels=voxels,
        mask=mask, norm="per-glyph", width=160, height=120,
    )
    assert renderer.glyph_count == kept
    assert_same_depth(ours.depth, np.load(depth))
    assert ours.png() == png.read_bytes()
    # The whole volume without voxels: every voxel of the 10 x 10 x 10 fit.
    whole = glyphcast.Renderer()
    whole.render_sh(coeffs, image.affine, basis="dipy", block=True, width=32, height=32)
    assert whole.glyph_count == 1000


def test_a_block_of_tensors_is_the_command_lines(cli_depth, tmp_path):
    coeffs = np.zeros((3, 4, 2, 6), dtype=np.float32)
    for index in np.ndindex(3, 4, 2):
        i, j, k = index
        coeffs[index] = [1.0 + i, 0.1 * j, 0.05 * k, 0.5, 0.0, 0.3 + 0.2 * j]
    affine = np.diag([2.0, 2.0, 2.5, 1.0])
    affine[:3, 3] = [-3.0, 1.0, 5.0]
    path = tmp_path / "tensors.nii.gz"
    nib.save(nib.Nifti1Image(coeffs, affine), path)
    cli = cli_depth("--tensor", path, "--order", 2, "--block", "--width", 90)
    ours = glyphcast.render_tensor(coeffs, affine, order=2, block=True, width=90)
    assert_same_depth(ours.depth, cli)


@pytest.mark.parametrize(
    "keywords, message",
    [
        (dict(slice="axial:1"), r"^give either block=True or slice, not both$"),
        (dict(slices="mid"), r"^give either block=True or slices, not both$"),
        (dict(views="axial"), r"^give either block=True or views, not both$"),
        (dict(lightbox=2), r"^give either block=True or lightbox, not both$"),
        (dict(underlay=np.ones((10, 10, 10))), r"^block=True does not go with underlay$"),
        (dict(voxels="0:2,0:2,10:12"), r"leave no voxel of this 10x10x10 volume"),
    ],
)
def test_what_a_block_does_not_take_raises(fod, keywords, message):
    image = nib.load(fod)
    with pytest.raises(ValueError, match=message):
        glyphcast.render_sh(image.get_fdata(), image.affine, basis="dipy", block=True,
                            **keywords)
