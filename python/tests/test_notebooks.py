"""The example notebooks run from top to bottom with nbclient on a fresh kernel (the
module as installed in this environment, lavapipe), and every image cell shows a picture
of glyphs: a PNG whose pixels are not all the background."""
import base64
import io
import pathlib

import numpy as np
import pytest

from conftest import ROOT

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")
pytest.importorskip("dipy")
pytest.importorskip("PIL")

NOTEBOOKS = sorted((ROOT / "examples" / "notebooks").glob("*.ipynb"))


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_notebook_runs_and_shows_glyphs(path: pathlib.Path):
    notebook = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(
        notebook, timeout=600, kernel_name="python3",
        resources={"metadata": {"path": str(path.parent)}},
    )
    client.execute()
    images = [
        output["data"]["image/png"]
        for cell in notebook.cells if cell.cell_type == "code"
        for output in cell.get("outputs", [])
        if "image/png" in output.get("data", {})
    ]
    assert len(images) >= 2, f"{path.name}: {len(images)} images"
    for data in images:
        raw = base64.b64decode(data)
        assert raw[:8] == b"\x89PNG\r\n\x1a\n"
        rgba = decode_png(raw)
        corner = rgba[0, 0]
        differing = np.any(rgba != corner, axis=-1).mean()
        assert differing > 0.01, f"{path.name}: {differing:.3f} of the pixels are glyphs"


def decode_png(raw: bytes) -> np.ndarray:
    """RGBA pixels of a PNG (Pillow)."""
    from PIL import Image
    return np.asarray(Image.open(io.BytesIO(raw)).convert("RGBA"))
