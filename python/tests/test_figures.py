"""The figure options (underlay, DTI ellipsoids, montages) through the Python module give
the CLI's depth map and pixels for the same file and options, bit for bit; their bad
values raise ValueError naming the keyword."""
import json

import nibabel as nib
import numpy as np
import pytest

import glyphcast
from conftest import assert_same_depth


@pytest.fixture(scope="module")
def sh(func_coef):
    image = nib.load(func_coef)
    return image.get_fdata(), image.affine


@pytest.fixture
def underlay_file(sh, tmp_path):
    """A scalar image on func_coef's grid (its first coefficient, the mean amplitude),
    with a NaN voxel (no value: drawn transparent)."""
    coeffs, affine = sh
    values = coeffs[..., 0].astype(np.float32)
    values[0, 0, 0] = np.nan
    path = tmp_path / "underlay.nii.gz"
    nib.save(nib.Nifti1Image(values, affine), path)
    return path, values


def assert_same_image(ours, cli):
    """Depth bit for bit, and the PNG the CLI wrote byte for byte (same encoder)."""
    depth, png = cli
    assert_same_depth(ours.depth, depth)
    assert ours.png() == png


def test_the_compute_path_draws_the_underlay_as_the_fragment_path(sh, underlay_file):
    """path="compute" composes the glyphs with the underlay through the same depth test;
    path="auto" (the default) is the fragment path on lavapipe, bit for bit."""
    coeffs, affine = sh
    path, _ = underlay_file
    images = {
        p: glyphcast.render_sh(coeffs, affine, basis="dipy", width=96, underlay=path, path=p)
        for p in ("fragment", "compute", "auto")
    }
    fragment, compute = images["fragment"], images["compute"]
    assert np.array_equal(np.isnan(fragment.depth), np.isnan(compute.depth))
    hit = ~np.isnan(fragment.depth)
    assert hit.sum() > 100
    assert np.allclose(fragment.depth[hit], compute.depth[hit], rtol=1e-5, atol=0)
    # One unit of the 8-bit sRGB encoding at most.
    difference = np.abs(fragment.rgba.astype(int) - compute.rgba.astype(int))
    assert difference.max() <= 1
    assert np.array_equal(images["auto"].rgba, fragment.rgba)
    assert_same_depth(images["auto"].depth, fragment.depth)


def test_render_sh_with_an_underlay_matches_cli(sh, func_coef, underlay_file, cli_render):
    coeffs, affine = sh
    path, values = underlay_file
    cli = cli_render("--sh", func_coef, "--basis", "dipy", "--width", 96,
                     "--underlay", path)
    renderer = glyphcast.Renderer(validation=True)
    from_file = renderer.render_sh(coeffs, affine, basis="dipy", width=96, underlay=path)
    assert_same_image(from_file, cli)
    # Drawn again from the uploaded frame, planes and all.
    assert_same_image(renderer.render(), cli)
    # The same values as an array on the coefficients' grid, and with their affine.
    from_array = glyphcast.render_sh(coeffs, affine, basis="dipy", width=96, underlay=values)
    assert_same_image(from_array, cli)
    paired = glyphcast.render_sh(coeffs, affine, basis="dipy", width=96,
                                 underlay=(values, affine))
    assert_same_image(paired, cli)
    # The underlay is drawn: the pixels differ from the glyphs alone.
    plain = glyphcast.render_sh(coeffs, affine, basis="dipy", width=96)
    assert not np.array_equal(plain.rgba, from_file.rgba)
    # Its window: a string as the CLI takes it, or a pair of numbers.
    lo, top = float(np.nanmin(values)), float(np.nanmax(values))
    hi = lo + (top - lo) / 2
    windowed = cli_render("--sh", func_coef, "--basis", "dipy", "--width", 96,
                          "--underlay", path, "--underlay-range", f"{lo}:{hi}")
    for window in (f"{lo}:{hi}", (lo, hi)):
        ours = glyphcast.render_sh(coeffs, affine, basis="dipy", width=96, underlay=path,
                                   underlay_range=window)
        assert_same_image(ours, windowed)
    assert not np.array_equal(ours.rgba, from_file.rgba)


