"""A cohort's QC as one SLURM job array: fit (CSD, band 8) -> peaks -> qc for every
subject (examples/slurm/qc-array.sbatch, one task per subject), then a group page.

    python tools/cohort_slurm.py N OUTDIR [options]              # the demo's N subjects
    python tools/cohort_slurm.py --subjects LIST OUTDIR [options]

tools/cohort-slurm.sh runs this with the right Python and binary; see
docs/guide/cohorts.md. Submits with the sbatch on the PATH (the cluster of the
environment: SLURM_CONF or the system's configuration), follows the array with squeue
(no accounting database needed: each task writes OUTDIR/cohort/status/NAME), and writes
OUTDIR/index.html. Finished subjects (OUTDIR/NAME) are skipped; the rest are submitted
again. Exit status 0 when every subject is done, 1 when any failed, 2 for bad input.
"""
import argparse
import datetime
import fcntl
import html
import os
import pathlib
import re
import shutil
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
SBATCH_SCRIPT = ROOT / "examples" / "slurm" / "qc-array.sbatch"
NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")
RESERVED = {"inputs", "logs", "cohort", "index.html", "work"}
TEMPORARY = re.compile(r"^\.(?P<name>.+)\.(?P<job>[0-9]+)\.(?P<task>[0-9]+)\.tmp$")
# squeue's states of a job that has not ended.
ACTIVE = {"PENDING", "RUNNING", "COMPLETING", "CONFIGURING", "SUSPENDED", "REQUEUED",
          "REQUEUE_FED", "REQUEUE_HOLD", "RESIZING", "SIGNALING", "STAGE_OUT", "STOPPED",
          "RESV_DEL_HOLD"}
DWI_SUFFIXES = (".nii.gz", ".nii")


class InputError(Exception):
    """Bad input: reported as `error: ...`, exit 2, nothing submitted."""


def fail(message, code=2):
    print(f"error: {message}", file=sys.stderr)
    sys.exit(code)


# ---- the subjects --------------------------------------------------------------------

def strip_dwi_suffix(path):
    for suffix in DWI_SUFFIXES:
        if path.name.endswith(suffix):
            return path.name[: -len(suffix)]
    return None


def find_dwi(folder):
    """The one DWI (NIfTI with a .bval and a .bvec of the same stem) in `folder`,
    folder/dwi or folder/ses-*/dwi."""
    places = [folder, folder / "dwi", *sorted(folder.glob("ses-*/dwi"))]
    found = []
    for place in places:
        if not place.is_dir():
            continue
        for path in sorted(place.iterdir()):
            stem = strip_dwi_suffix(path)
            if stem is None or not path.is_file():
                continue
            bval, bvec = place / f"{stem}.bval", place / f"{stem}.bvec"
            if bval.is_file() and bvec.is_file():
                found.append((path, bval, bvec))
    if not found:
        raise InputError(f"{folder} holds no DWI (a .nii or .nii.gz with a .bval and a "
                         ".bvec of the same name, in it, its dwi/ or ses-*/dwi/)")
    if len(found) > 1:
        names = ", ".join(str(f[0]) for f in found[:3])
        raise InputError(f"{folder} holds {len(found)} DWIs ({names}); give one a line as "
                         "NAME DWI BVAL BVEC")
    return found[0]


