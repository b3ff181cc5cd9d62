#!/usr/bin/env python3
"""A multi-shell DWI of known tissue mixtures and DIPY's MSMT-CSD on it, for tests/msmt.rs.

Run once by hand (CI never runs it; the tests read the files it writes):

    python3 -m venv /tmp/venv-msmt && /tmp/venv-msmt/bin/pip install dipy cvxpy
    /tmp/venv-msmt/bin/python tools/msmt_fixtures.py tests/data/msmt

It writes, into the folder given:
- dwi.nii.gz, dwi.bval, dwi.bvec: a 5x5x3 volume, 3 b=0 volumes and 3 shells of 40
  directions (b = 1000, 2000, 3000, each b-value jittered by up to 5 s/mm^2 as scanners
  report them). Each slice holds the same 25 mixtures of WM fibres, GM and CSF. Slice z=0:
  each fibre the signal of a prolate tensor, noise-free. Slice z=1: each fibre the fODF
  (9/(4 pi)) (u.d)^8 (non-negative and of band 8, so the model holds exactly) convolved
  with the WM response, noise-free. Slice z=2: slice 0 with Rician noise (sigma 20, S0 of
  white matter 1000). The affine has a negative determinant, so the
  b-vectors are in the voxel axes in every convention (DIPY's, FSL's, MRtrix's -fslgrad).
- wm.txt, gm.txt, csf.txt: the tissues' responses in MRtrix's multi-shell format (one row
  per shell, b = 0 first; zonal SH coefficients l = 0, 2, ..., 8 for WM, l = 0 for GM and
  CSF), as DIPY's multi_shell_fiber_response computes them from the tensors below.
- msmt-dipy.json: per voxel the known mixture (fractions, fibre directions) and DIPY's
  MultiShellDeconvModel fit with those responses (sh_order_max 8, descoteaux07 legacy,
  constraint on default_sphere): its coefficients as DIPY's own solver call gives them, the
  same QP solved to 1e-10 with Clarabel (through cvxpy), the volume fractions and the peaks.
- If MRtrix's dwi2fod is installed, the same fit by `dwi2fod msmt_csd` with the same
  response files: per voxel its WM, GM and CSF band-0 coefficients.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

import cvxpy
import dipy
import nibabel as nib
import numpy as np
from dipy.core.gradients import gradient_table
from dipy.core.sphere import HemiSphere, disperse_charges
from dipy.data import default_sphere
from dipy.direction import peak_directions
from dipy.reconst.mcsd import MultiShellDeconvModel, multi_shell_fiber_response
from dipy.reconst.shm import real_sh_descoteaux

SHELLS = [1000.0, 2000.0, 3000.0]
DIRECTIONS_PER_SHELL = 40
B0_VOLUMES = 3
SH_ORDER = 8
# Tissue models: WM a prolate tensor per fibre, GM and CSF isotropic; S0 per tissue.
WM = {"l1": 1.7e-3, "l2": 0.3e-3, "s0": 1000.0}
GM = {"d": 0.8e-3, "s0": 1300.0}
CSF = {"d": 3.0e-3, "s0": 3000.0}
NOISE_SIGMA = 20.0
RELATIVE_PEAK = 0.5
MIN_SEPARATION = 25.0


def unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def at_angle(a, degrees, towards):
    """The unit vector `degrees` from `a` in the plane of a and `towards`."""
    a = unit(a)
    t = unit(np.asarray(towards) - np.dot(towards, a) * a)
    r = np.radians(degrees)
    return np.cos(r) * a + np.sin(r) * t


def mixtures():
    """25 voxels: (wm fraction, [(fibre direction, share of the WM)], gm, csf)."""
    x, y, z = np.eye(3)
    d1 = unit([1, 0.3, 0.2])
    d2 = unit([0.2, 1, -0.4])
    d3 = unit([0.3, -0.2, 1])
    d4 = unit([-0.5, 0.5, 0.7])
    one = lambda d: [(d, 1.0)]
    cross = lambda a, deg, t, w=0.5: [(unit(a), w), (at_angle(a, deg, t), 1.0 - w)]
    m = [
        (1.0, one(x), 0.0, 0.0),
        (1.0, one(y), 0.0, 0.0),
        (1.0, one(z), 0.0, 0.0),
        (1.0, one(d1), 0.0, 0.0),
        (1.0, one(d2), 0.0, 0.0),
        (1.0, one(d3), 0.0, 0.0),
        (1.0, cross(x, 90, y), 0.0, 0.0),
        (1.0, cross(d1, 90, d3), 0.0, 0.0),
        (1.0, cross(d2, 75, d4), 0.0, 0.0),
        (1.0, cross(d3, 60, d1, 0.6), 0.0, 0.0),
        (1.0, cross(d4, 70, z, 0.55), 0.0, 0.0),
        (0.8, cross(z, 90, d1), 0.2, 0.0),
        (0.6, one(d4), 0.4, 0.0),
        (0.7, one(d1), 0.0, 0.3),
        (0.5, one(d2), 0.3, 0.2),
        (0.4, one(d3), 0.6, 0.0),
        (0.3, one(z), 0.2, 0.5),
        (0.7, cross(y, 80, d3), 0.0, 0.3),
        (0.6, cross(d1, 90, d2, 0.6), 0.2, 0.2),
        (0.0, [], 1.0, 0.0),
        (0.0, [], 0.0, 1.0),
        (0.0, [], 0.6, 0.4),
        (0.2, one(x), 0.8, 0.0),
        (0.1, one(d2), 0.3, 0.6),
        (0.9, one(d4), 0.1, 0.0),
    ]
    assert len(m) == 25
    return m


def gradient_scheme(rng):
    bvals = [0.0] * B0_VOLUMES
    bvecs = [[0.0, 0.0, 0.0]] * B0_VOLUMES
    for i, b in enumerate(SHELLS):
        theta = np.pi * rng.random(DIRECTIONS_PER_SHELL)
        phi = 2 * np.pi * rng.random(DIRECTIONS_PER_SHELL)
        hemi, _ = disperse_charges(HemiSphere(theta=theta, phi=phi), 3000)
        bvecs += hemi.vertices.tolist()
        bvals += (b + rng.integers(-5, 6, DIRECTIONS_PER_SHELL)).tolist()
    return np.array(bvals, dtype=float), np.array(bvecs)


def band8_fodf(fibres):
    """SH (descoteaux07 legacy, band 8) of the sum of share (9/(4 pi)) (u.d)^8."""
    sphere = default_sphere.subdivide(n=2)
    u = np.concatenate([sphere.vertices, -sphere.vertices])
    r = np.linalg.norm(u, axis=1)
    theta, phi = np.arccos(u[:, 2] / r), np.arctan2(u[:, 1], u[:, 0])
    basis, _, _ = real_sh_descoteaux(SH_ORDER, theta, phi)
    values = sum(w * 9.0 / (4 * np.pi) * (u @ d) ** 8 for d, w in fibres)
    if not fibres:
        return np.zeros(basis.shape[1])
    return np.linalg.lstsq(basis, values, rcond=None)[0]


def signal(bvals, bvecs, mixture, model=None):
    """The mixture's signal: fibres as tensors, or (with `model`) as band-8 fODFs
    convolved by DIPY's design (its X: columns CSF, GM, WM)."""
    wm, fibres, gm, csf = mixture
    if model is not None:
        sh_const = 0.5 / np.sqrt(np.pi)
        x = np.concatenate([[csf * sh_const, gm * sh_const], wm * band8_fodf(fibres)])
        return model._X @ x, x
    s = np.zeros(len(bvals))
    for d, share in fibres:
        c = bvecs @ d
        adc = WM["l2"] + (WM["l1"] - WM["l2"]) * c * c
        s += wm * share * WM["s0"] * np.exp(-bvals * adc)
    s += gm * GM["s0"] * np.exp(-bvals * GM["d"])
    s += csf * CSF["s0"] * np.exp(-bvals * CSF["d"])
    return s


