#!/usr/bin/env bash
# Fresh machine to picture: installs what is missing, builds, renders the built-in demo.
# Extra arguments go to `glyphcast demo` (e.g. -o other.png --width 1600 --height 1200).
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install-deps.sh
. tools/env.sh
cargo build --release --locked
exec target/release/glyphcast demo -o glyphcast-demo.png "$@"
