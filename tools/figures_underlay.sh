#!/usr/bin/env bash
# The underlay and anti-aliasing figures of the guide (docs/gallery/), from DIPY's small
# 64-direction test DWI (tests/data/dipy, BSD-3): tensors fitted by glyphcast fit, FA and
# colour-FA maps by tools/fa_map.py, drawn under the tensor glyphs.
#   bash tools/figures_underlay.sh [glyphcast binary]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-target/release/glyphcast}
data=tests/data/dipy
out=docs/gallery
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
"$bin" fit "$data/small_64D.nii" --bval "$data/small_64D.bval" --bvec "$data/small_64D.bvec" \
    --order 2 -o "$work/dti.nii" --quiet
python3 tools/fa_map.py "$work/dti.nii" "$work/fa.nii" "$work/colour-fa.nii"
common=(--tensor "$work/dti.nii" --order 2 --width 480 --height 480 --samples 16)
# FA under the middle axial slice.
"$bin" render "${common[@]}" --underlay "$work/fa.nii" -o "$out/underlay-fa.png"
# The same lit from the side with hard shadows: the glyphs' shadows fall on the FA.
"$bin" render "${common[@]}" --underlay "$work/fa.nii" --shadows --light -0.8,0.3,0.5 \
    -o "$out/underlay-shadows.png"
# Colour-FA under three orthogonal slices, glyphs and planes cutting each other.
"$bin" render "${common[@]}" --underlay "$work/colour-fa.nii" --underlay-range 0:0.6 \
    --slices mid -o "$out/underlay-slices.png"
# Anti-aliasing: the demo at one sample per pixel and at 16, transparent, small.
for samples in 1 16; do
    "$bin" demo --width 200 --height 150 --samples "$samples" --background none \
        -o "$out/samples-$samples.png"
done
