//! glyphcast's Python module: numpy in, images out. The extension is
//! `glyphcast._glyphcast`; the Python package `glyphcast` (python/glyphcast) wraps it
//! with the documented functions, keyword defaults and notebook display.
//!
//! Nothing here renders or parses on its own: scenes, volume slices, montages and render
//! options go through the same library calls as `glyphcast render` (`render::options`,
//! `volume::VolumeRequest`, `render::compose::montage`, `render::headless`), so the module and
//! the CLI draw the same pixels with the same defaults and checks; their messages name
//! each option as this module's keyword where the CLI names its flag (`errors`).
use glyphcast::io::png::encode_png_rgba8_at;
use numpy::{PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

mod arrays;
mod errors;
mod kwargs;
mod renderer;

use errors::{to_py, value_error};

/// A stiffness matrix's glyph scene (JSON) and its elastic summary (JSON), as
/// `glyphcast stiffness -o SCENE --summary FILE --surface SURFACE` writes them: `c` the
/// 6 x 6 Voigt matrix, `euler` Bunge angles in degrees (sample to crystal),
/// `allow_unstable` to take a matrix that is not positive definite, `surface` reynolds,
/// young, compressibility, shear-min, shear-max, poisson-min or poisson-max.
#[pyfunction]
#[pyo3(signature = (c, euler=None, allow_unstable=false, symmetric_part=false, surface="reynolds"))]
fn stiffness(
    c: Vec<Vec<f64>>,
    euler: Option<(f64, f64, f64)>,
    allow_unstable: bool,
    symmetric_part: bool,
    surface: &str,
) -> PyResult<(String, String)> {
    use glyphcast::glyph::stiffness::{ShearOrder, VoigtStiffness};
    use glyphcast_materials::{Options, Rotation, Stiffness, Surface};
    let drawn_surface = match surface {
        "reynolds" => None,
        name => match Surface::from_name(name) {
            Some(s) => Some(s),
            None => {
                return Err(value_error(
                    &format!("surface={name:?}"),
                    "not one of reynolds, young, compressibility, shear-min, shear-max, \
                     poisson-min, poisson-max",
                ));
            }
        },
    };
    if symmetric_part && drawn_surface.is_some() {
        return Err(value_error(
            "symmetric_part=True",
            "applies to surface=\"reynolds\" only",
        ));
    }
    let rows: Vec<[f64; 6]> = c
        .iter()
        .map(|row| <[f64; 6]>::try_from(row.as_slice()))
        .collect::<Result<_, _>>()
        .map_err(|_| value_error("C", "a 6 x 6 Voigt matrix is needed"))?;
    let matrix: [[f64; 6]; 6] = rows
        .try_into()
        .map_err(|_| value_error("C", "a 6 x 6 Voigt matrix is needed"))?;
    // The library's checks first (finite, symmetric), with its messages.
    let checked = VoigtStiffness::from_matrix(matrix, ShearOrder::Standard, "C").map_err(to_py)?;
    let options = Options { allow_unstable };
    let crystal = Stiffness::with_options(checked.in_order(ShearOrder::Standard), options)
        .map_err(|e| value_error("C", format!("{e} (allow_unstable=True draws it anyway)")))?;
    let sample = match euler {
        Some((phi1, phi, phi2)) => {
            let g = Rotation::from_bunge_degrees(phi1, phi, phi2)
                .map_err(|e| value_error("euler", e))?;
            crystal.rotated(&g)
        }
        None => crystal,
    };
    let scene = match drawn_surface {
        None => {
            let drawn = VoigtStiffness::from_matrix(*sample.voigt(), ShearOrder::Standard, "C")
                .map_err(to_py)?;
            glyphcast::demo::stiffness_row_scene(&[drawn], symmetric_part).map_err(to_py)?
        }
        Some(s) => {
            // Young's and compressibility's surfaces are tensor forms (surface_form), the
            // shear extremes plane glyphs of two forms (plane_forms), Poisson's ratio's
            // ratio glyphs of three (ratio_forms).
            let largest = sample.largest_radius(s);
            let (plane, ratio) = (sample.plane_forms(s), sample.ratio_forms(s));
            let glyph = match (plane, ratio) {
                (_, Some(f)) => glyphcast::demo::RowGlyph::of_ratio(
                    [&f.determinant, &f.trace, &f.denominator],
                    f.smaller_root,
                    largest,
                ),
                (Some(forms), None) => glyphcast::demo::RowGlyph::of_plane(
                    &forms.determinant,
                    &forms.trace,
                    forms.larger_root,
                    largest,
                ),
                (None, None) => {
                    let form = sample
                        .surface_form(s)
                        .ok_or_else(|| value_error("surface", "not a tensor form"))?;
                    glyphcast::demo::RowGlyph::of_form(
                        form.order,
                        &form.tensor,
                        form.reciprocal,
                        largest,
                    )
                }
            }
            .map_err(|e| value_error("C", format!("{}'s surface: {e}", s.name())))?;
            glyphcast::demo::material_row_scene(&[glyph]).map_err(to_py)?
        }
    };
    let summary = serde_json::to_string(&sample.summary())
        .map_err(|e| value_error("C", format!("the summary: {e}")))?;
    Ok((scene.to_json(), summary))
}

/// The render settings, one dict each (`key`, `name`, `kind`, `accepts`, `default`,
/// `read_by`, `doc`): the library's table, which the keyword options of every render
/// function follow.
#[pyfunction]
fn render_settings(py: Python<'_>) -> PyResult<Vec<Bound<'_, pyo3::types::PyDict>>> {
    use glyphcast::render::table::{Kind, RENDER_SETTINGS};
    RENDER_SETTINGS
        .iter()
        .map(|spec| {
            let row = pyo3::types::PyDict::new(py);
            row.set_item("key", spec.setting.keyword())?;
            row.set_item("name", spec.setting.name())?;
            let kind = match spec.kind {
                Kind::Number => "number",
                Kind::Count => "whole number",
                Kind::Name => "name",
                Kind::Switch => "switch or name",
                Kind::Numbers => "numbers",
            };
            row.set_item("kind", kind)?;
            row.set_item("accepts", spec.accepts)?;
            row.set_item("default", spec.default)?;
            row.set_item("read_by", spec.reads.to_string())?;
            row.set_item("doc", spec.doc.trim())?;
            Ok(row)
        })
        .collect()
}

/// PNG bytes of an (H, W, 4) uint8 RGBA image (sRGB, as rendered), with `dpi` (pixels
/// per inch) recorded as its print resolution if given.
#[pyfunction]
#[pyo3(signature = (rgba, dpi=None))]
fn encode_png<'py>(
    py: Python<'py>,
    rgba: PyReadonlyArray3<'py, u8>,
    dpi: Option<f64>,
) -> PyResult<Bound<'py, PyBytes>> {
    if let Some(dpi) = dpi.filter(|d| !(d.is_finite() && *d > 0.0 && *d <= 1e6)) {
        return Err(value_error(
            &format!("dpi={dpi}"),
            "must be above 0 (at most 1000000)",
        ));
    }
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
        .detach(|| encode_png_rgba8_at(std::path::Path::new("rgba"), (w, h), &pixels, dpi))
        .map_err(to_py)?;
    Ok(PyBytes::new(py, &png))
}

#[pymodule]
fn _glyphcast(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<renderer::Renderer>()?;
    m.add_function(wrap_pyfunction!(encode_png, m)?)?;
    m.add_function(wrap_pyfunction!(render_settings, m)?)?;
    m.add_function(wrap_pyfunction!(stiffness, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
