//! glyphcast's errors as Python exceptions: bad input (a scene, an array, an option) is a
//! `ValueError`, a file that cannot be read an `OSError`, host memory a `MemoryError`,
//! and the device (Vulkan, validation, GPU memory) a `RuntimeError`. The message is the
//! CLI's, with every setting it names spelled as this module's keyword
//! (`magnitude_range='1-2': not LOW:HIGH` where the CLI says `--magnitude-range '1-2'`).
use glyphcast::{Error, Setting};
use pyo3::PyErr;
use pyo3::exceptions::{PyMemoryError, PyOSError, PyRuntimeError, PyValueError};

/// The Python exception for `err`.
pub fn to_py(err: Error) -> PyErr {
    let message = err.spelled(&spell);
    match err {
        Error::Io { .. } => PyOSError::new_err(message),
        Error::OutOfMemory { .. } => PyMemoryError::new_err(message),
        Error::Vulkan { .. }
        | Error::Setup { .. }
        | Error::Allocation(_)
        | Error::Validation(_)
        | Error::Thread { .. } => PyRuntimeError::new_err(message),
        // Input, settings, conflicts, limits, data, unsupported requests and calls: the
        // caller's values (new kinds default here: the enum is non_exhaustive).
        _ => PyValueError::new_err(message),
    }
}

/// A `ValueError` naming `what`.
pub fn value_error(what: &str, message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(format!("{what}: {message}"))
}

/// `setting` as a keyword argument, with its value if any (`step=0.0001`); a switch
/// without a value is written as the keyword that turns it on (`legacy=True`).
pub fn spell(setting: Setting, value: Option<&str>) -> String {
    match (value, switch(setting)) {
        (Some(value), _) => format!("{}={value}", keyword(setting)),
        (None, Some(on)) => format!("{}={on}", keyword(setting)),
        (None, None) => keyword(setting).to_owned(),
    }
}

/// The keyword of `setting`: the CLI's flag with `_` for `-`, except where the module
/// takes the opposite switch (`symmetric` for `--nonsymmetric`). Settings the module has
/// no keyword for (the fits', the benchmark's) read the same way.
pub fn keyword(setting: Setting) -> &'static str {
    match setting {
        Setting::Width => "width",
        Setting::Height => "height",
        Setting::Method => "method",
        Setting::Path => "path",
        Setting::Precision => "precision",
        Setting::Step => "step",
        Setting::Refine => "refine",
        Setting::Color => "color",
        Setting::MagnitudeRange => "magnitude_range",
        Setting::Colorbar => "colorbar",
        Setting::Negative => "negative",
        Setting::Background => "background",
        Setting::Offset => "offset",
        Setting::Light => "light",
        Setting::Ambient => "ambient",
        Setting::Specular => "specular",
        Setting::Shininess => "shininess",
        Setting::Samples => "samples",
        Setting::Basis => "basis",
        Setting::Legacy => "legacy",
        Setting::ForceBasis => "force_basis",
        Setting::Frame => "frame",
        Setting::Lmax => "lmax",
        Setting::Order => "order",
        Setting::Nonsymmetric => "symmetric",
        Setting::TensorOrder => "tensor_order",
        Setting::Slice => "slice",
        Setting::Slices => "slices",
        Setting::Voxels => "voxels",
        Setting::Mask => "mask",
        Setting::Scale => "scale",
        Setting::Norm => "norm",
        Setting::MinAmplitude => "min_amplitude",
        Setting::Perspective => "perspective",
        Setting::Orientation => "orientation",
        Setting::Labels => "labels",
        Setting::Underlay => "underlay",
        Setting::UnderlayPlane => "underlay_plane",
        Setting::UnderlayRange => "underlay_range",
        Setting::Peaks => "peaks",
        Setting::PeakValues => "peak_values",
        Setting::PeaksColor => "peaks_color",
        Setting::PeaksNorm => "peaks_norm",
        Setting::PeaksScale => "peaks_scale",
        Setting::PeaksWidth => "peaks_width",
        Setting::PeaksFrame => "peaks_frame",
        Setting::Glyph => "glyph",
        Setting::Views => "views",
        Setting::Lightbox => "lightbox",
        Setting::Bval => "bval",
        Setting::Bvec => "bvec",
        Setting::BvecConvention => "bvec_convention",
        Setting::Odf => "odf",
        Setting::Lambda => "lambda",
        Setting::CsdAlgorithm => "csd_algorithm",
        Setting::Tau => "tau",
        Setting::Response => "response",
        Setting::ResponseFa => "response_fa",
        Setting::Count => "count",
        Setting::RelativeThreshold => "relative_threshold",
        Setting::MinSeparation => "min_separation",
        Setting::PanelSize => "panel_size",
        Setting::Workload => "workload",
    }
}

/// The value that turns a switch setting on, as a keyword takes it.
fn switch(setting: Setting) -> Option<&'static str> {
    match setting {
        Setting::Legacy | Setting::ForceBasis | Setting::Perspective | Setting::Labels => {
            Some("True")
        }
        Setting::Nonsymmetric => Some("False"),
        _ => None,
    }
}