def dti_volume(tmp_path):
    """Order-2 tensors (xx, xy, xz, yy, yz, zz) on a 3x2x2 grid of 2 mm voxels, prolate
    along x, y or z by voxel."""
    coeffs = np.zeros((3, 2, 2, 6), dtype=np.float32)
    for i in range(3):
        for j in range(2):
            for k in range(2):
                diagonal = [0.3, 0.3, 0.3]
                diagonal[(i + j + k) % 3] = 1.0 + 0.5 * i
                coeffs[i, j, k] = [diagonal[0], 0.05 * j, 0.0, diagonal[1], 0.0, diagonal[2]]
    affine = np.diag([2.0, 2.0, 2.0, 1.0])
    path = tmp_path / "dti.nii.gz"
    nib.save(nib.Nifti1Image(coeffs, affine), path)
    return coeffs, affine, path


def test_ellipsoids_match_cli(tmp_path, cli_render):
    coeffs, affine, path = dti_volume(tmp_path)
    cli = cli_render("--tensor", path, "--order", 2, "--glyph", "ellipsoid", "--width", 90)
    ours = glyphcast.render_tensor(coeffs, affine, order=2, glyph="ellipsoid", width=90)
    assert_same_image(ours, cli)
    peanuts = glyphcast.render_tensor(coeffs, affine, order=2, glyph="polynomial", width=90)
    assert not np.array_equal(peanuts.depth, ours.depth, equal_nan=True)


