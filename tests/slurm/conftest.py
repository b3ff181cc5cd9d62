"""The cohort scripts on a real SLURM cluster: the sbatch, squeue and scancel on the PATH
and the cluster of the environment (SLURM_CONF; tools/test.sh starts the local one with
tools/slurm-local.sh). The binary is GLYPHCAST_BIN (default target/debug/glyphcast);
the jobs draw on lavapipe with the validation layer on (GLYPHCAST_VALIDATION=1).
"""
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
LAVAPIPE = pathlib.Path(f"/usr/share/vulkan/icd.d/lvp_icd.{os.uname().machine}.json")

os.environ["GLYPHCAST_VALIDATION"] = "1"
if os.environ.get("GLYPHCAST_LAVAPIPE", "1") == "1" and LAVAPIPE.exists():
    os.environ.setdefault("VK_DRIVER_FILES", str(LAVAPIPE))


@pytest.fixture(scope="session")
def cluster():
    """Fails (not skips) when no cluster answers: these tests exist to run on one."""
    if shutil.which("sbatch") is None or shutil.which("squeue") is None:
        pytest.fail("sbatch/squeue are not on the PATH: start a cluster first "
                    "(bash tools/slurm-local.sh start; eval \"$(bash tools/slurm-local.sh env)\")")
    done = subprocess.run(["sinfo", "-h", "-o", "%T"], capture_output=True, text=True)
    states = done.stdout.split()
    if done.returncode != 0 or not any(s in ("idle", "mixed", "allocated") for s in states):
        pytest.fail(f"no usable SLURM node (sinfo: {done.stdout.strip()} {done.stderr.strip()})")


@pytest.fixture(scope="session")
def env(cluster):
    """The environment of the scripts: the binary, this Python."""
    binary = pathlib.Path(os.environ.get("GLYPHCAST_BIN", ROOT / "target/debug/glyphcast"))
    if not binary.is_file():
        pytest.fail(f"{binary} is missing: build it first (cargo build --bin glyphcast)")
    return dict(os.environ, GLYPHCAST_BIN=str(binary.resolve()),
                PYTHON=os.environ.get("PYTHON", sys.executable))
