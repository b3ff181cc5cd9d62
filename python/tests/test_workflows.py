"""glyphcast on workflow engines (issue 24): the cohort demo (N = 4 subjects through
Nipype's MultiProc: fit, peaks, qc), a pydra workflow of the same tasks, the Nipype
Render interface against the CLI, the fits' models and algorithms (multi-shell CSD with
its three images, DIPY's CSD) through both engines against the CLI, and the interfaces'
checks of their inputs.

Every run is real: the glyphcast binary (GLYPHCAST_BIN, else target/debug/glyphcast)
draws on lavapipe with the validation layer on (conftest sets GLYPHCAST_VALIDATION=1).
"""
import json
import os
import pathlib
import subprocess
import sys

import pytest

nipype = pytest.importorskip("nipype", reason="the test venv installs nipype")
pydra = pytest.importorskip("pydra", reason="the test venv installs pydra")

from traits.api import TraitError  # noqa: E402

from glyphcast.nipype import Fit, Peaks, Qc, Render  # noqa: E402
from glyphcast.pydra import fit_task, peaks_task, qc_task  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
DIPY = ROOT / "tests" / "data" / "dipy"
MSMT = ROOT / "tests" / "data" / "msmt"
MSMT_RESPONSES = {"response": MSMT / "wm.txt", "response_gm": MSMT / "gm.txt",
                  "response_csf": MSMT / "csf.txt"}


@pytest.fixture(autouse=True)
def binary(cli_binary, monkeypatch):
    """The interfaces run the binary the other tests compare with."""
    monkeypatch.setenv("GLYPHCAST_BIN", str(cli_binary))
    return cli_binary


@pytest.fixture(scope="module")
def fod(tmp_path_factory, cli_binary):
    """CSD fODFs of small_64D, fitted by the CLI."""
    out = tmp_path_factory.mktemp("fod") / "fod.nii.gz"
    subprocess.run(
        [str(cli_binary), "fit", str(DIPY / "small_64D.nii"), "--bval",
         str(DIPY / "small_64D.bval"), "--bvec", str(DIPY / "small_64D.bvec"),
         "--odf", "csd", "--order", "8", "--quiet", "-o", str(out)],
        check=True, capture_output=True,
    )
    return out


def test_cohort_demo_runs_four_subjects_through_nipype_multiproc(tmp_path, cli_binary):
    out = tmp_path / "cohort"
    env = dict(os.environ, GLYPHCAST_BIN=str(cli_binary), PYTHON=sys.executable)
    done = subprocess.run(
        ["bash", str(ROOT / "tools" / "cohort-demo.sh"), "4", str(out),
         "--panel-size", "96", "--processes", "2"],
        env=env, capture_output=True, text=True,
    )
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    # MultiProc ran the workflow (not the Linear plugin).
    assert "[MultiProc]" in done.stdout + done.stderr
    checksums = set()
    for n in range(1, 5):
        folder = out / f"sub-{n:02d}" / "qc"
        assert (folder / "index.html").is_file(), folder
        names = {p.name for p in folder.iterdir()}
        # The peaks of `peaks` drawn over the mosaic's panels: peaks-mosaic.png.
        assert names == {"index.html", "qc.json", "odf-mosaic.png", "peaks-mosaic.png",
                         "zoom-1.png", "zoom-2.png", "zoom-3.png"}, names
        sidecar = json.loads((folder / "qc.json").read_text())
        roles = [i["role"] for i in sidecar["inputs"]]
        assert roles == ["fod", "peaks"], roles
        assert "peaks-mosaic.png" in [f["file"] for f in sidecar["figures"]]
        assert sidecar["settings"]["panel_size"] == 96
        checksums.add(sidecar["inputs"][0]["sha256"])
        page = (folder / "index.html").read_text()
        assert f"sub-{n:02d}_dwi_fod.nii.gz" in page
    # Each subject is its own perturbed copy: four different fits.
    assert len(checksums) == 4


