//! Keyword arguments into the library's requests: the render options
//! ([`RenderOptions`]) and the volume options ([`VolumeRequest`]) under the names of the
//! CLI's flags, with `-` as `_` (`magnitude_range` for `--magnitude-range`); images the
//! CLI reads from files (`mask`, `underlay`) may also be arrays. A keyword the request
//! does not know is a `TypeError`, as for any Python function.
use std::path::PathBuf;

use glam::DMat4;
use glyphcast::render::options::{RenderOptions, Value};
use glyphcast::render::table::{Kind, RENDER_SETTINGS};
use glyphcast_dmri::io::tracks::Tractogram;
use glyphcast_dmri::volume::{
    CoefficientFrame, ImageRequest, ImageSource, PeakVolume, VolumeRequest,
};
use numpy::PyUntypedArray;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyTuple};

use crate::arrays;
use crate::errors::{to_py, value_error};

/// The keyword arguments of one call, taken one by one; `None` counts as not given.
pub struct Kwargs<'py> {
    given: Vec<(String, Bound<'py, PyAny>)>,
}

impl<'py> Kwargs<'py> {
    /// The entries of `dict` (none when absent).
    pub fn new(dict: Option<&Bound<'py, PyDict>>) -> PyResult<Self> {
        let mut given = Vec::new();
        if let Some(dict) = dict {
            for (key, value) in dict.iter() {
                given.push((key.extract::<String>()?, value));
            }
        }
        Ok(Self { given })
    }

