"""A notebook with a view, run by nbclient (a kernel, no browser) and exported by
nbconvert to HTML: the view's cell shows its last frame as a picture and nothing else of
the widget (no widget's text, no repr); the saved cell holds one widget output and the
copy of the last frame. The widgets' state is not stored, as JupyterLab saves a notebook
by default: nbconvert then shows each output's next kind (the plain text, the picture)."""
import base64
import re

import numpy as np
import pytest

import glyphcast

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
nbconvert = pytest.importorskip("nbconvert")
pytest.importorskip("ipykernel")
pytest.importorskip("jupyter_rfb")
pytest.importorskip("PIL")

from notebook_browser import decode  # noqa: E402

WIDTH, HEIGHT = 96, 72
SETUP = """\
import numpy as np
import glyphcast

rng = np.random.default_rng(5)
coeffs = rng.normal(0.0, 0.12, (5, 5, 3, 15))
coeffs[..., 0] = 1.0
"""
SHOW = f"""\
view = glyphcast.show_sh(coeffs, basis="tournier07", slice="axial:1",
                         width={WIDTH}, height={HEIGHT})
view
"""
# A later cell moves the view: the copy kept in the view's cell must follow.
MOVE = "view.slice = 'coronal'"
WIDGET = "application/vnd.jupyter.widget-view+json"


def last_frame():
    coeffs = np.random.default_rng(5).normal(0.0, 0.12, (5, 5, 3, 15))
    coeffs[..., 0] = 1.0
    renderer = glyphcast.Renderer()
    return renderer.render_sh(coeffs, basis="tournier07", slice="coronal:2",
                              width=WIDTH, height=HEIGHT).rgba[..., :3]


@pytest.fixture(scope="module")
def executed(tmp_path_factory):
    notebook = nbformat.v4.new_notebook()
    notebook.cells = [nbformat.v4.new_code_cell(c) for c in (SETUP, SHOW, MOVE)]
    client = nbclient.NotebookClient(
        notebook, timeout=300, kernel_name="python3", store_widget_state=False,
        resources={"metadata": {"path": str(tmp_path_factory.mktemp("export"))}},
    )
    client.execute()
    return notebook


def test_the_saved_cell_holds_one_widget_and_the_last_frame(executed):
    outputs = executed.cells[1].outputs
    widgets = [o for o in outputs if WIDGET in o.get("data", {})]
    assert len(widgets) == 1, [list(o.get("data", {})) for o in outputs]
    assert widgets[0]["data"]["text/plain"] == ""
    for output in outputs:
        assert output["output_type"] != "stream", output
        text = output.get("data", {}).get("text/plain", "")
        assert "Widget" not in text and "object at" not in text and "Box(" not in text, text
    images = [o for o in outputs if "image/png" in o.get("data", {})]
    assert len(images) == 1
    shown = decode(base64.b64decode(images[0]["data"]["image/png"]))
    assert np.array_equal(shown, last_frame()), "the saved picture is not the last frame"


def test_the_html_export_shows_the_picture_and_no_widget_text(executed):
    html, _ = nbconvert.HTMLExporter().from_notebook_node(executed)
    for text in ("RFBOutputContext", "HBox(", "VBox(", "GlyphView object at",
                 "Loading widget"):
        assert text not in html, text
    pictures = re.findall(r'<img[^>]*src="data:image/png;base64,([^"]+)"', html)
    assert len(pictures) == 1, len(pictures)
    assert np.array_equal(decode(base64.b64decode(pictures[0])), last_frame())
