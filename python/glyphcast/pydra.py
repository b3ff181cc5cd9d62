"""Pydra tasks of the ``glyphcast`` command line: ``fit_task``, ``peaks_task``,
``render_task`` and ``qc_task``, each a ``pydra.ShellCommandTask`` with typed input
and output specs (the API of pydra 0.25, what ``pip install pydra`` gives today; 1.0
is a pre-release with another API)::

    import pydra
    from glyphcast.pydra import fit_task, qc_task

    wf = pydra.Workflow(name="odf_qc", input_spec=["dwi", "bval", "bvec"])
    wf.add(fit_task(name="fit", dwi=wf.lzin.dwi, bval=wf.lzin.bval, bvec=wf.lzin.bvec))
    wf.add(qc_task(name="qc", fod=wf.fit.lzout.out_file))
    wf.set_output([("index_html", wf.qc.lzout.index_html)])

Input files are checked when they are given (a missing file raises at once), as are
choices (``negative``) and ranges (``panel_size``). The binary is ``$GLYPHCAST_BIN`` if
set, else ``glyphcast`` on the PATH.
"""
import typing as ty

import attr
from fileformats.generic import Directory, File
from pydra import ShellCommandTask
from pydra.engine.specs import LazyField, ShellOutSpec, ShellSpec, SpecInfo

from .nipype import QC_FIGURES, glyphcast_binary

__all__ = ["fit_task", "peaks_task", "render_task", "qc_task"]


def _given(value):
    """Whether `value` is a value to check now: given, and not yet to come from another
    task (a lazy field is checked by its own task)."""
    return value is not attr.NOTHING and value is not None and not isinstance(value, LazyField)


def _choice(*values):
    def check(_instance, attribute, value):
        if _given(value) and value not in values:
            choices = ", ".join(map(repr, values))
            raise ValueError(f"{attribute.name}={value!r}: expected one of {choices}")

    return check


def _between(low, high):
    def check(_instance, attribute, value):
        if _given(value) and not low <= value <= high:
            raise ValueError(f"{attribute.name}={value}: must be {low} to {high}")

    return check


def _arg(kind, argstr, help_string, position=None, mandatory=False, validator=None,
         default=attr.NOTHING):
    metadata = {"argstr": argstr, "help_string": help_string}
    if position is not None:
        metadata["position"] = position
    if mandatory:
        metadata["mandatory"] = True
    return attr.ib(type=kind, default=default, metadata=metadata, validator=validator)


def _optional(kind, argstr, help_string, validator=None):
    return attr.ib(type=kind, default=attr.NOTHING,
                   metadata={"argstr": argstr, "help_string": help_string},
                   validator=validator)


def _output_template(template, help_string, position=-1, argstr="-o"):
    metadata = {
        "argstr": argstr,
        "output_file_template": template,
        "keep_extension": False,
        "help_string": help_string,
    }
    if position is not None:
        metadata["position"] = position
    return attr.ib(type=str, metadata=metadata)


def _spec(name, fields):
    return SpecInfo(name=name, fields=list(fields.items()), bases=(ShellSpec,))


_FIT_FIELDS = {
    "dwi": _arg(File, "", "DWI series (NIfTI or MRtrix)", position=1, mandatory=True),
    "bval": _optional(File, "--bval", "FSL b-values"),
    "bvec": _optional(File, "--bvec", "FSL b-vectors"),
    "bvec_convention": _optional(str, "--bvec-convention", "frame of bvec (default fsl)",
                                 _choice("fsl", "voxel", "world")),
    "order": _arg(int, "--order", "SH band", default=8, validator=_between(0, 12)),
    "odf": _arg(str, "--odf", "fibre ODF model", default="csd",
                validator=_choice("csd", "msmt", "csa", "qball")),
    "basis": _optional(str, "--basis", "SH basis of the output (default tournier07)",
                       _choice("tournier07", "descoteaux07", "mrtrix", "dipy", "dipy-new")),
    "legacy": _arg(bool, "--legacy", "the legacy variant of the SH basis", default=False),
    "reg_lambda": _optional(float, "--lambda", "regularisation weight (--lambda)"),
    "csd_algorithm": _optional(str, "--csd-algorithm", "CSD: mrtrix (default) or dipy",
                               _choice("mrtrix", "dipy")),
    "tau": _optional(float, "--tau", "CSD: the constraint's threshold"),
    "response": _optional(File, "--response", "CSD: the response; msmt: the WM response"),
    "response_fa": _optional(float, "--response-fa", "FA threshold of the response voxels",
                             _between(0.0, 1.0)),
    "response_gm": _optional(File, "--response-gm", "msmt: the GM response"),
    "response_csf": _optional(File, "--response-csf", "msmt: the CSF response"),
    "mask": _optional(File, "--mask", "voxels to fit"),
    "quiet": _arg(bool, "--quiet", "no progress", default=True),
    "out_file": _output_template("{dwi}_fod.nii.gz", "coefficients out"),
}

