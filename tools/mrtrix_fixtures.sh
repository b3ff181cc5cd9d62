#!/usr/bin/env bash
# MRtrix3 reference outputs of `dwi2fod csd` on DIPY's small_64D, for tests/csd_mrtrix.rs.
#
# Run by hand where MRtrix3 is installed (CI never runs it; the tests read what it
# writes into tests/data/mrtrix/, whose README records the MRtrix version):
#
#     bash tools/mrtrix_fixtures.sh
#
# Two inputs are made once and then kept, so that a rerun reproduces the same outputs:
# the response (dwi2response tournier, lmax 8) and a set of 300 constraint directions
# (dirgen, whose start is random). Delete them to make new ones.
set -euo pipefail

# Relative paths from the repository root, so that the command history MRtrix writes into
# each header is the same on every run and every machine: the outputs are byte for byte
# reproducible.
cd "$(dirname "$0")/.."
data=tests/data/dipy
out=tests/data/mrtrix
tmp=tests/data/mrtrix-work
mkdir -p "$out"
rm -rf "$tmp"
mkdir "$tmp"
trap 'rm -rf "$tmp"' EXIT

# The DWI with its gradient table in scanner coordinates, read from FSL's bvecs as
# glyphcast's default --bvec-convention fsl reads them.
mrconvert -quiet "$data/small_64D.nii" -fslgrad "$data/small_64D.bvec" "$data/small_64D.bval" \
    "$tmp/dwi.mif"

if [ ! -f "$out/response.txt" ]; then
    dwi2response tournier -quiet "$tmp/dwi.mif" "$out/response.txt" -lmax 8 \
        -number 30 -iter_voxels 100 -scratch "$tmp"
fi
if [ ! -f "$out/dirs300.txt" ]; then
    # [azimuth elevation] in radians, the format dwi2fod -directions reads.
    dirgen -quiet 300 "$out/dirs300.txt"
fi

# CSD with the committed directions: what glyphcast must reproduce exactly.
dwi2fod -quiet csd "$tmp/dwi.mif" "$out/response.txt" "$out/fod_dirs300.mif" -lmax 8 \
    -directions "$out/dirs300.txt" -force
sh2peaks -quiet "$out/fod_dirs300.mif" "$out/peaks_dirs300.mif" -force

# CSD with dwi2fod's built-in 300 directions: what glyphcast's own set comes close to.
dwi2fod -quiet csd "$tmp/dwi.mif" "$out/response.txt" "$tmp/fod_builtin.mif" -lmax 8
sh2peaks -quiet "$tmp/fod_builtin.mif" "$out/peaks_builtin.mif" -force

dwi2fod -version | head -n 1
