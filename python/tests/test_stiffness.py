"""Stiffness matrices from Python: ``glyphcast.stiffness`` draws the Reynolds glyph of a
Voigt matrix and returns the same numbers as ``glyphcast stiffness --summary``, held to
the closed forms of a cubic crystal."""
import json
import subprocess

import numpy as np
import pytest

import glyphcast

C11, C12, C44 = 168.4, 121.4, 75.4  # copper, GPa


def cubic(c11, c12, c44):
    c = np.zeros((6, 6))
    c[:3, :3] = c12
    np.fill_diagonal(c[:3, :3], c11)
    c[3:, 3:] = np.eye(3) * c44
    return c


def test_the_glyph_and_the_numbers_of_a_cubic_crystal():
    image, summary = glyphcast.stiffness(cubic(C11, C12, C44), width=96, height=72)
    assert image.rgba.shape == (72, 96, 4)
    assert np.isfinite(image.depth).sum() > 500
    # Cubic closed forms: E along <100> is 1/S11, and the bulk modulus (C11 + 2 C12) / 3
    # is the Voigt and the Reuss average alike.
    s11 = (C11 + C12) / ((C11 - C12) * (C11 + 2 * C12))
    assert summary["young"]["min"] == pytest.approx(1 / s11, rel=1e-9)
    bulk = (C11 + 2 * C12) / 3
    assert summary["bulk"]["voigt"] == pytest.approx(bulk, rel=1e-12)
    assert summary["bulk"]["reuss"] == pytest.approx(bulk, rel=1e-9)


def test_bunge_angles_keep_the_extremes_and_turn_the_glyph():
    plain_image, plain = glyphcast.stiffness(cubic(C11, C12, C44), width=96, height=72)
    turned_image, turned = glyphcast.stiffness(
        cubic(C11, C12, C44), euler=(30, 40, 50), width=96, height=72
    )
    for key in ("min", "max"):
        assert turned["young"][key] == pytest.approx(plain["young"][key], rel=1e-6)
    assert not np.array_equal(plain_image.rgba, turned_image.rgba)


def test_the_numbers_are_the_command_lines(cli_binary, tmp_path):
    matrix = cubic(246.5, 147.3, 124.7)
    path = tmp_path / "nickel.txt"
    np.savetxt(path, matrix)
    summary_path = tmp_path / "summary.json"
    done = subprocess.run(
        [str(cli_binary), "stiffness", str(path), "--euler", "10,20,30",
         "--summary", str(summary_path)],
        capture_output=True, text=True,
    )
    assert done.returncode == 0, done.stderr
    _, ours = glyphcast.stiffness(matrix, euler=(10, 20, 30), width=32, height=32)
    assert ours == json.loads(summary_path.read_text())


def test_an_unstable_or_malformed_matrix_is_refused():
    unstable = cubic(246.5, 260.0, 124.7)
    with pytest.raises(ValueError, match="positive definite"):
        glyphcast.stiffness(unstable)
    image, _ = glyphcast.stiffness(unstable, allow_unstable=True, width=32, height=32)
    assert image.rgba.shape == (32, 32, 4)
    with pytest.raises(ValueError, match="6 x 6"):
        glyphcast.stiffness(np.zeros((5, 6)))
    asymmetric = cubic(C11, C12, C44)
    asymmetric[0, 1] += 10
    with pytest.raises(ValueError, match="C12"):
        glyphcast.stiffness(asymmetric)


def sphere_depth(eye, radius, width, height, fov_y_deg=30.0):
    """Per pixel the ray distance to the sphere of ``radius`` about the origin, NaN for a
    miss, for the scene format's perspective camera looking at the origin, up z."""
    eye = np.asarray(eye, dtype=float)
    forward = -eye / np.linalg.norm(eye)
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    i, j = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    sx = (2 * i / width - 1) * width / height
    sy = 1 - 2 * j / height
    tan = np.tan(np.radians(fov_y_deg) / 2)
    d = forward + tan * (sx[..., None] * right + sy[..., None] * up)
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    b = d @ eye
    disc = b * b - (eye @ eye - radius * radius)
    return np.where(disc > 0, -b - np.sqrt(np.maximum(disc, 0)), np.nan)


