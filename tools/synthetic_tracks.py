"""Synthetic streamlines through a volume, for the figures of docs/guide/tracks.md:
usage `python tools/synthetic_tracks.py VOLUME.nii.gz OUT.tck`. Forty smooth curves
(arcs that bend and cross) through the volume's world box, in scanner millimetres,
written as an MRtrix .tck by nibabel."""
import sys

import nibabel as nib
import numpy as np
from nibabel.streamlines import Tractogram, save


def main(volume, out):
    image = nib.load(volume)
    shape = np.array(image.shape[:3])
    corners = np.array([[i, j, k] for i in (0, shape[0] - 1) for j in (0, shape[1] - 1)
                        for k in (0, shape[2] - 1)], dtype=float)
    world = nib.affines.apply_affine(image.affine, corners)
    low, high = world.min(axis=0), world.max(axis=0)
    centre, half = (low + high) / 2, (high - low) / 2
    rng = np.random.default_rng(7)
    lines = []
    s = np.linspace(-1.0, 1.0, 80)[:, None]
    for n in range(40):
        # A direction mostly along x, y or z in turn, bent by a quadratic term.
        axis = np.zeros(3)
        axis[n % 3] = 1.0
        direction = axis + 0.35 * rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        bend = 0.4 * rng.normal(size=3)
        start = centre + 0.6 * half * rng.uniform(-1, 1, size=3)
        points = start + 1.1 * s * half * direction + (s ** 2) * bend * half
        lines.append(points.astype(np.float32))
    save(Tractogram(lines, affine_to_rasmm=np.eye(4)), out)


if __name__ == "__main__":
    main(*sys.argv[1:3])
