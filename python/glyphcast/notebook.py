"""An interactive glyph view for Jupyter: orbit, zoom, pan and slice in a notebook.

The glyphs are drawn on the kernel's machine by a kept :class:`glyphcast.Renderer` (any
Vulkan device, Mesa's lavapipe included) and the frames are sent to the browser through
jupyter_rfb's remote frame buffer (``pip install glyphcast[notebook]``):

- drag to orbit, the wheel to zoom, shift-drag (or the right or middle button) to pan,
  double-click or ``r`` to reset the camera;
- the slice: the controls above the view, or the keys ``PageUp``/``PageDown`` (or the
  up and down arrows) for its index and ``a``, ``c``, ``s`` for its plane;
- the method, the colour mode and the negative lobes: the controls above the view.

A frame is drawn only when something changed, and jupyter_rfb sends a new one only when
the browser has shown the last (``max_buffered_frames``, 1 here). While the view moves
(a drag, the wheel) the frames are drafts, drawn at ``draft`` times the size (0.5) and
scaled up by the browser; the full size follows when the input stops. Frames in motion
travel as JPEG (``quality``), and the last one again as a lossless PNG.

A view is one widget output, a box of its controls, the frame buffer and the box of its
messages, followed by a copy of the last frame, a PNG that a saved notebook shows without
a kernel (hidden while the live view is on the page). The box's plain text is empty and
the saved copy hides the widget's placeholder, so that a notebook opened without a kernel
or exported by nbconvert shows the picture and nothing else of the view. The controls
wrap onto more rows in a narrow cell (a JupyterLab with its side panel open).
"""
import asyncio
import base64
import math
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from ._calls import at_the_call

try:
    import ipywidgets
    from IPython.display import display
    from IPython.utils.capture import capture_output
    from jupyter_rfb import RemoteFrameBuffer
    from jupyter_rfb.widget import CSS as _RFB_CSS
except ImportError as error:
    # Without the extra the first missing module is IPython (ipywidgets' and
    # jupyter_rfb's own dependency): name the extra, not that module. No chained
    # traceback: the message says all of it.
    kind = ModuleNotFoundError if isinstance(error, ModuleNotFoundError) else ImportError
    raise kind(
        "glyphcast's notebook view (show_sh, show_tensor, show_scene) needs the "
        f"notebook extra, which is not installed ({error}): "
        "pip install glyphcast[notebook] (from a wheel: pip install "
        "'glyphcast-VERSION.whl[notebook]'; or pip install jupyter_rfb ipywidgets)",
        name=error.name,
    ) from None

from . import Renderer, Rendering

__all__ = ["GlyphView", "show_sh", "show_tensor", "show_scene"]

PLANES = ("axial", "coronal", "sagittal")
METHODS = ("exact", "affine", "interval", "fixed", "impostor", "mesh:3")
COLORS = ("direction", "magnitude", "uniform", "sign")
NEGATIVE = ("abs", "hide")
# The controls' entry for an option left to its default.
_DEFAULT = "default"

WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"

# While a live view is on the page, the static copy of its last frame (the PNG output
# after it and the saved style's, for readers without a kernel) is hidden; JupyterLab
# and Notebook 7.
_CSS = _RFB_CSS + """
.jp-OutputArea-child:has(.renderview-wrapper) + .jp-OutputArea-child:has(style.glyphcast-saved)
    + .jp-OutputArea-child:has(img) {
    display: none;
}
"""

# Saved with the copy (the style of an HTML output: no widget code is loaded without a
# kernel): in an output area that holds a glyphcast view's copy, an output that is text
# without elements, JupyterLab's "Loading widget..." or "Error displaying widget" where a
# widget never rendered, is hidden, and so is an empty text output (the view's widget in
# nbconvert's HTML) and this style's own output. A live widget has elements, a text
# output its <pre>, a picture its <img>: they stay. JupyterLab, Notebook 7 and
# nbconvert's HTML share these classes. One rule a selector: a selector a browser
# refuses (:has inside :has is one) drops its whole rule.
_SAVED_CSS = """<style class="glyphcast-saved">
.jp-OutputArea:has(.glyphcast-saved) .jp-OutputArea-output:not(:has(*)) {
    display: none;
}
.jp-OutputArea:has(.glyphcast-saved) .jp-OutputArea-child:has(> .jp-OutputArea-output > pre:empty) {
    display: none;
}
.jp-OutputArea-child:has(style.glyphcast-saved) {
    display: none;
}
</style>"""

