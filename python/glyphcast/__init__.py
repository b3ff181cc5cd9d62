"""glyphcast: exact GPU ray casting of fODF and higher-order tensor glyphs.

numpy in, images out. Every function returns a :class:`Rendering`, a named tuple
``(rgba, depth)``: ``rgba`` is uint8 (H, W, 4), sRGB; ``depth`` is float32 (H, W), the
ray distance to the first hit, NaN for misses (what ``glyphcast render --depth-out``
writes). A notebook shows a Rendering as its image.

The keyword options are those of ``glyphcast render``, with ``-`` as ``_``
(``magnitude_range`` for ``--magnitude-range``), with the same defaults and checks:

- drawing: every render setting of :func:`render_settings` (the library's table: its
  key, what it accepts, its default and which methods read it), numbers as numbers,
  names as strings, ``light`` and ``magnitude_range`` as sequences (or the command
  line's "X,Y,Z" and "LOW:HIGH"); ``glyph`` ("polynomial" or "ellipsoid": the DTI
  ellipsoid of order-2 tensors);
- the image: ``labels`` (anatomical directions at the edges), ``colorbar`` (with
  ``color="magnitude"``: the colour bar on the right) and ``colorbar_label``;
- volumes (``render_sh``, ``render_tensor``): ``slice`` ("AXIS[:INDEX]", or an int:
  that axial index), ``slices``, ``voxels``, ``block`` (``True``: every voxel of
  ``voxels``, the whole volume without it, in 3D and in perspective, at most 100000
  glyphs; not with ``slice``, ``slices``, ``views``, ``lightbox`` or ``underlay``),
  ``mask`` (an (X, Y, Z) array or a path),
  ``scale``, ``norm`` ("sqrt", the default, "robust", "global", "per-glyph", "none"; or
  FURY's ``True`` for "per-glyph", ``False`` for "none"), ``min_amplitude``, ``lmax``
  (or DIPY's ``sh_order_max``), ``frame``, ``perspective``, ``orientation``,
  ``tensor_order`` (the stored order of order-2 tensors' six entries: glyphcast, fsl,
  dipy or mrtrix; (..., 3, 3) matrices are taken as they are);
  ``underlay`` (an anatomical image drawn behind the glyphs of each slice: a
  NIfTI/MRtrix path, an (X, Y, Z) or (X, Y, Z, 3) array on the coefficients' grid, or
  ``(array, affine)``) with ``underlay_range`` ("LOW:HIGH" or ``(low, high)``) and
  ``underlay_plane`` ("back", the default, or "centre": through the glyph centres); a
  montage of panels, each the image of its view alone (with its underlay): ``views``
  ("axial,coronal,sagittal" or a list, each optionally ":INDEX") or ``lightbox`` (N
  evenly spaced slices of the ``slice`` plane, each captioned with its slice).

Arrays are taken as they come: float32 or float64, C or Fortran order, strided or
reversed views (``shm_coeff[:, :, 2:5]``), each copied once. A voxel with a NaN or
infinite coefficient is left out with one warning that counts them, as the command
line does; warnings point at the caller's line.

Basis names are DIPY's and any case: ``"dipy"`` is DIPY 1.x's default, descoteaux07
with ``legacy=True``, and ``"dipy-new"`` its ``legacy=False`` basis; ``basis="descoteaux07"``
names both and needs ``legacy=True`` or ``legacy=False`` (without it, on an array or a file
that records no basis, it is a ``ValueError`` naming both choices; see
docs/guide/conventions.md); ``"tournier07"``/``"mrtrix"`` is MRtrix3's.
- peaks: ``peaks`` (a peak image's path, or an array on the coefficients' grid,
  directions in the coefficients' frame: (X, Y, Z, 3N) as ``glyphcast peaks`` and MRtrix
  ``sh2peaks`` write it; with ``peak_values``, DIPY's unit ``peak_dirs`` (X, Y, Z, N, 3)
  and ``peak_values`` (X, Y, Z, N), both paths or both arrays) drawn as capsules through
  the voxel centres, with ``peaks_color``, ``peaks_norm``, ``peaks_scale`` and
  ``peaks_width``.
- tracks: ``tracks`` (a tractogram's path, .tck, .trk or .trx; or streamlines in RAS+
  millimetres: a list of (N, 3) arrays, nibabel's ``ArraySequence``, a nibabel
  ``Tractogram``, or a DIPY ``StatefulTractogram`` in RASMM) drawn as tubes in the glyphs'
  depth buffer, with ``tracks_color``, ``tracks_radius`` (millimetres), ``tracks_style``
  (``"tubes"``, exact, or ``"lines"``, fast), ``tracks_max`` (a uniform subsample) and ``slab`` (on slice views, only the parts within that many
  millimetres of a slice's plane).

The messages of the errors are the CLI's, with each option named by its keyword
(``step=0.0001: must be in 0.001 to 2 ...`` where the CLI says ``--step 0.0001``). Bad
input raises ValueError (OSError for a file that cannot be read), a device failure
RuntimeError. A ValueError or TypeError is raised from the function you called: its
traceback ends there, not in the frames below it (``GLYPHCAST_FULL_TRACEBACK=1`` keeps
them). ``validation=True`` (or GLYPHCAST_VALIDATION=1) turns on the Vulkan
validation layer; any validation error then raises RuntimeError.
"""
import json
import os
import sys
import warnings
from typing import NamedTuple

