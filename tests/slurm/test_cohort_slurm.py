"""Cohorts on a real SLURM cluster (docs/guide/cohorts.md): the job array of
tools/cohort-slurm.sh with its group page, a task killed half-way (SIGKILL, as a lost
node; SIGTERM, as scancel, a time limit or pre-emption) and the run that completes the
cohort, the refusals, and the demo workflow through Nipype's SLURM plugin.

Every run is real: sbatch, the scheduler's daemons and the glyphcast binary drawing on
lavapipe. Small subjects (DIPY's small_64D, 10 x 10 x 10) and small panels keep the
whole file to a few minutes on two cores. The SIGKILL of a task is sent to its processes
through /proc, so the tests run on the cluster's (one) node.
"""
import html
import os
import pathlib
import re
import signal
import subprocess
import time

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
COHORT_SLURM = ROOT / "tools" / "cohort-slurm.sh"
COHORT_DEMO = ROOT / "tools" / "cohort-demo.sh"
DIPY = ROOT / "tests" / "data" / "dipy"
PANEL = "64"
QC_FILES = {"index.html", "qc.json", "odf-mosaic.png", "peaks-mosaic.png",
            "zoom-1.png", "zoom-2.png", "zoom-3.png"}


def run_cohort(env, *args):
    return subprocess.run(["bash", str(COHORT_SLURM), *map(str, args),
                           "--panel-size", PANEL, "--poll", "0.5"],
                          env=env, capture_output=True, text=True, timeout=600)


def assert_complete(out, name):
    folder = out / name
    assert {p.name for p in folder.iterdir()} == {f"{name}_fod.nii.gz",
                                                  f"{name}_peaks.nii.gz", "qc"}, folder
    assert {p.name for p in (folder / "qc").iterdir()} == QC_FILES, folder
    assert f"{name}_fod.nii.gz" in (folder / "qc" / "index.html").read_text()


def hidden_leftovers(out):
    return sorted(p.name for p in out.iterdir() if p.name.startswith("."))


def status(out, name):
    lines = (out / "cohort" / "status" / name).read_text().splitlines()
    return dict(line.split("=", 1) for line in lines)


def page_rows(out):
    """{subject: row html} of the group page."""
    text = (out / "index.html").read_text()
    rows = re.findall(r"<tr id=\"[^\"]*\"><td>(.*?)</tr>", text, re.S)
    found = {}
    for row in rows:
        name = re.sub(r"<[^>]+>", "", row.split("</td>", 1)[0])
        found[html.unescape(name)] = row
    return found


def submitted_job(stderr):
    match = re.search(r"submitted array (\d+): (\d+) subjects \(([^)]*)\)", stderr)
    assert match, stderr
    return match[1], int(match[2]), match[3]


def test_array_runs_four_subjects_and_the_group_page_names_them(tmp_path, env):
    out = tmp_path / "cohort"
    done = run_cohort(env, 4, out)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    job, count, spec = submitted_job(done.stderr)
    assert (count, spec) == (4, "1-4")
    names = [f"sub-{n:02d}" for n in range(1, 5)]
    for name in names:
        assert_complete(out, name)
        record = status(out, name)
        assert record["state"] == "done" and record["job"].startswith(f"{job}_"), record
        assert float(record["wall_s"]) > 0 and float(record["cpu_s"]) > 0, record
    # Each subject is its own noisy copy: four different fits, four different pages.
    fods = {(out / n / f"{n}_fod.nii.gz").read_bytes() for n in names}
    assert len(fods) == 4
    assert hidden_leftovers(out) == []
    rows = page_rows(out)
    assert sorted(rows) == names
    for name, row in rows.items():
        assert ">done<" in row, row
        assert f'href="{name}/qc/index.html"' in row and f'src="{name}/qc/odf-mosaic.png"' in row
    assert "4 done" in (out / "index.html").read_text()

    # Again: nothing is submitted, nothing is rewritten.
    stamps = {n: (out / n / "qc" / "qc.json").stat().st_mtime_ns for n in names}
    again = run_cohort(env, 4, out)
    assert again.returncode == 0, again.stderr[-3000:]
    assert "4 of 4 subjects already done: skipped" in again.stderr
    assert "submitted array" not in again.stderr
    assert stamps == {n: (out / n / "qc" / "qc.json").stat().st_mtime_ns for n in names}