def read_subject_list(listing):
    """[(name, dwi, bval, bvec)] of a subject list: one subject a line, a folder or
    `[NAME] DWI BVAL BVEC` (tabs or spaces); `#` comments and blank lines skipped;
    relative paths are taken from the list's folder."""
    try:
        text = listing.read_text()
    except OSError as err:
        raise InputError(f"cannot read the subject list {listing}: {err.strerror}") from None
    base = listing.resolve().parent
    subjects, seen = [], {}
    for number, raw in enumerate(text.splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        where = f"{listing} line {number}"
        fields = line.split("\t") if "\t" in line else line.split()
        fields = [f.strip() for f in fields if f.strip()]
        paths = [(base / os.path.expanduser(f)).resolve() for f in fields]
        if len(fields) == 1:
            folder = paths[0]
            if not folder.is_dir():
                raise InputError(f"{where}: {folder} is not a folder (give a subject folder "
                                 "or DWI BVAL BVEC)")
            try:
                dwi, bval, bvec = find_dwi(folder)
            except InputError as err:
                raise InputError(f"{where}: {err}") from None
            name = folder.parent.name if folder.name == "dwi" else folder.name
        elif len(fields) in (3, 4):
            if len(fields) == 4:
                name, (dwi, bval, bvec) = fields[0], paths[1:]
            else:
                (dwi, bval, bvec) = paths
                stem = strip_dwi_suffix(dwi) or dwi.name
                name = stem[: -len("_dwi")] if stem.endswith("_dwi") else stem
            for role, path in (("DWI", dwi), ("b-values", bval), ("b-vectors", bvec)):
                if not path.is_file():
                    raise InputError(f"{where}: the {role} file {path} does not exist")
        else:
            raise InputError(f"{where}: {len(fields)} fields; a line is a subject folder, "
                             "DWI BVAL BVEC, or NAME DWI BVAL BVEC")
        if not NAME.match(name) or name in RESERVED:
            raise InputError(f"{where}: '{name}' cannot name a subject folder (letters, "
                             f"digits, '.', '_', '-'; not {', '.join(sorted(RESERVED))})")
        if name in seen:
            raise InputError(f"{where}: the subject '{name}' is also on line {seen[name]}")
        seen[name] = number
        subjects.append((name, dwi, bval, bvec))
    if not subjects:
        raise InputError(f"the subject list {listing} names no subject")
    return subjects


def demo_subjects(count, inputs):
    """The demo's subjects sub-01 ... (small_64D with seeded noise), made when missing."""
    sys.path.insert(0, str(ROOT / "tools"))
    try:
        from cohort_subjects import make_subject
    except ImportError as err:
        fail(f"the demo's subjects need numpy and nibabel ({err}); set PYTHON to a Python "
             "that has them, or give --subjects")
    subjects = []
    for number in range(1, count + 1):
        stem = make_subject(number, inputs)
        subjects.append((f"sub-{number:02d}", pathlib.Path(f"{stem}.nii.gz"),
                         pathlib.Path(f"{stem}.bval"), pathlib.Path(f"{stem}.bvec")))
    return subjects


# ---- the scheduler -------------------------------------------------------------------

def run_tool(args):
    """Runs a SLURM client; a missing one is a clear error."""
    try:
        return subprocess.run(args, capture_output=True, text=True)
    except FileNotFoundError:
        fail(f"'{args[0]}' is not on the PATH: run this where the SLURM clients are "
             "(a login node), or start the local cluster (tools/slurm-local.sh start)", 1)


def job_active(job, tries=24, pause=5.0):
    """Whether any task of the job `job` has not ended (squeue; a job the controller
    has forgotten has ended). squeue errors other than that are retried for two minutes."""
    for attempt in range(tries):
        done = run_tool(["squeue", "-h", "-j", str(job), "-t", "all", "-o", "%T"])
        if done.returncode == 0:
            return any(state.strip() in ACTIVE for state in done.stdout.splitlines())
        if "Invalid job id" in done.stderr:
            return False
        if attempt + 1 < tries:
            print(f"warning: squeue failed ({done.stderr.strip()}); trying again",
                  file=sys.stderr)
            time.sleep(pause)
    fail(f"squeue keeps failing: {done.stderr.strip()}; the array {job} may still run: "
         "run the same command again to wait for it", 1)


def array_spec(indices):
    """1,2,3,5 -> '1-3,5'."""
    parts, start = [], None
    for i, index in enumerate(indices):
        if start is None:
            start = index
        if i + 1 == len(indices) or indices[i + 1] != index + 1:
            parts.append(str(start) if start == index else f"{start}-{index}")
            start = None
    return ",".join(parts)


def write_atomically(path, text):
    temporary = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    temporary.write_text(text)
    os.replace(temporary, path)


def read_status(out, name):
    path = out / "cohort" / "status" / name
    try:
        lines = path.read_text().splitlines()
    except OSError:
        return {}
    return dict(line.split("=", 1) for line in lines if "=" in line)


def remove_stale_temporaries(out, names):
    """Removes the hidden working folders of tasks that have ended (.NAME.JOB.TASK.tmp of
    this cohort's subjects, whose job squeue no longer shows running): what a task
    stopped by SIGKILL or a lost node leaves."""
    verdicts = {}
    for entry in sorted(out.iterdir()):
        match = TEMPORARY.match(entry.name)
        if not match or match["name"] not in names or not entry.is_dir():
            continue
        job = match["job"]
        if job not in verdicts:
            verdicts[job] = job_active(job)
        if not verdicts[job]:
            shutil.rmtree(entry)
            print(f"removed the unfinished {entry.name} (its task ended)", file=sys.stderr)


def complete(folder):
    return (folder / "qc" / "index.html").is_file() and (folder / "qc" / "qc.json").is_file()


def last_line(path):
    try:
        lines = [line for line in path.read_text(errors="replace").splitlines() if line.strip()]
    except OSError:
        return ""
    return lines[-1].strip() if lines else ""


def subject_states(out, subjects):
    """{name: (state, message, status)}: done, failed or not run."""
    states = {}
    for name, *_ in subjects:
        status = read_status(out, name)
        folder = out / name
        if complete(folder):
            states[name] = ("done", "", status)
        elif folder.exists():
            states[name] = ("failed", f"{folder} exists but is not a complete set "
                            "(no qc/index.html and qc/qc.json); move it away to redo it", status)
        elif status.get("state") == "failed":
            states[name] = ("failed", status.get("message", ""), status)
        elif status.get("state") in ("running", "queued", "done"):
            slurm_log = out / "logs" / f"slurm-{status.get('job', '')}.out"
            tail = last_line(slurm_log) or last_line(out / "logs" / f"{name}.log")
            what = ("ended without finishing (SIGKILL, a lost node, or cancelled before it "
                    "started)") if status.get("state") != "done" else "left no set"
            states[name] = ("failed", f"task {status.get('job', '?')} {what}"
                            + (f"; last log line: {tail}" if tail else ""), status)
        else:
            states[name] = ("not run", "", status)
    return states


# ---- the group page ------------------------------------------------------------------

def seconds(status, key):
    value = status.get(key)
    try:
        return f"{float(value):.1f} s"
    except (TypeError, ValueError):
        return ""


def group_page(out, subjects, states):
    """OUTDIR/index.html: a row per subject with its state, the thumbnail of its ODF
    mosaic and a link to its page."""
    counts = {}
    for state, _, _ in states.values():
        counts[state] = counts.get(state, 0) + 1
    summary = ", ".join(f"{n} {state}" for state, n in sorted(counts.items()))
    rows = []
    for name, dwi, _, _ in subjects:
        state, message, status = states[name]
        esc = html.escape
        page = f"{name}/qc/index.html"
        if state == "done":
            cell = '<td class="done">done</td>'
            picture = (f'<a href="{esc(page)}"><img src="{esc(name)}/qc/odf-mosaic.png" '
                       f'width="220" loading="lazy" alt="ODF mosaic of {esc(name)}"></a>')
            link = f'<a href="{esc(page)}">{esc(name)}</a>'
        else:
            log = f"logs/{name}.log"
            log_link = (f' (<a href="{esc(log)}">log</a>)' if (out / log).is_file() else "")
            cell = (f'<td class="{"failed" if state == "failed" else "missing"}">{esc(state)}'
                    f'{log_link}<br><code>{esc(message)}</code></td>')
            picture, link = "", esc(name)
        rows.append(
            f'<tr id="{esc(name)}"><td>{link}</td>{cell}<td>{picture}</td>'
            f"<td class=\"n\">{seconds(status, 'wall_s') if state == 'done' else ''}</td>"
            f"<td class=\"n\">{seconds(status, 'cpu_s') if state == 'done' else ''}</td>"
            f"<td><code>{esc(status.get('job', ''))}</code> {esc(status.get('host', ''))}</td>"
            f"<td><code>{esc(str(dwi))}</code></td></tr>")
    not_done = [name for name, *_ in subjects if states[name][0] != "done"]
    jump = ""
    if not_done:
        links = ", ".join(f'<a href="#{html.escape(n)}">{html.escape(n)}</a>' for n in not_done)
        jump = f"<p>Not done: {links}.</p>"
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    title = f"ODF QC of {len(subjects)} subjects: {out.name}"
    return f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>{html.escape(title)}</title>
<style>
body {{ font-family: sans-serif; margin: 1.5em; }}
table {{ border-collapse: collapse; }}
th, td {{ border: 1px solid #ccc; padding: 0.3em 0.6em; vertical-align: top; text-align: left; }}
td.done {{ color: #16632b; font-weight: bold; }}
td.failed {{ color: #a11; font-weight: bold; }}
td.missing {{ color: #666; }}
td.n {{ white-space: nowrap; text-align: right; }}
td code {{ font-weight: normal; font-size: 0.85em; }}
img {{ display: block; background: #000; }}
</style></head>
<body>
<h1>{html.escape(title)}</h1>
<p>{html.escape(summary)}. Written {stamp} by <code>tools/cohort-slurm.sh</code>: each
subject is <code>glyphcast fit</code> (CSD, band 8), <code>peaks</code> and <code>qc</code>,
one task of a SLURM job array. Wall and CPU (user + system) time are the task's.
Run the same command again to redo the subjects that are not done.</p>
{jump}
<table>
<thead><tr><th>subject</th><th>status</th><th>ODF mosaic</th><th>wall</th><th>CPU</th>
<th>task, node</th><th>DWI</th></tr></thead>
<tbody>
{chr(10).join(rows)}
</tbody></table>
</body></html>
"""


# ---- the run -------------------------------------------------------------------------

def parse_args():
    parser = argparse.ArgumentParser(
        prog="tools/cohort-slurm.sh",
        usage="%(prog)s (N | --subjects LIST) OUTDIR [options]",
        description="A cohort's ODF QC as one SLURM job array, with a group page.")
    parser.add_argument("targets", nargs="+", metavar="[N] OUTDIR",
                        help="N demo subjects (without --subjects) and the output folder")
    parser.add_argument("--subjects", type=pathlib.Path, metavar="LIST",
                        help="a file: one subject a line, a folder or [NAME] DWI BVAL BVEC")
    parser.add_argument("--partition", help="sbatch --partition")
    parser.add_argument("--time", help="sbatch --time, per task (e.g. 00:30:00)")
    parser.add_argument("--mem", help="sbatch --mem, per task (e.g. 2G)")
    parser.add_argument("--cpus", type=int, default=1, help="sbatch --cpus-per-task (1)")
    parser.add_argument("--container", metavar="IMAGE",
                        help="run glyphcast in this Apptainer image (apptainer exec)")
    parser.add_argument("--panel-size", type=int, metavar="PX", help="qc --panel-size")
    parser.add_argument("--sbatch-arg", action="append", default=[], metavar="ARG",
                        help="one more sbatch option (repeatable), e.g. --sbatch-arg=--qos=low")
    parser.add_argument("--poll", type=float, default=5.0, metavar="S",
                        help="seconds between squeue polls (5)")
    # tools/cohort-slurm.sh checks the arguments before it builds anything.
    parser.add_argument("--check-arguments", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.subjects is None:
        if len(args.targets) != 2:
            parser.error("give N OUTDIR (the demo's N subjects) or --subjects LIST OUTDIR")
        try:
            args.count = int(args.targets[0])
        except ValueError:
            parser.error(f"N must be a number of subjects, not '{args.targets[0]}'")
        if not 1 <= args.count <= 99:
            parser.error("N must be 1 to 99 demo subjects")
    elif len(args.targets) != 1:
        parser.error("with --subjects LIST give only OUTDIR (the list sets the subjects)")
    args.outdir = pathlib.Path(args.targets[-1])
    if args.cpus < 1:
        parser.error("--cpus must be at least 1")
    if args.panel_size is not None and not 64 <= args.panel_size <= 4096:
        parser.error("--panel-size must be 64 to 4096 pixels (glyphcast qc's range)")
    if args.poll <= 0:
        parser.error("--poll must be positive")
    return args


def main():
    args = parse_args()
    out = args.outdir.resolve()
    if out.exists() and not out.is_dir():
        fail(f"{out} exists and is not a folder")
    # The subjects first: a bad list submits nothing and writes nothing.
    try:
        subjects = (read_subject_list(args.subjects) if args.subjects
                    else None)
    except InputError as err:
        fail(str(err))
    if args.check_arguments:
        return
    binary = None
    if not args.container:
        binary = os.environ.get("GLYPHCAST_BIN") or shutil.which("glyphcast")
        if not binary or not os.access(binary, os.X_OK):
            fail(f"no glyphcast binary: GLYPHCAST_BIN is '{os.environ.get('GLYPHCAST_BIN', '')}' "
                 "and none is on the PATH (or give --container IMAGE)")
        binary = str(pathlib.Path(binary).resolve())
    elif not pathlib.Path(args.container).is_file():
        fail(f"the container image {args.container} does not exist")
    for folder in (out, out / "cohort" / "status", out / "logs"):
        folder.mkdir(parents=True, exist_ok=True)
    # One run per OUTDIR at a time (on this machine; the array check below covers others).
    lock = open(out / "cohort" / "lock", "w")
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        fail(f"another tools/cohort-slurm.sh is running on {out}", 1)
    if subjects is None:
        subjects = demo_subjects(args.count, out / "inputs")
    names = {name for name, *_ in subjects}

    # An array of an earlier run that still runs: wait for it, never submit beside it.
    job_file = out / "cohort" / "job"
    if job_file.is_file():
        earlier = job_file.read_text().strip()
        if earlier and job_active(earlier):
            print(f"waiting for the earlier array {earlier} on {out}", file=sys.stderr)
            while job_active(earlier):
                time.sleep(args.poll)
    remove_stale_temporaries(out, names)

    states = subject_states(out, subjects)
    todo = [i for i, (name, *_) in enumerate(subjects, 1) if states[name][0] != "done"
            and not (out / name).exists()]
    skipped = sum(1 for state, _, _ in states.values() if state == "done")
    if skipped:
        print(f"{skipped} of {len(subjects)} subjects already done: skipped", file=sys.stderr)
    if todo:
        manifest = "".join(f"{name}\t{dwi}\t{bval}\t{bvec}\n"
                           for name, dwi, bval, bvec in subjects)
        if any("\t" in str(p) or "\n" in str(p) for s in subjects for p in s):
            fail("a subject's path holds a tab or a newline")
        write_atomically(out / "cohort" / "subjects.tsv", manifest)
        command = ["sbatch", "--parsable", f"--array={array_spec(todo)}",
                   "--job-name=glyphcast-qc", f"--cpus-per-task={args.cpus}",
                   f"--output={out}/logs/slurm-%A_%a.out"]
        for flag, value in (("--partition", args.partition), ("--time", args.time),
                            ("--mem", args.mem)):
            if value:
                command.append(f"{flag}={value}")
        command += args.sbatch_arg
        command += [str(SBATCH_SCRIPT), str(out)]
        command += ["--container", args.container] if args.container else ["--bin", binary]
        if args.panel_size:
            command += ["--panel-size", str(args.panel_size)]
        done = run_tool(command)
        if done.returncode != 0:
            fail(f"sbatch refused the array: {done.stderr.strip()}", 1)
        job = done.stdout.strip().split(";")[0]
        if not job.isdigit():
            fail(f"sbatch printed no job id: {done.stdout.strip()}", 1)
        write_atomically(job_file, job + "\n")
        for index in todo:
            name = subjects[index - 1][0]
            write_atomically(out / "cohort" / "status" / name,
                             f"state=queued\njob={job}_{index}\n")
        print(f"submitted array {job}: {len(todo)} subjects ({array_spec(todo)})",
              file=sys.stderr, flush=True)
        reported = set()
        while True:
            active = job_active(job)
            for index in todo:
                name = subjects[index - 1][0]
                status = read_status(out, name)
                if name not in reported and status.get("state") in ("done", "failed"):
                    reported.add(name)
                    detail = (f"wall {status.get('wall_s')} s, CPU {status.get('cpu_s')} s"
                              if status["state"] == "done" else status.get("message", ""))
                    print(f"{name}: {status['state']} ({detail})", file=sys.stderr, flush=True)
            if not active:
                break
            time.sleep(args.poll)
        remove_stale_temporaries(out, names)
        states = subject_states(out, subjects)

    write_atomically(out / "index.html", group_page(out, subjects, states))
    failed = [name for name, (state, _, _) in states.items() if state != "done"]
    for name in failed:
        print(f"{name}: {states[name][0]}: {states[name][1]}", file=sys.stderr)
    print(out / "index.html")
    if failed:
        print(f"{len(failed)} of {len(subjects)} subjects not done; run the same command "
              "again to redo them", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
