//! glyphcast's Python module: numpy in, images out. The extension is
//! `glyphcast._glyphcast`; the Python package `glyphcast` (python/glyphcast) wraps it
//! with the documented functions, keyword defaults and notebook display.
//!
//! Nothing here renders or parses on its own: scenes, volume slices, montages and render
//! options go through the same library calls as `glyphcast render` (`render::options`,
//! `volume::VolumeRequest`, `render::compose::montage`, `render::headless`), so the module and
//! the CLI draw the same pixels with the same defaults and checks; their messages name
//! each option as this module's keyword where the CLI names its flag (`errors`).
use glyphcast::io::png::encode_png_rgba8;
use numpy::{PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

mod arrays;
mod errors;
mod kwargs;
mod renderer;

use errors::{to_py, value_error};

/// PNG bytes of an (H, W, 4) uint8 RGBA image (sRGB, as rendered).
#[pyfunction]
fn encode_png<'py>(
    py: Python<'py>,
    rgba: PyReadonlyArray3<'py, u8>,
) -> PyResult<Bound<'py, PyBytes>> {
    let shape = rgba.shape();
    if shape[2] != 4 {
        return Err(value_error(
            "rgba",
            format!("shape {shape:?} where (H, W, 4) is needed"),
        ));
    }
    let (h, w) = (shape[0] as u32, shape[1] as u32);
    // Any strides (a view, a crop): copied into C order when not already in it.
    let pixels = rgba
        .as_array()
        .as_standard_layout()
        .into_owned()
        .into_raw_vec_and_offset()
        .0;
    let png = py
        .detach(|| encode_png_rgba8(std::path::Path::new("rgba"), w, h, &pixels))
        .map_err(to_py)?;
    Ok(PyBytes::new(py, &png))
}

#[pymodule]
fn _glyphcast(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<renderer::Renderer>()?;
    m.add_function(wrap_pyfunction!(encode_png, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