def test_surfaces_of_a_cubic_crystal():
    """A cubic crystal's linear compressibility is the same in every direction (S11 +
    2 S12 = 1 / (3 K)): its surface is the sphere of radius 1 (the largest radius of one
    material), held to the closed-form depth; Young's surface is drawn, and differs."""
    c = cubic(C11, C12, C44)
    image, summary = glyphcast.stiffness(c, surface="compressibility", width=96, height=72)
    beta = 1 / (C11 + 2 * C12)
    assert summary["linear_compressibility"]["min"] == pytest.approx(beta, rel=1e-9)
    want = sphere_depth([2.4, -3.6, 2.2], 1.0, 96, 72)
    hit = np.isfinite(want) & np.isfinite(image.depth)
    assert hit.sum() > 1000
    assert np.nanmax(np.abs(image.depth[hit] - want[hit])) < 1e-4
    # Coverage differs at most on the silhouette's pixels.
    assert (np.isfinite(want) != np.isfinite(image.depth)).sum() < 60
    young, _ = glyphcast.stiffness(c, surface="young", width=96, height=72)
    assert np.isfinite(young.depth).sum() > 500
    assert not np.array_equal(young.rgba, image.rgba)


def test_a_surface_that_cannot_be_drawn_is_refused():
    with pytest.raises(ValueError, match="surface"):
        glyphcast.stiffness(cubic(C11, C12, C44), surface="bulk")
    with pytest.raises(ValueError, match="symmetric_part"):
        glyphcast.stiffness(cubic(C11, C12, C44), surface="young", symmetric_part=True)


def test_the_shear_surfaces_of_a_cubic_crystal():
    """G_min(u) <= G_max(u) in every direction and both surfaces are drawn on one scale
    (the largest G over all pairs, C44 for copper): shear-max encloses shear-min, so
    where both are hit the shear-max surface is the nearer, and shear-min covers no pixel
    that shear-max leaves empty (but for the silhouette's)."""
    c = cubic(C11, C12, C44)
    low, summary = glyphcast.stiffness(c, surface="shear-min", width=96, height=72)
    high, _ = glyphcast.stiffness(c, surface="shear-max", width=96, height=72)
    # Copper's shear moduli range from (C11 - C12) / 2 to C44.
    assert summary["shear"]["min"] == pytest.approx((C11 - C12) / 2, rel=1e-6)
    assert summary["shear"]["max"] == pytest.approx(C44, rel=1e-6)
    low_hit, high_hit = np.isfinite(low.depth), np.isfinite(high.depth)
    assert low_hit.sum() > 300 and high_hit.sum() > low_hit.sum()
    both = low_hit & high_hit
    assert np.all(high.depth[both] <= low.depth[both] + 1e-4)
    assert (low_hit & ~high_hit).sum() < 10
    # The two surfaces differ (they touch only along the cube axes and body diagonals).
    assert np.nanmedian(low.depth[both] - high.depth[both]) > 1e-2


def test_the_poisson_surfaces_of_an_auxetic_crystal():
    """Alpha cristobalite (tetragonal) is auxetic: its smallest Poisson's ratio is
    negative in most directions, and drawn in the negative colour of color="sign"; its
    largest is positive in most. Copper's ratios are positive everywhere."""
    cristobalite = np.array([
        [59.4, 3.8, -4.4, 0, 0, 0],
        [3.8, 59.4, -4.4, 0, 0, 0],
        [-4.4, -4.4, 42.4, 0, 0, 0],
        [0, 0, 0, 67.2, 0, 0],
        [0, 0, 0, 0, 67.2, 0],
        [0, 0, 0, 0, 0, 25.7],
    ])

    def blue_share(c, surface, width=96, height=72):
        image, summary = glyphcast.stiffness(c, surface=surface, color="sign",
                                             width=width, height=height)
        hit = np.isfinite(image.depth)
        assert hit.sum() > 100, surface
        rgb = image.rgba[..., :3].astype(int)
        return (rgb[..., 2] > rgb[..., 0])[hit].mean(), summary

    low, summary = blue_share(cristobalite, "poisson-min")
    assert summary["poisson"]["min"] < -0.4
    assert low > 0.95
    # Drawn on the scale of the smallest ratio's -0.51, the largest (at most 0.096) is
    # small: a larger image gives it pixels.
    high, _ = blue_share(cristobalite, "poisson-max", 288, 216)
    assert high < 0.5
    copper, _ = blue_share(cubic(C11, C12, C44), "poisson-max")
    assert copper == 0.0
