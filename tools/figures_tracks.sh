#!/usr/bin/env bash
# The pictures of docs/guide/tracks.md: DIPY's small_64D fitted by CSD (as a DIPY user
# fits it) with the streamlines DIPY tracks through its own CSD fit of it
# (tools/dipy_tracks.py: deterministic tracking, saved by DIPY as a .trk), drawn as
# tubes; DIPY's bundled tractograms lie elsewhere in the scanner frame:
# - docs/gallery/tracks-slab.png: the default axial slice, the parts of 150 of the
#   streamlines within 1 mm of it (--slab 1), 640 pixels wide;
# - docs/gallery/tracks-block.png: every voxel of the two middle axial slices in 3D
#   with 40 of the streamlines whole, perspective, 640 pixels wide;
# - docs/gallery/tracks-lines.png: the same block with 1,500 of the streamlines as lines
#   (--tracks-style lines, a pixel wide).
# Usage: tools/figures_tracks.sh [GLYPHCAST_BINARY]   (default: builds target/release)
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -ge 1 ]; then
    glyphcast=$1
else
    . tools/env.sh
    cargo build --release --locked -p glyphcast-cli
    glyphcast=target/release/glyphcast
fi
python=${PYTHON:-target/py-venv/bin/python}
data=tests/data/dipy
out=docs/gallery
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$glyphcast" fit "$data/small_64D.nii" --bval "$data/small_64D.bval" \
    --bvec "$data/small_64D.bvec" --odf csd --csd-algorithm dipy --order 8 --basis dipy \
    --quiet -o "$work/csd.nii.gz"
"$python" tools/dipy_tracks.py "$data" "$work/tracks.trk"
"$glyphcast" render --sh "$work/csd.nii.gz" --basis dipy --tracks "$work/tracks.trk" \
    --slab 1 --tracks-radius 0.08 --tracks-max 150 --width 640 -o "$out/tracks-slab.png"
"$glyphcast" render --sh "$work/csd.nii.gz" --basis dipy --tracks "$work/tracks.trk" \
    --tracks-radius 0.08 --tracks-max 40 --block --voxels :,:,4:6 --perspective --width 640 \
    -o "$out/tracks-block.png"
"$glyphcast" render --sh "$work/csd.nii.gz" --basis dipy --tracks "$work/tracks.trk" \
    --tracks-style lines --tracks-radius 0.02 --tracks-max 1500 --block --voxels :,:,4:6 \
    --perspective --width 640 -o "$out/tracks-lines.png"
echo "wrote $out/tracks-slab.png, $out/tracks-block.png and $out/tracks-lines.png"