import numpy as np

from ._glyphcast import __version__, encode_png, render_settings
from ._glyphcast import stiffness as _stiffness
from ._glyphcast import Renderer as _Renderer
from ._calls import at_the_call

# The notebook view (glyphcast.notebook) is imported on first use: it needs jupyter_rfb
# (`pip install glyphcast[notebook]`), which nothing else here does.
_NOTEBOOK_NAMES = ("GlyphView", "show_sh", "show_tensor", "show_scene")


def __getattr__(name):
    if name in _NOTEBOOK_NAMES:
        from . import notebook

        return getattr(notebook, name)
    raise AttributeError(f"module 'glyphcast' has no attribute {name!r}")


__all__ = [
    "Rendering",
    "Renderer",
    "render_scene",
    "render_sh",
    "render_tensor",
    "stiffness",
    "encode_png",
    "render_settings",
    "__version__",
]


class Rendering(NamedTuple):
    """A rendered image: ``rgba`` uint8 (H, W, 4) and ``depth`` float32 (H, W)."""

    rgba: np.ndarray
    depth: np.ndarray

    def png(self, dpi=None) -> bytes:
        """The image as PNG bytes; ``dpi`` (pixels per inch) is recorded as its print
        resolution if given, as ``glyphcast render --dpi`` does."""
        return encode_png(self.rgba, dpi)

    def save_png(self, path, dpi=None) -> None:
        """Writes the image as a PNG file (``dpi``: as for :meth:`png`)."""
        with open(path, "wb") as file:
            file.write(self.png(dpi))

    def _repr_png_(self) -> bytes:
        return self.png()


def _scene_argument(scene):
    """A scene dict as JSON text, or a path as text; returns (text, is_path)."""
    if isinstance(scene, (str, os.PathLike)):
        return os.fspath(scene), True
    if isinstance(scene, dict):
        return json.dumps(scene, default=_json_value, allow_nan=False), False
    raise ValueError(
        f"scene: a dict in the scene format or a path is needed, not {type(scene).__name__}"
    )


def _json_value(value):
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")


def _float_array(value):
    return None if value is None else np.asarray(value, dtype=np.float64)


_PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))


def _warn(message):
    """Warns with the line of the first caller outside this package (``stacklevel``
    counted at run time: the public functions reach here through different depths)."""
    frame, level = sys._getframe(1), 2
    while frame is not None and os.path.dirname(
        os.path.abspath(frame.f_code.co_filename)
    ) == _PACKAGE_DIR:
        frame, level = frame.f_back, level + 1
    warnings.warn(message, UserWarning, stacklevel=level)