def write_response(path, rows, shells):
    with open(path, "w") as f:
        f.write("# Shells: " + ",".join(f"{b:g}" for b in shells) + "\n")
        f.write("# Made by tools/msmt_fixtures.py (DIPY multi_shell_fiber_response)\n")
        for row in rows:
            f.write(" ".join(repr(float(v)) for v in np.atleast_1d(row)) + "\n")


def solve_tight(X, reg, s):
    x = cvxpy.Variable(X.shape[1])
    problem = cvxpy.Problem(cvxpy.Minimize(0.5 * cvxpy.sum_squares(X @ x - s)), [reg @ x >= 0])
    problem.solve(solver="CLARABEL", tol_gap_abs=1e-10, tol_gap_rel=1e-10, tol_feas=1e-10)
    return x.value


def default_solver_name(model, s):
    """The solver cvxpy picks for DIPY's own QP (DIPY does not choose one)."""
    fitter = model.fitter
    x = cvxpy.Variable(fitter._P_mat.shape[0])
    q = -np.dot(fitter._X.T, s)
    problem = cvxpy.Problem(
        cvxpy.Minimize(0.5 * cvxpy.quad_form(x, cvxpy.Constant(fitter._P_mat), True) + q @ x),
        [fitter._reg_mat @ x <= fitter._h_mat],
    )
    problem.solve()
    return problem.solver_stats.solver_name


