"""The notebook view without a browser (the kernel's half; test_notebook_browser.py has
the browser's): `import glyphcast` needs no jupyter_rfb, the view's frames are
glyphcast's renders for its camera, slice and options, a refused option changes
nothing, a wrong array is raised from the user's call, and without the notebook extra
the view names it."""
import subprocess
import sys
import traceback

import numpy as np
import pytest

import glyphcast
from conftest import assert_same_depth

pytest.importorskip("jupyter_rfb")

from glyphcast import notebook  # noqa: E402


def coefficients():
    rng = np.random.default_rng(3)
    coeffs = rng.normal(0.0, 0.12, (6, 5, 4, 15))
    coeffs[..., 0] = 1.0
    return coeffs


def test_import_glyphcast_needs_no_jupyter():
    code = ("import sys, glyphcast; assert 'jupyter_rfb' not in sys.modules; "
            "assert 'glyphcast.notebook' not in sys.modules; glyphcast.show_sh; "
            "assert 'jupyter_rfb' in sys.modules")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_without_the_notebook_extra_the_view_names_it():
    """IPython, ipywidgets, jupyter_rfb and anywidget made unimportable in a fresh
    Python, as where the extra is not installed: an ImportError (ModuleNotFoundError, as
    before) that names the extra, with no chained traceback."""
    code = """
import sys, traceback
for name in ("IPython", "ipywidgets", "jupyter_rfb", "anywidget"):
    sys.modules[name] = None
import glyphcast
try:
    glyphcast.show_sh
except ImportError as error:
    assert isinstance(error, ModuleNotFoundError), type(error)
    traceback.print_exc(file=sys.stdout)
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    text = done.stdout
    assert "pip install glyphcast[notebook]" in text, text
    assert text.splitlines()[-1].startswith("ModuleNotFoundError: glyphcast's notebook view"), text
    assert "During handling" not in text and "direct cause" not in text, text


def test_a_wrong_array_is_raised_from_show_sh():
    with pytest.raises(ValueError, match=r"coeffs: dim\[4\]: 14 coefficients") as caught:
        glyphcast.show_sh(coefficients()[..., :14], basis="tournier07", width=32, height=24)
    package = glyphcast.__file__.rpartition("/")[0]
    frames = [f for f in traceback.extract_tb(caught.value.__traceback__)
              if f.filename.startswith(package + "/")]
    assert len(frames) == 1, frames  # show_sh's; not the view's, its loader's, ...


def test_view_draws_glyphcasts_render_for_its_camera_slice_and_options():
    coeffs = coefficients()
    view = glyphcast.show_sh(coeffs, basis="tournier07", width=96, height=72,
                             controls=False)
    assert view.slice == "axial:2"  # the middle axial slice
    fresh = glyphcast.Renderer()
    first = fresh.render_sh(coeffs, basis="tournier07", slice="axial:2", width=96,
                            height=72)
    assert_same_depth(view.rendering.depth, first.depth)
    assert view.camera == fresh.camera

    moved = notebook.orbit(view.camera, 30, -12, 72)
    moved = notebook.pan(notebook.zoom(moved, -150), 5, 3, 72)
    view.camera = moved
    expected = fresh.render(camera=moved)
    assert_same_depth(view.rendering.depth, expected.depth)
    assert np.array_equal(view.rendering.rgba, expected.rgba)
    assert not np.array_equal(view.rendering.rgba, first.rgba)

    view.slice = "axial:0"  # a new index keeps the camera
    assert view.camera == moved
    fresh.render_sh(coeffs, basis="tournier07", slice="axial:0", width=96, height=72)
    assert np.array_equal(view.rendering.rgba, fresh.render(camera=moved).rgba)

    view.slice = "coronal"  # a new plane frames it anew
    assert view.slice == "coronal:2"
    framed = fresh.render_sh(coeffs, basis="tournier07", slice="coronal:2", width=96,
                             height=72)
    assert view.camera == fresh.camera
    assert np.array_equal(view.rendering.rgba, framed.rgba)

    view.set_options(color="magnitude", negative="hide")
    expected = fresh.render_sh(coeffs, basis="tournier07", slice="coronal:2", width=96,
                               height=72, color="magnitude", negative="hide")
    assert np.array_equal(view.rendering.rgba, expected.rgba)
    with pytest.raises(ValueError, match="method"):
        view.set_options(method="nonsense")
    assert view.options == {"basis": "tournier07", "color": "magnitude", "negative": "hide"}
    assert np.array_equal(view.png(), expected.png())


def test_a_montage_is_refused():
    with pytest.raises(ValueError, match="views"):
        glyphcast.show_sh(coefficients(), basis="tournier07", views="axial,coronal")