def test_pydra_workflow_of_fit_peaks_qc(tmp_path):
    wf = pydra.Workflow(name="odf_qc", input_spec=["dwi", "bval", "bvec"],
                        cache_dir=str(tmp_path / "cache"))
    wf.inputs.dwi = str(DIPY / "small_64D.nii")
    wf.inputs.bval = str(DIPY / "small_64D.bval")
    wf.inputs.bvec = str(DIPY / "small_64D.bvec")
    wf.add(fit_task(name="fit", dwi=wf.lzin.dwi, bval=wf.lzin.bval, bvec=wf.lzin.bvec))
    wf.add(peaks_task(name="peaks", in_file=wf.fit.lzout.out_file))
    wf.add(qc_task(name="qc", fod=wf.fit.lzout.out_file, peaks=wf.peaks.lzout.out_file,
                   panel_size=96, validation=True))
    wf.set_output([("index_html", wf.qc.lzout.index_html),
                   ("sidecar", wf.qc.lzout.sidecar),
                   ("figures", wf.qc.lzout.figures)])
    with pydra.Submitter(plugin="cf") as submitter:
        submitter(wf)
    result = wf.result()
    assert not result.errored
    page = pathlib.Path(str(result.output.index_html))
    assert "small_64D_fod.nii.gz" in page.read_text()
    sidecar = json.loads(pathlib.Path(str(result.output.sidecar)).read_text())
    assert sidecar["volume"]["sh_band"] == 8
    names = sorted(pathlib.Path(str(f)).name for f in result.output.figures)
    assert names == ["odf-mosaic.png", "peaks-mosaic.png", "zoom-1.png", "zoom-2.png",
                     "zoom-3.png"]


def test_nipype_render_gives_the_cli_picture(tmp_path, fod, cli, monkeypatch):
    node_dir = tmp_path / "node"
    node_dir.mkdir()
    monkeypatch.chdir(node_dir)
    render = Render(sh=str(fod), views="axial,coronal", width=80, height=80, labels=True,
                    negative="hide", validation=True)
    assert render.cmdline.endswith("-o fod.png")
    result = render.run()
    made = pathlib.Path(result.outputs.out_file)
    cli_png = tmp_path / "cli.png"
    cli("render", "--sh", fod, "--views", "axial,coronal", "--width", "80", "--height",
        "80", "--labels", "--negative", "hide", "-o", cli_png)
    assert made.read_bytes() == cli_png.read_bytes()


def _voxels(path):
    nibabel = pytest.importorskip("nibabel")
    return nibabel.load(str(path)).get_fdata()