def mrtrix_fit(out_dir, shape, affine):
    """dwi2fod msmt_csd on the fixture: per voxel each tissue's band-0 coefficient and the
    WM fODF (tournier07, scanner axes, as MRtrix stores it), indexed as the fixture."""
    if shutil.which("dwi2fod") is None:
        return None
    version = subprocess.run(["dwi2fod", "-version"], capture_output=True, text=True).stdout
    result = {"command": "dwi2fod msmt_csd dwi.nii.gz -fslgrad dwi.bvec dwi.bval "
              "wm.txt wm.mif gm.txt gm.mif csf.txt csf.mif -lmax 8,0,0",
              "version": version.splitlines()[0] if version else ""}
    with tempfile.TemporaryDirectory() as tmp:
        files = {}
        for name in ["wm", "gm", "csf"]:
            files[name] = f"{tmp}/{name}.mif"
        subprocess.run(["dwi2fod", "msmt_csd", f"{out_dir}/dwi.nii.gz", "-fslgrad",
                        f"{out_dir}/dwi.bvec", f"{out_dir}/dwi.bval", "-lmax", "8,0,0",
                        f"{out_dir}/wm.txt", files["wm"], f"{out_dir}/gm.txt", files["gm"],
                        f"{out_dir}/csf.txt", files["csf"], "-quiet", "-force"], check=True)
        for name, path in files.items():
            nii = f"{tmp}/{name}.nii"
            subprocess.run(["mrconvert", path, nii, "-quiet", "-force"], check=True)
            image = nib.load(nii)
            values = np.asarray(image.dataobj, dtype=np.float64)
            if values.ndim == 3:
                values = values[..., None]
            # MRtrix may store the axes in another order or direction: map by position.
            to_out = np.linalg.inv(image.affine) @ affine
            out = np.zeros(shape + values.shape[3:])
            for index in np.ndindex(shape):
                o = np.rint(to_out @ np.array([*index, 1.0]))[:3].astype(int)
                out[index] = values[tuple(o)]
            result[name] = out
    return result


