"""The peer comparison of the README's performance section: glyphcast's exact frame against
FURY 2's `sph_glyph` on the same field, in alternating runs (run by tools/bench-fury.sh,
which makes the virtual environment and picks the driver; see there).

The field is the one `glyphcast bench --workload fodf:COUNT:BAND` draws: glyphcast writes
it out (`--save-scene --scene-arrays`: centres and tournier07 coefficients as float64
.npy), and the same coefficients, centres and camera go into FURY's scene:

- basis: FURY 2.0's `sph_glyph` evaluates the full real SH series (every l up to l_max,
  m = -l..l, index l^2 + l + m) with B_l^m = sqrt2 N P_l^|m| cos(m phi) for m > 0,
  sqrt2 N P_l^|m| sin(|m| phi) for m < 0 (P with the Condon-Shortley phase, from scipy's
  lpmv), N P_l^0 for m = 0, whatever `basis_type` says (that only picks how l_max follows
  from the coefficient count). That is glyphcast's tournier07 (non-legacy, MRtrix3's)
  function by function, so the coefficients are copied to their (l, m) slots and the odd
  bands are zero; `basis_check` compares the two bases at random directions;
- radius |f(u)| (FURY: abs, clamped to 1; glyphcast's scene: negative = abs), scale 1;
- FURY places voxel (i, j, k) of the (X, Y, Z, N) array at (i, j, k): the actor is moved
  by the first centre, and every centre is checked against that grid;
- camera: glyphcast's eye, target, up and vertical field of view (pygfx's fov is the
  vertical one for a landscape view with aspect 1), near/far planes fixed.

Timing. glyphcast: `glyphcast bench` (GPU median of --frames after --warmup, from Vulkan
timestamps). FURY: wall-clock median of --frames offscreen draws after --warmup, each a
whole frame as FURY's ShowManager draws it (the compute pass that places the mesh
vertices, the render pass, the read-back of the image, which is also what waits for the
device), at pixel ratio 1 (as many pixels as glyphcast: pygfx's default supersamples 2x2
on a screen of pixel ratio 1) and without post-processing anti-aliasing (ppaa "none",
one sample per pixel as glyphcast's frame). Also timed, in the same pair: the frame with
pygfx's default anti-aliasing (ppaa "ddaa", a post pass that costs about as much as the
glyphs on lavapipe) and the frame with the glyphs hidden (clear and read-back: the ratio
is also given less that). The pairs alternate (glyphcast, FURY, glyphcast, FURY, ...) so
that a busy machine slows both.

Coverage (on the timed frame, fury.png): glyphcast's is `glyphcast render --method exact
--background none --samples 1` (alpha > 0); FURY's, the pixels not at the background
colour (pure green, which no shaded glyph pixel can take: FURY's glyphs are red or blue,
lit with white). Counted: the pixels of glyphcast's coverage that FURY leaves empty, most
of them one-pixel slivers along the silhouettes (a tessellation lies inside the surface
it samples); the holes, those of them inside glyphcast's coverage (the pixel and its 8
neighbours all glyphcast's), as pixels and as connected regions; the pinholes, empty
pixels that FURY's own coverage encloses; and the pixels FURY covers that glyphcast
leaves empty (a few when the shapes and camera agree).
"""

import argparse
import json
import math
import os
import re
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

BACKGROUND = (0, 255, 0)
# pygfx's default post-processing anti-aliasing (Renderer(ppaa="default")).
DEFAULT_PPAA = "ddaa"


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--glyphcast", required=True, help="the glyphcast binary")
    p.add_argument("--out", required=True, type=Path, help="folder for the PNGs and tables")
    p.add_argument("--workload", default="fodf:256:8")
    p.add_argument("--width", type=int, default=1280)
    p.add_argument("--height", type=int, default=720)
    p.add_argument("--frames", type=int, default=20, help="measured frames a run")
    p.add_argument("--warmup", type=int, default=3, help="frames before them, not measured")
    p.add_argument("--pairs", type=int, default=3, help="alternating (glyphcast, FURY) pairs")
    p.add_argument("--sphere", default="symmetric362", help="FURY's sphere (its default)")
    return p.parse_args()


