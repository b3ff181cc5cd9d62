#!/usr/bin/env python3
"""Fractional anisotropy (FA) and colour-FA maps from a DTI volume written by
`glyphcast fit --order 2` (a 4D float32 NIfTI-1 .nii or .nii.gz of xx, xy, xz, yy,
yz, zz per voxel), for `glyphcast render --underlay` (docs/guide/volumes.md, "Anatomical underlay"):

    python3 tools/fa_map.py dti.nii fa.nii [colour-fa.nii]

FA = sqrt(3/2) |D - tr(D)/3 I| / |D| (Frobenius norms: Basser and Pierpaoli 1996), 0
where the tensor is zero. Colour-FA is |e1| * FA per channel (x red, y green, z blue),
e1 the principal eigenvector, found by power iteration on D shifted to be positive
definite. The tensor volume's header (affine) is kept. Standard library only.
"""
import gzip
import math
import struct
import sys


def opener(path):
    """open() for a plain file, gzip.open() for a name ending in .gz."""
    return gzip.open if path.endswith(".gz") else open


def read(path):
    with opener(path)(path, "rb") as stream:
        data = stream.read()
    if struct.unpack("<i", data[0:4])[0] != 348 or data[344:348] != b"n+1\0":
        sys.exit(f"{path}: not a single-file little-endian NIfTI-1 (.nii, .nii.gz)")
    dims = struct.unpack("<8h", data[40:56])
    datatype = struct.unpack("<h", data[70:72])[0]
    if datatype != 16 or dims[0] != 4 or dims[4] != 6:
        sys.exit(f"{path}: expected float32 [x, y, z, 6] (glyphcast fit --order 2)")
    offset = int(struct.unpack("<f", data[108:112])[0])
    n = dims[1] * dims[2] * dims[3]
    values = struct.unpack(f"<{6 * n}f", data[offset : offset + 24 * n])
    return data[:348], dims[1:4], n, values


def write(path, header, shape, values):
    header = bytearray(header)
    dims = [len(shape)] + list(shape) + [1] * (7 - len(shape))
    header[40:56] = struct.pack("<8h", *dims)
    header[70:74] = struct.pack("<hh", 16, 32)
    header[108:112] = struct.pack("<f", 352.0)
    header[112:120] = struct.pack("<ff", 1.0, 0.0)
    with opener(path)(path, "wb") as out:
        out.write(bytes(header) + b"\0\0\0\0" + struct.pack(f"<{len(values)}f", *values))


def principal(d):
    xx, xy, xz, yy, yz, zz = d
    shift = abs(xx) + abs(yy) + abs(zz) + 2 * (abs(xy) + abs(xz) + abs(yz))
    m = [[xx + shift, xy, xz], [xy, yy + shift, yz], [xz, yz, zz + shift]]
    v = [1.0, 0.7, 0.3]
    for _ in range(60):
        w = [sum(m[r][c] * v[c] for c in range(3)) for r in range(3)]
        norm = math.sqrt(sum(x * x for x in w)) or 1.0
        v = [x / norm for x in w]
    return v


def main():
    if len(sys.argv) not in (3, 4):
        print(__doc__, file=sys.stderr)
        return 2
    header, (nx, ny, nz), n, values = read(sys.argv[1])
    fa, rgb = [0.0] * n, [0.0] * (3 * n)
    for voxel in range(n):
        # NIfTI order: x fastest; the 6 coefficients are the 4th axis, so n apart.
        d = [values[voxel + c * n] for c in range(6)]
        xx, xy, xz, yy, yz, zz = d
        norm2 = xx * xx + yy * yy + zz * zz + 2 * (xy * xy + xz * xz + yz * yz)
        if not norm2 > 0 or any(math.isnan(x) for x in d):
            continue
        mean = (xx + yy + zz) / 3
        dev2 = (xx - mean) ** 2 + (yy - mean) ** 2 + (zz - mean) ** 2
        dev2 += 2 * (xy * xy + xz * xz + yz * yz)
        fa[voxel] = min(1.0, math.sqrt(1.5 * dev2 / norm2))
        e = principal(d)
        for c in range(3):
            rgb[voxel + c * n] = abs(e[c]) * fa[voxel]
    write(sys.argv[2], header, (nx, ny, nz), fa)
    if len(sys.argv) == 4:
        write(sys.argv[3], header, (nx, ny, nz, 3), rgb)
    return 0


if __name__ == "__main__":
    sys.exit(main())
