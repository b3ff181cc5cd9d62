#!/usr/bin/env python3
"""Tractogram fixtures for crates/glyphcast-dmri/tests/tracks.rs: files other tools wrote,
and the points those tools' own readers give, in RAS+ millimetres.

Run by hand (CI never runs it; the tests read what it writes):

    python3 -m venv target/py-venv
    target/py-venv/bin/pip install numpy nibabel dipy trx-python
    target/py-venv/bin/python tools/tracks_fixtures.py tests/data/tracks

Into the folder it writes:
- tracks300.trk, EuDX_small_25.trk: DIPY's bundled TrackVis files, copied.
- complex_big_endian.trk (big-endian, per-point scalars and per-streamline properties)
  and standard.LPS.trk (voxel order LPS): nibabel's test files, copied.
- tracks30_oblique.trk: the same thirty streamlines written by nibabel's TrkFile
  with a vox_to_ras that permutes, flips, scales and rotates the axes.
- tracks30.tck: every tenth streamline of tracks300.trk as nibabel read it, written by
  nibabel's TckFile (MRtrix's conventions: float32 little-endian, NaN and Inf triplets).
- tracks30.trx (float32 positions, uint32 offsets, stored) and
  tracks30_f16.trx (float16 positions, uint64 offsets, deflated): the same streamlines
  written by trx-python, each point with its distance along the streamline (dpv/along).
- for each NAME: NAME.points.npy (every point, float32, shape (N, 3)) and NAME.json
  (where each streamline starts, the reader and its version, per-point values), as
  nibabel (.trk, .tck) or trx-python (.trx) read the file, in RAS+ millimetres.
"""
import json
import os
import shutil
import sys
import zipfile

import dipy
import nibabel as nib
import numpy as np
import trx
import trx.trx_file_memmap as tmm
from importlib.metadata import version

EVERY = 10


def write_reference(out_dir, name, points, offsets, reader, point_values=None):
    points = np.asarray(points, dtype=np.float32).reshape(-1, 3)
    np.save(os.path.join(out_dir, f"{name}.points.npy"), np.ascontiguousarray(points, "<f4"))
    record = {
        "file": name,
        "reader": reader,
        "streamlines": len(offsets),
        "points": int(points.shape[0]),
        "offsets": [int(o) for o in offsets],
        "point_values": {
            key: np.asarray(values, dtype=np.float64).reshape(points.shape[0], -1).round(7).tolist()
            for key, values in (point_values or {}).items()
        },
    }
    with open(os.path.join(out_dir, f"{name}.json"), "w") as f:
        json.dump(record, f, indent=0)
        f.write("\n")


def nibabel_reference(out_dir, name):
    loaded = nib.streamlines.load(os.path.join(out_dir, name))
    streamlines = loaded.streamlines
    offsets = streamlines._offsets[: len(streamlines)]
    values = {key: seq.get_data() for key, seq in loaded.tractogram.data_per_point.items()}
    write_reference(
        out_dir, name, streamlines.get_data(), offsets, f"nibabel {nib.__version__}", values
    )
    return loaded


def trx_reference(out_dir, name):
    loaded = tmm.load(os.path.join(out_dir, name))
    streamlines = loaded.streamlines
    offsets = streamlines._offsets[: len(streamlines)]
    values = {key: seq._data for key, seq in loaded.data_per_vertex.items()}
    write_reference(
        out_dir, name, streamlines._data, offsets, f"trx-python {version('trx-python')}", values
    )
    loaded.close()


def main(out_dir):
    os.makedirs(out_dir, exist_ok=True)
    dipy_files = os.path.join(os.path.dirname(dipy.__file__), "data", "files")
    nibabel_files = os.path.join(os.path.dirname(nib.__file__), "tests", "data")
    for folder, name in [
        (dipy_files, "tracks300.trk"),
        (dipy_files, "EuDX_small_25.trk"),
        (nibabel_files, "complex_big_endian.trk"),
        (nibabel_files, "standard.LPS.trk"),
    ]:
        shutil.copyfile(os.path.join(folder, name), os.path.join(out_dir, name))
        nibabel_reference(out_dir, name)

    # The same streamlines in the formats other tools write: every tenth of tracks300.
    source = nib.streamlines.load(os.path.join(out_dir, "tracks300.trk"))
    subset = source.streamlines[::EVERY].copy()  # compact: trx-python writes the view's whole buffer
    tractogram = nib.streamlines.Tractogram(subset, affine_to_rasmm=np.eye(4))
    nib.streamlines.save(tractogram, os.path.join(out_dir, "tracks30.tck"))
    nibabel_reference(out_dir, "tracks30.tck")

    # A TrackVis file whose vox_to_ras permutes, flips and scales the axes (2, 1.5 and
    # 3 mm voxels, rotated 10 degrees about one), written by nibabel's TrkFile: its points
    # on file are voxel millimetres of that grid.
    angle = np.deg2rad(10.0)
    rotation = np.array(
        [[0, -np.cos(angle), np.sin(angle)], [1, 0, 0], [0, np.sin(angle), np.cos(angle)]]
    )
    oblique = np.eye(4)
    oblique[:3, :3] = rotation @ np.diag([2.0, 1.5, 3.0])
    oblique[:3, 3] = [-40.0, 12.5, -7.0]
    header = {
        nib.streamlines.Field.VOXEL_TO_RASMM: oblique.astype(np.float32),
        nib.streamlines.Field.VOXEL_SIZES: np.array([2.0, 1.5, 3.0], np.float32),
        nib.streamlines.Field.DIMENSIONS: np.array([60, 80, 40], np.int16),
        nib.streamlines.Field.VOXEL_ORDER: "".join(nib.aff2axcodes(oblique)),
    }
    nib.streamlines.TrkFile(tractogram, header=header).save(
        os.path.join(out_dir, "tracks30_oblique.trk")
    )
    nibabel_reference(out_dir, "tracks30_oblique.trk")

    # A per-point scalar: each point's distance along its streamline from the first.
    along = [
        np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(s, axis=0), axis=1))])
        .astype(np.float32)
        for s in subset
    ]
    reference_trk = os.path.join(out_dir, "tracks300.trk")
    for name, dtypes, compression in [
        ("tracks30.trx", (np.float32, np.uint32), zipfile.ZIP_STORED),
        ("tracks30_f16.trx", (np.float16, np.uint64), zipfile.ZIP_DEFLATED),
    ]:
        with_values = nib.streamlines.Tractogram(
            subset, data_per_point={"along": along}, affine_to_rasmm=np.eye(4)
        )
        trx_file = tmm.TrxFile.from_tractogram(
            with_values,
            reference=reference_trk,
            dtype_dict={
                "positions": dtypes[0],
                "offsets": dtypes[1],
                "dpv": {"along": np.float32},
                "dps": {},
            },
        )
        tmm.save(trx_file, os.path.join(out_dir, name), compression_standard=compression)
        trx_file.close()
        trx_reference(out_dir, name)
    print("written:", sorted(os.listdir(out_dir)), "trx-python", trx.__file__)


if __name__ == "__main__":
    main(sys.argv[1])
