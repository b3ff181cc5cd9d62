#!/usr/bin/env python3
"""Times one slice of an SH volume rendered through the Python module against the same
slice through `glyphcast render` (docs/guide/performance.md).

    python tools/bench_python_slice.py GLYPHCAST_BIN VOLUME.nii [RUNS]

Run it with the Python of a virtual environment holding a release build of the module
(`pip install ./python`) and give a release build of the CLI. Both render the middle
axial slice at 1920x1080 with basis tournier07; the module's time covers reading the
file with nibabel as well as rendering (a fresh device per call, as the CLI opens one),
and the depth maps are checked to be identical. Prints the median and range of each.
"""
import os
import statistics
import subprocess
import sys
import tempfile
import time

import nibabel as nib
import numpy as np

import glyphcast


def main() -> int:
    if len(sys.argv) not in (3, 4):
        print(__doc__, file=sys.stderr)
        return 2
    binary, volume = sys.argv[1], sys.argv[2]
    runs = int(sys.argv[3]) if len(sys.argv) == 4 else 5
    size = ["--width", "1920", "--height", "1080"]
    with tempfile.TemporaryDirectory() as out:
        depth_file = os.path.join(out, "depth.npy")
        cli_times = []
        for _ in range(runs):
            started = time.perf_counter()
            subprocess.run(
                [binary, "render", "--sh", volume, "--basis", "tournier07", *size,
                 "-o", os.path.join(out, "slice.png"), "--depth-out", depth_file],
                check=True, capture_output=True,
            )
            cli_times.append(time.perf_counter() - started)
        cli_depth = np.load(depth_file)
    py_times = []
    for _ in range(runs):
        started = time.perf_counter()
        image = nib.load(volume)
        out = glyphcast.render_sh(image.get_fdata(), image.affine, basis="tournier07",
                                  width=1920, height=1080)
        py_times.append(time.perf_counter() - started)
    assert np.array_equal(out.depth, cli_depth, equal_nan=True), "depth maps differ"
    glyphs = np.isfinite(cli_depth).sum()
    for name, times in [("CLI (whole process)", cli_times), ("Python render_sh", py_times)]:
        print(f"{name}: median {statistics.median(times):.2f} s "
              f"(range {min(times):.2f} to {max(times):.2f} s over {runs} runs)")
    print(f"identical depth maps ({glyphs} pixels hit)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
