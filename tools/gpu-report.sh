#!/usr/bin/env bash
# The GPU table in one command, on any machine with a Vulkan device:
#   tools/gpu-report.sh [--quick] [--bin PATH] [--counts N,N,...] OUTDIR
# builds glyphcast (or takes the release binary PATH built elsewhere: a GPU machine that
# reaches no registry needs only it and the Vulkan loader), measures
#   - the first image: whole `glyphcast render` processes, default method and impostor,
#     on the demo scene and on the 256-glyph band-8 peer field;
#   - `glyphcast bench --sweep gpu`: band-8 fODF fields of 10^3 to 10^6 glyphs at
#     1280x720, 1920x1080 and 3840x2160, methods exact, affine, interval, fixed, impostor,
#     mesh:3, mesh:5 on the fragment path, exact on the compute path and on --path auto
#     (the path it takes on this device), accuracy against
#     the float64 reference on the 10^3 field;
# and writes OUTDIR/<device>.md naming the device and driver (the raw results beside it
# in OUTDIR/<device>/). --quick: 100 and 1000 glyphs at 320x180 and 640x360, a couple of
# minutes on lavapipe (the test suite runs it). --counts: the field sizes of the frame
# sweep (default 1000,10000,100000,1000000). The report is written again after each field
# size, so a run cut off (a time limit) keeps the sizes it finished. The device is Vulkan's choice
# (discrete > integrated > virtual > CPU); GLYPHCAST_DEVICE or VK_DRIVER_FILES pick another.
set -euo pipefail
usage() {
    echo "usage: tools/gpu-report.sh [--quick] [--bin PATH] [--counts N,N,...] OUTDIR" >&2
    exit 2
}
quick=0 bin="" out="" counts=""
while [ $# -gt 0 ]; do
    case "$1" in
    --quick) quick=1 ;;
    --bin) [ $# -ge 2 ] || usage; bin=$2; shift ;;
    --bin=*) bin=${1#--bin=} ;;
    --counts) [ $# -ge 2 ] || usage; counts=$2; shift ;;
    --counts=*) counts=${1#--counts=} ;;
    -h | --help) usage ;;
    -*) echo "error: unknown option '$1'" >&2; usage ;;
    *) [ -z "$out" ] || usage; out=$1 ;;
    esac
    shift
done
[ -n "$out" ] || usage
if [ -n "$counts" ] && ! [[ $counts =~ ^[1-9][0-9]*(,[1-9][0-9]*)*$ ]]; then
    echo "error: --counts '$counts': not a list of glyph counts (like 1000,10000)" >&2
    exit 2
fi
root=$(cd "$(dirname "$0")/.." && pwd)
if [ -z "$bin" ]; then
    . "$root/tools/env.sh"
    (cd "$root" && cargo build --release --locked --bin glyphcast)
    bin=$root/target/release/glyphcast
fi
if [ ! -x "$bin" ] || [ -d "$bin" ]; then
    echo "error: $bin: --bin: not an executable file" >&2
    exit 1
fi
mkdir -p "$out"
work=$(mktemp -d "$out/.gpu-report.XXXXXX")
trap 'rm -rf "$work"' EXIT
started=$(date +%s)

# Wall seconds of a whole command (its output kept in $work/last.log).
wall() {
    local t0 t1
    t0=$(date +%s.%N)
    "$@" >"$work/last.log" 2>&1 || { echo "failed: $* (see below)" >&2; cat "$work/last.log" >&2; return 1; }
    t1=$(date +%s.%N)
    awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", b - a }'
}
# Median of the wall seconds of RUNS runs of a command.
median_wall() {
    local runs=$1 i
    shift
    for ((i = 0; i < runs; i++)); do wall "$@"; echo; done | sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'
}