def _fit_cli(binary, *args):
    """`glyphcast fit ARGS` (no GPU, so no --validation); fails the test on an error."""
    done = subprocess.run([str(binary), "fit", *map(str, args)], capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr


def _msmt_cli(binary, folder):
    """The CLI's msmt fit of the fixture with its three responses: WM, GM, CSF."""
    folder.mkdir()
    wm = folder / "wm.nii.gz"
    _fit_cli(binary, MSMT / "dwi.nii.gz", "--bval", MSMT / "dwi.bval", "--bvec",
        MSMT / "dwi.bvec", "--odf", "msmt", "--order", "8", "--response", MSMT / "wm.txt",
        "--response-gm", MSMT / "gm.txt", "--response-csf", MSMT / "csf.txt", "--quiet",
        "-o", wm)
    return [wm, folder / "wm_gm.nii.gz", folder / "wm_csf.nii.gz"]


def test_nipype_fit_msmt_gives_the_cli_three_images(tmp_path, cli_binary, monkeypatch):
    node_dir = tmp_path / "node"
    node_dir.mkdir()
    monkeypatch.chdir(node_dir)
    fit = Fit(dwi=str(MSMT / "dwi.nii.gz"), bval=str(MSMT / "dwi.bval"),
              bvec=str(MSMT / "dwi.bvec"), odf="msmt",
              **{k: str(v) for k, v in MSMT_RESPONSES.items()})
    outputs = fit.run().outputs
    made = [pathlib.Path(outputs.out_file), pathlib.Path(outputs.gm_file),
            pathlib.Path(outputs.csf_file)]
    assert [p.name for p in made] == ["dwi_fod.nii.gz", "dwi_fod_gm.nii.gz",
                                      "dwi_fod_csf.nii.gz"]
    expected = _msmt_cli(cli_binary, tmp_path / "cli")
    for got, want in zip(made, expected):
        assert got.parent == node_dir
        a, b = _voxels(got), _voxels(want)
        assert a.shape == b.shape and (a == b).all(), got.name
    # The WM image is an fODF of band 8, the tissues band 0.
    assert _voxels(made[0]).shape[3] == 45
    assert _voxels(made[1]).ndim == 3 or _voxels(made[1]).shape[3] == 1


def test_nipype_fit_takes_dipy_csd(tmp_path, cli_binary, monkeypatch):
    node_dir = tmp_path / "node"
    node_dir.mkdir()
    monkeypatch.chdir(node_dir)
    common = ["--bval", DIPY / "small_64D.bval", "--bvec", DIPY / "small_64D.bvec",
              "--odf", "csd", "--order", "6", "--quiet"]
    fit = Fit(dwi=str(DIPY / "small_64D.nii"), bval=str(DIPY / "small_64D.bval"),
              bvec=str(DIPY / "small_64D.bvec"), odf="csd", order=6, csd_algorithm="dipy",
              tau=0.1, basis="dipy")
    assert "--csd-algorithm dipy" in fit.cmdline and "--basis dipy" in fit.cmdline
    made = pathlib.Path(fit.run().outputs.out_file)
    dipy_cli, mrtrix_cli = tmp_path / "dipy.nii.gz", tmp_path / "mrtrix.nii.gz"
    _fit_cli(cli_binary, DIPY / "small_64D.nii", *common, "--csd-algorithm", "dipy",
             "--tau", "0.1", "--basis", "dipy", "-o", dipy_cli)
    _fit_cli(cli_binary, DIPY / "small_64D.nii", *common, "--basis", "dipy", "-o", mrtrix_cli)
    assert (_voxels(made) == _voxels(dipy_cli)).all()
    # The algorithm reached the command: MRtrix's (the default) fits otherwise.
    assert not (_voxels(made) == _voxels(mrtrix_cli)).all()
    # No tissue images for single-shell CSD.
    assert sorted(p.name for p in node_dir.iterdir()) == ["small_64D_fod.nii.gz"]


def test_pydra_fit_msmt_gives_the_cli_three_images(tmp_path, cli_binary):
    task = fit_task(dwi=str(MSMT / "dwi.nii.gz"), bval=str(MSMT / "dwi.bval"),
                    bvec=str(MSMT / "dwi.bvec"), odf="msmt", cache_dir=str(tmp_path / "c"),
                    **{k: str(v) for k, v in MSMT_RESPONSES.items()})
    result = task()
    assert not result.errored
    made = [pathlib.Path(str(result.output.out_file)),
            pathlib.Path(str(result.output.gm_file)),
            pathlib.Path(str(result.output.csf_file))]
    expected = _msmt_cli(cli_binary, tmp_path / "cli")
    for got, want in zip(made, expected):
        assert got.is_file(), got
        assert (_voxels(got) == _voxels(want)).all(), got.name


def test_nipype_interfaces_refuse_bad_inputs_before_running(tmp_path, fod):
    missing = str(tmp_path / "missing.nii.gz")
    with pytest.raises(TraitError):
        Qc(fod=missing)
    with pytest.raises(TraitError):
        Qc(fod=str(fod), negative="both")
    with pytest.raises(TraitError):
        Qc(fod=str(fod), panel_size=10)
    with pytest.raises(TraitError):
        Fit(dwi=str(DIPY / "small_64D.nii"), odf="dti")
    with pytest.raises(TraitError):
        Fit(dwi=str(DIPY / "small_64D.nii"), csd_algorithm="fsl")
    with pytest.raises(TraitError):
        Fit(dwi=str(DIPY / "small_64D.nii"), response_gm=missing)
    # msmt's responses go together: one alone is refused when the command is made.
    with pytest.raises(ValueError, match="response_csf"):
        Fit(dwi=str(DIPY / "small_64D.nii"), odf="msmt",
            response_gm=str(MSMT / "gm.txt")).cmdline
    with pytest.raises(TraitError):
        Peaks(in_file=missing)
    with pytest.raises(TraitError):
        Render(sh=str(fod), samples=3)
    # Options that exclude each other are refused when the second is set, a mandatory
    # input left out when the command line is made: before anything runs.
    with pytest.raises(OSError, match="mutually exclusive"):
        Render(sh=str(fod), views="axial", lightbox=4)
    with pytest.raises(ValueError, match="fod"):
        Qc().cmdline
    assert not list(tmp_path.iterdir())


def test_pydra_tasks_refuse_bad_inputs_before_running(tmp_path, fod):
    with pytest.raises(Exception, match="missing.nii.gz"):
        qc_task(fod=str(tmp_path / "missing.nii.gz"))
    with pytest.raises(ValueError, match="negative"):
        qc_task(fod=str(fod), negative="both")
    with pytest.raises(ValueError, match="panel_size"):
        qc_task(fod=str(fod), panel_size=10)
    with pytest.raises(ValueError, match="odf"):
        fit_task(dwi=str(DIPY / "small_64D.nii"), odf="dti")
    with pytest.raises(ValueError, match="csd_algorithm"):
        fit_task(dwi=str(DIPY / "small_64D.nii"), csd_algorithm="fsl")
    with pytest.raises(Exception, match="missing.txt"):
        fit_task(dwi=str(DIPY / "small_64D.nii"), response=str(tmp_path / "missing.txt"))
    assert not list(tmp_path.iterdir())
