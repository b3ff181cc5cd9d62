"""Bad arrays and options raise ValueError (TypeError for an unknown keyword) with a
message that names the argument; the CLI's own checks keep the CLI's text."""
import json
import os
import re
import subprocess
import traceback

import nibabel as nib
import numpy as np
import pytest

import glyphcast
from conftest import ROOT


@pytest.fixture(scope="module")
def sh():
    image = nib.load(ROOT / "tests/data/dipy/func_coef.nii.gz")
    return image.get_fdata(), image.affine


def raises(exception, match, call, *args, **kwargs):
    with pytest.raises(exception, match=match):
        call(*args, **kwargs)


def test_wrong_coefficient_count(sh):
    coeffs, affine = sh
    raises(ValueError, r"coeffs: dim\[4\]: 44 coefficients per voxel is not \(L\+1\)\(L\+2\)/2",
           glyphcast.render_sh, coeffs[..., :44].copy(), affine, basis="dipy")
    raises(ValueError, r"coeffs: dim\[4\]: 5 coefficients per voxel, but a .*needs 6",
           glyphcast.render_tensor, np.ones((2, 2, 2, 5)), order=2)


def test_nan_and_infinity_leave_the_voxel_out_with_a_warning(sh):
    """Issue 28: as on the command line (the test of the same picture and words is
    test_dipy_user.py's); before, a NaN raised ValueError here alone."""
    coeffs, affine = sh
    bad = coeffs.copy()
    bad[1, 2, 3, 7] = np.nan
    bad[0, 0, 3, 0] = np.inf
    with pytest.warns(UserWarning, match=r"^coeffs: 2 voxel\(s\) with NaN or infinite "
                                         r"coefficients left out$"):
        glyphcast.render_sh(bad, affine, basis="dipy", slice="axial:3")


def test_wrong_dimensionality(sh):
    coeffs, affine = sh
    raises(ValueError, r"coeffs: a 3D array of shape \[2, 3, 4\] where a 4D array",
           glyphcast.render_sh, coeffs[..., 0].copy(), affine, basis="dipy")
    raises(ValueError, r"coeffs: a 5D array", glyphcast.render_sh, coeffs[..., None],
           affine, basis="dipy")
    raises(ValueError, r"affine: shape \[3, 3\] where a 4x4 matrix is needed",
           glyphcast.render_sh, coeffs, np.eye(3), basis="dipy")
    raises(ValueError, r"mask: a 2D array", glyphcast.render_sh, coeffs, affine,
           basis="dipy", mask=np.ones((2, 3)))


def test_wrong_dtype(sh):
    coeffs, affine = sh
    raises(ValueError, r"coeffs: dtype int64 where float32 or float64 is needed",
           glyphcast.render_sh, coeffs.astype(np.int64), affine, basis="dipy")
    raises(ValueError, r"coeffs: dtype float16", glyphcast.render_sh,
           coeffs.astype(np.float16), affine, basis="dipy")
    raises(ValueError, r"coeffs: a numpy array is needed, not list", glyphcast.render_sh,
           coeffs.tolist(), affine, basis="dipy")


def test_bad_affine(sh):
    coeffs, _ = sh
    raises(ValueError, r"affine: matrix: the affine is not finite", glyphcast.render_sh,
           coeffs, np.full((4, 4), np.nan), basis="dipy")


def test_options_are_named_by_keyword_where_the_cli_names_the_flag(sh, cli_binary, tmp_path):
    """The CLI's message, each option spelled as the keyword: `--slice 'diagonal': ...`
    there, `slice='diagonal': ...` here."""
    coeffs, affine = sh
    root = ROOT
    file = root / "tests/data/dipy/func_coef.nii.gz"
    for flag, keyword, value in [
        ("--basis", "basis", "nonsense"),
        ("--slice", "slice", "diagonal"),
        ("--method", "method", "magic"),
        ("--norm", "norm", "loud"),
        ("--background", "background", "mauve"),
        ("--magnitude-range", "magnitude_range", "1-2"),
        ("--step", "step", "0.0001"),
        ("--views", "views", "axial,axial"),
        ("--lightbox", "lightbox", "0"),
        ("--glyph", "glyph", "cuboid"),
    ]:
        options = {"basis": "dipy", keyword: value}
        args = [f"--{k.replace('_', '-')}={v}" for k, v in options.items()]
        done = subprocess.run(
            [str(cli_binary), "render", "--sh", str(file), *args,
             "-o", str(tmp_path / "x.png")],
            capture_output=True, text=True,
        )
        assert done.returncode in (1, 2), done.stderr
        errors = [line for line in done.stderr.splitlines() if line.startswith("error: ")]
        assert len(errors) == 1, done.stderr
        assert errors[0].startswith(f"error: {flag} "), errors[0]
        if keyword in ("step", "lightbox"):
            options[keyword] = float(value) if keyword == "step" else int(value)
        with pytest.raises(ValueError) as caught:
            glyphcast.render_sh(coeffs, affine, **options)
        message = str(caught.value)
        assert message.startswith(f"{keyword}="), message
        assert "--" not in message, message
        cli_words = errors[0].removeprefix(f"error: {flag} ")
        assert message.removeprefix(f"{keyword}=") == cli_words


