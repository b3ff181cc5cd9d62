#!/usr/bin/env bash
# N small subjects from DIPY's small_64D (perturbed copies) through a Nipype workflow
# (MultiProc, or SLURM/SLURMGraph on a cluster): glyphcast fit (CSD) -> peaks -> qc, writing
# OUTDIR/sub-XX/qc/index.html for each (tools/cohort_demo.py does the work).
#
#   bash tools/cohort-demo.sh N OUTDIR [cohort_demo.py options: --panel-size PX ...]
#   bash tools/cohort-demo.sh N OUTDIR --plugin MultiProc|Linear|SLURM|SLURMGraph
#
# Python: $PYTHON, else the test venv target/py-venv (made, with nipype, nibabel and the
# glyphcast module, when missing). Binary: $GLYPHCAST_BIN, else target/release/glyphcast
# (built when missing). Lavapipe draws when no GPU is there (GLYPHCAST_LAVAPIPE=1 forces it).
set -euo pipefail
if [ $# -lt 2 ]; then
    echo "usage: bash tools/cohort-demo.sh N OUTDIR [--panel-size PX] [--plugin MultiProc|Linear|SLURM|SLURMGraph] [--sbatch-args ARGS]" >&2
    exit 2
fi
root="$(cd "$(dirname "$0")/.." && pwd)"
count="$1" out="$2"
shift 2
. "$root/tools/env.sh"
if [ -z "${GLYPHCAST_BIN:-}" ]; then
    GLYPHCAST_BIN="$root/target/release/glyphcast"
    [ -x "$GLYPHCAST_BIN" ] || (cd "$root" && cargo build --locked --release --bin glyphcast)
fi
export GLYPHCAST_BIN
python="${PYTHON:-}"
if [ -z "$python" ]; then
    venv="$root/target/py-venv"
    [ -x "$venv/bin/python" ] || python3 -m venv "$venv"
    python="$venv/bin/python"
    if ! "$python" -c 'import nipype, nibabel, glyphcast' 2>/dev/null; then
        "$python" -m pip install -q --disable-pip-version-check 'maturin>=1.9,<2' numpy nibabel nipype
        (cd "$root/python" && VIRTUAL_ENV="$venv" PATH="$venv/bin:$PATH" maturin develop --locked --quiet)
    fi
fi
exec "$python" "$root/tools/cohort_demo.py" "$count" "$out" "$@"
