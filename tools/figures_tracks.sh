#!/usr/bin/env bash
# The pictures of docs/guide/tracks.md: DIPY's small_64D fitted by CSD (as a DIPY user
# fits it) with streamlines through it drawn as tubes. The streamlines are synthetic
# (tools/synthetic_tracks.py: curves through the volume's world box, written as an
# MRtrix .tck by nibabel), since DIPY's bundled tractograms lie elsewhere in the
# scanner frame:
# - docs/gallery/tracks-slab.png: the default axial slice, the parts of the streamlines
#   within 2 mm of it (--slab 2), 640 pixels wide;
# - docs/gallery/tracks-block.png: every voxel of the middle four axial slices in 3D
#   with every third streamline whole (--tracks-max 12), perspective, 640 pixels wide.
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
"$python" tools/synthetic_tracks.py "$work/csd.nii.gz" "$work/tracks.tck"
"$glyphcast" render --sh "$work/csd.nii.gz" --basis dipy --tracks "$work/tracks.tck" \
    --slab 2 --tracks-radius 0.2 --width 640 -o "$out/tracks-slab.png"
"$glyphcast" render --sh "$work/csd.nii.gz" --basis dipy --tracks "$work/tracks.tck" \
    --tracks-radius 0.15 --tracks-max 12 --block --voxels :,:,3:7 --perspective --width 640 \
    -o "$out/tracks-block.png"
echo "wrote $out/tracks-slab.png and $out/tracks-block.png"