def test_settings_that_would_be_ignored_are_refused_as_the_cli_refuses_them(
        sh, cli_binary, tmp_path):
    """A magnitude range without the magnitude colour, and a step, precision or
    refinement the method does not read: the CLI exits 2 and the module raises
    ValueError, with the same message in each one's spelling."""
    coeffs, affine = sh
    file = ROOT / "tests/data/dipy/func_coef.nii.gz"
    for options, first, words in [
        ({"magnitude_range": "0:1"}, "magnitude_range", "needs color=magnitude"),
        ({"method": "exact", "step": 0.01}, "step=0.01", "method=exact does not read it"),
        ({"method": "exact", "precision": 0.5}, "precision=0.5",
         "method=exact does not read it"),
        ({"method": "impostor", "refine": "none"}, "refine='none'",
         "method=impostor does not read it"),
    ]:
        args = [f"--{k.replace('_', '-')}={v}" for k, v in options.items()]
        done = subprocess.run(
            [str(cli_binary), "render", "--sh", str(file), "--basis=dipy", *args,
             "-o", str(tmp_path / "x.png")],
            capture_output=True, text=True,
        )
        assert done.returncode == 2, done.stderr
        assert not (tmp_path / "x.png").exists()
        with pytest.raises(ValueError) as caught:
            glyphcast.render_sh(coeffs, affine, basis="dipy", **options)
        message = str(caught.value)
        assert message.startswith(first), message
        assert words in message, message
        assert "--" not in message, message


def test_unknown_keyword_is_a_type_error(sh):
    coeffs, affine = sh
    raises(TypeError, "unexpected keyword argument 'colour'", glyphcast.render_sh, coeffs,
           affine, basis="dipy", colour="sign")
    raises(ValueError, r"step: expected a number, got str", glyphcast.render_sh, coeffs,
           affine, basis="dipy", method="fixed", step="small")


def test_bad_scenes(scenes, tmp_path):
    scene = json.loads((scenes / "order4_pair.json").read_text())
    scene["glyphs"][0]["coeffs"][1] = scene["glyphs"][0]["coeffs"][1][:-1]
    raises(ValueError, r"^scene: glyphs\[0\]\.coeffs\[1\]", glyphcast.render_scene, scene)
    raises(OSError, "missing.json", glyphcast.render_scene, tmp_path / "missing.json")
    raises(ValueError, "scene: a dict in the scene format or a path is needed, not int",
           glyphcast.render_scene, 3)
    raises(ValueError, r"^width=0: must be in 1 to 16384$", glyphcast.render_scene,
           scenes / "order4_pair.json", width=0)


def test_glyphs_that_cannot_be_drawn_name_the_scene_file(scenes, tmp_path):
    """A reciprocal glyph whose form vanishes on the sphere (f = x^4, zero along y and z)
    has an unbounded surface: refused naming the file and the glyph set, as the CLI
    names them, for a scene file and for a scene given as a dict."""
    scene = json.loads((scenes / "order4_pair.json").read_text())
    scene["glyphs"][0]["shape"] = "reciprocal"
    scene["glyphs"][0]["coeffs"][1] = [1] + [0] * 14
    path = tmp_path / "unbounded.json"
    path.write_text(json.dumps(scene))
    raises(ValueError, "^" + re.escape(f"{path}: glyphs[0]: glyph 1: guaranteed least |f|"),
           glyphcast.render_scene, path)
    raises(ValueError, "^" + re.escape("scene: glyphs[0]: glyph 1: guaranteed least |f|"),
           glyphcast.render_scene, scene)


def glyphcast_frames(error):
    """The frames of ``error``'s traceback in glyphcast's own files."""
    package = os.path.dirname(os.path.abspath(glyphcast.__file__))
    return [frame for frame in traceback.extract_tb(error.__traceback__)
            if os.path.dirname(os.path.abspath(frame.filename)) == package]


def test_a_wrong_array_is_raised_from_the_users_call(sh):
    """The check is the native module's, frames below the public function; the traceback
    stops at the function the user called (one frame of glyphcast), and the message is
    the check's."""
    coeffs, affine = sh
    renderer = glyphcast.Renderer()
    for call in (glyphcast.render_sh, renderer.render_sh):
        with pytest.raises(ValueError, match=r"coeffs: dim\[4\]: 44 coefficients") as caught:
            call(coeffs[..., :44].copy(), affine, basis="dipy")
        frames = glyphcast_frames(caught.value)
        assert [frame.name for frame in frames] == ["render_sh"], frames
        text = "".join(traceback.format_exception(caught.value))
        assert len(text.splitlines()) <= 8, text
    with pytest.raises(ValueError, match="must be symmetric") as caught:
        glyphcast.render_tensor(np.arange(81.0).reshape(1, 1, 1, 3, 3, 9)[..., 0], order=2)
    assert len(glyphcast_frames(caught.value)) == 1
