"""The notebook view in a real browser: JupyterLab on a free port, headless Chromium
driven by Selenium, the kernel on lavapipe with the validation layer on (conftest.py).

A notebook with a view of a small SH volume is run with JupyterLab's own command; the
frame Chromium shows must equal a fresh Renderer's render of the same slice. A drag
across the view must change the frame to a fresh render from the view's new camera
(read from the kernel), pixel for pixel (the settled frame is a PNG). The notebook is
then saved from JupyterLab and opened by a server that can start no kernel: the cell
shows the last view, the saved PNG, equal to that render, and nothing of the widget (no
"Loading widget..."). In a JupyterLab 1000 pixels wide with its file browser open, and
at 800, the controls fit the cell: no horizontal overflow, a slice slider wider than 100
pixels, no dropdown's text cut.

Skipped where chromium, chromedriver, selenium or JupyterLab are missing, except in CI
(CI=true or 1), where they are installed (tools/install-deps.sh, tools/test.sh) and their
absence fails the test.
"""
import base64
import json
import os
import time

import nbformat
import numpy as np
import pytest

import notebook_browser as nb

reason = nb.missing()
if reason is not None:
    if os.environ.get("CI") in ("true", "1"):
        pytest.fail(f"CI must run the browser test: {reason}", pytrace=False)
    pytest.skip(reason, allow_module_level=True)

import glyphcast  # noqa: E402

WIDTH, HEIGHT = 360, 270

SETUP = """\
import numpy as np
import glyphcast

rng = np.random.default_rng(7)
coeffs = rng.normal(0.0, 0.12, (8, 8, 3, 45))
coeffs[..., 0] = 1.0
"""
SHOW = f"""\
view = glyphcast.show_sh(coeffs, basis="tournier07", slice="axial:1",
                         width={WIDTH}, height={HEIGHT})
view
"""


def coefficients():
    rng = np.random.default_rng(7)
    coeffs = rng.normal(0.0, 0.12, (8, 8, 3, 45))
    coeffs[..., 0] = 1.0
    return coeffs


def fresh_render(camera=None):
    """What glyphcast itself draws for the view's input, from ``camera``."""
    renderer = glyphcast.Renderer()
    first = renderer.render_sh(coefficients(), basis="tournier07", slice="axial:1",
                               width=WIDTH, height=HEIGHT)
    return first if camera is None else renderer.render(camera)


@pytest.fixture
def folder(tmp_path):
    notebook = nbformat.v4.new_notebook()
    notebook.cells = [nbformat.v4.new_code_cell(SETUP), nbformat.v4.new_code_cell(SHOW)]
    notebook.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                       "language": "python"}
    nbformat.write(notebook, tmp_path / "view.ipynb")
    return tmp_path


@pytest.mark.parametrize("frontend", ["lab", "notebook"])
def test_drag_orbits_to_glyphcasts_render_and_the_saved_notebook_keeps_it(folder, frontend):
    started = time.monotonic()
    server = nb.Server(str(folder), frontend=frontend)
    try:
        with nb.chromium() as driver:
            nb.open_notebook(driver, server, "view.ipynb")
            nb.wait_for(lambda: nb.kernel_idle(driver), 90, "the kernel")
            nb.command(driver, "notebook:run-all-cells")
            nb.wait_for(lambda: driver.find_elements("css selector", nb.VIEW_IMAGE), 120,
                        "the view")
            before = nb.settled_frame(driver)
            expected = fresh_render().rgba[..., :3]
            assert before.shape == (HEIGHT, WIDTH, 3)
            assert np.array_equal(before, expected), "the first frame is not glyphcast's"

            kernel = server.kernel()
            home = nb.kernel_value(kernel, "view.camera")
            drag(driver)
            after = nb.settled_frame(driver)
            camera = nb.kernel_value(kernel, "view.camera")
            assert camera != home, "the drag did not move the camera"
            assert np.mean(np.any(after != before, axis=-1)) > 0.05, "the frame did not change"
            expected = fresh_render(camera).rgba[..., :3]
            differing = np.any(after != expected, axis=-1)
            assert not differing.any(), (
                f"{differing.sum()} pixels differ from glyphcast's render for {camera}")
            stats = nb.kernel_value(kernel, "view.stats()")
            # Every frame sent was shown (one in flight at most: max_buffered_frames).
            assert stats["sent_frames"] >= 2 and stats["latency"], stats
            assert stats["confirmed_frames"] == stats["sent_frames"], stats
            driver.save_screenshot(str(folder / "browser.png"))
            kernel.stop_channels()

            # The static copy follows the last frame half a second after it; then save.
            time.sleep(1.0)
            nb.command(driver, "docmanager:save")
        saved = last_still(folder / "view.ipynb")
        assert np.array_equal(saved, after), "the saved PNG is not the last view"
    finally:
        server.stop()

    # A reader without a kernel: the saved notebook shows the last view.
    reader = nb.Server(str(folder), kernels=False, frontend=frontend)
    try:
        with nb.chromium() as driver:
            nb.open_notebook(driver, reader, "view.ipynb")
            still = ".jp-OutputArea-child img"
            nb.wait_for(lambda: [e for e in driver.find_elements("css selector", still)
                                 if e.is_displayed() and e.size["width"] > 0], 60,
                        "the saved picture")
            time.sleep(1.0)
            assert reader.api("sessions") == [] and reader.api("kernels") == []
            kind, raw = nb.shown_image(driver, still)
            assert kind == "image/png"
            assert np.array_equal(nb.decode(raw), after)
            assert widget_texts(driver) == [], "the saved notebook shows the widget's place"
            driver.save_screenshot(str(folder / "reopened.png"))
    finally:
        reader.stop()
    keep = os.environ.get("GLYPHCAST_BROWSER_SCREENSHOTS")
    if keep:
        os.makedirs(keep, exist_ok=True)
        for name in ("browser.png", "reopened.png"):
            os.replace(folder / name, os.path.join(keep, f"{frontend}-{name}"))
    assert time.monotonic() - started < 180