def wait_for(predicate, what, timeout=240):
    start = time.monotonic()
    while time.monotonic() - start < timeout:
        found = predicate()
        if found:
            return found
        time.sleep(0.05)
    pytest.fail(f"timed out waiting for {what}")


def kill_task(job, task):
    """SIGKILL to every process of array task `job`_`task` on this node (the batch
    script and glyphcast: the processes whose environment names that task)."""
    marks = {f"SLURM_ARRAY_JOB_ID={job}".encode(), f"SLURM_ARRAY_TASK_ID={task}".encode()}
    killed = []
    for proc in pathlib.Path("/proc").iterdir():
        if not proc.name.isdigit():
            continue
        try:
            environment = set((proc / "environ").read_bytes().split(b"\0"))
            command = (proc / "comm").read_text().strip()
        except OSError:
            continue
        if marks <= environment and command != "slurmstepd":
            try:
                os.kill(int(proc.name), signal.SIGKILL)
                killed.append(command)
            except ProcessLookupError:
                pass
    return killed


def working_fit(out, name):
    """The hidden working folder of `name`'s task once its fit is written (the task is
    then in peaks or qc: half-way)."""
    for entry in out.glob(f".{name}.*.tmp"):
        if (entry / f"{name}_fod.nii.gz").is_file():
            return entry
    return None


def test_killed_tasks_leave_no_partial_subject_and_a_rerun_redoes_only_them(tmp_path, env):
    out = tmp_path / "cohort"
    run = subprocess.Popen(["bash", str(COHORT_SLURM), "3", str(out), "--panel-size", PANEL,
                            "--poll", "0.5"], env=env, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True)
    try:
        job = wait_for(lambda: (out / "cohort" / "job").is_file()
                       and (out / "cohort" / "job").read_text().strip(), "the submission")
        # sub-02: SIGKILL to the task's every process, half-way, as when its node dies: no
        # trap runs. (scancel --signal=KILL cancels as plain scancel does: SIGTERM first.)
        wait_for(lambda: working_fit(out, "sub-02"), "sub-02's fit")
        killed = kill_task(job, 2)
        assert killed, "no process of task 2 found"
        # sub-03: scancel's SIGTERM, half-way (a time limit and pre-emption send the same).
        wait_for(lambda: working_fit(out, "sub-03"), "sub-03's fit")
        subprocess.run(["scancel", f"{job}_3"], check=True)
        stdout, stderr = run.communicate(timeout=300)
    finally:
        if run.poll() is None:
            run.kill()
    assert run.returncode == 1, stdout + stderr
    assert "2 of 3 subjects not done" in stderr, stderr
    assert_complete(out, "sub-01")
    for name in ("sub-02", "sub-03"):
        assert not (out / name).exists(), f"{name} was killed but its folder exists"
    # The SIGTERM'd task removed its own working folder; the command removed the
    # SIGKILL'd one's once the array had ended.
    assert hidden_leftovers(out) == []
    assert status(out, "sub-03")["state"] == "failed"
    assert "SIGTERM" in status(out, "sub-03")["message"]
    rows = page_rows(out)
    assert sorted(rows) == ["sub-01", "sub-02", "sub-03"]
    assert ">done<" in rows["sub-01"]
    assert "failed" in rows["sub-02"] and "ended without finishing" in rows["sub-02"], rows
    assert "failed" in rows["sub-03"] and "SIGTERM" in rows["sub-03"], rows

    # The same command again: only the killed subjects are submitted; sub-01 is untouched.
    kept = (out / "sub-01" / "qc" / "qc.json").stat()
    again = run_cohort(env, 3, out)
    assert again.returncode == 0, again.stderr[-3000:]
    assert "1 of 3 subjects already done: skipped" in again.stderr
    _, count, spec = submitted_job(again.stderr)
    assert (count, spec) == (2, "2-3")
    for name in ("sub-01", "sub-02", "sub-03"):
        assert_complete(out, name)
    now = (out / "sub-01" / "qc" / "qc.json").stat()
    assert (now.st_ino, now.st_mtime_ns) == (kept.st_ino, kept.st_mtime_ns)
    assert hidden_leftovers(out) == []
    assert all(">done<" in row for row in page_rows(out).values())


