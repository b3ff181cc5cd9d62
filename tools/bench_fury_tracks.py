"""The streamline comparison: glyphcast's exact tubes and its lines against FURY 2's line
drawing on the same streamlines, in alternating runs (run by tools/bench-fury.sh with a
tracks workload, which makes the virtual environment and picks the driver; see there).

The set is the one `glyphcast bench --workload tracks:COUNT:POINTS[:slab]` draws (and, as
lines, `...:lines`): glyphcast writes its streamlines (`--save-tracks`, an MRtrix .tck,
read here by nibabel) and its camera (`--save-scene`), and the same points and camera go
into FURY's scene:

- `line`: FURY's `actor.line` (pygfx's screen-space line: each segment a quad of the
  line's thickness in pixels, drawn flat), coloured per point by the local direction,
  |x|, |y|, |z| as glyphcast colours its tubes; thickness 1.6 pixels at 1920x1080, the
  width glyphcast's 0.2 mm radius tubes take on the screen in the 3D view
  (`--line-px` sets it);
- `streamtube`: FURY's `actor.streamtube` (tubes tessellated by a compute pass, 8 sides,
  flat end caps, Phong-lit), radius 0.2 mm as glyphcast's, the closest FURY has to
  glyphcast's exact tubes; one colour (its per-point colours take a CPU path); up to
  a million segments.

Timing as for the glyphs (tools/bench_fury.py): glyphcast's `bench` GPU median (Vulkan
timestamps) of --frames after --warmup, tubes and lines; FURY's wall-clock median of
whole offscreen frames (the render pass and the read-back that waits for the device),
pixel ratio 1, no
post-processing anti-aliasing; and FURY's frame without the streamlines (clear and
read-back), the ratios also given less that. Pairs alternate (glyphcast, FURY, ...) so
that a busy machine slows both.
"""

import argparse
import json
import os
import statistics
import time
from pathlib import Path

import numpy as np

from bench_fury import FuryFrame, glyphcast_bench, run, save_png, span

# FURY's background: black, as glyphcast's default.
BACKGROUND = (0, 0, 0)
# FURY's streamtube is timed up to this many segments: beyond, its tessellation (16
# triangles a segment) outgrows what lavapipe draws in a sensible time.
MAX_STREAMTUBE_SEGMENTS = 1_000_000


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--glyphcast", required=True, help="the glyphcast binary")
    p.add_argument("--out", required=True, type=Path, help="folder for the PNGs and tables")
    p.add_argument("--workload", default="tracks:1000:100",
                   help="tracks:COUNT:POINTS[:slab] (its lines: the same with :lines)")
    p.add_argument("--width", type=int, default=1920)
    p.add_argument("--height", type=int, default=1080)
    p.add_argument("--frames", type=int, default=5, help="measured frames a run")
    p.add_argument("--warmup", type=int, default=1, help="frames before them, not measured")
    p.add_argument("--pairs", type=int, default=3, help="alternating (glyphcast, FURY) pairs")
    p.add_argument("--line-px", type=float, default=1.6, help="FURY's line thickness, pixels")
    return p.parse_args()


def load_tracks(args):
    """The workload's streamlines (nibabel's reading of glyphcast's .tck) and camera."""
    import nibabel as nib

    scene_path, tck_path = args.out / "tracks.json", args.out / "tracks.tck"
    out = run([args.glyphcast, "bench", "--workload", args.workload, "--width", args.width,
               "--height", args.height, "--frames", 1, "--warmup", 0, "--save-scene",
               scene_path, "--save-tracks", tck_path])
    scene = json.loads(scene_path.read_text())
    lines = [np.asarray(s, dtype=np.float64) for s in nib.streamlines.load(tck_path).streamlines]
    device = next((l[len("Device: "):] for l in out.splitlines() if l.startswith("Device: ")),
                  "?")
    return scene, lines, device


def direction_colors(line):
    """|x|, |y|, |z| of the local direction at each point (the segment's after it; the
    last point the last segment's)."""
    d = np.diff(line, axis=0)
    d /= np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-12)
    return np.abs(np.vstack([d, d[-1:]]))


def fury_tracks(scene, lines, kind, width, height, line_px):
    """FURY 2's offscreen frame of the streamlines as `kind` (line or streamtube) with
    glyphcast's camera (bench_fury.FuryFrame), on black."""
    from fury import actor

    if kind == "line":
        colors = np.vstack([direction_colors(l) for l in lines])
        drawn = actor.line(lines, colors=colors)
        drawn.material.thickness = line_px
    else:
        drawn = actor.streamtube(lines, radius=0.2, segments=8, colors=(0.9, 0.6, 0.3))
    return FuryFrame(scene["camera"], drawn, width, height, depth_range=(100.0, 1000.0),
                     background=BACKGROUND)