@pytest.mark.parametrize("frontend", ["lab", "notebook"])
def test_the_controls_fit_a_narrow_cell(folder, frontend):
    """1000 pixels wide, JupyterLab's file browser open (the cell is about 600 wide),
    then 800: the controls wrap; none overflows the cell or is cut."""
    server = nb.Server(str(folder), frontend=frontend)
    try:
        with nb.chromium(width=1000, height=900) as driver:
            nb.open_notebook(driver, server, "view.ipynb")
            if frontend == "lab":
                driver.execute_script("window.jupyterapp.shell.activateById('filebrowser')")
            nb.wait_for(lambda: nb.kernel_idle(driver), 90, "the kernel")
            nb.command(driver, "notebook:run-all-cells")
            nb.wait_for(lambda: driver.find_elements("css selector", nb.VIEW_IMAGE), 120,
                        "the view")
            nb.settled_frame(driver)
            for width in (1000, 800):
                driver.set_window_size(width, 900)
                time.sleep(1.0)
                layout = controls_layout(driver)
                if frontend == "lab":
                    assert layout["sidebar"] > 150, layout  # the file browser is open
                assert layout["box"]["scroll"] <= layout["box"]["client"] + 1, layout
                assert layout["box"]["right"] <= layout["cell"] + 1, layout
                assert layout["page"]["scroll"] <= layout["page"]["client"] + 1, layout
                assert all(right <= layout["box"]["right"] + 1
                           for right in layout["children"]), layout
                assert layout["slider"] > 100, layout
                for select in layout["selects"]:
                    assert select["need"] <= select["have"], layout
                for label in layout["labels"]:
                    assert label["scroll"] <= label["client"], layout
                if width == 1000:
                    driver.save_screenshot(str(folder / "controls-1000.png"))
    finally:
        server.stop()
    keep = os.environ.get("GLYPHCAST_BROWSER_SCREENSHOTS")
    if keep:
        os.makedirs(keep, exist_ok=True)
        os.replace(folder / "controls-1000.png",
                   os.path.join(keep, f"{frontend}-controls-1000.png"))


# The controls' geometry: the box's scroll and client widths and right edge, the right
# edges of its children and of the cell's output, the slider track's width, each
# dropdown's room and the width its chosen text needs (the canvas's measure in the
# select's font, and its padding, which holds the arrow), each label's widths, and the
# notebook's own horizontal scroll.
LAYOUT = """
const box = document.querySelector('.glyphcast-controls');
const cell = box.closest('.jp-OutputArea-output').getBoundingClientRect();
const context = document.createElement('canvas').getContext('2d');
const selects = [...box.querySelectorAll('select')].map(s => {
    const style = getComputedStyle(s);
    context.font = `${style.fontStyle} ${style.fontWeight} ${style.fontSize} ${style.fontFamily}`;
    const text = s.options[s.selectedIndex].text;
    return {text, have: s.clientWidth, need: Math.ceil(context.measureText(text).width
        + parseFloat(style.paddingLeft) + parseFloat(style.paddingRight))};
});
const page = document.querySelector('.jp-WindowedPanel-outer, .jp-Notebook');
const sidebar = document.querySelector('#jp-left-stack');
return {
    box: {scroll: box.scrollWidth, client: box.clientWidth,
          right: box.getBoundingClientRect().right},
    cell: cell.right,
    children: [...box.children].map(c => c.getBoundingClientRect().right),
    slider: box.querySelector('.widget-slider .slider').getBoundingClientRect().width,
    selects,
    labels: [...box.querySelectorAll('.widget-label')].map(l => (
        {text: l.textContent, scroll: l.scrollWidth, client: l.clientWidth})),
    page: {scroll: page.scrollWidth, client: page.clientWidth},
    sidebar: sidebar ? sidebar.getBoundingClientRect().width : 0,
};
"""


def controls_layout(driver):
    return driver.execute_script(LAYOUT)


def widget_texts(driver):
    """The visible outputs that say a widget is loading or missing."""
    return driver.execute_script(
        "return [...document.querySelectorAll('.jp-OutputArea-output')]"
        ".filter(e => e.offsetParent !== null && e.getClientRects().length"
        " && /Loading widget|Error displaying widget/.test(e.textContent))"
        ".map(e => e.textContent)")


def drag(driver):
    """A drag across the view: pointer down, twelve moves to the right and up, up."""
    from selenium.webdriver.common.action_chains import ActionChains

    view = driver.find_element("css selector", nb.VIEW_IMAGE)
    actions = ActionChains(driver, duration=30)
    actions.move_to_element(view).click_and_hold()
    for _ in range(12):
        actions.move_by_offset(8, -3)
    actions.release().perform()


def last_still(path):
    """The PNG the saved notebook keeps after the view: the view's cell's last image."""
    notebook = json.loads(path.read_text())
    cell = notebook["cells"][1]
    kinds = [list(o.get("data", {})) for o in cell["outputs"]]
    widget = [i for i, k in enumerate(kinds) if "application/vnd.jupyter.widget-view+json" in k]
    images = [i for i, k in enumerate(kinds) if "image/png" in k]
    assert widget and images and images[-1] > widget[-1], kinds
    raw = base64.b64decode(cell["outputs"][images[-1]]["data"]["image/png"])
    return nb.decode(raw)
