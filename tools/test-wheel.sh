#!/usr/bin/env bash
# The Python tests against the wheel a user installs, not against the development build:
# builds the wheel (tools/build-wheel.sh: release, manylinux_2_28, abi3), installs it
# with pip into a fresh virtual environment (target/wheel-test-venv, made anew each run)
# with the test suite's own packages, checks that `glyphcast` is imported from that
# installation, and runs python/tests there on lavapipe with the validation layer on.
#
#   bash tools/test-wheel.sh [PYTEST ARGS...]
#
# Not part of tools/test.sh: the wheel is a release build of the whole library, many
# minutes from cold on a small machine. The tests that compare with the command line
# run the development build of `glyphcast` (cargo build --bin glyphcast), or the binary
# GLYPHCAST_BIN names.
set -euo pipefail
cd "$(dirname "$0")/.."
export GLYPHCAST_LAVAPIPE="${GLYPHCAST_LAVAPIPE:-1}"
. tools/env.sh
target="${CARGO_TARGET_DIR:-$PWD/target}"
wheels="$target/wheels"
rm -rf "$wheels"
bash tools/build-wheel.sh "$wheels"
wheel=$(ls "$wheels"/glyphcast-*.whl)

venv="$target/wheel-test-venv"
rm -rf "$venv"
python3 -m venv "$venv"
"$venv/bin/python" -m pip install -q --disable-pip-version-check \
    "$wheel[test]" dipy
# From the wheel's installation, not from python/ in this tree.
(cd "$target" && "$venv/bin/python" - "$venv" <<'EOF'
import pathlib, sys
import glyphcast, glyphcast._glyphcast as module
venv = pathlib.Path(sys.argv[1]).resolve()
for path in (glyphcast.__file__, module.__file__):
    if venv not in pathlib.Path(path).resolve().parents:
        sys.exit(f"glyphcast comes from {path}, not from the wheel in {venv}")
print("glyphcast from", pathlib.Path(module.__file__).parent)
EOF
)
# The command line the parity tests compare with: GLYPHCAST_BIN, or the development
# build (made here; a no-op after tools/test.sh).
if [ -z "${GLYPHCAST_BIN:-}" ]; then
    cargo build --locked --bin glyphcast
    export GLYPHCAST_BIN="$target/debug/glyphcast"
fi
# Run from outside the tree, so that nothing in it is importable by accident.
root=$PWD
(cd "$target" && "$venv/bin/python" -m pytest -q -p no:cacheprovider "$root/python/tests" "$@")