def run(cmd, **kw):
    """Runs a command, echoing it; its output returned (stderr included)."""
    print("$ " + " ".join(str(c) for c in cmd), flush=True)
    res = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, **kw)
    if res.returncode != 0:
        sys.stderr.write(res.stdout + res.stderr)
        raise SystemExit(f"error: {cmd[0]} exited with {res.returncode}")
    return res.stdout + res.stderr


# --- the field -----------------------------------------------------------------------


def load_field(args):
    """glyphcast's workload as its scene file and arrays (written by `bench --save-scene`)."""
    scene_path = args.out / "field.json"
    out = run([args.glyphcast, "bench", "--workload", args.workload,
               "--width", args.width, "--height", args.height, "--frames", 1,
               "--warmup", 0, "--save-scene", scene_path, "--scene-arrays"])
    device = re.search(r"^device: (.*)$", out, re.M)
    scene = json.loads(scene_path.read_text())
    (glyphs,) = scene["glyphs"]
    want = {"kind": "sh", "basis": "tournier07", "legacy": False, "negative": "abs"}
    for key, value in want.items():
        if glyphs.get(key) != value:
            raise SystemExit(f"error: the field's {key} is {glyphs.get(key)!r}, not {value!r}")
    if glyphs["scale"] != 1.0:
        raise SystemExit(f"error: the field's glyph scale is {glyphs['scale']}, not 1")
    centers = np.load(scene_path.parent / glyphs["centers"])
    coeffs = np.load(scene_path.parent / glyphs["coeffs"])
    return scene, glyphs["order"], centers, coeffs, device.group(1) if device else "?"


def tournier07_to_fury(coeffs, band):
    """(n, count of even bands) tournier07 coefficients -> (n, (band+1)^2) FURY's."""
    out = np.zeros((coeffs.shape[0], (band + 1) ** 2))
    src = 0
    for l in range(0, band + 1, 2):
        for m in range(-l, l + 1):
            out[:, l * l + l + m] = coeffs[:, src]
            src += 1
    assert src == coeffs.shape[1], (src, coeffs.shape)
    return out


def tournier07_values(band, u):
    """glyphcast's tournier07 basis (even bands, index l(l+1)/2 + m) at unit vectors u,
    written out independently of FURY and scipy: factor * Q_l^|m|(z) * Re/Im (x+iy)^|m|
    with the fully normalised Legendre recurrences (Condon-Shortley phase inside Q)."""
    x, y, z = u[:, 0], u[:, 1], u[:, 2]
    q = {}
    q[0, 0] = np.full_like(z, 1 / math.sqrt(4 * math.pi))
    for m in range(1, band + 1):
        q[m, m] = -math.sqrt((2 * m + 1) / (2 * m)) * q[m - 1, m - 1]
    for m in range(0, band):
        q[m + 1, m] = math.sqrt(2 * m + 3) * z * q[m, m]
        for l in range(m + 2, band + 1):
            a = math.sqrt((4 * l * l - 1) / (l * l - m * m))
            b = math.sqrt(((l - 1) ** 2 - m * m) / (4 * (l - 1) ** 2 - 1))
            q[l, m] = a * (z * q[l - 1, m] - b * q[l - 2, m])
    power = [(np.ones_like(x), np.zeros_like(x))]
    for _ in range(band):
        re, im = power[-1]
        power.append((re * x - im * y, re * y + im * x))
    cols = []
    for l in range(0, band + 1, 2):
        for m in range(-l, l + 1):
            re, im = power[abs(m)]
            if m == 0:
                cols.append(q[l, 0])
            elif m > 0:
                cols.append(math.sqrt(2) * q[l, m] * re)
            else:
                cols.append(math.sqrt(2) * q[l, -m] * im)
    return np.stack(cols, axis=1)


