"""The example notebooks as a reader opens them, without running them: every install
line names something pip can install (a wheel built from the repository or the python/
folder, not a bare `glyphcast`, which no package index serves), and the notebook is
saved with its outputs (each code cell run, the pictures in it)."""
import json
import pathlib
import re

import pytest

from conftest import ROOT

NOTEBOOKS = sorted((ROOT / "examples" / "notebooks").glob("*.ipynb"))


def cells(path: pathlib.Path):
    return json.loads(path.read_text())["cells"]


def install_lines(path: pathlib.Path):
    """The `pip install ...` commands of every cell's text."""
    text = "\n".join("".join(cell["source"]) for cell in cells(path))
    return re.findall(r"pip install ([^`\n]*)", text)


def test_there_are_notebooks():
    assert NOTEBOOKS, "examples/notebooks holds no notebook"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_install_lines_name_a_wheel_or_the_source(path: pathlib.Path):
    lines = install_lines(path)
    assert lines, f"{path.name} says nothing of how to install glyphcast"
    for line in lines:
        words = line.split()
        ours = [w for w in words if "glyphcast" in w or w.rstrip("/").endswith("python")]
        assert ours, f"{path.name}: `pip install {line}` installs no glyphcast"
        for word in ours:
            assert word.endswith(".whl") or "/" in word, (
                f"{path.name}: `pip install {line}`: {word} is no wheel or folder; "
                "no package index serves glyphcast"
            )


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_the_notebook_is_saved_with_its_outputs(path: pathlib.Path):
    code = [cell for cell in cells(path) if cell["cell_type"] == "code"]
    assert code, path.name
    for n, cell in enumerate(code):
        assert cell.get("execution_count"), f"{path.name}: code cell {n} was not run"
        for output in cell["outputs"]:
            assert output.get("output_type") != "error", f"{path.name}: cell {n} failed"
    counts = [cell["execution_count"] for cell in code]
    assert counts == list(range(1, len(code) + 1)), f"{path.name}: run out of order: {counts}"
    images = [o for cell in code for o in cell["outputs"] if "image/png" in o.get("data", {})]
    assert len(images) >= 2, f"{path.name}: {len(images)} pictures saved"
