#!/usr/bin/env bash
# The shadows picture of docs/guide/shadows.md (docs/gallery/shadows-pair.png): the small
# glyph above a flat one of tests/shadows.rs (tests/scenes/sphere_above_flat.json), lit
# from the side, without shadows, with --shadows and with --shadows soft:6, 320 x 320
# each, side by side (joined by Python's PIL).
# Usage: tools/figures_shadows.sh [GLYPHCAST_BINARY]   (default: builds target/release)
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -ge 1 ]; then
    glyphcast=$1
else
    . tools/env.sh
    cargo build --release --locked -p glyphcast-cli
    glyphcast=target/release/glyphcast
fi
scene=tests/scenes/sphere_above_flat.json
out=docs/gallery
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The world direction (1, 0.25, 0.8) towards the light, in the camera's view coordinates
# (as tests/shadows.rs view_light turns it).
light=0.78981,0.34213,0.50907
common=(--color uniform --light "$light" --width 320 --height 320)
"$glyphcast" render "$scene" "${common[@]}" -o "$work/off.png"
"$glyphcast" render "$scene" "${common[@]}" --shadows -o "$work/hard.png"
"$glyphcast" render "$scene" "${common[@]}" --shadows soft:6 -o "$work/soft.png"
python3 - "$work" "$out/shadows-pair.png" <<'PY'
import sys
from PIL import Image
work, target = sys.argv[1], sys.argv[2]
panels = [Image.open(f"{work}/{name}.png") for name in ("off", "hard", "soft")]
joined = Image.new("RGBA", (sum(p.width for p in panels), panels[0].height))
for i, panel in enumerate(panels):
    joined.paste(panel, (i * panel.width, 0))
joined.save(target)
PY
echo "wrote $out/shadows-pair.png"