# Radians of orbit per pixel of drag, as a fraction of the view's height: a drag across
# the whole height turns the view by half a turn.
_ORBIT_PER_HEIGHT = math.pi
# The wheel: the distance to the target (or an orthographic view's height) scales by
# exp(delta * _ZOOM_PER_DELTA); a notch of a mouse wheel is about 100.
_ZOOM_PER_DELTA = 0.002
# Seconds without a new frame before the static copy of the view is written.
_STILL_DELAY = 0.5
# Seconds without an input before a moving view (the wheel) is drawn at its full size.
_FINAL_DELAY = 0.25


def _vector(value):
    return np.asarray(value, dtype=np.float64)


def _rotate(vector, axis, angle):
    """``vector`` turned by ``angle`` radians about the unit ``axis`` (Rodrigues)."""
    c, s = math.cos(angle), math.sin(angle)
    return vector * c + np.cross(axis, vector) * s + axis * np.dot(axis, vector) * (1 - c)


def _frame(camera):
    """The camera's forward, right and corrected up, as docs/scene-format.md defines."""
    eye, target = _vector(camera["eye"]), _vector(camera["target"])
    fwd = target - eye
    fwd /= np.linalg.norm(fwd)
    right = np.cross(fwd, _vector(camera.get("up", (0, 0, 1))))
    right /= np.linalg.norm(right)
    return fwd, right, np.cross(right, fwd)


def orbit(camera, dx, dy, height):
    """``camera`` turned about its target by a drag of (dx, dy) pixels in a view
    ``height`` pixels high: right turns the scene to the right, down tilts it towards
    the viewer."""
    eye, target = _vector(camera["eye"]), _vector(camera["target"])
    _, right, up = _frame(camera)
    offset = eye - target
    yaw = -dx / height * _ORBIT_PER_HEIGHT
    pitch = -dy / height * _ORBIT_PER_HEIGHT
    offset, up = _rotate(offset, up, yaw), up
    right = _rotate(right, up, yaw)
    offset, up = _rotate(offset, right, pitch), _rotate(up, right, pitch)
    return dict(camera, eye=(target + offset).tolist(), up=up.tolist())


def zoom(camera, delta):
    """``camera`` moved towards its target (``delta`` < 0) or away from it (> 0)."""
    factor = math.exp(delta * _ZOOM_PER_DELTA)
    if camera.get("projection") == "orthographic":
        return dict(camera, height=camera["height"] * factor)
    eye, target = _vector(camera["eye"]), _vector(camera["target"])
    return dict(camera, eye=(target + (eye - target) * factor).tolist())


def pan(camera, dx, dy, height):
    """``camera`` and its target shifted so that the scene follows a drag of (dx, dy)
    pixels in a view ``height`` pixels high (at the target's depth)."""
    eye, target = _vector(camera["eye"]), _vector(camera["target"])
    _, right, up = _frame(camera)
    if camera.get("projection") == "orthographic":
        world_height = camera["height"]
    else:
        fov = math.radians(camera.get("fov_y_deg", 30.0))
        world_height = 2 * np.linalg.norm(eye - target) * math.tan(fov / 2)
    shift = (-dx * right + dy * up) * (world_height / height)
    return dict(camera, eye=(eye + shift).tolist(), target=(target + shift).tolist())


