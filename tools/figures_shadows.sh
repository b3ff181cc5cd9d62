#!/usr/bin/env bash
# The pictures of docs/guide/shadows.md, from the scenes of tests/shadows.rs (the small
# glyph above a flat one, tests/scenes/sphere_above_flat.json, and nine crossing-fibre
# fODFs, tests/scenes/fibre_field.json), panels joined by Python's PIL:
# - docs/gallery/shadows-pair.png: the small glyph lit from the side, without shadows,
#   with --shadows and with --shadows soft:6, 320 x 320 each;
# - docs/gallery/ambient-occlusion.png: each scene without and with --ambient-occlusion
#   (reach 1, and 0.5 for the fODFs), --ambient 0.6 --specular 0, 260 x 260 each.
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
ao=(--ambient 0.6 --specular 0 --color uniform --width 260 --height 260)
"$glyphcast" render "$scene" "${ao[@]}" -o "$work/ball.png"
"$glyphcast" render "$scene" "${ao[@]}" --ambient-occlusion -o "$work/ball-ao.png"
fibres=tests/scenes/fibre_field.json
"$glyphcast" render "$fibres" "${ao[@]}" -o "$work/fibres.png"
"$glyphcast" render "$fibres" "${ao[@]}" --ambient-occlusion 0.5 -o "$work/fibres-ao.png"
# Panels side by side, `gap` transparent pixels apart.
join() {
    python3 - "$work" "$@" <<'PY'
import sys
from PIL import Image
work, gap, target, names = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4:]
panels = [Image.open(f"{work}/{name}.png").convert("RGBA") for name in names]
width = sum(p.width for p in panels) + gap * (len(panels) - 1)
joined = Image.new("RGBA", (width, panels[0].height), (0, 0, 0, 0))
x = 0
for panel in panels:
    joined.paste(panel, (x, 0))
    x += panel.width + gap
joined.save(target)
PY
}
join 0 "$out/shadows-pair.png" off hard soft
join 10 "$out/ambient-occlusion.png" ball ball-ao fibres fibres-ao
echo "wrote $out/shadows-pair.png and $out/ambient-occlusion.png"
