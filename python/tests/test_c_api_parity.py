"""The C API and the Python module draw the same glyphs from the same coefficients.

The C example engine (examples/c/main.c, built against include/glyphcast.h and run by
tools/c-example.sh) draws nine SH glyphs of band 4 through
``glyphcast_renderer_set_sh_glyphs``, with ``--no-plane`` alone on its clear colour, and
with ``--describe`` writes what its last frame drew: the image size, the camera, the
settings it changed, and the glyphs' centres, scales and coefficients as it handed them
over, with their basis. ``render_sh`` then draws those coefficients as the 3 x 3 x 1
volume whose voxel centres are the glyphs' centres, with the same basis keywords, the
same scale (``norm="none"``), settings, camera and image size.

DIPY's default basis (descoteaux07, ``legacy=True``): the glyphs cover the same pixels in
both and have the same colours to within a few levels of 255. descoteaux07 without the
legacy flag draws another picture, through either path, so a basis or flag lost on
either side fails the test.
"""
import json
import subprocess

import numpy as np
from PIL import Image

import glyphcast
from conftest import ROOT

# Colour difference allowed at a pixel both cover, in levels of 255 (sRGB): the two
# paths hand the GPU the same rays through different matrices (the engine's projection
# and view against the camera's), which moves a hit by float32 rounding.
COLOUR_TOLERANCE = 3


def c_example(tmp_path, basis):
    """The C example's last frame (RGBA, uint8) and its --describe record."""
    png = tmp_path / f"c-{basis}.png"
    record = tmp_path / f"c-{basis}.json"
    done = subprocess.run(
        ["bash", str(ROOT / "tools" / "c-example.sh"), str(png), "--basis", basis,
         "--no-plane", "--describe", str(record)],
        capture_output=True, text=True,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert "0 validation message(s)" in done.stdout, done.stdout
    rgba = np.asarray(Image.open(png).convert("RGBA"))
    return rgba, json.loads(record.read_text())


def python_render(record, legacy):
    """``render_sh`` of the record's glyphs as a volume, from the record's camera."""
    sh = record["sh"]
    centers = np.array(sh["centers"], dtype=float).reshape(-1, 3)
    coefficients = np.array(sh["coefficients"], dtype=float).reshape(len(centers), -1)
    # The centres lie on a grid in x and y at z = 0: voxel (i, j, 0) is at
    # origin + spacing (i, j, 0), the voxel centres of the affine below.
    origin = centers.min(axis=0)
    spacing = np.diff(np.unique(centers[:, 0]))[0]
    index = np.rint((centers - origin) / spacing).astype(int)
    assert np.allclose(origin + spacing * index, centers), "the glyphs lie on a grid"
    volume = np.zeros((*(index.max(axis=0) + 1), coefficients.shape[1]))
    volume[tuple(index.T)] = coefficients
    assert volume.shape == (3, 3, 1, 15)
    affine = np.diag([spacing, spacing, spacing, 1.0])
    affine[:3, 3] = origin
    (scale,) = set(sh["scales"])
    with glyphcast.Renderer(validation=True) as renderer:
        renderer.render_sh(
            volume, affine, basis=sh["basis"], legacy=legacy, slice=0, norm="none",
            scale=scale, width=record["width"], height=record["height"],
            method=record["method"], ambient=record["ambient"], light=record["light"],
        )
        assert renderer.glyph_count == 9
        return renderer.render(camera=record["camera"])


def c_coverage(rgba):
    """The pixels the C example's glyphs cover: those not of its clear colour (the top
    left corner's, which no glyph reaches in this view)."""
    clear = rgba[0, 0, :3]
    return np.any(rgba[..., :3] != clear, axis=-1)


def test_the_c_api_draws_dipy_legacy_coefficients_as_python_does(tmp_path):
    legacy_c, record = c_example(tmp_path, "descoteaux07-legacy")
    assert (record["sh"]["basis"], record["sh"]["legacy"]) == ("descoteaux07", True)
    assert record["plane"] is False
    legacy_py = python_render(record, legacy=True)
    assert legacy_py.rgba.shape == legacy_c.shape
    covered = c_coverage(legacy_c)
    assert np.isnan(legacy_py.depth[0, 0])
    assert covered.sum() > 1500, "the glyphs fill a good part of the picture"
    # The same pixels covered ...
    hits = np.isfinite(legacy_py.depth)
    assert np.array_equal(covered, hits), (
        f"{np.sum(covered & ~hits)} pixels covered in C only, "
        f"{np.sum(hits & ~covered)} in Python only"
    )
    # ... in the same colours.
    difference = np.abs(
        legacy_c[..., :3].astype(int) - legacy_py.rgba[..., :3].astype(int)
    ).max(axis=-1)
    assert difference[covered].max() <= COLOUR_TOLERANCE, (
        f"largest colour difference {difference[covered].max()}, "
        f"{np.sum(difference[covered] > COLOUR_TOLERANCE)} pixels over {COLOUR_TOLERANCE}"
    )

    # Without the legacy flag both paths draw another picture, and again the same one.
    plain_c, plain_record = c_example(tmp_path, "descoteaux07")
    assert plain_record["sh"]["coefficients"] == record["sh"]["coefficients"]
    assert plain_record["camera"] == record["camera"]
    plain_py = python_render(record, legacy=False)
    pairs = [(legacy_c, plain_c, "C"), (legacy_py.rgba, plain_py.rgba, "Python")]
    for legacy, plain, what in pairs:
        changed = np.abs(legacy[..., :3].astype(int) - plain[..., :3].astype(int)).max(axis=-1)
        assert np.sum(changed > 10 * COLOUR_TOLERANCE) > 200, f"{what}: the basis changed nothing"
    plain_covered = c_coverage(plain_c)
    assert np.array_equal(plain_covered, np.isfinite(plain_py.depth))
    plain_difference = np.abs(
        plain_c[..., :3].astype(int) - plain_py.rgba[..., :3].astype(int)
    ).max(axis=-1)
    assert plain_difference[plain_covered].max() <= COLOUR_TOLERANCE
