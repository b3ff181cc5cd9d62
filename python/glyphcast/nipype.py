"""Nipype interfaces of the ``glyphcast`` command line: ``Fit`` (``glyphcast fit``:
single-shell CSD as MRtrix3 or DIPY computes it, multi-shell multi-tissue CSD with its
GM and CSF images, CSA, Q-ball), ``Peaks``, ``Render`` and ``Qc`` (one subject's figure set).

Each is a ``CommandLine`` interface whose inputs and outputs are traits, so it slots
into a Nipype workflow (QSIRecon-style) like any FSL or MRtrix interface::

    from nipype import Node, Workflow
    from glyphcast.nipype import Fit, Peaks, Qc

    fit = Node(Fit(bval="dwi.bval", bvec="dwi.bvec"), name="fit")
    peaks = Node(Peaks(), name="peaks")
    qc = Node(Qc(), name="qc")
    wf = Workflow(name="odf_qc")
    wf.connect([(fit, peaks, [("out_file", "in_file")]),
                (fit, qc, [("out_file", "fod")]),
                (peaks, qc, [("out_file", "peaks")])])

Values are checked when they are set, before anything runs: an input file that does not
exist, an option outside its choices or range raise ``TraitError`` at once. The binary
is ``$GLYPHCAST_BIN`` if set, else ``glyphcast`` on the PATH (``cargo install --path .``
or the container of container/). Drawing needs a Vulkan device: lavapipe
(``mesa-vulkan-drivers``) renders on the CPU, with no display and no GPU.
"""
import os
import shutil

from nipype.interfaces.base import (
    CommandLine,
    CommandLineInputSpec,
    Directory,
    File,
    OutputMultiObject,
    TraitedSpec,
    isdefined,
    traits,
)

__all__ = ["Fit", "Peaks", "Render", "Qc", "glyphcast_binary", "tissue_file"]


def glyphcast_binary():
    """The glyphcast executable: $GLYPHCAST_BIN, else `glyphcast` on the PATH."""
    return os.environ.get("GLYPHCAST_BIN") or shutil.which("glyphcast") or "glyphcast"


class _GlyphcastCommand(CommandLine):
    """A glyphcast subcommand; `_subcommand` names it."""

    _subcommand = None

    def __init__(self, **inputs):
        super().__init__(command=f"{glyphcast_binary()} {self._subcommand}", **inputs)


class _DrawingInputSpec(CommandLineInputSpec):
    """Options every drawing command shares."""

    method = traits.Str(argstr="--method %s", desc="how glyphs are drawn (default exact)")
    samples = traits.Enum(1, 4, 16, argstr="--samples %d", desc="samples per pixel")
    basis = traits.Enum(
        "tournier07", "descoteaux07", "mrtrix", "dipy", "dipy-new",
        argstr="--basis %s", desc="SH basis (default: the file's record)",
    )
    orientation = traits.Enum(
        "radiological", "neurological", argstr="--orientation %s",
        desc="which side the subject's right is drawn on (default radiological)",
    )
    device = traits.Str(argstr="--device %s", desc="Vulkan device: part of its name or index")
    validation = traits.Bool(argstr="--validation", desc="the Vulkan validation layer")


# ---------------------------------------------------------------------------- fit


def tissue_file(path, tissue):
    """`path` with ``_TISSUE`` before its extension (.nii, .nii.gz, .mif, .mif.gz), as
    ``glyphcast fit --odf msmt`` names its GM and CSF images by default."""
    folder, name = os.path.split(path)
    lower = name.lower()
    ending = next((e for e in (".nii.gz", ".mif.gz", ".nii", ".mif") if lower.endswith(e)), "")
    stem = name[:len(name) - len(ending)]
    return os.path.join(folder, f"{stem}_{tissue}{name[len(stem):]}")


