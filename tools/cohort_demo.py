"""A cohort through glyphcast on Nipype: N small subjects made from DIPY's small_64D
(tests/data/dipy), each a perturbed copy (Gaussian noise of 3 % of the mean b=0 signal,
seeded by the subject's number, so every run makes the same cohort), run through
fit (CSD, band 8) -> peaks -> qc in one Nipype workflow (MultiProc by default).

    python tools/cohort_demo.py N OUTDIR [--plugin MultiProc|Linear|SLURM|SLURMGraph]
        [--panel-size PX] [--processes P] [--sbatch-args ARGS] [--poll S]

Writes OUTDIR/inputs/sub-XX/dwi/ (the subjects), OUTDIR/sub-XX/qc/index.html (each
subject's figure set, written by `glyphcast qc` straight into place, all or nothing) and
OUTDIR/work (Nipype's cache: a second run redoes nothing). The binary is $GLYPHCAST_BIN,
else `glyphcast` on the PATH. On a cluster: --plugin SLURM (Nipype submits each node as
a job and polls squeue) or SLURMGraph (the whole graph at once, with dependencies), with
the sbatch on the PATH; see docs/guide/cohorts.md.
"""
import argparse
import getpass
import os
import pathlib
import sys

from nipype import Function, Node, Workflow
from nipype.interfaces.utility import IdentityInterface

from cohort_subjects import make_subject
from glyphcast.nipype import Fit, Peaks, Qc

PLUGINS = ("MultiProc", "Linear", "SLURM", "SLURMGraph")


def subject_files(subject, inputs, out_root):
    """The DWI, its tables and the figure set's folder of `subject` (sub-XX), whose
    parent is made here (glyphcast qc writes into an existing folder)."""
    import os

    stem = os.path.join(inputs, subject, "dwi", f"{subject}_dwi")
    os.makedirs(os.path.join(out_root, subject), exist_ok=True)
    return (f"{stem}.nii.gz", f"{stem}.bval", f"{stem}.bvec",
            os.path.join(out_root, subject, "qc"))


def workflow(subjects, inputs, out_root, panel_size):
    """fit -> peaks -> qc for every subject (Nipype iterables)."""
    source = Node(IdentityInterface(fields=["subject"]), name="subjects")
    source.iterables = ("subject", subjects)
    files = Node(Function(input_names=["subject", "inputs", "out_root"],
                          output_names=["dwi", "bval", "bvec", "qc_dir"],
                          function=subject_files), name="files")
    files.inputs.inputs = str(inputs)
    files.inputs.out_root = str(out_root)
    fit = Node(Fit(odf="csd", order=8), name="fit")
    peaks = Node(Peaks(), name="peaks")
    qc = Node(Qc(panel_size=panel_size), name="qc")
    if os.environ.get("GLYPHCAST_VALIDATION") == "1":
        qc.inputs.validation = True
    wf = Workflow(name="glyphcast_cohort", base_dir=str(out_root / "work"))
    # Crash files beside the cache, not in the caller's folder.
    wf.config["execution"]["crashdump_dir"] = str(out_root / "work" / "crash")
    wf.connect([
        (source, files, [("subject", "subject")]),
        (files, fit, [("dwi", "dwi"), ("bval", "bval"), ("bvec", "bvec")]),
        (fit, peaks, [("out_file", "in_file")]),
        (fit, qc, [("out_file", "fod")]),
        (peaks, qc, [("out_file", "peaks")]),
        (files, qc, [("qc_dir", "out_dir")]),
    ])
    return wf


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("count", type=int)
    parser.add_argument("outdir", type=pathlib.Path)
    parser.add_argument("--plugin", choices=PLUGINS, default="MultiProc")
    parser.add_argument("--sbatch-args", default="", metavar="ARGS",
                        help="SLURM plugins: sbatch options for every job, e.g. "
                             "'--partition=short --time=00:10:00 --mem=2G'")
    parser.add_argument("--poll", type=float, default=2.0, metavar="S",
                        help="SLURM plugin: seconds between squeue polls (2)")
    parser.add_argument("--processes", type=int, default=os.cpu_count() or 2)
    parser.add_argument("--panel-size", type=int, default=400)
    args = parser.parse_args()
    if not 1 <= args.count <= 99:
        sys.exit("error: N must be 1 to 99 subjects")
    out_root = args.outdir.resolve()
    inputs = out_root / "inputs"
    for number in range(1, args.count + 1):
        make_subject(number, inputs)
    subjects = [f"sub-{n:02d}" for n in range(1, args.count + 1)]
    wf = workflow(subjects, inputs, out_root, args.panel_size)
    plugin_args = {}
    if args.plugin == "MultiProc":
        plugin_args = {"n_procs": args.processes}
    elif args.plugin in ("SLURM", "SLURMGraph"):
        # Nipype names each job after $LOGNAME, which a batch shell may lack.
        if not os.environ.get("LOGNAME"):
            os.environ["LOGNAME"] = getpass.getuser()
        plugin_args = {"sbatch_args": f"--cpus-per-task=1 {args.sbatch_args}".strip()}
        if args.plugin == "SLURM":
            plugin_args["poll_sleep_duration"] = args.poll
        else:
            plugin_args["dont_resubmit_completed_jobs"] = True
    wf.run(plugin=args.plugin, plugin_args=plugin_args)
    for subject in subjects:
        page = out_root / subject / "qc" / "index.html"
        if not page.is_file():
            sys.exit(f"error: {page} was not written")
        print(page)


if __name__ == "__main__":
    main()
