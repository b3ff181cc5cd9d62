#!/usr/bin/env bash
# Every picture of the README's gallery and the guide, made again from the data in this
# tree (DIPY's small_64D, tests/data/dipy, BSD-3, and examples/stiffness/) with the
# commands the pages show beside them:
#   bash tools/gallery.sh [GLYPHCAST_BINARY]     (default: builds target/release)
# Writes docs/gallery/*.png and docs/images/fodf-csd.png. Parts: tools/gallery_figures_a.sh
# (ellipsoids, lighting, colour bar, views, lightbox), tools/figures_underlay.sh
# (underlays, anti-aliasing), tools/figures_dipy.sh (DIPY's fODFs over FA),
# tools/figures_shadows.sh (shadows and ambient occlusion); here: the CSD
# slice, peaks, the stiffness row and the QC page (a screenshot by headless Chromium,
# skipped with a note where none is installed). The cohort page needs a SLURM cluster:
# docs/guide/cohorts.md has its command.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -ge 1 ]; then
    bin=$(realpath "$1")
else
    . tools/env.sh
    cargo build --release --locked -p glyphcast-cli
    bin=$PWD/target/release/glyphcast
fi
export GLYPHCAST_LAVAPIPE="${GLYPHCAST_LAVAPIPE:-1}"
bash tools/gallery_figures_a.sh "$bin"
bash tools/figures_underlay.sh "$bin"
bash tools/figures_dipy.sh "$bin"
bash tools/figures_shadows.sh "$bin"

data=tests/data/dipy
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
dwi=("$data/small_64D.nii" --bval "$data/small_64D.bval" --bvec "$data/small_64D.bvec")
"$bin" fit "${dwi[@]}" --odf csd --order 8 --quiet -o "$work/fod.nii.gz"
"$bin" fit "${dwi[@]}" --order 2 --quiet -o "$work/dti.nii.gz"
# The CSD slice of the README and the fitting guide.
"$bin" render --sh "$work/fod.nii.gz" --norm per-glyph --negative hide --width 360 \
    --height 360 -o docs/images/fodf-csd.png
# fODFs with their peaks over the l = 0 image.
"$bin" peaks "$work/fod.nii.gz" -o "$work/peaks.nii.gz"
"$bin" render --sh "$work/fod.nii.gz" --norm per-glyph --scale 0.4 --negative hide \
    --peaks "$work/peaks.nii.gz" --peaks-color white --labels --width 480 --height 480 \
    -o docs/gallery/peaks.png
# Three crystals on one scale (docs/guide/materials.md).
"$bin" stiffness examples/stiffness/copper.txt examples/stiffness/quartz.csv \
    examples/stiffness/cristobalite.json -o "$work/row.json"
"$bin" render "$work/row.json" -o docs/gallery/stiffness-row.png --width 900 --height 400 \
    --color magnitude --colorbar
# Their Young's modulus and linear compressibility surfaces (docs/guide/materials.md).
"$bin" stiffness examples/stiffness/copper.txt examples/stiffness/quartz.csv \
    examples/stiffness/cristobalite.json --surface young -o "$work/young.json"
"$bin" render "$work/young.json" -o docs/gallery/stiffness-young.png --width 900 \
    --height 400 --color magnitude --colorbar --colorbar-label "Young's modulus (GPa)"
"$bin" stiffness examples/stiffness/copper.txt examples/stiffness/quartz.csv \
    examples/stiffness/cristobalite.json --surface compressibility -o "$work/beta.json"
"$bin" render "$work/beta.json" -o docs/gallery/stiffness-compressibility.png --width 900 \
    --height 400 --color sign
# Cristobalite's smallest Poisson's ratio, negative (auxetic) in most directions.
"$bin" stiffness examples/stiffness/cristobalite.json --surface poisson-min -o "$work/nu.json"
"$bin" render "$work/nu.json" -o docs/gallery/stiffness-poisson.png --width 450 \
    --height 400 --color sign
# The QC page: the top of index.html, as a browser shows it.
"$bin" qc "$work/fod.nii.gz" --peaks "$work/peaks.nii.gz" --quiet -o "$work/qc"
browser=$(command -v chromium || command -v chromium-browser || command -v google-chrome || true)
if [ -n "$browser" ]; then
    "$browser" --headless --no-sandbox --disable-gpu --hide-scrollbars \
        --window-size=1200,900 --screenshot="$PWD/docs/gallery/qc-page.png" \
        "file://$work/qc/index.html" 2>/dev/null
else
    echo "note: no Chromium: docs/gallery/qc-page.png left as it is" >&2
fi
echo "wrote docs/gallery/*.png and docs/images/fodf-csd.png"