def test_a_subject_list_runs_folders_and_file_sets(tmp_path, env):
    # A folder (BIDS-like: sub-x/dwi/sub-x_dwi.*) and a named file set of another folder.
    bids = tmp_path / "data" / "sub-x" / "dwi"
    bids.mkdir(parents=True)
    for ext in ("bval", "bvec"):
        (bids / f"sub-x_dwi.{ext}").write_bytes((DIPY / f"small_64D.{ext}").read_bytes())
    (bids / "sub-x_dwi.nii").write_bytes((DIPY / "small_64D.nii").read_bytes())
    listing = tmp_path / "subjects.txt"
    listing.write_text("# a real cohort\ndata/sub-x\n\n"
                       f"dipy {DIPY}/small_64D.nii {DIPY}/small_64D.bval {DIPY}/small_64D.bvec\n")
    out = tmp_path / "qc"
    done = run_cohort(env, "--subjects", listing, out)
    assert done.returncode == 0, done.stderr[-3000:]
    assert_complete(out, "sub-x")
    assert_complete(out, "dipy")
    assert sorted(page_rows(out)) == ["dipy", "sub-x"]
    assert not (out / "inputs").exists()


def test_bad_input_is_refused_before_anything_is_submitted(tmp_path, env):
    listing = tmp_path / "subjects.txt"
    listing.write_text(f"{DIPY}/small_64D.nii {DIPY}/small_64D.bval {tmp_path}/missing.bvec\n")
    out = tmp_path / "qc"
    done = run_cohort(env, "--subjects", listing, out)
    assert done.returncode == 2
    assert f"{listing} line 1: the b-vectors file {tmp_path}/missing.bvec does not exist" \
        in done.stderr, done.stderr
    assert not out.exists()
    for args in (["4"], ["x", out], ["2", out, "--subjects", listing]):
        refused = run_cohort(env, *args)
        assert refused.returncode == 2 and "error:" in refused.stderr, refused.stderr
    assert not out.exists()


def test_a_folder_the_array_did_not_write_is_never_touched(tmp_path, env):
    # OUTDIR/sub-01 exists but is not a complete set (the user's, another tool's): the
    # run does not submit it, does not remove it, and says so; exit 1.
    out = tmp_path / "cohort"
    (out / "sub-01").mkdir(parents=True)
    (out / "sub-01" / "notes.txt").write_text("mine")
    done = run_cohort(env, 1, out)
    assert done.returncode == 1, done.stderr
    assert "submitted array" not in done.stderr
    assert (out / "sub-01" / "notes.txt").read_text() == "mine"
    assert "is not a complete set" in page_rows(out)["sub-01"]


def test_the_demo_through_nipypes_slurm_plugin(tmp_path, env):
    out = tmp_path / "nipype"
    done = subprocess.run(["bash", str(COHORT_DEMO), "4", str(out), "--plugin", "SLURM",
                           "--panel-size", PANEL, "--poll", "0.5"],
                          env=env, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    for n in range(1, 5):
        folder = out / f"sub-{n:02d}" / "qc"
        assert {p.name for p in folder.iterdir()} == QC_FILES, folder
    # The nodes ran as SLURM jobs: the plugin's batch scripts and their jobs' logs.
    logs = list((out / "work").rglob("slurm-*.out"))
    assert len(logs) >= 12, logs  # fit, peaks and qc of 4 subjects at least
