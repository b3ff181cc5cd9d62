#!/usr/bin/env bash
# What hidden glyphs cost, in one command: `glyphcast bench` of the front layer of a
# 16 x 16 x 16 block of band-8 fODFs alone and of the whole block (head-on, from a
# corner, and with the front layer copied into every layer) with culling off, in passes
# and by early outs, and of two flat fields with culling off and on (--cull occluded, the
# default), on the fragment path, then the front layer and the block on the compute
# path. Prints one row per run: GPU median per frame, passes, the work per covered pixel
# (fragment shader invocations and glyph evaluations, counted in a frame of their own),
# and how the frame was culled.
#
#   bash tools/bench-visibility.sh [GLYPHCAST_BINARY] [FRAMES]
#
# Timing is noisy on a shared machine: compare rows of one run, and run it twice.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-target/release/glyphcast}
frames=${2:-5}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
size=(--width 1280 --height 720)
row() {
    local label=$1
    shift
    "$bin" bench "${size[@]}" --frames "$frames" --warmup 1 --out "$out" "$@" >/dev/null 2>&1
    python3 - "$label" "$out/results.csv" <<'EOF'
import csv, sys
label, path = sys.argv[1], sys.argv[2]
r = next(csv.DictReader(open(path)))
px = max(int(r["covered_pixels"]), 1)
per = lambda k: f"{int(r[k]) / px:.2f}" if r.get(k) else "-"
print(f"| {label} | {r['glyphs']} | {100 * px / (int(r['width']) * int(r['height'])):.1f} % "
      f"| {float(r['gpu_ms_median']):.0f} | {r['passes']} | {per('fragments')} "
      f"| {per('evaluations')} | {r['culling']} |")
EOF
}
echo "| workload | glyphs | covered | GPU ms | passes | fragments/px | evaluations/px | cull |"
echo "|---|---|---|---|---|---|---|---|"
row "front layer, block:16:16:1:8" --workload block:16:16:1:8
for cull in off passes early-out; do
    row "block:16:16:16:8 head-on, cull $cull" --workload block:16:16:16:8 --cull $cull
    row "block:16:16:16:8:corner, cull $cull" --workload block:16:16:16:8:corner --cull $cull
    row "block:16:16:16:8:stacked, cull $cull" --workload block:16:16:16:8:stacked --cull $cull
done
for cull in off occluded; do
    row "peer field fodf:256:8, cull $cull" --workload fodf:256:8 --cull $cull
    row "fodf:10000:8, cull $cull" --workload fodf:10000:8 --cull $cull
done
row "front layer, compute path" --workload block:16:16:1:8 --path compute
row "block:16:16:16:8 head-on, compute path" --workload block:16:16:16:8 --path compute
