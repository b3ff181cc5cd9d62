"""Streamlines DIPY tracks through its own CSD fit of small_64D, saved by DIPY as a
TrackVis .trk: the tractogram of the streamlines figures (tools/figures_tracks.sh), so
that the tubes are what a DIPY user tracks through the very fODFs drawn under them.

    python tools/dipy_tracks.py DATA_DIR OUT.trk

DATA_DIR holds small_64D.nii, .bval and .bvec (tests/data/dipy). As DIPY's tracking
tutorial does it: the response by auto_response_ssst, CSD of order 8, deterministic
tracking along the fODF's maximum (DeterministicMaximumDirectionGetter, 30 degrees at
most a step), stopped where FA falls below 0.1, seeded at 2x2x2 points in every voxel
of FA above 0.3, steps of 0.5 mm; kept if 5 mm or longer. Written with save_trk in
RASMM with small_64D.nii as reference, so the points are scanner millimetres (the .trk
header holds the image's affine) as glyphcast places the fit's glyphs.
"""

import sys

import numpy as np
from dipy.data import default_sphere
from dipy.direction import DeterministicMaximumDirectionGetter
from dipy.io.stateful_tractogram import Space, StatefulTractogram
from dipy.io.streamline import save_trk
from dipy.reconst.csdeconv import ConstrainedSphericalDeconvModel, auto_response_ssst
from dipy.reconst.dti import TensorModel, fractional_anisotropy
from dipy.tracking import utils
from dipy.tracking.local_tracking import LocalTracking
from dipy.tracking.stopping_criterion import ThresholdStoppingCriterion
from dipy.tracking.streamline import Streamlines, length

from dipy_fixtures import load_small_64d


def main(data_dir, out_path):
    image, data, gtab = load_small_64d(data_dir)

    fa = np.nan_to_num(fractional_anisotropy(TensorModel(gtab).fit(data).evals))
    response, _ = auto_response_ssst(gtab, data, roi_radii=10, fa_thr=0.7)
    csd = ConstrainedSphericalDeconvModel(gtab, response, sh_order_max=8).fit(data)
    getter = DeterministicMaximumDirectionGetter.from_shcoeff(
        csd.shm_coeff, max_angle=30.0, sphere=default_sphere
    )
    stopping = ThresholdStoppingCriterion(fa, 0.1)
    seeds = utils.seeds_from_mask(fa > 0.3, image.affine, density=2)
    tracked = LocalTracking(getter, stopping, seeds, image.affine, step_size=0.5)
    streamlines = Streamlines(s for s in tracked if length(s) >= 5.0)
    tractogram = StatefulTractogram(streamlines, image, Space.RASMM)
    save_trk(tractogram, out_path, bbox_valid_check=True)
    points = np.concatenate(list(streamlines)) if len(streamlines) else np.zeros((0, 3))
    print(f"{out_path}: {len(streamlines)} streamlines, {len(points)} points, "
          f"{len(seeds)} seeds in {int((fa > 0.3).sum())} voxels of FA > 0.3")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
