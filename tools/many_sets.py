#!/usr/bin/env python3
"""Writes a scene of N one-glyph sets (random order-4 tensors on a grid), the case of
issue 11's "many small glyph sets": python3 tools/many_sets.py N OUT.json [--one-set]
(--one-set writes the same glyphs as a single set, to compare). Standard library only."""
import json
import random
import sys


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(args) != 2:
        sys.exit(__doc__)
    count, out = int(args[0]), args[1]
    side = max(1, int(count ** 0.5))
    rng = random.Random(1)
    centers, coeffs = [], []
    for i in range(count):
        centers.append([i % side - side / 2, i // side - side / 2, 0])
        c = [rng.uniform(-1, 1) for _ in range(15)]
        c[0] = abs(c[0]) + 1
        coeffs.append(c)
    def glyph_set(cs, ks):
        return {"kind": "tensor", "order": 4, "centers": cs, "scale": 0.4, "coeffs": ks}
    if "--one-set" in sys.argv:
        sets = [glyph_set(centers, coeffs)]
    else:
        sets = [glyph_set([c], [k]) for c, k in zip(centers, coeffs)]
    scene = {
        "version": 1,
        "glyphs": sets,
        "camera": {"eye": [0, 0, 1.4 * side], "target": [0, 0, 0], "up": [0, 1, 0], "fov_y_deg": 45},
        "image": {"width": 640, "height": 640},
    }
    with open(out, "w") as f:
        json.dump(scene, f)


if __name__ == "__main__":
    main()
