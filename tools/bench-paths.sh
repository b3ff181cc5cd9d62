#!/usr/bin/env bash
# Which ray caster `--path auto` takes on this device, and what that costs against each
# path asked for by name: `glyphcast bench` of two flat fields of band-8 fODFs (the peer
# field, 256 glyphs, and 10,000 glyphs) at 1280x720 with --path auto, fragment and
# compute, interleaved ROUNDS times (default 3), one row per run: the path taken and the
# GPU median per frame.
#
#   bash tools/bench-paths.sh [GLYPHCAST_BINARY] [ROUNDS] [FRAMES]
#
# Timing is noisy on a shared machine: compare rows of one run.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-target/release/glyphcast}
rounds=${2:-3}
frames=${3:-5}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "| workload | --path | path taken | GPU ms |"
echo "|---|---|---|---|"
for round in $(seq "$rounds"); do
    for workload in fodf:256:8 fodf:10000:8; do
        for path in auto fragment compute; do
            "$bin" bench --workload "$workload" --width 1280 --height 720 --frames "$frames" \
                --warmup 1 --path "$path" --out "$out" >/dev/null 2>&1
            python3 - "$workload" "$path" "$out/results.csv" <<'PY'
import csv, sys
workload, asked, path = sys.argv[1:]
r = next(csv.DictReader(open(path)))
print(f"| {workload} | {asked} | {r['path']} | {float(r['gpu_ms_median']):.1f} |")
PY
        done
    done
done
