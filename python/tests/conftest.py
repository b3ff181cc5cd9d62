"""Shared fixtures: lavapipe with the validation layer on, the CLI to compare with, the
repository's scenes and DIPY data.

Validation: GLYPHCAST_VALIDATION=1 is set for the whole session, so every Renderer turns
the layer on and a validation error in any render raises RuntimeError, failing the test.
"""
import os
import pathlib
import subprocess

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
LAVAPIPE = pathlib.Path(f"/usr/share/vulkan/icd.d/lvp_icd.{os.uname().machine}.json")

os.environ["GLYPHCAST_VALIDATION"] = "1"
if os.environ.get("GLYPHCAST_LAVAPIPE", "1") == "1" and LAVAPIPE.exists():
    os.environ.setdefault("VK_DRIVER_FILES", str(LAVAPIPE))


@pytest.fixture(scope="session")
def cli_binary():
    """The built `glyphcast` binary: GLYPHCAST_BIN, else target/debug/glyphcast."""
    binary = pathlib.Path(os.environ.get("GLYPHCAST_BIN", ROOT / "target/debug/glyphcast"))
    if not binary.exists():
        pytest.fail(f"{binary} is missing: build it first (cargo build --bin glyphcast)")
    return binary


@pytest.fixture(scope="session")
def cli(cli_binary):
    """Runs `glyphcast` with the validation layer on; fails the test on a non-zero exit."""
    binary = cli_binary

    def run(*args):
        done = subprocess.run(
            [str(binary), *map(str, args), "--validation"], capture_output=True, text=True
        )
        assert done.returncode == 0, done.stderr
        return done

    return run


@pytest.fixture
def cli_depth(cli, tmp_path):
    """The depth map of `glyphcast render ARGS`, read from its --depth-out."""

    def render(*args):
        depth = tmp_path / "cli-depth.npy"
        cli("render", *args, "-o", tmp_path / "cli.png", "--depth-out", depth)
        return np.load(depth)

    return render


@pytest.fixture
def cli_render(cli, tmp_path):
    """The depth map and the PNG bytes of `glyphcast render ARGS`."""

    def render(*args):
        depth, png = tmp_path / "cli-depth.npy", tmp_path / "cli.png"
        cli("render", *args, "-o", png, "--depth-out", depth)
        return np.load(depth), png.read_bytes()

    return render


@pytest.fixture(scope="session")
def scenes():
    return ROOT / "tests" / "scenes"


@pytest.fixture(scope="session")
def func_coef():
    """DIPY's func_coef.nii.gz (vendored in tests/data/dipy)."""
    return ROOT / "tests" / "data" / "dipy" / "func_coef.nii.gz"


def assert_same_depth(python, cli):
    """Bit-identical depth maps, NaN (misses) in the same pixels, and something hit."""
    assert python.dtype == np.float32 and cli.dtype == np.float32
    assert python.shape == cli.shape
    assert np.isfinite(python).any(), "nothing was hit: the comparison would be vacuous"
    assert np.array_equal(python, cli, equal_nan=True)
