#!/usr/bin/env bash
# What culling can still gain, in one command: for the front layer of a 16 x 16 x 16
# block of band-8 fODFs and for the block (head-on, from a corner, stacked, and stacked
# seen from four times as far, where every layer's gaps line up behind the front
# layer's), the glyph evaluations per covered pixel that `glyphcast bench` measures with
# --cull early-out and --cull passes next to the floor: the fewest that any exact
# culling can make with the same proxies (the visibility_floor example, float64 on the
# CPU), and an estimate of that floor with tighter proxies (13-axis k-DOPs).
#
#   bash tools/visibility-floor.sh [GLYPHCAST_BINARY] [STEP]
#
# STEP samples every STEP-th pixel for the floor (default 2). Takes about a minute.
# With SCENES=DIR set, the six scene files are kept in DIR (front.json, head-on.json,
# corner.json, stacked.json, front-far.json, stacked-far.json), for `glyphcast bench`.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-target/release/glyphcast}
step=${2:-2}
cargo build --release --locked -q --example visibility_floor
floor=target/release/examples/visibility_floor
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
scenes=${SCENES:-$out}
mkdir -p "$scenes"
size=(--width 1280 --height 720)
save() {  # save NAME WORKLOAD: the workload's scene file
    "$bin" bench "${size[@]}" --workload "$2" --frames 1 --save-scene "$scenes/$1.json" \
        --out "$out" >/dev/null 2>&1
}
save front block:16:16:1:8
save head-on block:16:16:16:8
save corner block:16:16:16:8:corner
save stacked block:16:16:16:8:stacked
# The stacked block from four times as far, framed the same through a narrower field of
# view (the front layer at z = 0 keeps its size on screen).
python3 - "$scenes" <<'EOF'
import json, math, sys
out = sys.argv[1]
s = json.load(open(f"{out}/stacked.json"))
c = s["camera"]
z = c["eye"][2]
c["eye"][2] = 4 * z
c["fov_y_deg"] = 2 * math.degrees(math.atan(math.tan(math.radians(c["fov_y_deg"] / 2)) / 4))
json.dump(s, open(f"{out}/stacked-far.json", "w"))
s = json.load(open(f"{out}/front.json"))
s["camera"] = c
json.dump(s, open(f"{out}/front-far.json", "w"))
EOF
evaluations() {  # evaluations SCENE CULL: the bench's evaluations per covered pixel
    "$bin" bench "$1" --frames 1 --cull "$2" --out "$out" >/dev/null 2>&1
    python3 -c 'import csv, sys; r = next(csv.DictReader(open(sys.argv[1])))
print("%.2f" % (int(r["evaluations"]) / max(int(r["covered_pixels"]), 1)))' "$out/results.csv"
}
echo "| scene | covered pixels | proxy fragments/px | early outs | passes | floor | floor with k-DOPs (estimate) |"
echo "|---|---|---|---|---|---|---|"
for name in front head-on corner stacked front-far stacked-far; do
    line=$("$floor" "$scenes/$name.json" "$step")
    python3 - "$name" "$line" "$(evaluations "$scenes/$name.json" early-out)" \
        "$(evaluations "$scenes/$name.json" passes)" <<'EOF'
import sys
name, line, early, passes = sys.argv[1:]
# "SCENE: covered pixels N, proxy fragments/px F, floor evaluations/px E, with ... K"
v = [item.rsplit(" ", 1)[1] for item in line.rsplit(": ", 1)[1].split(", ")]
print(f"| {name} | {int(v[0]):,} | {v[1]} | {early} | {passes} | {v[2]} | {v[3]} |")
EOF
done