class GlyphView(RemoteFrameBuffer):
    """A live view of glyphs in a notebook: a slice of an SH or tensor volume, or a
    scene. Make one with :func:`show_sh`, :func:`show_tensor` or :func:`show_scene`
    (their arguments are those of :func:`glyphcast.render_sh`, ``render_tensor`` and
    ``render_scene``); a cell whose last line is the view shows it.

    ``camera`` is the view's camera (a dict like a scene's), and can be set;
    ``rendering`` is the last full-size frame, a :class:`glyphcast.Rendering` (colour
    and depth). ``draft``: the scale of the frames drawn while the view moves (None:
    full size throughout).
    """

    _css = _CSS

    @at_the_call
    def __init__(self, kind, data, affine=None, *, width=800, height=600, renderer=None,
                 controls=True, draft=0.5, **options):
        if kind not in ("sh", "tensor", "scene"):
            raise ValueError(f"kind {kind!r}: expected sh, tensor or scene")
        for key in ("views", "lightbox"):
            if options.get(key) is not None:
                raise ValueError(
                    f"{key}: a montage has a camera per panel; the view shows one slice"
                )
        self._kind, self._data, self._affine = kind, data, affine
        self._size = (int(width), int(height))
        device = {"device": options.pop("device", None),
                  "validation": bool(options.pop("validation", False))}
        self._renderer = renderer if renderer is not None else Renderer(**device)
        # The drafts: frames drawn at `draft` times the size while the view moves, by a
        # second renderer (on the device `device` or GLYPHCAST_DEVICE names) that a
        # thread loads after each load; the full size when the view stops.
        if draft is not None and not 0 < draft <= 1:
            raise ValueError(f"draft={draft!r}: a scale in (0, 1], or None")
        self._draft_scale = None if draft is None or draft == 1 else float(draft)
        self._draft_renderer = None
        self._draft = None  # the future of its load
        self._draft_pool = None
        if self._draft_scale is not None:
            self._draft_renderer = Renderer(**device)
            self._draft_pool = ThreadPoolExecutor(1, thread_name_prefix="glyphcast-draft")
        self._moving = False
        self._final_timer = None
        self._options = dict(options)
        self._plane, self._index = None, None
        if kind != "scene":
            self._plane, self._index = self._parse_slice(self._options.pop("slice", None))
        self._load()
        self._home = self._renderer.camera
        self._camera = dict(self._home)
        self._rendering = self._shown = self._renderer.render(self._camera)
        self._dirty = False
        # Input to frame: the browser's time of the first input a frame answers, by the
        # frame's index; the latencies measured when the browser showed the frame.
        self._pending_input = None
        self._input_of_frame = {}
        self._latencies = []
        self._render_times = []
        self._drag = None
        self._still = None
        self._still_handle = None
        self._still_timer = None
        # jupyter_rfb's frame has a 1-pixel border inside its size: 2 more pixels
        # show the image at its own size. Its box of messages (_output_context), which
        # it shows where it is made, is shown in the view's box instead: one widget
        # output, not three (and no widget reprs in a saved notebook's text).
        with capture_output(stdout=True, stderr=False, display=True):
            super().__init__(
                css_width=f"{width + 2}px", css_height=f"{height + 2}px",
                resizable=False, max_buffered_frames=1,
            )
        self.observe(self._frame_shown, names=["_frame_feedback"])
        self._controls = None
        if controls:
            self._controls = self._make_controls(slices=kind != "scene")
        self._box = ipywidgets.VBox(
            [c for c in (self._controls, self, self._output_context) if c is not None],
            layout=ipywidgets.Layout(width="100%", min_width="0"),
        )
        self._box.add_class("glyphcast-view")

    def __repr__(self):
        if "_size" not in vars(self):
            return "<glyphcast view, refused>"
        width, height = self._size
        shown = "a scene" if self._plane is None else f"slice {self.slice}"
        return f"<glyphcast view {width}x{height}, {self._kind}: {shown}>"

    def close(self, *args, **kwargs):
        """Closes the view in every browser showing it; its renderers go with it."""
        if "_output_context" not in vars(self):
            return  # refused before it was a widget: nothing is open
        super().close(*args, **kwargs)
        for widget in (getattr(self, "_controls", None), getattr(self, "_box", None)):
            if widget is not None:
                widget.close()
        self._draft_renderer = None
        if self._draft_pool is not None:
            self._draft_pool.shutdown(wait=False)

    # ---- what is drawn

    @property
    def camera(self):
        """The camera of the view (a dict like a scene's ``camera``)."""
        return dict(self._camera)

    @camera.setter
    @at_the_call
    def camera(self, camera):
        self._camera = dict(camera)
        self._changed()

    @property
    def rendering(self) -> Rendering:
        """The last full-size frame: a :class:`glyphcast.Rendering` (rgba and depth)."""
        return self._rendering

    @property
    def size(self):
        """The image's (width, height) in pixels."""
        return self._size

    @property
    def slice(self):
        """The slice on show, ``"PLANE:INDEX"`` (None for a scene); can be set."""
        return None if self._plane is None else f"{self._plane}:{self._index}"

    @slice.setter
    @at_the_call
    def slice(self, value):
        plane, index = self._parse_slice(value)
        self._reload(plane=plane, index=index)

    @property
    def options(self):
        """The render options the glyphs are drawn with (keywords of ``render_sh``)."""
        return dict(self._options)

    @at_the_call
    def set_options(self, **options):
        """Draws the glyphs again with these options changed (``method``, ``color``,
        ``negative`` or any other keyword of ``render_sh``); None resets one to its
        default. Refused options raise as ``render_sh`` does, and change nothing."""
        self._reload(options=options)

    def reset_camera(self):
        """Back to the camera the glyphs were first framed with."""
        self.camera = self._home

    def png(self) -> bytes:
        """The last full-size frame as PNG bytes."""
        return self._rendering.png()

    def save_png(self, path) -> None:
        """Writes the last full-size frame to a PNG file."""
        self._rendering.save_png(path)

    def stats(self):
        """jupyter_rfb's frame statistics (``fps``, ``roundtrip``, ``sent_frames``,
        ...) with ``render``: the seconds each frame took to draw, and ``latency``: for each input that changed the view, the seconds from its
        arrival at the kernel to the browser's showing the frame that answers it (the
        browser's clock, ``Date.now()``: the same as the kernel's when both run on one
        machine); all since :meth:`reset_stats`."""
        stats = self.get_stats()
        stats["latency"] = list(self._latencies)
        stats["render"] = list(self._render_times)
        return stats

    def reset_stats(self):
        """Starts the statistics of :meth:`stats` again."""
        super().reset_stats()
        if hasattr(self, "_latencies"):
            self._latencies.clear()
            self._render_times.clear()

    # ---- loading

    def _parse_slice(self, value):
        """(plane, index) of a ``slice`` argument: "PLANE[:INDEX]", an int (an axial
        index) or None (the middle axial slice)."""
        if value is None:
            plane, index = "axial", None
        elif isinstance(value, (int, np.integer)):
            plane, index = "axial", int(value)
        else:
            plane, _, index = str(value).partition(":")
            plane = plane.strip().lower()
            index = int(index) if index.strip() else None
        if plane not in PLANES:
            raise ValueError(f"slice={value!r}: expected axial, coronal or sagittal")
        if index is None:
            index = self._extent(plane) // 2
        return plane, index

    def _extent(self, plane):
        """Slices of ``plane`` in the volume: the length of the voxel axis nearest to
        the plane's normal in world space (the array's axes through its affine)."""
        shape = np.shape(self._data)[:3]
        affine = np.eye(4) if self._affine is None else np.asarray(self._affine, float)
        normal = PLANES.index(plane)  # axial: world z (2), coronal: y (1), sagittal: x (0)
        normal = 2 - normal
        columns = np.abs(affine[:3, :3]) / np.linalg.norm(affine[:3, :3], axis=0)
        return shape[int(np.argmax(columns[normal]))]

    def _load(self):
        """Loads what the view shows, and then (in a thread) the same into the drafts'
        renderer, at their size."""
        state = (self._plane, self._index, dict(self._options))
        self._load_into(self._renderer, state, 1.0, warn=True)
        if self._draft_pool is not None:
            self._draft = self._draft_pool.submit(
                self._load_into, self._draft_renderer, state, self._draft_scale, False)

    def _load_into(self, renderer, state, scale, warn):
        plane, index, options = state
        width, height = (max(1, round(n * scale)) for n in self._size)
        options = dict(options, width=width, height=height)
        if self._kind == "scene":
            renderer._load_scene(self._data, options, warn=warn)
        else:
            options["slice"] = f"{plane}:{index}"
            renderer._load_volume(self._kind, self._data, self._affine, options, warn=warn)

    def _reload(self, plane=None, index=None, options=None):
        """Loads again with a new slice or new options, keeping the camera unless the
        plane changed; on a refusal everything stays as it was and the error is raised."""
        before = (self._plane, self._index, dict(self._options))
        new_plane = plane is not None and plane != self._plane
        if plane is not None:
            self._plane, self._index = plane, index
        if options:
            for key, value in options.items():
                if value is None:
                    self._options.pop(key, None)
                else:
                    self._options[key] = value
        try:
            self._load()
        except Exception:
            self._plane, self._index, self._options = before
            self._load()
            raise
        if new_plane:
            self._home = self._renderer.camera
            self._camera = dict(self._home)
        self._sync_controls()
        self._changed()

    # ---- drawing

    def _changed(self, moving=False):
        """Something changed: a new frame is due. ``moving``: the camera follows an
        input that more will follow (a drag, the wheel): a draft now, the full size once
        the inputs stop (at the pointer's release, or after a pause)."""
        self._dirty = True
        self._moving = moving and self._draft_scale is not None
        if self._final_timer is not None:
            self._final_timer.cancel()
            self._final_timer = None
        if self._moving:
            try:
                loop = asyncio.get_running_loop()
                self._final_timer = loop.call_later(_FINAL_DELAY, self._moved)
            except RuntimeError:
                self._moving = False
        self.request_draw()
        if not self._has_visible_views:
            # No browser shows the view (a notebook run by nbclient): draw now, so that
            # rendering, png() and the static copy follow.
            self._moving = False
            self._draw()
            self._write_still()

    def _moved(self):
        """The inputs stopped: the full-size frame."""
        self._final_timer = None
        if self._moving:
            self._moving = False
            self._dirty = True
            self.request_draw()

    def _draw(self):
        """The frame to show: drawn again only if something changed; a draft while the
        view moves."""
        if not self._dirty:
            return self._shown
        started = time.perf_counter()
        if self._moving:
            self._draft.result()  # loaded in the background since the last load
            self._shown = self._draft_renderer.render(self._camera)
        else:
            self._rendering = self._shown = self._renderer.render(self._camera)
            self._dirty = False
        self._render_times.append(time.perf_counter() - started)
        return self._shown

    def get_frame(self):
        """jupyter_rfb's draw: the frame, drawn again only if something changed."""
        pending, self._pending_input = self._pending_input, None
        frame = self._draw().rgba
        if self._moving:
            self._dirty = True  # the full size is still due
        if pending is not None:
            # The index this frame will be sent with (jupyter_rfb counts them).
            self._input_of_frame[self._rfb_frame_index + 1] = pending
        self._schedule_still()
        return frame

    def _frame_shown(self, change):
        feedback = change["new"]
        index, shown = feedback.get("index", 0), feedback.get("localtime")
        for sent in [i for i in self._input_of_frame if i <= index]:
            started = self._input_of_frame.pop(sent)
            if shown is not None:
                self._latencies.append(shown - started)

    # ---- the static copy of the last view

    def _ipython_display_(self):
        # The box alone, as a widget: its plain text (what nbconvert and a frontend
        # without the widget show) is empty, not the widgets' reprs.
        bundle = self._box._repr_mimebundle_()
        data, metadata = bundle if isinstance(bundle, tuple) else (bundle, {})
        display({WIDGET_VIEW: data[WIDGET_VIEW], "text/plain": ""}, metadata=metadata,
                raw=True)
        display({"text/html": _SAVED_CSS, "text/plain": ""}, raw=True)
        self._still = None
        self._still_handle = display(self._still_bundle(), raw=True, display_id=True)

    def _still_bundle(self):
        self._still = self._rendering
        width, height = self._size
        return {
            "image/png": base64.b64encode(self._rendering.png()).decode("ascii"),
            "text/plain": f"<glyphcast view, {width}x{height}: the last frame>",
        }

    def _schedule_still(self):
        if self._still_timer is not None:
            self._still_timer.cancel()
            self._still_timer = None
        try:
            loop = asyncio.get_running_loop()
        except RuntimeError:
            return
        self._still_timer = loop.call_later(_STILL_DELAY, self._write_still)

    def _write_still(self):
        self._still_timer = None
        if self._still_handle is not None and self._still is not self._rendering:
            self._still_handle.update(self._still_bundle(), raw=True)

    # ---- input

    def handle_event(self, event):
        """jupyter_rfb's input: the drag, the wheel, double-clicks and keys."""
        kind = event.get("type") or event.get("event_type")
        # The input's arrival here, on the clock of the browser's frame confirmations
        # (Date.now(): the same clock when the browser runs on this machine).
        stamp = time.time()
        camera = None
        height = self._size[1]
        moving = False
        if kind == "pointer_down":
            self._drag = (event["x"], event["y"])
        elif kind == "pointer_up":
            self._drag = None
            self._moved()
        elif kind == "pointer_move" and self._drag is not None and event.get("buttons"):
            x0, y0 = self._drag
            dx, dy = event["x"] - x0, event["y"] - y0
            self._drag = (event["x"], event["y"])
            panning = "Shift" in event.get("modifiers", ()) or (
                set(event["buttons"]) & {2, 3}
            )
            if panning:
                camera = pan(self._camera, dx, dy, height)
            else:
                camera = orbit(self._camera, dx, dy, height)
            moving = True
        elif kind == "wheel":
            camera = zoom(self._camera, event.get("dy", 0.0))
            moving = True
        elif kind == "double_click":
            camera = dict(self._home)
        elif kind == "key_down":
            self._key(event.get("key", ""), stamp)
            return
        if camera is not None:
            self._note_input(stamp)
            self._camera = camera
            self._changed(moving=moving)

    def _note_input(self, stamp):
        if stamp is not None and self._pending_input is None:
            self._pending_input = stamp

    def _key(self, key, stamp):
        step = {"PageUp": 1, "ArrowUp": 1, "PageDown": -1, "ArrowDown": -1}.get(key)
        plane = {"a": "axial", "c": "coronal", "s": "sagittal"}.get(key.lower())
        if key.lower() == "r":
            self._note_input(stamp)
            self.reset_camera()
        elif self._plane is None:
            return
        elif step is not None:
            index = min(max(self._index + step, 0), self._extent(self._plane) - 1)
            if index != self._index:
                self._note_input(stamp)
                self._reload(plane=self._plane, index=index)
        elif plane is not None and plane != self._plane:
            self._note_input(stamp)
            self._reload(plane=plane, index=self._extent(plane) // 2)

    # ---- the controls

    def _make_controls(self, slices=True):
        # The controls wrap onto more rows rather than overflow a narrow cell: each
        # dropdown keeps the width of its label and longest choice (never cut), and the
        # slice slider takes the rest of its row, at least _SLIDER_MIN wide.
        label = {"description_width": "initial"}
        items = {}
        if slices:
            items["plane"] = ipywidgets.Dropdown(
                options=PLANES, value=self._plane, description="plane", style=label,
                layout=_dropdown_layout("plane", PLANES))
            items["index"] = ipywidgets.IntSlider(
                value=self._index, min=0, max=self._extent(self._plane) - 1,
                description="slice", continuous_update=True, style=label,
                layout=ipywidgets.Layout(flex=f"1 1 {_SLIDER_MIN}", width="auto",
                                         min_width=_SLIDER_MIN))
        for key, choices in (("method", METHODS), ("color", COLORS),
                             ("negative", NEGATIVE)):
            current = self._options.get(key, _DEFAULT)
            options = [_DEFAULT, *choices]
            if current not in options:
                options.append(current)
            items[key] = ipywidgets.Dropdown(
                options=options, value=current, description=key, style=label,
                layout=_dropdown_layout(key, options))
        self._control_items = items
        self._syncing = False
        for key, control in items.items():
            control.observe(lambda change, key=key: self._control_changed(key, change),
                            names="value")
        box = ipywidgets.HBox(list(items.values()), layout=ipywidgets.Layout(
            flex_flow="row wrap", align_items="center", width="100%", min_width="0"))
        box.add_class("glyphcast-controls")
        return box

    def _control_changed(self, key, change):
        if self._syncing:
            return
        with self._output_context:
            try:
                if key == "plane":
                    self._reload(plane=change["new"],
                                 index=self._extent(change["new"]) // 2)
                elif key == "index":
                    self._reload(plane=self._plane, index=int(change["new"]))
                else:
                    value = change["new"]
                    self._reload(options={key: None if value == _DEFAULT else value})
            except (ValueError, RuntimeError) as error:
                self.print(f"glyphcast: {error}")
                self._sync_controls()

    def _sync_controls(self):
        if self._controls is None:
            return
        items = self._control_items
        self._syncing = True
        try:
            if "plane" in items:
                items["plane"].value = self._plane
                items["index"].max = self._extent(self._plane) - 1
                items["index"].value = self._index
            for key in ("method", "color", "negative"):
                value = self._options.get(key, _DEFAULT)
                if value not in items[key].options:
                    items[key].options = [*items[key].options, value]
                items[key].value = value
        finally:
            self._syncing = False


# The slice slider's least width (its label, the track, the readout): below it the
# slider goes to a row of its own.
_SLIDER_MIN = "260px"


def _dropdown_layout(description, choices):
    """A dropdown as wide as its label and its longest choice need (at most 8 pixels
    a character in JupyterLab's 13-pixel font, 40 for the gaps, the padding and the
    arrow): never narrower, so that no choice is cut."""
    characters = len(description) + max(len(str(c)) for c in choices)
    least = 8 * characters + 40
    return ipywidgets.Layout(width="auto", min_width=f"{least}px", flex="0 0 auto")


@at_the_call
def show_sh(coeffs, affine=None, *, basis, width=800, height=600, renderer=None,
            controls=True, draft=0.5, **options) -> GlyphView:
    """A live view of a slice of an (X, Y, Z, K) SH volume: the arguments of
    :func:`glyphcast.render_sh` (``slice``, ``basis``, ``mask``, ``underlay``, the render
    settings, ...), and ``renderer`` (a :class:`glyphcast.Renderer` to draw with; a new
    one by default), ``controls`` (the slice, method, colour and negative-lobe
    controls above the view) and ``draft`` (the scale of the frames drawn while the
    view moves; None: full size throughout)."""
    return GlyphView("sh", coeffs, affine, basis=basis, width=width, height=height,
                     renderer=renderer, controls=controls, draft=draft, **options)


@at_the_call
def show_tensor(coeffs, affine=None, *, order, width=800, height=600, renderer=None,
                controls=True, draft=0.5, **options) -> GlyphView:
    """A live view of a slice of a tensor volume: the arguments of
    :func:`glyphcast.render_tensor`; see :func:`show_sh`."""
    return GlyphView("tensor", coeffs, affine, order=order, width=width, height=height,
                     renderer=renderer, controls=controls, draft=draft, **options)


@at_the_call
def show_scene(scene, *, width=800, height=600, renderer=None, controls=True,
               draft=0.5, **options) -> GlyphView:
    """A live view of a scene (a dict in the scene format, or a path): the arguments of
    :func:`glyphcast.render_scene`; see :func:`show_sh`."""
    return GlyphView("scene", scene, None, width=width, height=height, renderer=renderer,
                     controls=controls, draft=draft, **options)
