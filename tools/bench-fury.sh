#!/usr/bin/env bash
# The peer comparison of the README's performance section, in one command: glyphcast's
# exact frame against FURY 2.0's `sph_glyph` on the 256-glyph band-8 fODF field at
# 1280x720 (the field of `glyphcast bench --workload fodf:256:8`), on lavapipe.
#
#   tools/bench-fury.sh [--mesa25] [--bin PATH] [--workload SPEC] [--pairs 3] [--frames 20] [--warmup 3] OUTDIR
#
# - makes or reuses the virtual environment target/fury-venv with FURY 2.0.0 from PyPI
#   (FURY 2 draws with pygfx on wgpu, that is Vulkan: here, the same lavapipe);
# - takes glyphcast's field as glyphcast writes it (`bench --save-scene --scene-arrays`):
#   the same tournier07 coefficients, centres and camera go into FURY's scene, with
#   FURY's default sphere (symmetric362), offscreen, pixel ratio 1;
# - runs glyphcast's bench and FURY's frames in alternating pairs (glyphcast, FURY,
#   glyphcast, FURY, ...), each FURY/glyphcast ratio printed, so that a busy machine slows
#   both;
# - saves OUTDIR/glyphcast.png, OUTDIR/fury.png (the timed FURY frame), OUTDIR/fury-ddaa.png
#   (with pygfx's default anti-aliasing), OUTDIR/holes.png, and counts FURY's holes (pixels
#   of glyphcast's exact coverage that FURY leaves empty); OUTDIR/results.json has it all.
#
# --workload tracks:COUNT:POINTS[:slab]: streamlines instead (tools/bench_fury_tracks.py):
#   glyphcast's exact tubes and its lines against FURY's `line` and `streamtube` on the
#   same streamlines (`bench --save-tracks`), at 1920x1080, 5 frames after 1 warm-up
#   unless given.
# --mesa25: both sides on Mesa 25's lavapipe (tools/mesa25.sh) instead of the system's.
# --bin: the glyphcast binary (default: target/release/glyphcast, built when missing).
# What each number means: tools/bench_fury.py.
set -euo pipefail
usage() {
    echo "usage: tools/bench-fury.sh [--mesa25] [--bin PATH] [--workload SPEC] [--pairs N] [--frames N] [--warmup N] OUTDIR" >&2
    exit 2
}
mesa25=0 bin="" out="" extra=() script=bench_fury.py
while [ $# -gt 0 ]; do
    case "$1" in
    --mesa25) mesa25=1 ;;
    --bin) [ $# -ge 2 ] || usage; bin=$2; shift ;;
    --pairs | --frames | --warmup) [ $# -ge 2 ] || usage; extra+=("$1" "$2"); shift ;;
    --workload)
        [ $# -ge 2 ] || usage
        extra+=("$1" "$2")
        case "$2" in tracks:*) script=bench_fury_tracks.py ;; esac
        shift
        ;;
    -h | --help) usage ;;
    -*) echo "error: unknown option '$1'" >&2; usage ;;
    *) [ -z "$out" ] || usage; out=$1 ;;
    esac
    shift
done
[ -n "$out" ] || usage
root=$(cd "$(dirname "$0")/.." && pwd)

# The driver: lavapipe, the system's or Mesa 25's, for both sides.
if [ "$mesa25" = 1 ]; then
    eval "$(bash "$root/tools/mesa25.sh")"
fi
export GLYPHCAST_LAVAPIPE=1
. "$root/tools/env.sh"
if [ -z "${VK_DRIVER_FILES:-}" ]; then
    echo "error: no lavapipe ICD file (/usr/share/vulkan/icd.d/lvp_icd.$(uname -m).json): install mesa-vulkan-drivers" >&2
    exit 1
fi

if [ -z "$bin" ]; then
    bin=$root/target/release/glyphcast
    [ -x "$bin" ] || (cd "$root" && cargo build --release --locked --bin glyphcast)
fi
if [ ! -x "$bin" ] || [ -d "$bin" ]; then
    echo "error: $bin: --bin: not an executable file" >&2
    exit 1
fi

venv=$root/target/fury-venv
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
if [ "$("$venv/bin/python" -c 'import importlib.metadata as m; print(m.version("fury"))' 2>/dev/null)" != 2.0.0 ] \
    || ! "$venv/bin/python" -c 'import nibabel' 2>/dev/null; then
    # nibabel reads the streamlines glyphcast writes for the tracks comparison.
    "$venv/bin/python" -m pip install -q --disable-pip-version-check fury==2.0.0 nibabel
fi

mkdir -p "$out"
echo "driver: $VK_DRIVER_FILES; glyphcast: $bin; $(date -u '+%Y-%m-%d %H:%M UTC')"
# glfw (imported by FURY) complains without a runtime folder: give it a passing one.
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    XDG_RUNTIME_DIR=$(mktemp -d)
    export XDG_RUNTIME_DIR
    trap 'rm -rf "$XDG_RUNTIME_DIR"' EXIT
fi
"$venv/bin/python" "$root/tools/$script" --glyphcast "$bin" --out "$out" "${extra[@]}"