def main():
    args = parse_args()
    if args.workload.endswith(":lines"):
        raise SystemExit("error: give the tubes' workload; its lines are timed beside it")
    args.out.mkdir(parents=True, exist_ok=True)
    import fury
    import pygfx
    import wgpu

    scene, lines, device = load_tracks(args)
    segments = sum(len(l) - 1 for l in lines)
    print(f"streamlines: {args.workload}, {len(lines)} streamlines (polylines drawn), "
          f"{segments} segments, {args.width}x{args.height}; glyphcast's device: {device}")
    frames = {}
    kinds = ["line"]
    if segments <= MAX_STREAMTUBE_SEGMENTS:
        kinds.append("streamtube")
    else:
        print(f"FURY streamtube: not timed (more than {MAX_STREAMTUBE_SEGMENTS} segments)")
    for kind in kinds:
        t0 = time.perf_counter()
        frames[kind] = fury_tracks(scene, lines, kind, args.width, args.height, args.line_px)
        print(f"FURY {kind}: made and first drawn in {time.perf_counter() - t0:.1f} s")
        save_png(args.out / f"fury-{kind}.png", frames[kind].draw())
    adapter = frames["line"].sm.renderer.device.adapter.info
    print(f"FURY {fury.__version__} (pygfx {pygfx.__version__}, wgpu {wgpu.__version__}); "
          f"adapter: {adapter.get('device')} ({adapter.get('description')}, "
          f"{adapter.get('backend_type')})")

    print(f"\n{args.pairs} alternating pairs, {args.frames} frames after {args.warmup} "
          f"warm-up each; {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print("| pair | glyphcast tubes (GPU median) | glyphcast lines | FURY line "
          "| FURY streamtube | FURY, nothing drawn | FURY line / glyphcast tubes "
          "| FURY line / glyphcast lines | (FURY line - nothing) / glyphcast lines "
          "| FURY streamtube / glyphcast tubes |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    rows = []
    for pair in range(1, args.pairs + 1):
        result = glyphcast_bench(args, args.workload)
        gc = result["gpu_ms_median"]
        gl = glyphcast_bench(args, args.workload + ":lines")["gpu_ms_median"]
        line = statistics.median(frames["line"].time(args.frames, args.warmup))
        tube = (statistics.median(frames["streamtube"].time(args.frames, args.warmup))
                if "streamtube" in frames else float("nan"))
        empty = statistics.median(frames["line"].time(args.frames, args.warmup, visible=False))
        rows.append({"pair": pair, "glyphcast_ms": gc, "glyphcast_lines_ms": gl,
                     "ratio_line_to_lines": line / gl,
                     "ratio_line_less_empty_to_lines": (line - empty) / gl,
                     "glyphcast_segments":
                     result["tube_segments"], "glyphcast_tube_bytes": result["tube_bytes"],
                     "fury_line_ms": line, "fury_streamtube_ms": tube,
                     "fury_nothing_ms": empty, "ratio_line": line / gc,
                     "ratio_streamtube": tube / gc, "ratio_line_less_empty": (line - empty) / gc})
        r = rows[-1]
        print(f"| {pair} | {gc:.1f} ms | {gl:.1f} ms | {line:.1f} ms | {tube:.1f} ms "
              f"| {empty:.1f} ms | {r['ratio_line']:.2f} | {r['ratio_line_to_lines']:.2f} "
              f"| {r['ratio_line_less_empty_to_lines']:.2f} | {r['ratio_streamtube']:.2f} |",
              flush=True)

    print(f"FURY {fury.__version__}'s line takes {span(rows, 'ratio_line_to_lines')} times "
          f"glyphcast's lines ({span(rows, 'ratio_line_less_empty_to_lines')} less FURY's empty "
          f"frame) and {span(rows, 'ratio_line')} times glyphcast's exact tubes; its streamtube "
          f"{span(rows, 'ratio_streamtube')} times the tubes")
    print("pictures: " + ", ".join(str(args.out / f"fury-{k}.png") for k in frames))
    (args.out / "results.json").write_text(json.dumps({
        "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "glyphcast_device": device, "fury": fury.__version__, "pygfx": pygfx.__version__,
        "wgpu": wgpu.__version__, "fury_adapter": adapter, "workload": args.workload,
        "streamlines": len(lines), "segments": segments, "size": [args.width, args.height],
        "frames": args.frames, "warmup": args.warmup, "line_px": args.line_px,
        "pairs": rows, "VK_DRIVER_FILES": os.environ.get("VK_DRIVER_FILES"),
    }, indent=2, default=str) + "\n")


if __name__ == "__main__":
    main()
