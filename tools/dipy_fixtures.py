#!/usr/bin/env python3
"""Reference outputs of DIPY's ODF models on small_64D, for tests/odf.rs.

Run once by hand (CI never runs it; the tests read the JSON it writes):

    python3 -m venv /work/venv-dipy && /work/venv-dipy/bin/pip install dipy
    /work/venv-dipy/bin/python tools/dipy_fixtures.py tests/data/dipy tests/data/dipy/odf-dipy.json

The b-vectors are used as stored (DIPY's frame: the voxel axes), so the Rust side must
read them with the library's FitInputs (no --bvec-convention transform). The model
parameters are written into the fixture next to the numbers.
"""
import json
import sys

import dipy
import nibabel as nib
import numpy as np
from dipy.core.gradients import gradient_table
from dipy.data import default_sphere
from dipy.direction import peak_directions
from dipy.reconst.csdeconv import ConstrainedSphericalDeconvModel, auto_response_ssst
from dipy.reconst.dti import TensorModel, fractional_anisotropy
from dipy.reconst.shm import CsaOdfModel, QballModel

ODF_ORDER = 6
CSD_ORDER = 8
SMOOTH = 0.006
CSD_LAMBDA = 1.0
CSD_TAU = 0.1
FA_RESPONSE = 0.7
ROI_RADIUS = 10
RELATIVE_PEAK = 0.5
MIN_SEPARATION = 25.0
FA_TEST = 0.6
EXTRA_VOXELS = 10
HIGH_VOXELS = 30


def load_small_64d(data_dir):
    """small_64D's image, its data as float64 and its gradient table, as DIPY reads them
    (b-vectors as stored, NaN read as 0)."""
    image = nib.load(f"{data_dir}/small_64D.nii")
    data = np.asarray(image.dataobj, dtype=np.float64)
    bvals = np.loadtxt(f"{data_dir}/small_64D.bval")
    bvecs = np.loadtxt(f"{data_dir}/small_64D.bvec")
    if bvecs.shape[0] == 3:
        bvecs = bvecs.T
    return image, data, gradient_table(bvals, bvecs=np.nan_to_num(bvecs))


def main(data_dir, out_path):
    image, data, gtab = load_small_64d(data_dir)

    tensor = TensorModel(gtab).fit(data)
    fa = np.nan_to_num(fractional_anisotropy(tensor.evals))
    positive = np.all(data > 0, axis=-1)
    high_pool = np.argwhere((fa > FA_TEST) & positive)
    rng = np.random.default_rng(14)
    high = high_pool[np.sort(rng.choice(len(high_pool), size=HIGH_VOXELS, replace=False))]
    low_pool = np.argwhere((fa <= FA_TEST) & (fa > 0.05) & positive)
    low = low_pool[np.sort(rng.choice(len(low_pool), size=EXTRA_VOXELS, replace=False))]
    voxels = np.concatenate([high, low])

    csa = CsaOdfModel(gtab, ODF_ORDER, smooth=SMOOTH).fit(data).shm_coeff
    qball = QballModel(gtab, ODF_ORDER, smooth=SMOOTH).fit(data).shm_coeff
    response, ratio = auto_response_ssst(
        gtab, data, roi_radii=ROI_RADIUS, fa_thr=FA_RESPONSE
    )
    csd_model = ConstrainedSphericalDeconvModel(
        gtab, response, sh_order_max=CSD_ORDER, lambda_=CSD_LAMBDA, tau=CSD_TAU
    )
    # DIPY's peaks are sphere vertices (no refinement): a subdivided default sphere keeps
    # their discretisation (about 1 degree) well below the 5 degrees the test allows.
    peak_sphere = default_sphere.subdivide(n=2)
    records = []
    for v in voxels:
        x, y, z = (int(i) for i in v)
        csd_fit = csd_model.fit(data[x, y, z])
        odf = csd_fit.odf(peak_sphere)
        dirs, values, _ = peak_directions(
            odf,
            peak_sphere,
            relative_peak_threshold=RELATIVE_PEAK,
            min_separation_angle=MIN_SEPARATION,
        )
        records.append(
            {
                "voxel": [x, y, z],
                "fa": float(fa[x, y, z]),
                "dti_principal": tensor.evecs[x, y, z][:, 0].tolist(),
                "csa": csa[x, y, z].tolist(),
                "qball": qball[x, y, z].tolist(),
                "csd": csd_fit.shm_coeff.tolist(),
                "csd_peak_directions": dirs[:3].tolist(),
                "csd_peak_values": values[:3].tolist(),
            }
        )
    fixture = {
        "source": "tools/dipy_fixtures.py on tests/data/dipy/small_64D (b-vectors as stored)",
        "dipy_version": dipy.__version__,
        "numpy_version": np.__version__,
        "basis": "descoteaux07 legacy (DIPY default, legacy=True)",
        "csa": {"model": "CsaOdfModel", "sh_order_max": ODF_ORDER, "smooth": SMOOTH,
                "min_signal": 1e-5},
        "qball": {"model": "QballModel", "sh_order_max": ODF_ORDER, "smooth": SMOOTH,
                  "min_signal": 1e-5},
        "csd": {"model": "ConstrainedSphericalDeconvModel", "sh_order_max": CSD_ORDER,
                "lambda_": CSD_LAMBDA, "tau": CSD_TAU, "reg_sphere": "small_sphere (symmetric362)",
                "response": "auto_response_ssst(roi_radii=10, fa_thr=0.7)",
                "response_evals": response[0].tolist(), "response_s0": float(response[1]),
                # The response as the model uses it: sqrt(4 pi/(2l+1)) r_l per even l.
                "response_rh": [float(csd_model.R[i, i]) for i in np.unique(
                    [int(l * (l - 1) / 2) for l in range(0, CSD_ORDER + 1, 2)])],
                "constraint_directions": np.round(csd_model.sphere.vertices, 12).tolist()},
        "peaks": {"function": "peak_directions", "sphere": "default_sphere.subdivide(n=2)",
                  "sphere_vertices": int(len(peak_sphere.vertices)),
                  "relative_peak_threshold": RELATIVE_PEAK,
                  "min_separation_angle": MIN_SEPARATION},
        "dti": {"model": "TensorModel (WLS)", "fa_threshold_of_the_test": FA_TEST},
        "voxels": records,
    }
    # One voxel a line: small, and diffs stay readable.
    voxel_lines = ",\n".join(json.dumps(r) for r in fixture.pop("voxels"))
    head = json.dumps(fixture, indent=1)[:-2]
    with open(out_path, "w") as f:
        f.write(f'{head},\n "voxels": [\n{voxel_lines}\n]}}\n')
    angles = [
        np.degrees(np.arccos(min(1.0, abs(np.dot(r["csd_peak_directions"][0], r["dti_principal"])))))
        for r in records if r["fa"] > FA_TEST
    ]
    print(f"{len(high_pool)} voxels with FA > {FA_TEST}, {len(records)} stored; response {response}; "
          f"median CSD-DTI angle {np.median(angles):.2f} deg")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