@pytest.mark.parametrize(
    "python, flags",
    [
        ({"views": "axial,coronal,sagittal"}, ["--views", "axial,coronal,sagittal"]),
        ({"views": ["sagittal:0", "axial"]}, ["--views", "sagittal:0,axial"]),
        ({"lightbox": 3}, ["--lightbox", 3]),
        ({"lightbox": 2, "slice": "coronal", "labels": True},
         ["--lightbox", 2, "--slice", "coronal", "--labels"]),
    ],
)
def test_montages_match_cli(sh, func_coef, cli_render, python, flags):
    coeffs, affine = sh
    cli = cli_render("--sh", func_coef, "--basis", "dipy", "--width", 48, "--height", 40,
                     *flags)
    ours = glyphcast.render_sh(coeffs, affine, basis="dipy", width=48, height=40, **python)
    assert_same_image(ours, cli)
    panels = len(python["views"].split(",")) if isinstance(python.get("views"), str) else (
        len(python["views"]) if "views" in python else python["lightbox"])
    columns = panels if "views" in python else int(np.ceil(np.sqrt(panels)))
    rows = -(-panels // columns)
    assert ours.rgba.shape == (40 * rows, 48 * columns, 4)


def test_a_montage_is_drawn_again_but_not_from_one_camera(sh, scenes):
    coeffs, affine = sh
    renderer = glyphcast.Renderer(validation=True)
    first = renderer.render_sh(coeffs, affine, basis="dipy", width=32, lightbox=2)
    again = renderer.render()
    assert_same_depth(again.depth, first.depth)
    assert np.array_equal(again.rgba, first.rgba)
    assert renderer.glyph_count > 0
    camera = json.loads((scenes / "order4_pair.json").read_text())["camera"]
    with pytest.raises(ValueError, match=r"^camera: a montage"):
        renderer.render(camera=camera)


def test_bad_figure_options_name_the_keyword(sh, underlay_file, tmp_path):
    coeffs, affine = sh
    path, values = underlay_file
    dti, dti_affine, _ = dti_volume(tmp_path)
    cases = [
        (dict(glyph="cuboid"), r"^glyph='cuboid': not one of polynomial, ellipsoid$"),
        (dict(glyph="ellipsoid"), r"^glyph=ellipsoid: draws order-2 symmetric tensors .*"
                                  r"a tensor volume with order=2"),
        (dict(views="axial,axial"), r"^views='axial,axial': axial is listed twice$"),
        (dict(views="axial,oblique"), r"^views='axial,oblique': 'oblique' is not axial"),
        (dict(views="axial", lightbox=2), r"^give either views or lightbox, not both$"),
        (dict(views="axial", slice="coronal"), r"^views: names each panel's slice: give no "
                                               r"slice or slices with it$"),
        (dict(lightbox=0), r"^lightbox=0: must be 1 to 64 slices$"),
        (dict(lightbox=9), r"^lightbox=9: the axial plane has 4 slices in coeffs$"),
        (dict(lightbox=2, slices="mid"), r"^lightbox: takes slice, not slices$"),
        (dict(underlay_plane="back"), r"^underlay_plane: needs underlay \(the image it "
                                      r"places\)$"),
        (dict(underlay=path, underlay_plane="middle"), r"^underlay_plane='middle': expected "
                                                       r"back .* or centre"),
        (dict(slice=True), r"^slice: expected \"AXIS\[:INDEX\]\" or a whole number"),
        (dict(colorbar_label="x"), r"^colorbar_label: labels the colour bar: give "
                                   r"colorbar=True too$"),
        (dict(underlay_range="0:1"), r"^underlay_range: needs underlay \(the image it "
                                     r"windows\)$"),
        (dict(underlay=path, underlay_range="1-2"), r"^underlay_range='1-2': not LOW:HIGH"),
        (dict(underlay=path, underlay_range=(2, 1)), r"^underlay_range='2:1': not LOW:HIGH"),
        (dict(underlay=values[..., None]), r"^underlay: a 4D array of shape \[2, 3, 4, 1\]"),
        (dict(path="gpu"), r"^path='gpu': not one of auto, fragment, compute"),
        (dict(order=2), r"^order: applies to tensor volumes only$"),
        (dict(legacy=True, basis=None), r"^legacy=True: needs basis too"),
    ]
    for options, message in cases:
        kwargs = {"basis": "dipy", "width": 32, **options}
        with pytest.raises(ValueError, match=message) as caught:
            glyphcast.render_sh(coeffs, affine, **kwargs)
        assert "--" not in str(caught.value), caught.value
    with pytest.raises(ValueError, match=r"^lmax: applies to SH volumes only$"):
        glyphcast.render_tensor(dti, dti_affine, order=2, lmax=2)
    with pytest.raises(ValueError, match=r"^symmetric=False: applies to tensor volumes only$"):
        glyphcast.render_sh(coeffs, affine, basis="dipy", symmetric=False)
    with pytest.raises(ValueError, match=r"^views: expected a string or a list of strings"):
        glyphcast.render_sh(coeffs, affine, basis="dipy", views=3)


def test_glyph_sets_every_scene_set_as_the_cli_does(tmp_path, cli, cli_render, scenes):
    # A scene of order-2 tensors: the DTI volume's view, as the CLI saves it.
    _, _, volume = dti_volume(tmp_path)
    scene = tmp_path / "dti.json"
    cli("render", "--tensor", volume, "--order", 2, "--width", 80,
        "-o", tmp_path / "dti.png", "--save-scene", scene)
    expected = cli_render(scene, "--glyph", "ellipsoid")
    ours = glyphcast.render_scene(scene, glyph="ellipsoid")
    assert_same_image(ours, expected)
    assert not np.array_equal(glyphcast.render_scene(scene).depth, ours.depth, equal_nan=True)
    with pytest.raises(ValueError, match=r"^glyph=ellipsoid: draws symmetric tensors of "
                                         r"order 2 \(DTI\), and glyph set 0 is a symmetric "
                                         r"tensor of order 4$"):
        glyphcast.render_scene(scenes / "order4_pair.json", glyph="ellipsoid")
