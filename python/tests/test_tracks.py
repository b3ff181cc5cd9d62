"""Streamlines drawn as tubes with the glyphs through the Python module: ``tracks=`` as a
.tck path, a list of (N, 3) arrays or a nibabel Tractogram draws what ``glyphcast render
--tracks`` draws, bit for bit; bad streamlines and options raise ValueError naming the
keyword."""
import nibabel as nib
import numpy as np
import pytest
from nibabel.streamlines import Tractogram, save

import glyphcast
from conftest import assert_same_depth


def streamlines():
    """Three streamlines through DIPY's func_coef grid (identity affine, voxels 0..1,
    0..2, 0..3 in millimetres): two along x at the height of axial slice 1, one across."""
    s = np.linspace(0.0, 1.0, 21)[:, None]
    return [
        np.hstack([-0.6 + 2.2 * s, 0.8 + 0 * s, 1.05 + 0 * s]),
        np.hstack([-0.6 + 2.2 * s, 1.6 + 0.2 * s, 0.9 + 0.1 * s]),
        np.hstack([0.5 + 0 * s, -0.5 + 3.0 * s, 0.2 + 1.6 * s]),
    ]


KWARGS = dict(basis="tournier07", legacy=True, scale=0.4, slice="axial:1", width=120,
              height=110, tracks_radius=0.08)
FLAGS = ["--basis", "tournier07", "--legacy", "--scale", 0.4, "--slice", "axial:1",
         "--width", 120, "--height", 110, "--tracks-radius", 0.08]


def test_track_arrays_and_files_draw_what_the_cli_draws(func_coef, cli_render, tmp_path):
    image = nib.load(func_coef)
    coeffs, affine = image.get_fdata(), image.affine
    lines = streamlines()
    tck = tmp_path / "lines.tck"
    save(Tractogram(lines, affine_to_rasmm=np.eye(4)), str(tck))
    depth, png = cli_render("--sh", func_coef, *FLAGS, "--tracks", tck)
    for given in (tck, str(tck), lines, [l.astype(np.float32) for l in lines],
                  Tractogram(lines, affine_to_rasmm=np.eye(4))):
        ours = glyphcast.render_sh(coeffs, affine, tracks=given, **KWARGS)
        assert_same_depth(ours.depth, depth)
        assert ours.png() == png
    plain = glyphcast.render_sh(coeffs, affine, **{k: v for k, v in KWARGS.items()
                                                    if k != "tracks_radius"})
    assert np.isfinite(depth).sum() > np.isfinite(plain.depth).sum()
    # A slab and a colour, as the flags.
    depth, png = cli_render("--sh", func_coef, *FLAGS, "--tracks", tck, "--slab", 0.3,
                            "--tracks-color", "yellow")
    ours = glyphcast.render_sh(coeffs, affine, tracks=lines, slab=0.3, tracks_color="yellow",
                               **KWARGS)
    assert_same_depth(ours.depth, depth)
    assert ours.png() == png
    yellow = (ours.rgba[..., 0] > 100) & (ours.rgba[..., 1] > 100) & (ours.rgba[..., 2] < 60)
    assert yellow.sum() > 30
    # Lines instead of tubes, as the flag draws them, and not what the tubes draw.
    depth, png = cli_render("--sh", func_coef, *FLAGS, "--tracks", tck, "--tracks-style",
                            "lines")
    ours = glyphcast.render_sh(coeffs, affine, tracks=lines, tracks_style="lines", **KWARGS)
    assert_same_depth(ours.depth, depth)
    assert ours.png() == png
    assert ours.png() != glyphcast.render_sh(coeffs, affine, tracks=lines, **KWARGS).png()


@pytest.mark.parametrize("tracks, words", [
    ([np.zeros((4, 2))], r"tracks: streamline 0 has shape \[4, 2\]"),
    ([np.array([[0.0, np.nan, 0.0]])], r"tracks: streamline 0 has a point coordinate NaN"),
    ([np.zeros((3, 3), dtype=np.int64)], r"tracks: dtype int64"),
])
def test_bad_streamlines_raise_value_errors_naming_tracks(func_coef, tracks, words):
    image = nib.load(func_coef)
    with pytest.raises(ValueError, match=words):
        glyphcast.render_sh(image.get_fdata(), image.affine, tracks=tracks, **KWARGS)


def test_track_options_need_tracks(func_coef):
    image = nib.load(func_coef)
    with pytest.raises(ValueError, match=r"slab: needs tracks"):
        glyphcast.render_sh(image.get_fdata(), image.affine, basis="tournier07", legacy=True,
                            slab=2.0)
    with pytest.raises(ValueError, match=r"tracks_style='ribbons'.*tubes or lines"):
        glyphcast.render_sh(image.get_fdata(), image.affine, basis="tournier07", legacy=True,
                            tracks=streamlines(), tracks_style="ribbons")
    with pytest.raises(ValueError, match=r"tracks_radius=-1"):
        glyphcast.render_sh(image.get_fdata(), image.affine, basis="tournier07", legacy=True,
                            tracks=streamlines(), tracks_radius=-1.0)
