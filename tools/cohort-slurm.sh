#!/usr/bin/env bash
# A cohort's ODF QC on SLURM: one job array (examples/slurm/qc-array.sbatch), one task
# per subject (glyphcast fit -> peaks -> qc), then the group page OUTDIR/index.html.
#
#   bash tools/cohort-slurm.sh N OUTDIR [options]               # the demo's N subjects
#   bash tools/cohort-slurm.sh --subjects LIST OUTDIR [options] # a real cohort
#   options: --partition P --time T --mem M --cpus C --container IMAGE --panel-size PX
#            --sbatch-arg ARG --poll S      (tools/cohort_slurm.py --help)
#
# Uses the sbatch and squeue on the PATH and the cluster they are configured for
# (SLURM_CONF, e.g. the local cluster's: tools/slurm-local.sh). Running it again skips
# the finished subjects and redoes the rest; exit 1 when any subject is not done.
# Python: $PYTHON, else (the demo's subjects need numpy and nibabel) the test venv
# target/py-venv, made when missing; with --subjects, python3. Binary: $GLYPHCAST_BIN,
# else `glyphcast` on the PATH, else target/release/glyphcast (built when missing); with
# --container, the image's. The file system of OUTDIR and the binary must be the
# compute nodes' too (a shared one on a real cluster).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
. "$root/tools/env.sh"
demo=1 container=0
for arg in "$@"; do
    case "$arg" in
    --subjects | --subjects=*) demo=0 ;;
    --container | --container=*) container=1 ;;
    -h | --help) exec python3 "$root/tools/cohort_slurm.py" --help ;;
    esac
done
# Bad arguments or a bad subject list are refused before anything is built or installed.
python3 "$root/tools/cohort_slurm.py" --check-arguments "$@"
if [ "$container" = 0 ] && [ -z "${GLYPHCAST_BIN:-}" ]; then
    if command -v glyphcast >/dev/null 2>&1; then
        GLYPHCAST_BIN="$(command -v glyphcast)"
    else
        GLYPHCAST_BIN="$root/target/release/glyphcast"
        [ -x "$GLYPHCAST_BIN" ] || (cd "$root" && cargo build --locked --release --bin glyphcast)
    fi
fi
[ -n "${GLYPHCAST_BIN:-}" ] && export GLYPHCAST_BIN
python="${PYTHON:-}"
if [ -z "$python" ]; then
    if [ "$demo" = 1 ]; then
        venv="$root/target/py-venv"
        [ -x "$venv/bin/python" ] || python3 -m venv "$venv"
        python="$venv/bin/python"
        "$python" -c 'import numpy, nibabel' 2>/dev/null ||
            "$python" -m pip install -q --disable-pip-version-check numpy nibabel
    else
        python=python3
    fi
fi
exec "$python" "$root/tools/cohort_slurm.py" "$@"