def main(out_dir):
    os.makedirs(out_dir, exist_ok=True)
    rng = np.random.default_rng(26)
    bvals, bvecs = gradient_scheme(rng)
    mix = mixtures()
    shape = (5, 5, 3)
    shells = np.array([0.0] + SHELLS)
    wm_rf = np.array([[WM["l1"], WM["l2"], WM["l2"], WM["s0"]]] * len(SHELLS))
    gm_rf = np.array([[GM["d"]] * 3 + [GM["s0"]]] * len(SHELLS))
    csf_rf = np.array([[CSF["d"]] * 3 + [CSF["s0"]]] * len(SHELLS))
    response = multi_shell_fiber_response(SH_ORDER, shells, wm_rf, gm_rf, csf_rf)
    gtab = gradient_table(bvals, bvecs=bvecs)
    model = MultiShellDeconvModel(gtab, response, sh_order_max=SH_ORDER)
    data = np.zeros(shape + (len(bvals),))
    truth = []
    for z in range(3):
        for j in range(5):
            for i in range(5):
                m = mix[j * 5 + i]
                exact = None
                if z == 1:
                    s, exact = signal(bvals, bvecs, m, model)
                else:
                    s = signal(bvals, bvecs, m)
                if z == 2:
                    re = s + rng.normal(0, NOISE_SIGMA, s.shape)
                    im = rng.normal(0, NOISE_SIGMA, s.shape)
                    s = np.sqrt(re * re + im * im)
                data[i, j, z] = s
                record = {"voxel": [i, j, z], "noisy": z == 2,
                          "wm_model": "band-8 fODF" if z == 1 else "tensor",
                          "wm": m[0], "gm": m[2], "csf": m[3],
                          "fibres": [d.tolist() for d, _ in m[1]],
                          "shares": [w for _, w in m[1]]}
                if exact is not None:
                    record["true_csf_gm_wm"] = exact.tolist()
                truth.append(record)
    affine = np.diag([-2.0, 2.0, 2.0, 1.0])
    affine[:3, 3] = [4.0, -4.0, -2.0]
    nib.save(nib.Nifti1Image(data.astype(np.float32), affine), f"{out_dir}/dwi.nii.gz")
    np.savetxt(f"{out_dir}/dwi.bval", bvals[None, :], fmt="%g")
    np.savetxt(f"{out_dir}/dwi.bvec", bvecs.T, fmt="%.8f")
    data = np.asarray(nib.load(f"{out_dir}/dwi.nii.gz").dataobj, dtype=np.float64)

    # DIPY's columns: CSF, GM, then WM's zonal l = 0, 2, ..., 8; rows: shells.
    write_response(f"{out_dir}/wm.txt", response.response[:, 2:], shells)
    write_response(f"{out_dir}/gm.txt", response.response[:, 1:2], shells)
    write_response(f"{out_dir}/csf.txt", response.response[:, 0:1], shells)

    fit = model.fit(data)
    coeff = fit.all_shm_coeff
    fractions = fit.volume_fractions
    peak_sphere = default_sphere.subdivide(n=2)
    sampling, _, _ = real_sh_descoteaux(SH_ORDER, peak_sphere.theta, peak_sphere.phi)
    solver = default_solver_name(model, data[0, 0, 0])
    mrtrix = mrtrix_fit(out_dir, shape, affine)
    records = []
    for t in truth:
        i, j, z = t["voxel"]
        c = coeff[i, j, z]
        tight = solve_tight(model._X, model.fitter._reg, data[i, j, z])
        odf = sampling @ c[2:]
        dirs, values, _ = peak_directions(odf, peak_sphere, relative_peak_threshold=RELATIVE_PEAK,
                                          min_separation_angle=MIN_SEPARATION)
        record = dict(t)
        record.update({
            "dipy_csf_gm_wm": [float(f"{v:.7g}") for v in c],
            "tight_csf_gm_wm": tight.tolist(),
            "dipy_fractions_csf_gm_wm": fractions[i, j, z].tolist(),
            "dipy_peak_directions": dirs[:3].tolist(),
            "dipy_peak_values": values[:3].tolist(),
        })
        if mrtrix is not None:
            record["mrtrix_band0_wm_gm_csf"] = [float(mrtrix[n][i, j, z, 0])
                                                for n in ["wm", "gm", "csf"]]
            record["mrtrix_wm_world"] = [float(f"{v:.7g}") for v in mrtrix["wm"][i, j, z]]
        records.append(record)
    fixture = {
        "source": "tools/msmt_fixtures.py",
        "dipy_version": dipy.__version__,
        "cvxpy_version": cvxpy.__version__,
        "numpy_version": np.__version__,
        "dipy_solver": f"cvxpy default ({solver})",
        "tight_solver": "cvxpy CLARABEL, tol_gap_abs = tol_gap_rel = tol_feas = 1e-10",
        "model": "MultiShellDeconvModel(gtab, multi_shell_fiber_response(8, [0,1000,2000,3000], ...), "
                 "sh_order_max=8, iso=2, reg_sphere=default_sphere)",
        "basis": "descoteaux07 legacy (DIPY default); coefficients: CSF, GM (band 0), WM (45)",
        "tissues": {"wm": WM, "gm": GM, "csf": CSF},
        "shells": shells.tolist(),
        "noise_sigma": NOISE_SIGMA,
        "constraint_directions": np.round(default_sphere.vertices, 12).tolist(),
        "peaks": {"function": "peak_directions", "sphere": "default_sphere.subdivide(n=2)",
                  "relative_peak_threshold": RELATIVE_PEAK,
                  "min_separation_angle": MIN_SEPARATION},
        "mrtrix": None if mrtrix is None else {"command": mrtrix["command"],
                                               "version": mrtrix["version"]},
        "voxels": records,
    }
    voxel_lines = ",\n".join(json.dumps(r) for r in fixture.pop("voxels"))
    head = json.dumps(fixture, indent=1)[:-2]
    with open(f"{out_dir}/msmt-dipy.json", "w") as f:
        f.write(f'{head},\n "voxels": [\n{voxel_lines}\n]}}\n')
    clean = [r for r in records if r["wm_model"] == "band-8 fODF"]
    err = max(abs(r["dipy_fractions_csf_gm_wm"][1] - r["gm"]) for r in clean)
    gap = max(np.abs(np.array(r["dipy_csf_gm_wm"]) - r["tight_csf_gm_wm"]).max() for r in records)
    print(f"{len(records)} voxels; solver {solver}; GM fraction error on band-8 fODF voxels {err:.3g}; "
          f"DIPY's solve vs the tight solve: {gap:.3g}")


if __name__ == "__main__":
    main(sys.argv[1])
