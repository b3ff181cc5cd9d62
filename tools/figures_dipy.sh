#!/usr/bin/env bash
# The DIPY figures of docs/guide/figures.md (docs/gallery/dipy-*.png), from DIPY's small
# 64-direction test DWI (tests/data/dipy, BSD-3): CSD fODFs (band 8, DIPY's basis) and
# tensors fitted by glyphcast fit, FA by tools/fa_map.py; the fODFs over FA with every
# default a DIPY user gets (underlay behind the glyphs, the default sizes), and a 3D
# block of them:
#   bash tools/figures_dipy.sh [glyphcast binary]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-target/release/glyphcast}
data=tests/data/dipy
out=docs/gallery
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
dwi=("$data/small_64D.nii" --bval "$data/small_64D.bval" --bvec "$data/small_64D.bvec")
"$bin" fit "${dwi[@]}" --odf csd --csd-algorithm dipy --order 8 --basis dipy -o "$work/csd.nii" --quiet
"$bin" fit "${dwi[@]}" --order 2 -o "$work/dti.nii" --quiet
python3 tools/fa_map.py "$work/dti.nii" "$work/fa.nii"
common=(--sh "$work/csd.nii" --underlay "$work/fa.nii" --underlay-range 0:1 --samples 16
    --background black)
# The three-view figure: axial, coronal and sagittal through the middle, labelled.
"$bin" render "${common[@]}" --views axial,coronal,sagittal --labels --width 360 \
    --height 360 -o "$out/dipy-views.png"
# A lightbox of 9 axial slices, each captioned with its slice.
"$bin" render "${common[@]}" --lightbox 9 --width 220 --height 220 -o "$out/dipy-lightbox.png"
# A block: all 10 x 10 voxels of six axial slices in 3D, seen from above-left-front,
# with the default sizes (a block takes no underlay).
"$bin" render --sh "$work/csd.nii" --block --voxels :,:,2:8 \
    --negative hide --samples 16 --background black --width 720 -o "$out/dipy-block.png"