class Renderer:
    """One Vulkan device, its pipelines and the glyphs last rendered, kept across calls.

    ``render_scene``, ``render_sh`` and ``render_tensor`` load (prepare and upload) the
    glyphs and draw them; ``render(camera=...)`` draws them again from another camera
    without uploading again. Everything is freed when the object goes, or at
    ``release()`` (glyphs) and ``close()`` (the device).
    """

    def __init__(self, *, device=None, validation=False):
        self._native = _Renderer(device=device, validation=validation)

    @property
    def device(self) -> str:
        """The Vulkan device, as the CLI prints it."""
        return self._native.device

    @property
    def glyph_count(self) -> int:
        """Glyphs loaded."""
        return self._native.glyph_count

    @property
    def camera(self):
        """The camera the loaded glyphs are drawn with, as a dict like a scene's
        ``camera`` (the one the load framed, or the last one given to :meth:`render`);
        None before a load and for a montage (a camera per panel)."""
        view = self._native.view
        return None if view is None else json.loads(view[0])

    @property
    def size(self):
        """The loaded image's ``(width, height)`` in pixels; None where :attr:`camera` is."""
        view = self._native.view
        return None if view is None else (view[1], view[2])

    @at_the_call
    def render_scene(self, scene, *, width=None, height=None, method=None, **options):
        """Renders a scene: a dict in the scene format, or the path of a scene file."""
        self._load_scene(scene, dict(options, width=width, height=height, method=method))
        return self.render()

    @at_the_call
    def render_sh(
        self,
        coeffs,
        affine=None,
        *,
        basis,
        legacy=None,
        slice=None,
        mask=None,
        scale=None,
        norm=None,
        width=None,
        height=None,
        **options,
    ):
        """Renders a slice of an (X, Y, Z, K) volume of SH coefficients (as nibabel's
        ``get_fdata()`` gives it) with its 4x4 ``affine`` (identity if None), as
        ``glyphcast render --sh`` does: ``basis`` is tournier07, descoteaux07 (with
        ``legacy=True`` or ``legacy=False``: alone it is refused), mrtrix, dipy (DIPY's
        default, descoteaux07 legacy) or dipy-new (descoteaux07, ``legacy=False``), in any
        case; ``slice`` is
        "AXIS[:INDEX]" or an axial index (default: the middle axial slice). With ``views`` or ``lightbox``
        the result is the montage's one image; with ``block=True`` every voxel of ``voxels``
        ("i0:i1,j0:j1,k0:k1") is drawn in 3D, framed whole from a corner."""
        options.update(
            basis=basis, legacy=legacy, slice=slice, mask=mask, scale=scale, norm=norm,
            width=width, height=height,
        )
        return self._volume("sh", coeffs, affine, options)

    @at_the_call
    def render_tensor(
        self,
        coeffs,
        affine=None,
        *,
        order,
        symmetric=True,
        slice=None,
        mask=None,
        scale=None,
        norm=None,
        width=None,
        height=None,
        **options,
    ):
        """Renders a slice of an (X, Y, Z, K) volume of Cartesian tensor coefficients, as
        ``glyphcast render --tensor`` does (``symmetric``: the unique entries, else all
        3^order; ``glyph="ellipsoid"`` draws order-2 tensors as DTI ellipsoids).

        Order-2 tensors: ``coeffs`` holds six entries per voxel in the order
        ``tensor_order`` names, "glyphcast" (xx, xy, xz, yy, yz, zz; also "fsl"), "dipy"
        (xx, xy, yy, xz, yz, zz: DIPY's ``lower_triangular()``) or "mrtrix" (xx, yy, zz,
        xy, xz, yz); without it glyphcast's order is assumed, and refused where the values
        show another. Or (X, Y, Z, 3, 3) symmetric matrices (DIPY's ``quadratic_form``),
        which need no order. Higher orders are in glyphcast's order."""
        options.update(
            order=order, symmetric=symmetric, slice=slice, mask=mask, scale=scale,
            norm=norm, width=width, height=height,
        )
        return self._volume("tensor", coeffs, affine, options)

    @at_the_call
    def render(self, camera=None) -> Rendering:
        """Draws the loaded glyphs again, from their camera or from ``camera`` (a dict
        like a scene's ``camera``: projection, eye, target, up, fov_y_deg or height; not
        for a montage, whose panels have a camera each)."""
        text = None if camera is None else json.dumps(camera, default=_json_value)
        rgba, depth = self._native.render(text)
        return Rendering(rgba, depth)

    @property
    def culling(self):
        """What culling of hidden glyphs the last frame drawn was asked for (``cull``)
        and what it did, as ``glyphcast render`` prints it: ``"occluded: early outs (1
        pass)"``, ``"occluded: 9 passes"``, ``"off (1 pass)"``, or ``"occluded: none
        (...)"`` with the reason; ``None`` before the first frame and for a montage."""
        return self._native.culling

    def release(self) -> None:
        """Frees the loaded glyphs (the device stays open)."""
        self._native.release()

    def close(self) -> None:
        """Frees the glyphs and the device; the renderer cannot be used afterwards."""
        self._native = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _load_scene(self, scene, options, warn=True):
        """Loads a scene without drawing it (``render_scene``'s first half); ``warn``:
        whether its notes are warned of."""
        text, is_path = _scene_argument(scene)
        for message in self._native.load_scene(text, is_path, options):
            if warn:
                _warn(message)

    def _volume(self, kind, coeffs, affine, options):
        self._load_volume(kind, coeffs, affine, options)
        return self.render()

    def _load_volume(self, kind, coeffs, affine, options, warn=True):
        """Loads a slice of a volume without drawing it (``render_sh``'s and
        ``render_tensor``'s first half); ``warn``: whether its notes and warnings are
        warned of."""
        if kind == "tensor":
            coeffs = _tensor_coefficients(coeffs, options)
        for key in ("mask", "underlay"):
            value = options.get(key)
            if isinstance(value, (list, np.generic)):
                options[key] = np.asarray(value)
        if isinstance(options.get("underlay"), tuple) and len(options["underlay"]) == 2:
            array, own_affine = options["underlay"]
            options["underlay"] = (np.asarray(array), _float_array(own_affine))
        notes, warned = self._native.load_volume(kind, coeffs, _float_array(affine), options)
        for message in list(notes) + list(warned) if warn else []:
            _warn(message)