def basis_check(band):
    """The largest difference, over 2000 random directions, between FURY's basis matrix
    and glyphcast's tournier07 through `tournier07_to_fury`."""
    from fury.utils import create_sh_basis_matrix

    rng = np.random.default_rng(7)
    u = rng.normal(size=(2000, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    ours = tournier07_values(band, u)  # (2000, 45)
    fury = create_sh_basis_matrix(u, band).astype(np.float64)  # (2000, 81)
    # Each even-band function in FURY's slot; each odd-band column of FURY's left out.
    embed = tournier07_to_fury(np.eye(ours.shape[1]), band)  # (45, 81)
    diff = np.abs(ours @ embed - fury * (embed.sum(axis=0) > 0)).max()
    return float(diff)


def grid_of(centers, coeffs):
    """FURY's (X, Y, 1, N) array: glyph k at voxel (i, j) with centre = first + (i, j)."""
    origin = centers.min(axis=0)
    ij = np.rint(centers - origin).astype(int)
    if np.abs(centers - origin - ij).max() > 1e-9 or np.any(ij[:, 2] != 0):
        raise SystemExit("error: the glyph centres are not a unit grid in the z = 0 plane")
    nx, ny = ij[:, 0].max() + 1, ij[:, 1].max() + 1
    grid = np.zeros((nx, ny, 1, coeffs.shape[1]), dtype=np.float32)
    grid[ij[:, 0], ij[:, 1], 0] = coeffs
    return grid, origin


# --- FURY's scene ---------------------------------------------------------------------


class FuryFrame:
    """FURY 2's offscreen ShowManager drawing `actor` with glyphcast's camera `cam` (a
    scene file's camera: perspective or orthographic), pixel ratio 1."""

    def __init__(self, cam, actor, width, height, depth_range=(1.0, 200.0),
                 background=BACKGROUND):
        import pygfx as gfx
        from fury import window

        self.actor = actor
        self.scene = window.Scene(background=tuple(c / 255 for c in background) + (1.0,))
        self.scene.add(actor)
        if cam["projection"] == "perspective":
            # pygfx's fov is the vertical one for a landscape view given aspect 1 (the
            # viewport's aspect then widens it).
            camera = gfx.PerspectiveCamera(cam["fov_y_deg"], 1.0, depth_range=depth_range)
        else:
            h = cam["height"]
            camera = gfx.OrthographicCamera(h * width / height, h, maintain_aspect=True,
                                            depth_range=depth_range)
        camera.add(gfx.DirectionalLight())  # as FURY does for a camera of its own
        self.scene.add(camera)
        self.sm = window.ShowManager(scene=self.scene, camera=camera, size=(width, height),
                                     window_type="offscreen", pixel_ratio=1)
        # ShowManager frames the scene (show_object) when it makes the screen and again
        # at every resize event (the first draw sends one), and gives the camera a
        # trackball controller: the controller lets go of the camera, and glyphcast's
        # camera goes on after a first draw, checked to stay through the next.
        for screen in self.sm.screens:
            screen.controller.enabled = False
            screen.controller.remove_camera(camera)
        self.camera, self.cam, self.depth_range = camera, cam, depth_range
        self.sm.render()
        self.draw()
        self.place_camera()
        self.draw()
        if not np.allclose(camera.world.position, cam["eye"], atol=1e-9):
            raise SystemExit("error: FURY moved the camera: " + str(camera.world.position))

    def place_camera(self):
        cam, camera = self.cam, self.camera
        camera.local.position = tuple(cam["eye"])
        camera.world.reference_up = tuple(cam["up"])
        camera.look_at(tuple(cam["target"]))
        if cam["projection"] == "perspective":
            camera.fov = cam["fov_y_deg"]
        camera.depth_range = self.depth_range

    def draw(self, ppaa="none"):
        """One whole frame; the image (H, W, 4 uint8)."""
        self.sm.renderer.ppaa = ppaa
        return np.asarray(self.sm.window.draw())

    def time(self, frames, warmup, visible=True, ppaa="none"):
        """Wall-clock ms of `frames` whole frames after `warmup`, the actor shown or not."""
        self.actor.visible = visible
        self.sm.renderer.ppaa = ppaa
        for _ in range(warmup):
            self.draw()
        ms = []
        for _ in range(frames):
            t0 = time.perf_counter()
            self.draw()
            ms.append(1e3 * (time.perf_counter() - t0))
        self.actor.visible = True
        return ms


# --- glyphcast -----------------------------------------------------------------------


def glyphcast_bench(args, workload):
    """`glyphcast bench` on `workload` at the comparison's size and frames: its result
    row from results.json (GPU ms median, min and max, tube segments and bytes, ...)."""
    folder = args.out / "glyphcast-bench"
    folder.mkdir(exist_ok=True)
    run([args.glyphcast, "bench", "--workload", workload, "--width", args.width,
         "--height", args.height, "--frames", args.frames, "--warmup", args.warmup,
         "--out", folder])
    (result,) = json.loads((folder / "results.json").read_text())["results"]
    return result


def span(rows, key):
    """"LOW to HIGH" of `key` over the pairs' rows."""
    values = [r[key] for r in rows]
    return f"{min(values):.2f} to {max(values):.2f}"


# --- pictures and holes --------------------------------------------------------------


def save_png(path, rgba):
    from PIL import Image

    Image.fromarray(np.ascontiguousarray(rgba)).save(path)


def holes(args, fury_rgba):
    """FURY's frame against glyphcast's exact coverage, pixel by pixel (see the top)."""
    from PIL import Image
    from scipy import ndimage

    mask_png = args.out / "glyphcast-coverage.png"
    run([args.glyphcast, "render", args.out / "field.json", "-o", mask_png, "--method",
         "exact", "--background", "none", "--samples", 1, "--width", args.width,
         "--height", args.height])
    exact = np.asarray(Image.open(mask_png).convert("RGBA"))[..., 3] > 0
    fury = np.any(fury_rgba[..., :3] != np.array(BACKGROUND, dtype=np.uint8), axis=-1)
    missed = exact & ~fury
    # Inside: the pixel and its 8 neighbours are all glyphcast's.
    inside = ndimage.binary_erosion(exact, structure=np.ones((3, 3), dtype=bool))
    hole = inside & ~fury
    pinhole = ndimage.binary_fill_holes(fury) & ~fury
    extra = fury & ~exact
    # A picture: glyphcast's coverage grey, missed edge pixels orange, holes red, FURY's
    # own pixels outside glyphcast's blue.
    pic = np.full(exact.shape + (3,), 255, dtype=np.uint8)
    pic[exact] = (170, 170, 170)
    pic[missed] = (255, 160, 0)
    pic[hole] = (220, 0, 0)
    pic[extra] = (0, 60, 255)
    save_png(args.out / "holes.png", pic)
    return {"exact_pixels": int(exact.sum()), "fury_pixels": int(fury.sum()),
            "missed_pixels": int(missed.sum()), "hole_pixels": int(hole.sum()),
            "hole_regions": int(ndimage.label(hole)[1]),
            "pinhole_pixels": int(pinhole.sum()),
            "pinhole_regions": int(ndimage.label(pinhole)[1]),
            "extra_pixels": int(extra.sum())}


def main():
    args = parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    import fury
    import pygfx
    import wgpu

    scene, band, centers, coeffs, device = load_field(args)
    print(f"field: {args.workload}, {len(centers)} glyphs, band {band} tournier07, "
          f"{args.width}x{args.height}; glyphcast's device: {device}")
    diff = basis_check(band)
    print(f"basis: FURY's sph_glyph basis against glyphcast's tournier07, max |difference| "
          f"over 2000 directions: {diff:.2e}")
    if diff > 1e-5:
        raise SystemExit("error: FURY's basis is not tournier07 in this FURY")
    grid, origin = grid_of(centers, tournier07_to_fury(coeffs, band))
    from fury import actor

    glyphs = actor.sph_glyph(grid, sphere=args.sphere)
    glyphs.local.position = tuple(float(v) for v in origin)
    frame = FuryFrame(scene["camera"], glyphs, args.width, args.height)
    adapter = frame.sm.renderer.device.adapter.info
    print(f"FURY {fury.__version__} (pygfx {pygfx.__version__}, wgpu {wgpu.__version__}), "
          f"sph_glyph sphere {args.sphere} ({glyphs.vertices_per_glyph} vertices, "
          f"{glyphs.faces_per_glyph} faces a glyph), basis 'standard', "
          f"{grid.shape[-1]} coefficients a glyph; adapter: {adapter.get('device')} "
          f"({adapter.get('description')}, {adapter.get('backend_type')})")

    image = frame.draw()
    save_png(args.out / "fury.png", image)
    save_png(args.out / "fury-ddaa.png", frame.draw(ppaa=DEFAULT_PPAA))
    run([args.glyphcast, "render", args.out / "field.json", "-o", args.out / "glyphcast.png",
         "--method", "exact", "--width", args.width, "--height", args.height])
    h = holes(args, image)
    print(f"coverage: glyphcast's exact {h['exact_pixels']} pixels, FURY's "
          f"{h['fury_pixels']}; FURY leaves {h['missed_pixels']} of glyphcast's empty, "
          f"{h['hole_pixels']} of them inside ({h['hole_regions']} holes: pixels whose 3x3 "
          f"neighbourhood is all glyphcast's); pinholes (empty pixels FURY's own coverage "
          f"encloses): {h['pinhole_pixels']} pixels in {h['pinhole_regions']} regions; "
          f"FURY only: {h['extra_pixels']} pixels")

    print(f"\n{args.pairs} alternating pairs, {args.frames} frames after {args.warmup} "
          f"warm-up each; {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print("| pair | glyphcast exact (GPU median) | FURY | FURY, ddaa | FURY, no glyphs "
          "| FURY / glyphcast | ddaa: FURY / glyphcast | (FURY - no glyphs) / glyphcast |")
    print("|---|---|---|---|---|---|---|---|")
    rows = []
    for pair in range(1, args.pairs + 1):
        result = glyphcast_bench(args, args.workload)
        gc = result["gpu_ms_median"], result["gpu_ms_min"], result["gpu_ms_max"]
        fu = statistics.median(frame.time(args.frames, args.warmup))
        dd = statistics.median(frame.time(args.frames, args.warmup, ppaa=DEFAULT_PPAA))
        empty = statistics.median(frame.time(args.frames, args.warmup, visible=False))
        rows.append({"pair": pair, "glyphcast_ms": gc[0], "glyphcast_min_ms": gc[1],
                     "glyphcast_max_ms": gc[2], "fury_ms": fu, "fury_ddaa_ms": dd,
                     "fury_no_glyphs_ms": empty, "ratio": fu / gc[0],
                     "ratio_ddaa": dd / gc[0], "ratio_less_empty": (fu - empty) / gc[0]})
        r = rows[-1]
        print(f"| {pair} | {gc[0]:.1f} ms | {fu:.1f} ms | {dd:.1f} ms | {empty:.1f} ms "
              f"| {r['ratio']:.2f} | {r['ratio_ddaa']:.2f} | {r['ratio_less_empty']:.2f} |",
              flush=True)
    print(f"glyphcast's exact frame is {span(rows, 'ratio')} times faster than FURY "
          f"{fury.__version__}'s sph_glyph ({span(rows, 'ratio_less_empty')} less FURY's frame "
          f"without glyphs; {span(rows, 'ratio_ddaa')} against FURY with pygfx's default "
          f"anti-aliasing, ddaa)")
    print("pictures: " + ", ".join(str(args.out / name) for name in
                                   ("glyphcast.png", "fury.png", "fury-ddaa.png", "holes.png")))
    (args.out / "results.json").write_text(json.dumps({
        "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "glyphcast_device": device, "fury": fury.__version__, "pygfx": pygfx.__version__,
        "wgpu": wgpu.__version__, "fury_adapter": adapter, "sphere": args.sphere,
        "workload": args.workload, "size": [args.width, args.height],
        "frames": args.frames, "warmup": args.warmup, "holes": h, "pairs": rows,
        "VK_DRIVER_FILES": os.environ.get("VK_DRIVER_FILES"),
    }, indent=2, default=str) + "\n")


if __name__ == "__main__":
    main()