class FitInputSpec(CommandLineInputSpec):
    dwi = File(exists=True, mandatory=True, argstr="%s", position=0,
               desc="DWI series (NIfTI or MRtrix)")
    bval = File(exists=True, argstr="--bval %s", desc="FSL b-values")
    bvec = File(exists=True, argstr="--bvec %s", desc="FSL b-vectors")
    bvec_convention = traits.Enum("fsl", "voxel", "world", argstr="--bvec-convention %s",
                                  desc="frame of bvec (default fsl)")
    order = traits.Range(low=0, high=12, value=8, usedefault=True, argstr="--order %d",
                         desc="SH band (even) or tensor order")
    odf = traits.Enum("csd", "msmt", "csa", "qball", argstr="--odf %s",
                      desc="fibre ODF model (msmt: multi-shell multi-tissue CSD, which "
                           "also writes gm_file and csf_file)")
    sh = traits.Bool(argstr="--sh", xor=["odf"], desc="SH series of the signal instead")
    basis = traits.Enum(
        "tournier07", "descoteaux07", "mrtrix", "dipy", "dipy-new",
        argstr="--basis %s", desc="SH basis of the output (default tournier07)",
    )
    legacy = traits.Bool(argstr="--legacy", desc="the legacy variant of the SH basis")
    reg_lambda = traits.Float(argstr="--lambda %g",
                              desc="regularisation weight (the command line's --lambda)")
    csd_algorithm = traits.Enum("mrtrix", "dipy", argstr="--csd-algorithm %s",
                                desc="CSD: MRtrix3's dwi2fod csd (default) or DIPY's")
    tau = traits.Float(argstr="--tau %g", desc="CSD: the constraint's threshold")
    response = File(exists=True, argstr="--response %s",
                    desc="CSD: the single-fibre response (MRtrix text); msmt: the WM "
                         "response, one row per shell")
    response_fa = traits.Range(low=0.0, high=1.0, argstr="--response-fa %g",
                               desc="CSD: FA threshold of the response voxels")
    response_gm = File(exists=True, argstr="--response-gm %s",
                       requires=["response", "response_csf"],
                       desc="msmt: the GM response (with response and response_csf)")
    response_csf = File(exists=True, argstr="--response-csf %s",
                        requires=["response", "response_gm"],
                        desc="msmt: the CSF response (with response and response_gm)")
    gm_file = File(argstr="--gm %s", genfile=True,
                   desc="msmt: the GM image (default: out_file's name with _gm)")
    csf_file = File(argstr="--csf %s", genfile=True,
                    desc="msmt: the CSF image (default: out_file's name with _csf)")
    tensor_order = traits.Enum("glyphcast", "fsl", "dipy", "mrtrix",
                               argstr="--tensor-order %s",
                               desc="stored order of a DTI fit's six entries (NIfTI)")
    mask = File(exists=True, argstr="--mask %s", desc="voxels to fit")
    out_file = File(argstr="-o %s", name_source=["dwi"], name_template="%s_fod.nii.gz",
                    keep_extension=False, position=-1, desc="coefficients out")
    quiet = traits.Bool(True, usedefault=True, argstr="--quiet", desc="no progress")


class FitOutputSpec(TraitedSpec):
    out_file = File(exists=True, desc="fitted coefficients (4D; msmt: the WM fODF)")
    gm_file = File(exists=True, desc="msmt: the GM image (band 0)")
    csf_file = File(exists=True, desc="msmt: the CSF image (band 0)")


class Fit(_GlyphcastCommand):
    """``glyphcast fit``: tensors, SH or fibre ODFs (CSD as MRtrix3 or DIPY computes it,
    multi-shell multi-tissue CSD, CSA, Q-ball) from a DWI."""

    _subcommand = "fit"
    input_spec = FitInputSpec
    output_spec = FitOutputSpec

    _TISSUES = {"gm_file": "gm", "csf_file": "csf"}

    def _gen_filename(self, name):
        # msmt's GM and CSF images are named here and passed on, so that the outputs
        # are what the command wrote; other models take no --gm/--csf.
        if name in self._TISSUES and self.inputs.odf == "msmt":
            out_file = self._filename_from_source("out_file")
            return os.path.abspath(tissue_file(out_file, self._TISSUES[name]))
        return None

    def _format_arg(self, name, spec, value):
        if name in self._TISSUES and value is None:
            return None  # not msmt: no tissue images
        return super()._format_arg(name, spec, value)

    def _list_outputs(self):
        outputs = super()._list_outputs()
        if self.inputs.odf == "msmt":
            for name in self._TISSUES:
                given = getattr(self.inputs, name)
                outputs[name] = os.path.abspath(given) if isdefined(given) \
                    else self._gen_filename(name)
        return outputs


# -------------------------------------------------------------------------- peaks


