#!/usr/bin/env python3
"""Tiles a 4D NIfTI-1 file (uncompressed .nii, single file) N x N times in x and y, and
optionally NZ times in z.

Used to make brain-slice-sized benchmark volumes from DIPY's small 10x10x10 test DWI
(docs/guide/performance.md):

    glyphcast fit --sh --order 8 --bval B --bvec V -o sh8.nii small_64D.nii
    python3 tools/tile_nifti.py sh8.nii tiled.nii 10
    python3 tools/tile_nifti.py fod.nii brain.nii 10 6    # 100 x 100 x 60 (`qc`'s cost)

Standard library only. The header is copied with its x and y dimensions multiplied; the
affine is kept, so the tiled volume extends the original's grid.
"""
import struct
import sys


def main() -> int:
    if len(sys.argv) not in (4, 5):
        print("usage: tile_nifti.py IN.nii OUT.nii N [NZ]", file=sys.stderr)
        return 2
    source, target, count = sys.argv[1], sys.argv[2], int(sys.argv[3])
    count_z = int(sys.argv[4]) if len(sys.argv) == 5 else 1
    data = open(source, "rb").read()
    if struct.unpack("<i", data[0:4])[0] != 348 or data[344:348] not in (b"n+1\0",):
        print(f"{source}: not a single-file little-endian NIfTI-1 (.nii)", file=sys.stderr)
        return 1
    dims = struct.unpack("<8h", data[40:56])
    bitpix = struct.unpack("<h", data[72:74])[0]
    offset = int(struct.unpack("<f", data[108:112])[0])
    nx, ny = dims[1], dims[2]
    nz = dims[3] if dims[0] >= 3 else 1
    if count_z > 1 and dims[0] < 3:
        print(f"{source}: no z axis to tile", file=sys.stderr)
        return 1
    rest = 1
    for d in dims[4 : dims[0] + 1]:
        rest *= d
    size = bitpix // 8
    body = data[offset : offset + nx * ny * nz * rest * size]
    row = nx * size
    out = bytearray()
    # Fortran order: x fastest, then y, then z, then every further axis.
    for c in range(rest):
        for _ in range(count_z):
            for z in range(nz):
                k = z + nz * c
                plane = body[k * ny * row : (k + 1) * ny * row]
                for _ in range(count):
                    for j in range(ny):
                        out += plane[j * row : (j + 1) * row] * count
    header = bytearray(data[:offset])
    tiled = [dims[0], nx * count, ny * count, *dims[3:8]]
    if dims[0] >= 3:
        tiled[3] = nz * count_z
    header[40:56] = struct.pack("<8h", *tiled)
    with open(target, "wb") as f:
        f.write(bytes(header) + bytes(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