_FIT_INPUT = _spec("FitInput", _FIT_FIELDS)

# msmt writes three images; the GM and CSF ones are named here and passed on, so that
# the task's outputs are the files the command wrote.
_FIT_MSMT_INPUT = _spec("FitMsmtInput", {
    **_FIT_FIELDS,
    "gm_file": _output_template("{dwi}_fod_gm.nii.gz", "msmt: the GM image",
                                position=None, argstr="--gm"),
    "csf_file": _output_template("{dwi}_fod_csf.nii.gz", "msmt: the CSF image",
                                 position=None, argstr="--csf"),
})

_PEAKS_INPUT = _spec("PeaksInput", {
    "in_file": _arg(File, "", "ODF SH coefficients", position=1, mandatory=True),
    "count": _optional(int, "--count", "peaks per voxel", _between(1, 32)),
    "quiet": _arg(bool, "--quiet", "no summary", default=True),
    "out_file": _output_template("{in_file}_peaks.nii.gz", "peaks out"),
})

_RENDER_INPUT = _spec("RenderInput", {
    "sh": _arg(File, "--sh", "SH volume", mandatory=True),
    "slice": _optional(str, "--slice", "axial|coronal|sagittal[:INDEX]"),
    "views": _optional(str, "--views", "montage of views"),
    "labels": _arg(bool, "--labels", "orientation letters", default=False),
    "negative": _optional(str, "--negative", "abs or hide", _choice("abs", "hide")),
    "width": _optional(int, "--width", "pixels", _between(1, 16384)),
    "height": _optional(int, "--height", "pixels", _between(1, 16384)),
    "validation": _arg(bool, "--validation", "Vulkan validation layer", default=False),
    "out_file": _output_template("{sh}.png", "PNG out"),
})


def _qc_path(name):
    def collect(inputs, output_dir):
        folder = output_dir / inputs.out_dir
        if name == "figures":
            return [folder / f for f in QC_FIGURES if (folder / f).exists()]
        return folder if name == "out_dir" else folder / name

    return collect


_QC_INPUT = _spec("QcInput", {
    "fod": _arg(File, "", "fibre ODFs (SH coefficients)", position=1, mandatory=True),
    "peaks": _optional(File, "--peaks", "their peaks"),
    "mask": _optional(File, "--mask", "brain mask"),
    "underlay": _optional(File, "--underlay", "FA, T1 or colour-FA"),
    "panel_size": _optional(int, "--panel-size", "panel side in pixels", _between(64, 4096)),
    "negative": _optional(str, "--negative", "hide or abs", _choice("hide", "abs")),
    "validation": _arg(bool, "--validation", "Vulkan validation layer", default=False),
    "quiet": _arg(bool, "--quiet", "no progress", default=True),
    "out_dir": _arg(str, "-o", "the set's folder, in the task's directory", position=-1,
                    default="qc"),
})

_QC_OUTPUT = SpecInfo(
    name="QcOutput",
    fields=[
        ("out_dir", attr.ib(type=Directory, metadata={
            "help_string": "the figure set", "callable": _qc_path("out_dir")})),
        ("index_html", attr.ib(type=File, metadata={
            "help_string": "the page", "callable": _qc_path("index.html")})),
        ("sidecar", attr.ib(type=File, metadata={
            "help_string": "qc.json", "callable": _qc_path("qc.json")})),
        ("figures", attr.ib(type=ty.List[File], metadata={
            "help_string": "the PNGs", "callable": _qc_path("figures")})),
    ],
    bases=(ShellOutSpec,),
)


def _task(subcommand, input_spec, output_spec=None, **kwargs):
    return ShellCommandTask(
        executable=[glyphcast_binary(), subcommand],
        input_spec=input_spec,
        output_spec=output_spec,
        **kwargs,
    )


def fit_task(**kwargs):
    """``glyphcast fit`` (CSD as MRtrix3 computes it, band 8, by default); output
    ``out_file``. With ``odf="msmt"`` (given as a value, not a lazy field: it decides
    the outputs) also ``gm_file`` and ``csf_file``."""
    odf = kwargs.get("odf")
    if isinstance(odf, LazyField):
        raise ValueError("odf: give the model as a value; it decides the task's outputs")
    return _task("fit", _FIT_MSMT_INPUT if odf == "msmt" else _FIT_INPUT, **kwargs)


def peaks_task(**kwargs):
    """``glyphcast peaks``; output ``out_file``."""
    return _task("peaks", _PEAKS_INPUT, **kwargs)


def render_task(**kwargs):
    """``glyphcast render --sh``; output ``out_file`` (PNG)."""
    return _task("render", _RENDER_INPUT, **kwargs)


def qc_task(**kwargs):
    """``glyphcast qc``; outputs ``out_dir``, ``index_html``, ``sidecar``, ``figures``."""
    return _task("qc", _QC_INPUT, _QC_OUTPUT, **kwargs)

