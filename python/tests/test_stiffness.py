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
