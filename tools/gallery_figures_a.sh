#!/usr/bin/env bash
# The figure gallery of docs/guide/figures.md, part A: DTI ellipsoids, lighting, the colour
# bar, a three-view montage and a lightbox, all from DIPY's small_64D (BSD-3, in
# tests/data/dipy), fitted by glyphcast itself. Writes docs/gallery/*.png.
# Usage: tools/gallery_figures_a.sh [GLYPHCAST_BINARY]   (default: builds target/release)
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -ge 1 ]; then
    glyphcast=$1
else
    . tools/env.sh
    cargo build --release --locked
    glyphcast=target/release/glyphcast
fi
data=tests/data/dipy
out=docs/gallery
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
inputs=("$data/small_64D.nii" --bval "$data/small_64D.bval" --bvec "$data/small_64D.bvec")
"$glyphcast" fit "${inputs[@]}" --order 2 --quiet -o "$work/dti.nii.gz"
"$glyphcast" fit "${inputs[@]}" --order 6 --sh --quiet -o "$work/fod.nii.gz"

# DTI ellipsoids coloured by principal direction, beside the polynomial ("peanut") glyph.
"$glyphcast" render --tensor "$work/dti.nii.gz" --order 2 --glyph ellipsoid \
    --width 360 --height 360 -o "$out/ellipsoids.png"
"$glyphcast" render --tensor "$work/dti.nii.gz" --order 2 \
    --width 360 --height 360 -o "$out/peanuts.png"
# Lighting: a matte light from the upper left against the default.
"$glyphcast" render --sh "$work/fod.nii.gz" --light -1,1,0.6 --ambient 0.3 --specular 0 \
    --width 360 --height 360 -o "$out/lighting.png"
# Magnitude colours with their colour bar, in data units.
"$glyphcast" render --sh "$work/fod.nii.gz" --color magnitude --colorbar \
    --colorbar-label "fODF amplitude" --width 360 --height 360 -o "$out/colorbar.png"
# Three views side by side, labelled, and a 3 x 3 lightbox of axial slices.
"$glyphcast" render --tensor "$work/dti.nii.gz" --order 2 --glyph ellipsoid \
    --views axial,coronal,sagittal --labels --width 240 --height 240 -o "$out/views.png"
"$glyphcast" render --sh "$work/fod.nii.gz" --lightbox 9 --width 160 --height 160 \
    -o "$out/lightbox.png"
echo "wrote $out/{ellipsoids,peanuts,lighting,colorbar,views,lightbox}.png"