    /// Removes `key` and returns its value unless it is absent or `None`.
    fn take(&mut self, key: &str) -> Option<Bound<'py, PyAny>> {
        let at = self.given.iter().position(|(k, _)| k == key)?;
        let (_, value) = self.given.remove(at);
        (!value.is_none()).then_some(value)
    }

    /// A text option (`method="exact"`).
    pub fn text(&mut self, key: &str) -> PyResult<Option<String>> {
        self.take(key)
            .map(|v| {
                v.extract::<String>()
                    .map_err(|_| expected(key, "a string", &v))
            })
            .transpose()
    }

    /// A number (`step=0.02`).
    pub fn float(&mut self, key: &str) -> PyResult<Option<f64>> {
        self.take(key)
            .map(|v| {
                v.extract::<f64>()
                    .map_err(|_| expected(key, "a number", &v))
            })
            .transpose()
    }

    /// A non-negative whole number (`lmax=6`).
    pub fn count(&mut self, key: &str) -> PyResult<Option<u32>> {
        self.take(key)
            .map(|v| {
                v.extract::<u32>()
                    .map_err(|_| expected(key, "a whole number >= 0", &v))
            })
            .transpose()
    }

    /// A switch (`perspective=True`); absent is `default`.
    pub fn flag(&mut self, key: &str, default: bool) -> PyResult<bool> {
        self.take(key)
            .map(|v| {
                v.extract::<bool>()
                    .map_err(|_| expected(key, "True or False", &v))
            })
            .transpose()
            .map(|v| v.unwrap_or(default))
    }

    /// A switch that may be left out (`legacy=False` differs from no `legacy`).
    fn optional_flag(&mut self, key: &str) -> PyResult<Option<bool>> {
        self.take(key)
            .map(|v| {
                v.extract::<bool>()
                    .map_err(|_| expected(key, "True or False", &v))
            })
            .transpose()
    }

    /// `lmax`, or DIPY's name for it, `sh_order_max` (not both).
    fn lmax(&mut self) -> PyResult<Option<u32>> {
        let lmax = self.count("lmax")?;
        let sh_order_max = self.count("sh_order_max")?;
        match (lmax, sh_order_max) {
            (Some(_), Some(_)) => Err(value_error(
                "sh_order_max",
                "is DIPY's name for lmax: give one of them",
            )),
            (lmax, sh_order_max) => Ok(lmax.or(sh_order_max)),
        }
    }

    /// `slice`: "AXIS[:INDEX]", or a whole number: that index of the default plane
    /// (`slice=5` is "axial:5").
    fn slice(&mut self) -> PyResult<Option<String>> {
        let Some(value) = self.take("slice") else {
            return Ok(None);
        };
        if let Ok(text) = value.extract::<String>() {
            return Ok(Some(text));
        }
        if !value.is_instance_of::<pyo3::types::PyBool>()
            && let Ok(index) = value.extract::<u64>()
        {
            return Ok(Some(format!("axial:{index}")));
        }
        Err(expected(
            "slice",
            "\"AXIS[:INDEX]\" or a whole number >= 0 (an axial index)",
            &value,
        ))
    }

    /// `norm`: "sqrt", "robust", "global", "per-glyph" or "none", or FURY's switch: True is
    /// "per-glyph" (every glyph scaled to its own maximum), False is "none".
    fn norm(&mut self) -> PyResult<Option<String>> {
        let Some(value) = self.take("norm") else {
            return Ok(None);
        };
        if let Ok(text) = value.extract::<String>() {
            return Ok(Some(text));
        }
        if let Ok(on) = value.extract::<bool>() {
            return Ok(Some(if on { "per-glyph" } else { "none" }.into()));
        }
        Err(expected("norm", "a string or True/False", &value))
    }

    /// A `TypeError` for the first keyword nobody took.
    pub fn finish(self) -> PyResult<()> {
        match self.given.first() {
            Some((key, _)) => Err(PyTypeError::new_err(format!(
                "unexpected keyword argument '{key}'"
            ))),
            None => Ok(()),
        }
    }

    /// The image size: `width` and `height` (each side 1 to 16384; absent: the scene's,
    /// or the slice's aspect).
    pub fn image_request(&mut self) -> PyResult<ImageRequest> {
        let (width, height) = (self.count("width")?, self.count("height")?);
        ImageRequest::checked(width, height).map_err(to_py)
    }

    /// The render options: every setting of the library's table ([`RENDER_SETTINGS`]),
    /// under its key (`magnitude_range`). Numbers are Python numbers; names are strings;
    /// several numbers (`light`, `magnitude_range`) a sequence or the command line's
    /// text ("1,0,0", "0:2"). The device is the renderer's.
    pub fn render_options(&mut self) -> PyResult<RenderOptions> {
        let mut options = RenderOptions::default();
        for spec in RENDER_SETTINGS {
            let key = spec.setting.keyword();
            let Some(value) = self.take(key) else {
                continue;
            };
            let text: String;
            let numbers: Vec<f64>;
            let given = match spec.kind {
                Kind::Number | Kind::Count => {
                    let number = (!value.is_instance_of::<PyBool>())
                        .then(|| value.extract::<f64>().ok())
                        .flatten();
                    Value::Number(number.ok_or_else(|| expected(key, "a number", &value))?)
                }
                Kind::Name => {
                    text = value
                        .extract()
                        .map_err(|_| expected(key, "a string", &value))?;
                    Value::Text(&text)
                }
                // True is `on`, False `off` (`shadows=True`), or a name, or a number
                // (`ambient_occlusion=2`: the library refuses one where it takes none).
                Kind::Switch => match value.extract::<bool>() {
                    Ok(on) => Value::Text(if on { "on" } else { "off" }),
                    Err(_) => match value.extract::<f64>() {
                        Ok(number) => Value::Number(number),
                        Err(_) => {
                            text = value.extract().map_err(|_| {
                                expected(key, "True, False, a number or a string", &value)
                            })?;
                            Value::Text(&text)
                        }
                    },
                },
                Kind::Numbers => match value.extract::<String>() {
                    Ok(given) => {
                        text = given;
                        Value::Text(&text)
                    }
                    Err(_) => {
                        numbers = value.extract().map_err(|_| {
                            expected(key, "a sequence of numbers or a string", &value)
                        })?;
                        Value::Numbers(&numbers)
                    }
                },
            };
            options.set(spec.setting, given).map_err(to_py)?;
        }
        Ok(options)
    }

    /// A text option that may also be a list or tuple of texts, joined by commas
    /// (`views=["axial", "coronal"]` for `views="axial,coronal"`).
    pub fn list(&mut self, key: &str) -> PyResult<Option<String>> {
        let Some(value) = self.take(key) else {
            return Ok(None);
        };
        if let Ok(text) = value.extract::<String>() {
            return Ok(Some(text));
        }
        if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
            let items: Vec<String> = value
                .extract()
                .map_err(|_| expected(key, "a string or a list of strings", &value))?;
            return Ok(Some(items.join(",")));
        }
        Err(expected(key, "a string or a list of strings", &value))
    }

    /// A range: "LOW:HIGH" or a pair of numbers (`underlay_range=(0, 0.8)`).
    pub fn range(&mut self, key: &str) -> PyResult<Option<String>> {
        let Some(value) = self.take(key) else {
            return Ok(None);
        };
        if let Ok(text) = value.extract::<String>() {
            return Ok(Some(text));
        }
        // Rust prints each number as the shortest text that reads back as it.
        let (low, high): (f64, f64) = value
            .extract()
            .map_err(|_| expected(key, "\"LOW:HIGH\" or a pair of numbers", &value))?;
        Ok(Some(format!("{low}:{high}")))
    }

    /// An image: a file (a path) or a numpy array, converted by `array`.
    fn image<T>(
        &mut self,
        key: &str,
        array: impl FnOnce(&Bound<'py, PyAny>) -> PyResult<T>,
    ) -> PyResult<Option<ImageSource<T>>> {
        let Some(value) = self.take(key) else {
            return Ok(None);
        };
        if value.cast::<PyUntypedArray>().is_ok() || value.is_instance_of::<PyTuple>() {
            return array(&value).map(|v| Some(ImageSource::Memory(v)));
        }
        match value.extract::<PathBuf>() {
            Ok(path) => Ok(Some(ImageSource::File(path))),
            Err(_) => Err(expected(key, "a path or a numpy array", &value)),
        }
    }

    /// The volume options: `basis`, `legacy`, `frame`, `lmax` (SH), `order`, `symmetric`,
    /// `tensor_order` (tensors), `slice`, `slices`, `block`, `voxels`, `mask` (a path or an
    /// (X, Y, Z) array), `scale`, `norm`, `min_amplitude`, `perspective`, `orientation`,
    /// `glyph`, `underlay` (a path, an array on the coefficients' grid, or (array, affine)),
    /// `underlay_range` ("LOW:HIGH" or (low, high)), `views` ("axial,coronal" or a list)
    /// and `lightbox`; `peaks` (a path, or an array on the coefficients' grid: (X, Y, Z,
    /// 3N) as sh2peaks writes it, or DIPY's (X, Y, Z, N, 3) `peak_dirs`), `peak_values`
    /// (DIPY's amplitudes: a path with a peaks path, an array with a peaks array),
    /// `peaks_color`, `peaks_norm`, `peaks_scale`, `peaks_width` and `peaks_frame` (voxel
    /// or world: a path's default is the file's own frame, an array's `frame`); `tracks`
    /// (a tractogram path, or streamlines: (N, 3) arrays or a nibabel `Tractogram`),
    /// `tracks_color`, `tracks_radius`, `tracks_style`, `tracks_max` and `slab`. `affine` is the
    /// coefficients' (an underlay array's default).
    pub fn volume_request(&mut self, affine: DMat4) -> PyResult<VolumeRequest> {
        let underlay = |value: &Bound<'py, PyAny>| match value.cast::<PyTuple>() {
            Ok(pair) if pair.len() == 2 => {
                let own = arrays::affine_named("underlay", Some(&pair.get_item(1)?))?;
                arrays::underlay(&pair.get_item(0)?, own.affine)
            }
            Ok(_) => Err(value_error(
                "underlay",
                "a tuple must be (array, affine), the array with its own 4x4 affine",
            )),
            Err(_) => arrays::underlay(value, affine),
        };
        let mut request = VolumeRequest {
            basis: self.text("basis")?,
            legacy: self.optional_flag("legacy")?,
            force_basis: false,
            frame: self.text("frame")?,
            lmax: self.lmax()?,
            order: self.count("order")?,
            nonsymmetric: !self.flag("symmetric", true)?,
            tensor_order: self.text("tensor_order")?,
            slice: self.slice()?,
            slices: self.text("slices")?,
            block: self.flag("block", false)?,
            voxels: self.text("voxels")?,
            scale: self.float("scale")?,
            norm: self.norm()?,
            min_amplitude: self.float("min_amplitude")?,
            mask: self.image("mask", |value| arrays::mask(value))?,
            perspective: self.flag("perspective", false)?,
            orientation: self.text("orientation")?,
            glyph: self.text("glyph")?,
            underlay: self.image("underlay", underlay)?,
            underlay_range: self.range("underlay_range")?,
            underlay_plane: self.text("underlay_plane")?,
            views: self.list("views")?,
            lightbox: self.count("lightbox")?.map(|n| n as usize),
            peaks: None,
            peak_values: None,
            peaks_color: self.text("peaks_color")?,
            peaks_norm: self.text("peaks_norm")?,
            peaks_scale: self.float("peaks_scale")?,
            peaks_width: self.float("peaks_width")?,
            peaks_frame: self.text("peaks_frame")?,
            tracks: self.tracks()?,
            tracks_color: self.text("tracks_color")?,
            tracks_radius: self.float("tracks_radius")?,
            tracks_style: self.text("tracks_style")?,
            tracks_max: self.count("tracks_max")?.map(|n| n as usize),
            slab: self.float("slab")?,
        };
        // Peak arrays are in `peaks_frame`, else the coefficients' frame: what `frame`
        // says, else voxel axes.
        let frame = match request.peaks_frame().map_err(to_py)? {
            Some(frame) => frame,
            None => request.frame().map_err(to_py)?.unwrap_or_default(),
        };
        (request.peaks, request.peak_values) = self.peaks(affine, frame)?;
        Ok(request)
    }

    /// `tracks`: a tractogram file (.tck, .trk, .trx), or streamlines in RAS+
    /// millimetres (a sequence of (N, 3) arrays, or a nibabel `Tractogram`).
    fn tracks(&mut self) -> PyResult<Option<ImageSource<Tractogram>>> {
        let Some(value) = self.take("tracks") else {
            return Ok(None);
        };
        if let Ok(path) = value.extract::<PathBuf>() {
            return Ok(Some(ImageSource::File(path)));
        }
        arrays::tracks(&value).map(|t| Some(ImageSource::Memory(t)))
    }

    /// `peaks` and `peak_values`: paths, or arrays on the coefficients' grid (placed by
    /// `affine`, directions in `frame`), the values going with directions of the same
    /// kind.
    fn peaks(
        &mut self,
        affine: DMat4,
        frame: CoefficientFrame,
    ) -> PyResult<(Option<ImageSource<PeakVolume>>, Option<PathBuf>)> {
        let values = self.take("peak_values");
        let is_array = |v: &Bound<'py, PyAny>| v.cast::<PyUntypedArray>().is_ok();
        let peaks = self.image("peaks", |array| {
            let values = match &values {
                Some(v) if is_array(v) => Some(arrays::peaks("peak_values", v, affine)?),
                Some(v) => return Err(expected("peak_values", "a numpy array (as peaks)", v)),
                None => None,
            };
            let directions = arrays::peaks("peaks", array, affine)?;
            PeakVolume::from_arrays(directions, values, frame).map_err(to_py)
        })?;
        let path = match (&peaks, values) {
            (Some(ImageSource::Memory(_)), _) | (_, None) => None,
            (None, Some(_)) => {
                return Err(value_error(
                    "peak_values",
                    "needs peaks (the directions the values belong to)",
                ));
            }
            (_, Some(v)) if is_array(&v) => {
                return Err(value_error(
                    "peak_values",
                    "an array goes with a peaks array; with a peaks path, give the values' \
                     path",
                ));
            }
            (_, Some(v)) => Some(
                v.extract::<PathBuf>()
                    .map_err(|_| expected("peak_values", "a path or a numpy array", &v))?,
            ),
        };
        Ok((peaks, path))
    }
}

fn expected(key: &str, what: &str, value: &Bound<'_, PyAny>) -> PyErr {
    let type_name = value
        .get_type()
        .name()
        .map(|name| name.to_string())
        .unwrap_or_else(|_| "?".into());
    value_error(key, format!("expected {what}, got {type_name}"))
}
