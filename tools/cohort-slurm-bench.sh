#!/usr/bin/env bash
# Times tools/cohort-slurm.sh on the cluster of the environment: for each N, the demo's
# N subjects in a new folder WORKDIR/nN (removed first, so nothing is skipped), then one
# markdown row: N, the cohort's wall time (submission to group page), and each subject's
# task wall and CPU time (user + system of glyphcast fit, peaks and qc) as median
# (min to max), read from the tasks' records (OUTDIR/cohort/status/).
#
#   bash tools/cohort-slurm-bench.sh WORKDIR N [N ...] [-- cohort-slurm.sh options]
set -euo pipefail
if [ $# -lt 2 ]; then
    echo "usage: bash tools/cohort-slurm-bench.sh WORKDIR N [N ...] [-- options]" >&2
    exit 2
fi
root="$(cd "$(dirname "$0")/.." && pwd)"
work="$1"
shift
counts=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do counts+=("$1"); shift; done
[ $# -gt 0 ] && shift
mkdir -p "$work"
echo "| N | cohort wall | task wall, median (min to max) | task CPU, median (min to max) | load before |"
echo "|---|---|---|---|---|"
for n in "${counts[@]}"; do
    out="$work/n$n"
    # Only a folder this script made (its marker inside) is removed.
    if [ -e "$out" ]; then
        [ -f "$out/.cohort-slurm-bench" ] || { echo "error: $out exists and is not this script's" >&2; exit 1; }
        rm -rf "$out"
    fi
    mkdir -p "$out" && touch "$out/.cohort-slurm-bench"
    load="$(cut -d' ' -f1 /proc/loadavg)"
    start="$(date +%s.%N)"
    bash "$root/tools/cohort-slurm.sh" "$n" "$out" --poll 1 "$@" >/dev/null 2>"$out/bench.log" ||
        { echo "error: the cohort failed (see $out/bench.log)" >&2; exit 1; }
    end="$(date +%s.%N)"
    python3 - "$out" "$n" "$start" "$end" "$load" <<'PY'
import pathlib, statistics, sys
out, n, start, end, load = pathlib.Path(sys.argv[1]), int(sys.argv[2]), *map(float, sys.argv[3:6])
walls, cpus = [], []
for path in sorted((out / "cohort" / "status").iterdir()):
    record = dict(l.split("=", 1) for l in path.read_text().splitlines() if "=" in l)
    walls.append(float(record["wall_s"]))
    cpus.append(float(record["cpu_s"]))
assert len(walls) == n, walls
spread = lambda v: f"{statistics.median(v):.1f} s ({min(v):.1f} to {max(v):.1f})"
print(f"| {n} | {end - start:.1f} s | {spread(walls)} | {spread(cpus)} | {load:.2f} |")
PY
done
