#!/usr/bin/env python3
"""Two glyphcast binaries side by side: the first image and the frame, interleaved.

    python3 tools/compare-builds.py --before OLD --after NEW [--runs 7] [--frames 20]

- First image: whole `glyphcast render` processes with Mesa's shader cache off
  (MESA_SHADER_CACHE_DISABLE=true) and glyphcast's pipeline cache off, so every run
  creates its pipelines from the SPIR-V: the demo scene (orders 4, 6 and 8), the
  256-glyph band-8 peer field and the same field at band 12 (the largest shader). Wall
  and CPU (user + system, from wait4) medians; the two binaries alternate, the one that
  goes first changing every run.
- The frame: `glyphcast bench` of the peer field at 1280x720, GPU median per frame,
  three alternating rounds.

Prints one Markdown table with the ratios after / before. A report, not a test: on a
shared machine compare ratios, never absolute times.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time


def run(cmd, env=None):
    """Wall seconds and CPU seconds (user + system) of one whole process."""
    # stderr goes to a file: a pipe read only after the wait would stall a chatty child.
    with tempfile.TemporaryFile() as log:
        started = time.monotonic()
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=log, env=env)
        _, status, usage = os.wait4(proc.pid, 0)
        wall = time.monotonic() - started
        log.seek(0)
        err = log.read().decode(errors="replace")
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"error: {' '.join(cmd)} failed:\n{err}")
    return wall, usage.ru_utime + usage.ru_stime


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", required=True, help="the glyphcast binary before")
    parser.add_argument("--after", required=True, help="the glyphcast binary after")
    parser.add_argument("--runs", type=int, default=7, help="first-image runs of each")
    parser.add_argument("--frames", type=int, default=20, help="bench frames per round")
    args = parser.parse_args()
    bins = {"before": os.path.abspath(args.before), "after": os.path.abspath(args.after)}
    for label, path in bins.items():
        if not os.access(path, os.X_OK):
            sys.exit(f"error: --{label} {path}: not an executable file")
    work = tempfile.mkdtemp(prefix="glyphcast-compare-")
    scenes = {
        "demo scene (orders 4, 6, 8; 800x600)": os.path.join(work, "demo.json"),
        "256 band-8 glyphs, 1280x720": os.path.join(work, "peer8.json"),
        "256 band-12 glyphs, 1280x720": os.path.join(work, "peer12.json"),
    }
    paths = list(scenes.values())
    before = bins["before"]
    run([before, "demo", "--save-scene", paths[0], "-o", os.path.join(work, "demo.png")])
    for band, path in ((8, paths[1]), (12, paths[2])):
        run([before, "bench", "--workload", f"fodf:256:{band}", "--width", "1280",
             "--height", "720", "--frames", "1", "--warmup", "0", "--save-scene", path])
    env = dict(os.environ, MESA_SHADER_CACHE_DISABLE="true", GLYPHCAST_PIPELINE_CACHE="0")
    first = {(s, b): [] for s in scenes for b in bins}
    for i in range(args.runs):
        order = list(bins) if i % 2 == 0 else list(reversed(bins))
        for scene, path in scenes.items():
            for label in order:
                out = os.path.join(work, f"{label}.png")
                first[(scene, label)].append(run([bins[label], "render", path, "-o", out], env))
    frame = {b: [] for b in bins}
    for i in range(3):
        order = list(bins) if i % 2 == 0 else list(reversed(bins))
        for label in order:
            out = os.path.join(work, f"bench-{label}-{i}")
            os.makedirs(out)
            run([bins[label], "bench", "--workload", "fodf:256:8", "--width", "1280",
                 "--height", "720", "--frames", str(args.frames), "--out", out])
            with open(os.path.join(out, "results.json")) as f:
                results = json.load(f)["results"]
            frame[label].append(results[0]["gpu_ms_median"])
    print("| what | before | after | after / before |")
    print("|---|---|---|---|")
    for scene in scenes:
        for what, index in (("wall", 0), ("CPU", 1)):
            b = statistics.median(t[index] for t in first[(scene, "before")])
            a = statistics.median(t[index] for t in first[(scene, "after")])
            print(f"| first image, {scene}, {what} (median of {args.runs}) "
                  f"| {b * 1000:.0f} ms | {a * 1000:.0f} ms | {a / b:.2f} |")
    for i in range(3):
        b, a = frame["before"][i], frame["after"][i]
        print(f"| frame of 256 band-8 glyphs, GPU median, round {i + 1} "
              f"| {b:.1f} ms | {a:.1f} ms | {a / b:.2f} |")


if __name__ == "__main__":
    main()
