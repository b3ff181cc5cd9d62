#!/usr/bin/env bash
# Fresh machine to a passing test suite: installs what is missing, then runs every test
# on lavapipe with the Vulkan validation layer on (the tests turn it on themselves), and
# checks that the core builds, passes its tests and stays free of the front ends'
# dependencies without the default features (what an embedding engine gets).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
export GLYPHCAST_LAVAPIPE="${GLYPHCAST_LAVAPIPE:-1}"
. tools/env.sh
cargo test --locked "$@"
echo "== the core alone (--no-default-features)"
if cargo tree --locked --no-default-features -e normal --prefix none \
    | grep -E '^(winit|plotters|nifti|clap|indicatif) v'; then
    echo "error: the core's dependency tree holds a front end's crate (above)" >&2
    exit 1
fi
cargo test --locked --no-default-features --lib --examples