echo "== device" >&2
"$bin" bench --workload fodf:1:8 --width 16 --height 16 --frames 1 --warmup 0 >"$work/probe.md" 2>"$work/probe.log" || {
    cat "$work/probe.log" >&2
    echo "error: no Vulkan device could run glyphcast (above)" >&2
    exit 1
}
device=$(sed -n 's/^Device: //p' "$work/probe.md" | head -n 1)
name=${device%% (*}
file=$(printf '%s' "$name" | tr -c 'A-Za-z0-9._-' '_' | sed 's/__*/_/g; s/^_//; s/_$//')
[ -n "$file" ] || file=device
echo "device: $device" >&2

runs=5
[ "$quick" = 1 ] && runs=3
echo "== first image (whole process, $runs runs each)" >&2
"$bin" bench --workload fodf:256:8 --width 1280 --height 720 --frames 1 --warmup 0 \
    --save-scene "$work/peer.json" >/dev/null 2>&1
first_image=""
for scene in demo peer; do
    if [ $scene = demo ]; then cmd=("$bin" demo -o "$work/first.png"); else cmd=("$bin" render "$work/peer.json" -o "$work/first.png"); fi
    default=$(median_wall $runs "${cmd[@]}")
    impostor=$(median_wall $runs "${cmd[@]}" --method impostor)
    ratio=$(awk -v a="$default" -v b="$impostor" 'BEGIN { printf "%.2f", a / b }')
    label=$([ $scene = demo ] && echo "demo scene (24 glyphs, orders 1 to 12)" || echo "peer field (256 band-8 fODFs, 1280x720)")
    first_image+="| $label | $default | $impostor | $ratio |"$'\n'
done

echo "== frames" >&2
if [ "$quick" = 1 ]; then
    batches=("gpu${counts:+:$counts}")
    frames=(--quick)
else
    IFS=, read -r -a sizes <<<"${counts:-1000,10000,100000,1000000}"
    batches=()
    for n in "${sizes[@]}"; do batches+=("gpu:$n"); done
    frames=(--frames 10 --warmup 2)
fi
version=$("$bin" --version 2>/dev/null || echo "glyphcast (version unknown)")
commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo "-")
cpu=$(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo 2>/dev/null || echo "-")
mode=$([ "$quick" = 1 ] && echo "--quick " || echo "")
mode+=${counts:+--counts $counts }
raw="$out/$file"
rm -rf "${raw:?}" "$out/$file.md"
mkdir -p "$raw"
pivots="" details="" notes=""
# The report as it stands after $1 of the ${#batches[@]} field sizes, written whole
# (a temporary file renamed), so a run cut off keeps what it finished.
write_report() {
    local done=$1 report="$work/report.md" pivot_table
    # One header for the joined frame tables.
    pivot_table=$(printf '%s' "$pivots" | awk 'NR <= 2 || !/^\| glyphs \|/ && !/^\|---/')
    {
        echo "# glyphcast GPU report: $name"
        echo
        echo "- Device: $device"
        echo "- glyphcast: $version, commit $commit (of the tree the script ran from)"
        echo "- Host: $cpu, $(nproc) cores; $(date -u +%Y-%m-%d)"
        echo "- Command: \`tools/gpu-report.sh ${mode}--bin BIN OUTDIR\`, $(($(date +%s) - started)) s"
        if [ "$done" -lt ${#batches[@]} ]; then
            echo "- Incomplete: $done of ${#batches[@]} field sizes measured so far"
        fi
        echo
        echo "## First image: whole \`glyphcast render\` process, wall seconds (median of $runs)"
        echo
        echo "| scene | default (exact) | impostor | ratio |"
        echo "|---|---|---|---|"
        printf '%s' "$first_image"
        echo
        echo "## Frames: GPU milliseconds per frame (median of the timed frames)"
        echo
        echo "Band-8 fODF fields (\`--workload fodf:COUNT:8\`: one to three fibres per glyph) seen"
        echo "whole; timestamps around the glyph pass. Methods: see docs/guide/accuracy.md, \"Baselines and benchmarks\"."
        echo
        printf '%s\n' "$pivot_table"
        echo
        printf '%s' "$notes" | grep . || true
        echo
        echo "## Every configuration"
        echo
        printf '%s' "$details"
    } >"$report"
    mv "$report" "$out/$file.md"
}
write_report 0
measured=0
for batch in "${batches[@]}"; do
    dir="$raw/${batch//[:,]/-}"
    echo "-- $batch" >&2
    mkdir -p "$dir"  # bench --out writes into an existing folder only
    if "$bin" bench --sweep "$batch" "${frames[@]}" --out "$dir" >"$dir.md" 2>"$dir.log"; then
        pivots+=$(awk '/^GPU milliseconds per frame/ { on = 1; next } on && /^\|/ { print } on && /^$/ && seen++ { exit }' "$dir.md")$'\n'
        details+=$(sed -n '/^| label |/,$p' "$dir.md" | sed '/^GPU milliseconds per frame/,/^$/d')$'\n\n'
        notes+=$(grep '^- ' "$dir.md" || true)$'\n'
    else
        notes+="- $batch: the sweep failed: $(tail -n 1 "$dir.log")"$'\n'
    fi
    measured=$((measured + 1))
    write_report $measured
done
echo "wrote $out/$file.md" >&2
