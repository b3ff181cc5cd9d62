#!/usr/bin/env python3
"""Frames per second and input-to-frame latency of the notebook view while orbiting,
in a real browser (docs/guide/notebook.md).

    python tools/bench_notebook.py [SECONDS] [--width W --height H --size N --lmax L]
                                   [--draft SCALE]

Starts JupyterLab on a free port in a temporary folder with a notebook that shows a
view of an N x N slice of band-L SH glyphs (random coefficients, fixed seed; default
64 x 64, band 8) at W x H (default 800 x 600), opens it in headless Chromium (Selenium
and chromium-driver), runs it, then drags across the view back and forth for SECONDS
(default 10; the frames drawn meanwhile are drafts at SCALE times the size, default 0.5,
and 1 draws them all at full size) and reads the view's statistics from the kernel: frames sent, frames the
browser showed and the rate of those, and the latency of each input that moved the
camera, from its arrival at the kernel to the browser's showing the frame that answers
it. Run it with the Python of an environment holding glyphcast (a release build for
the numbers users get: `pip install ./python`), jupyterlab, jupyter_rfb, selenium and
pillow; the Vulkan driver is the loader's (GLYPHCAST_LAVAPIPE=1 with tools/env.sh picks
lavapipe).
"""
import argparse
import os
import statistics
import sys
import tempfile
import time

import nbformat

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "python", "tests"))
import notebook_browser as nb  # noqa: E402

CELL = """\
import numpy as np
import glyphcast

rng = np.random.default_rng(1)
coeffs = rng.normal(0.0, 0.1, ({n}, {n}, 1, {k}))
coeffs[..., 0] = 1.0
view = glyphcast.show_sh(coeffs, basis="tournier07", width={width}, height={height},
                         draft={draft})
view
"""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("seconds", nargs="?", type=float, default=10.0)
    parser.add_argument("--width", type=int, default=800)
    parser.add_argument("--height", type=int, default=600)
    parser.add_argument("--size", type=int, default=64)
    parser.add_argument("--lmax", type=int, default=8)
    parser.add_argument("--draft", type=float, default=0.5,
                        help="the scale of the frames drawn while the view moves "
                             "(the view's `draft`; 1: every frame at full size)")
    args = parser.parse_args()
    reason = nb.missing()
    if reason:
        print(reason, file=sys.stderr)
        return 2
    k = (args.lmax + 1) * (args.lmax + 2) // 2
    with tempfile.TemporaryDirectory() as folder:
        notebook = nbformat.v4.new_notebook()
        notebook.cells = [nbformat.v4.new_code_cell(CELL.format(
            n=args.size, k=k, width=args.width, height=args.height, draft=args.draft))]
        notebook.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3"}
        nbformat.write(notebook, os.path.join(folder, "bench.ipynb"))
        server = nb.Server(folder)
        try:
            with nb.chromium() as driver:
                nb.open_notebook(driver, server, "bench.ipynb")
                nb.wait_for(lambda: nb.kernel_idle(driver), 90, "the kernel")
                nb.command(driver, "notebook:run-all-cells")
                nb.wait_for(lambda: driver.find_elements("css selector", nb.VIEW_IMAGE),
                            300, "the view")
                nb.settled_frame(driver, timeout=300)
                kernel = server.kernel()
                device = nb.kernel_value(kernel, "view._renderer.device")
                glyphs = nb.kernel_value(kernel, "view._renderer.glyph_count")
                nb.run_in_kernel(kernel, "view.reset_stats()")
                started = time.monotonic()
                orbit(driver, args.seconds)
                dragged = time.monotonic() - started
                time.sleep(1.0)
                stats = nb.kernel_value(kernel, "view.stats()")
                kernel.stop_channels()
        finally:
            server.stop()
    latency = sorted(stats["latency"])
    shown = stats["confirmed_frames"]
    print(f"device: {device}")
    print(f"{glyphs} glyphs (a {args.size}x{args.size} slice, band {args.lmax}) at "
          f"{args.width}x{args.height}, drafts at {args.draft:g} times the size, "
          f"dragging for {dragged:.1f} s")
    print(f"frames sent {stats['sent_frames']}, shown {shown}: "
          f"{shown / dragged:.1f} frames per second over the drag "
          f"(jupyter_rfb's fps: {stats['fps']:.1f})")
    if latency:
        p90 = latency[min(len(latency) - 1, int(0.9 * len(latency)))]
        print(f"input to frame: median {statistics.median(latency) * 1000:.0f} ms, "
              f"90th percentile {p90 * 1000:.0f} ms, max {latency[-1] * 1000:.0f} ms "
              f"over {len(latency)} answered inputs")
    if stats["render"]:
        print(f"drawing a frame: median {statistics.median(stats['render']) * 1000:.0f} ms")
    print(f"JPEG/PNG encoding per frame: {stats['img_encoding'] * 1000:.1f} ms")
    return 0


def orbit(driver, seconds):
    """Drags across the view, back and forth, for about ``seconds``: moves of 6 pixels
    of 20 ms each (jupyter_rfb forwards one move per 20 ms), the button held throughout,
    in one chain of actions (chromedriver performs it at its own pace)."""
    from selenium.webdriver.common.action_chains import ActionChains

    view = driver.find_element("css selector", nb.VIEW_IMAGE)
    actions = ActionChains(driver, duration=20)
    actions.move_to_element(view).click_and_hold()
    for step in range(int(seconds / 0.02)):
        direction = 1 if (step // 25) % 2 == 0 else -1
        actions.move_by_offset(6 * direction, 2 * direction)
    actions.release().perform()


if __name__ == "__main__":
    sys.exit(main())
