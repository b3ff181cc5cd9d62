#!/usr/bin/env bash
# Fresh machine to a passing test suite: installs what is missing, then runs every test
# on lavapipe with the Vulkan validation layer on (the tests turn it on themselves; the
# wgpu layer's on wgpu 30 and on wgpu 29), and
# checks that the core stays free of the front ends' dependencies and compiles alone from
# its package's own files (what an embedding engine and crates.io get); runs the C
# API's tests (its generated header, the C example engine built with cc, the C++ engine
# built with CMake and pkg-config against the installed library); then builds the
# Python module's wheel, installs it into a virtual environment (target/py-venv, reused)
# and runs its tests (python/tests) against the CLI, the workflow engines' (Nipype,
# pydra), the example notebook and the notebook view in JupyterLab and headless Chromium
# included; then the GPU tests again on Mesa 25's
# lavapipe (GLYPHCAST_MESA25=0 skips them);
# last, as root, the cohort scripts on a one-node SLURM cluster it starts and stops
# (tests/slurm, tools/slurm-local.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
export GLYPHCAST_LAVAPIPE="${GLYPHCAST_LAVAPIPE:-1}"
. tools/env.sh
cargo test --locked "$@"
echo "== [${SECONDS} s] glyphcast-wgpu on wgpu 29 (Bevy 0.19's), as above on wgpu 30"
cargo test --locked -p glyphcast-wgpu --no-default-features --features wgpu29
echo "== [${SECONDS} s] the core alone, as an engine depends on it"
# Cargo keeps the layers apart: the core's own dependency tree holds no front end's crate.
# flate2 is looked for among the direct dependencies only: the png crate deflates with it.
core_tree=$(cargo tree --locked -p glyphcast -e normal --prefix none)
core_direct=$(cargo tree --locked -p glyphcast -e normal --prefix none --depth 1)
if grep -E '^(clap|winit|plotters|indicatif|nifti|ndarray|clarabel|sha2|pyo3|glyphcast-[a-z]+) v' <<<"$core_tree" \
    || grep -E '^flate2 v' <<<"$core_direct"; then
    echo "error: the core's dependency tree holds a front end's crate (above)" >&2
    exit 1
fi
# The core and its shaderc helper as crates.io would receive them, the helper's tests and
# its message on a split shaderc without its parts (tools/package-check.sh).
echo "== [${SECONDS} s] the core and its shaderc helper as crates.io would receive them"
bash tools/package-check.sh
echo "== [${SECONDS} s] a new crate outside the repository, built with nothing sourced"
bash tools/outside-crate.sh
echo "== [${SECONDS} s] the C API (capi/): its header up to date, the C example engine (examples/c/)"
cargo test --locked -p glyphcast-c
echo "== [${SECONDS} s] the Python module (python/)"
# The CLI the Python tests compare with: built by `cargo test` above (a no-op then).
cargo test --locked --no-run --test integration
venv=target/py-venv
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install -q --disable-pip-version-check \
    'maturin>=1.9,<2' numpy pytest nibabel dipy nipype 'pydra>=0.25,<1' \
    nbclient nbformat ipykernel pillow \
    'jupyter_rfb>=1.0,<2' ipywidgets jupyterlab 'notebook>=7,<8' selenium
# The module as users get it: a wheel, installed with pip into the environment, so the
# tests import it from site-packages, not from python/. Built in the dev profile in the
# shared target/ (minutes from cold, seconds when nothing changed); the release
# artifact (abi3, manylinux_2_28, by maturin --zig) is tools/build-wheel.sh's, whose
# own check, tools/test-wheel.sh, runs these tests against it in a fresh environment.
wheels=target/wheels/test
rm -rf "$wheels"
(cd python && VIRTUAL_ENV="$PWD/../$venv" PATH="$PWD/../$venv/bin:$PATH" \
    maturin build --locked --profile dev --quiet --out "../$wheels")
"$venv/bin/python" -m pip uninstall -q -y glyphcast >/dev/null 2>&1 || true
"$venv/bin/python" -m pip install -q --disable-pip-version-check --no-deps "$wheels"/glyphcast-*.whl
python=$PWD/$venv/bin/python
(cd / && "$python" -c 'import glyphcast; f = glyphcast.__file__
assert "site-packages" in f, "glyphcast imported from " + f')
# conftest.py turns the validation layer on (GLYPHCAST_VALIDATION=1) and picks lavapipe.
"$venv/bin/python" -m pytest -q python/tests
# ---- Mesa 25 (GLYPHCAST_MESA25=0 skips it) --------------------------------------------
# The GPU tests of the core (its embedding example, the command line's integration
# tests), of the C API (the C and C++ example engines) and of the Python module again,
# on Mesa 25's lavapipe: unpacked from Debian's bookworm-backports beside the system's
# driver by tools/mesa25.sh (which adds that suite to apt's sources if no source lists
# it; nothing is installed).
if [ "${GLYPHCAST_MESA25:-1}" = 1 ]; then
    echo "== [${SECONDS} s] again on Mesa 25's lavapipe (tools/mesa25.sh)"
    (
        eval "$(bash tools/mesa25.sh)"
        # Every library's unit tests, the embedding example and the command line's
        # integration tests, with the features of the workspace build above (so nothing
        # is compiled again).
        cargo test --locked --lib --examples
        cargo test --locked -p glyphcast-wgpu --no-default-features --features wgpu29 --examples
        cargo test --locked -p glyphcast-cli --test integration
        cargo test --locked -p glyphcast-c
        # The browser test once (above): its JupyterLab and Chromium are the same here,
        # and the view's frames are the Renderer's, which these tests cover on Mesa 25.
        "$venv/bin/python" -m pytest -q python/tests --ignore python/tests/test_notebook_browser.py
    )
fi
echo "== [${SECONDS} s] cohorts on SLURM (tests/slurm, on a local one-node cluster: tools/slurm-local.sh)"
if [ "$(id -u)" = 0 ]; then
    # The cluster stops on every exit, a failed test's included.
    trap 'bash tools/slurm-local.sh stop' EXIT
    bash tools/slurm-local.sh start
    eval "$(bash tools/slurm-local.sh env)"
    GLYPHCAST_BIN="$PWD/target/debug/glyphcast" PYTHON="$PWD/$venv/bin/python" \
        "$venv/bin/python" -m pytest -q tests/slurm
else
    echo "skipped: the local cluster's daemons run as root (run this as root, or start a" \
         "cluster and run pytest tests/slurm with SLURM_CONF set)" >&2
fi
echo "== [${SECONDS} s] done"