# The entries (row, column) of a symmetric 3x3 matrix in glyphcast's order.
_GLYPHCAST_ENTRIES = ((0, 0, 0, 1, 1, 2), (0, 1, 2, 1, 2, 2))


def _tensor_coefficients(coeffs, options):
    """The tensor array as the native module takes it: (X, Y, Z, 3, 3) symmetric matrices
    become their six entries in glyphcast's order (``tensor_order`` then set to it), and
    an array neither C- nor Fortran-contiguous (``lower_triangular()`` is a strided view)
    is copied once."""
    array = np.asarray(coeffs)
    if array.ndim == 5 and array.shape[3:] == (3, 3):
        if options.get("tensor_order") is not None:
            raise ValueError(
                "tensor_order: (X, Y, Z, 3, 3) matrices have no stored order; leave it out"
            )
        if options.get("order") != 2:
            raise ValueError(
                f"order={options.get('order')!r}: (X, Y, Z, 3, 3) matrices are order-2 "
                "tensors; give order=2"
            )
        asymmetry = np.abs(array - np.swapaxes(array, 3, 4))
        largest = np.abs(array).max(initial=0.0)
        if asymmetry.max(initial=0.0) > 1e-6 * largest:
            i, j, k, _, _ = np.unravel_index(np.argmax(asymmetry), asymmetry.shape)
            raise ValueError(
                f"coeffs: the (X, Y, Z, 3, 3) matrices must be symmetric (as DIPY's "
                f"quadratic_form is); voxel ({i}, {j}, {k}) is not"
            )
        rows, columns = _GLYPHCAST_ENTRIES
        array = array[..., rows, columns]
        options["tensor_order"] = "glyphcast"
    if not (array.flags.c_contiguous or array.flags.f_contiguous):
        array = np.ascontiguousarray(array)
    return array


def _split_device(options):
    return {
        "device": options.pop("device", None),
        "validation": bool(options.pop("validation", False)),
    }


