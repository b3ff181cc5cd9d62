#!/usr/bin/env bash
# Fresh machine to a passing test suite: installs what is missing, then runs every test
# on lavapipe with the Vulkan validation layer on (the tests turn it on themselves).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
export GLYPHCAST_LAVAPIPE="${GLYPHCAST_LAVAPIPE:-1}"
. tools/env.sh
cargo test --locked "$@"