class PeaksInputSpec(CommandLineInputSpec):
    in_file = File(exists=True, mandatory=True, argstr="%s", position=0,
                   desc="ODF SH coefficients")
    count = traits.Range(low=1, high=32, argstr="--count %d", desc="peaks per voxel")
    relative_threshold = traits.Range(low=0.0, high=1.0, argstr="--relative-threshold %g")
    min_separation = traits.Range(low=0.0, high=90.0, argstr="--min-separation %g")
    out_file = File(argstr="-o %s", name_source=["in_file"], name_template="%s_peaks.nii.gz",
                    keep_extension=False, position=-1, desc="peaks out (sh2peaks layout)")
    quiet = traits.Bool(True, usedefault=True, argstr="--quiet", desc="no summary")


class PeaksOutputSpec(TraitedSpec):
    out_file = File(exists=True, desc="peaks: 3 values per peak, NaN where absent")


class Peaks(_GlyphcastCommand):
    """``glyphcast peaks``: the largest maxima of each voxel's ODF."""

    _subcommand = "peaks"
    input_spec = PeaksInputSpec
    output_spec = PeaksOutputSpec


# ------------------------------------------------------------------------- render


class RenderInputSpec(_DrawingInputSpec):
    sh = File(exists=True, mandatory=True, argstr="--sh %s", desc="SH volume")
    slice = traits.Str(argstr="--slice %s", desc="axial|coronal|sagittal[:INDEX]")
    views = traits.Str(argstr="--views %s", xor=["lightbox", "slice"],
                       desc="montage: axial,coronal,sagittal (each optionally :INDEX)")
    lightbox = traits.Range(low=1, high=64, argstr="--lightbox %d", xor=["views"],
                            desc="montage of N slices")
    mask = File(exists=True, argstr="--mask %s")
    underlay = File(exists=True, argstr="--underlay %s")
    width = traits.Range(low=1, high=16384, argstr="--width %d")
    height = traits.Range(low=1, high=16384, argstr="--height %d")
    labels = traits.Bool(argstr="--labels", desc="orientation letters at the edges")
    negative = traits.Enum("abs", "hide", argstr="--negative %s")
    color = traits.Enum("direction", "magnitude", "uniform", "sign", argstr="--color %s")
    out_file = File(argstr="-o %s", name_source=["sh"], name_template="%s.png",
                    keep_extension=False, position=-1, desc="PNG out")


class RenderOutputSpec(TraitedSpec):
    out_file = File(exists=True, desc="the PNG")


class Render(_GlyphcastCommand):
    """``glyphcast render --sh``: a slice or montage of SH glyphs as a PNG."""

    _subcommand = "render"
    input_spec = RenderInputSpec
    output_spec = RenderOutputSpec


# ----------------------------------------------------------------------------- qc

QC_FIGURES = ("odf-mosaic.png", "peaks-mosaic.png", "zoom-1.png", "zoom-2.png", "zoom-3.png")


class QcInputSpec(_DrawingInputSpec):
    fod = File(exists=True, mandatory=True, argstr="%s", position=0,
               desc="fibre ODFs (SH coefficients)")
    peaks = File(exists=True, argstr="--peaks %s", desc="their peaks (glyphcast peaks)")
    mask = File(exists=True, argstr="--mask %s", desc="brain mask on the ODFs' grid")
    underlay = File(exists=True, argstr="--underlay %s", desc="FA, T1 or colour-FA")
    panel_size = traits.Range(low=64, high=4096, argstr="--panel-size %d",
                              desc="side of each panel in pixels")
    negative = traits.Enum("hide", "abs", argstr="--negative %s")
    out_dir = Directory("qc", usedefault=True, argstr="-o %s", position=-1,
                        desc="the set's folder (written whole or not at all)")
    quiet = traits.Bool(True, usedefault=True, argstr="--quiet", desc="no progress lines")


class QcOutputSpec(TraitedSpec):
    out_dir = Directory(exists=True, desc="the figure set")
    index_html = File(exists=True, desc="the page")
    sidecar = File(exists=True, desc="qc.json: inputs, checksums, settings, timings")
    figures = OutputMultiObject(File(exists=True), desc="the PNGs")


class Qc(_GlyphcastCommand):
    """``glyphcast qc``: one subject's quality-control figure set of fibre ODFs."""

    _subcommand = "qc"
    input_spec = QcInputSpec
    output_spec = QcOutputSpec

    def _list_outputs(self):
        out_dir = os.path.abspath(self.inputs.out_dir)
        figures = [os.path.join(out_dir, name) for name in QC_FIGURES
                   if os.path.exists(os.path.join(out_dir, name))]
        return {
            "out_dir": out_dir,
            "index_html": os.path.join(out_dir, "index.html"),
            "sidecar": os.path.join(out_dir, "qc.json"),
            "figures": figures,
        }
