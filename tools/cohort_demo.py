"""A cohort through glyphcast on Nipype: N small subjects made from DIPY's small_64D
(tests/data/dipy), each a perturbed copy (Gaussian noise of 3 % of the mean b=0 signal,
seeded by the subject's number, so every run makes the same cohort), run through
fit (CSD, band 8) -> peaks -> qc in one Nipype workflow with the MultiProc plugin.

    python tools/cohort_demo.py N OUTDIR [--plugin MultiProc|Linear|SLURMGraph]
        [--panel-size PX] [--processes P]

Writes OUTDIR/inputs/sub-XX/dwi/ (the subjects), OUTDIR/sub-XX/qc/index.html (each
subject's figure set, written by `glyphcast qc` straight into place, all or nothing) and
OUTDIR/work (Nipype's cache: a second run redoes nothing). The binary is $GLYPHCAST_BIN,
else `glyphcast` on the PATH. On a cluster: --plugin SLURMGraph (see the README).
"""
import argparse
import os
import pathlib
import shutil
import sys

import nibabel as nib
import numpy as np
from nipype import Function, Node, Workflow
from nipype.interfaces.utility import IdentityInterface

from glyphcast.nipype import Fit, Peaks, Qc

ROOT = pathlib.Path(__file__).resolve().parents[1]
DIPY = ROOT / "tests" / "data" / "dipy"
NOISE_FRACTION = 0.03


def make_subject(number, inputs):
    """Subject `number`'s DWI: small_64D plus seeded Gaussian noise, with its tables."""
    folder = inputs / f"sub-{number:02d}" / "dwi"
    folder.mkdir(parents=True, exist_ok=True)
    source = nib.load(str(DIPY / "small_64D.nii"))
    data = np.asarray(source.dataobj, dtype=np.float32)
    bvals = np.loadtxt(DIPY / "small_64D.bval")
    sigma = NOISE_FRACTION * float(data[..., bvals <= 50].mean())
    noise = np.random.default_rng(number).normal(0.0, sigma, data.shape)
    noisy = np.clip(data + noise, 0.0, None).astype(np.float32)
    image = nib.Nifti1Image(noisy, source.affine, source.header)
    image.set_data_dtype(np.float32)
    stem = f"sub-{number:02d}_dwi"
    nib.save(image, str(folder / f"{stem}.nii.gz"))
    shutil.copyfile(DIPY / "small_64D.bval", folder / f"{stem}.bval")
    shutil.copyfile(DIPY / "small_64D.bvec", folder / f"{stem}.bvec")
    return folder / stem


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
    parser.add_argument("--plugin", default="MultiProc")
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
    plugin_args = {"n_procs": args.processes} if args.plugin == "MultiProc" else {}
    wf.run(plugin=args.plugin, plugin_args=plugin_args)
    for subject in subjects:
        page = out_root / subject / "qc" / "index.html"
        if not page.is_file():
            sys.exit(f"error: {page} was not written")
        print(page)


if __name__ == "__main__":
    main()