@at_the_call
def render_scene(scene, *, width=None, height=None, method=None, **options) -> Rendering:
    """Renders a scene (a dict in the scene format, or a path) as ``glyphcast render
    SCENE`` does. Options: the render settings (:func:`render_settings`), glyph, labels,
    colorbar, colorbar_label, device and validation."""
    renderer = Renderer(**_split_device(options))
    return renderer.render_scene(scene, width=width, height=height, method=method, **options)


@at_the_call
def render_sh(
    coeffs,
    affine=None,
    *,
    basis,
    legacy=None,
    slice=None,
    mask=None,
    scale=None,
    norm=None,
    width=None,
    height=None,
    **options,
) -> Rendering:
    """Renders a slice of an (X, Y, Z, K) SH volume as ``glyphcast render --sh`` does;
    see :meth:`Renderer.render_sh`. ``device`` and ``validation`` pick the device."""
    renderer = Renderer(**_split_device(options))
    return renderer.render_sh(
        coeffs, affine, basis=basis, legacy=legacy, slice=slice, mask=mask, scale=scale,
        norm=norm, width=width, height=height, **options,
    )


@at_the_call
def render_tensor(
    coeffs,
    affine=None,
    *,
    order,
    symmetric=True,
    slice=None,
    mask=None,
    scale=None,
    norm=None,
    width=None,
    height=None,
    **options,
) -> Rendering:
    """Renders a slice of an (X, Y, Z, K) tensor volume as ``glyphcast render --tensor``
    does; see :meth:`Renderer.render_tensor`. ``device`` and ``validation`` pick the
    device."""
    renderer = Renderer(**_split_device(options))
    return renderer.render_tensor(
        coeffs, affine, order=order, symmetric=symmetric, slice=slice, mask=mask,
        scale=scale, norm=norm, width=width, height=height, **options,
    )


@at_the_call
def stiffness(C, *, surface="reynolds", euler=None, allow_unstable=False,
              symmetric_part=False, **options):
    """A glyph of a 6 x 6 Voigt stiffness matrix ``C`` (any units) and its elastic
    numbers, as ``glyphcast stiffness C -o SCENE --summary FILE --surface SURFACE`` and
    ``glyphcast render SCENE`` give them: returns ``(rendering, summary)``. ``surface``:
    ``"reynolds"`` (C_ijkl u_i u_j u_k u_l, the default), ``"young"`` (Young's modulus
    E(u), drawn exactly as r = 1/|s_ijkl u_i u_j u_k u_l|) or ``"compressibility"``
    (linear compressibility beta(u), inverse units; ``color="sign"`` shows where it is
    negative), ``"shear-min"`` or ``"shear-max"`` (the smallest or largest shear
    modulus G(u, v) over the shear directions v perpendicular to u, drawn exactly),
    radius in the units of ``C``, or ``"poisson-min"`` or ``"poisson-max"`` (the
    smallest or largest Poisson's ratio nu(u, v) over the transverse directions v
    perpendicular to u, dimensionless, drawn exactly; ``color="sign"`` shows the
    negative ratios of an auxetic crystal); a material's smallest and largest surfaces
    share one scale. ``summary`` is the dict
    of the summary file: Young's modulus (``young``: min, max and their directions),
    ``linear_compressibility``, ``shear`` and ``poisson`` extremes over all directions,
    ``bulk`` and ``shear_average`` (Voigt, Reuss, Hill), in the units of ``C``.
    ``euler``: Bunge angles (phi1, Phi, phi2) in degrees, sample to crystal, so that the
    glyph and the numbers are the sample frame's. A matrix that is not positive definite
    raises ValueError unless ``allow_unstable``. Other options are ``render_scene``'s.
    See docs/guide/materials.md."""
    matrix = np.asarray(C, dtype=float)
    if matrix.shape != (6, 6):
        raise ValueError(f"C: shape {matrix.shape} where a 6 x 6 Voigt matrix is needed")
    angles = None if euler is None else tuple(float(a) for a in euler)
    if angles is not None and len(angles) != 3:
        raise ValueError(f"euler: {len(angles)} angles where (phi1, Phi, phi2) is needed")
    scene, summary = _stiffness(matrix.tolist(), angles, bool(allow_unstable),
                                bool(symmetric_part), str(surface))
    return render_scene(json.loads(scene), **options), json.loads(summary)
